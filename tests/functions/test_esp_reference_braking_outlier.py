"""Reference plausibility while braking past the pedal onset (functions/esp.py ``braking_outlier``,
``esp.reference_braking_outlier_flag``; 0 = seeded defect, the 968b8ea rule).

Physics used as the reference (independent of the code's numbers): a smaller rolling radius (blown/deflated tire) makes
ONE wheel turn faster than the car; a wheel whose brake was released (inlet closed / outlet open: its own ABS, the rear
select-low, the GMA) comes back toward the car's speed from below, never above it. So, past the onset window, a wheel
is held back from the reference / left out only when it is alone (more than the 8 % band above the second fastest
wheel) and its valves have been quiet for the quiet time; the system-level check is the ice60 test in
test_esp_known_limits.py (brake_assist.md 8 criterion 5).
"""
from __future__ import annotations

import numpy as np
import pytest

import vehicle_assist as va
from vehicle_assist.functions import esp
from tests.support import packed_params

DT = 0.005  # ESP period (vehicle file esp.period_s)
DEFECT = "vehicle.esp.reference_braking_outlier_flag=0"


def _params(sets=()):
    """The SEDAN's packed parameters (brake assist, paper 002; hba_snow_60kph runs sedan_1p8t)."""
    return packed_params("hba_snow_60kph", *sets)


@pytest.fixture(scope="module")
def params():
    return _params()


@pytest.fixture(scope="module")
def params_defect():
    return _params([DEFECT])


def _run(params, vw, abs_quiet, valve_quiet, n, v_ref=10.0, braked_s=1.0):
    """n braking periods, ``braked_s`` after the pedal onset, reference ``v_ref`` (drifted low below the wheels)."""
    ctl = esp.initial_state()[0]
    ctl[esp.C_STARTED] = 1.0
    ctl[esp.C_V_REF] = v_ref
    ctl[esp.C_BRAKED_S] = braked_s
    for _ in range(n):
        esp.plausible_reference(ctl, np.asarray(vw, dtype=float), True, params, DT, 0.0,
                                np.asarray(abs_quiet, dtype=float), np.asarray(valve_quiet, dtype=float))
    return int(ctl[esp.C_REF_EXCLUDED])


def test_released_rear_nearest_the_car_speed_stays_in(params, params_defect):
    """ice60 mechanism: reference drifted low (10 m/s), RL at the car's 15 m/s, the others slipping at 9 m/s; RL's own
    ABS mode is OFF (quiet 1 s) but the rear select-low closed its inlet (valve quiet 0): it stays in the reference.
    The seeded defect (own ABS mode only) leaves it out after 0.1 s (20 periods)."""
    args = ((9.0, 9.0, 15.0, 9.0), (0.0, 0.0, 1.0, 0.0), (0.0, 0.0, 0.0, 0.0), 40)
    assert _run(params, *args) == -1
    assert _run(params_defect, *args) == 2


def test_two_fast_wheels_are_not_a_fast_tire(params, params_defect):
    """Two wheels together 50 % above a drifted-low reference, all valves quiet: not a lone wheel (not > 8 % above the
    second fastest), so none is left out; the defect leaves one out."""
    args = ((15.0, 15.0, 9.0, 9.0), (1.0, 1.0, 1.0, 1.0), (1.0, 1.0, 1.0, 1.0), 40)
    assert _run(params, *args) == -1
    assert _run(params_defect, *args) in (0, 1)  # one after the other (persistence 20 periods each)


def test_lone_quiet_fast_wheel_is_left_out(params):
    """A blown tire during a long braking: one wheel 40 % above the others, valves quiet: left out after the
    persistence time (20 periods), not before."""
    args = ((14.0, 10.0, 10.0, 10.0), (1.0, 1.0, 1.0, 1.0), (1.0, 1.0, 1.0, 1.0))
    assert _run(params, *args, 19) == -1
    assert _run(params, *args, 20) == 0


def test_onset_window_keeps_the_f4b_rule(params):
    """Within reference_braking_onset_s of the pedal (F4b: tire blown 0.05 s before the pedal, the intact wheels' ABS
    holds on the lifted reference and the select-low closes the blown rear's inlet) the wheel's own ABS mode decides:
    the released-but-own-mode-quiet rear is left out there."""
    args = ((9.0, 9.0, 15.0, 9.0), (0.0, 0.0, 1.0, 0.0), (0.0, 0.0, 0.0, 0.0), 40)
    assert _run(params, *args, braked_s=0.0) == 2
