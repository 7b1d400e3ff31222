"""Rise limit of the ESP/ABS reference speed while braking (functions/esp.py ``reference_update``,
``esp.reference_braking_rise_limit_flag``; 0 = seeded defect, the code before: an ABS-active wheel lifted the reference
freely).

Independent references: the kinematics of a constant-deceleration stop (the true speed is v0 - a*t, the accelerometer
reads -a) and the limit of ABS practice (the reference rises at most at the largest possible vehicle acceleration,
Kelsey-Hayes US 5,644,490; here a_x,meas + reference_braking_rise_margin_mps2, whose 2 m/s^2 is an "assumed" in the
vehicle file); at system level UN R13-H Annex 6 (ABS category 1: adhesion utilisation >= 0.75) on the friction the
curve leaves for braking, as tests/functions/test_esp_reference_plausibility.py.

Finding G8 (session g): the no-compensation twin of CMA-ES 2026 b200 #124 - ABS dumped the flat FL, it spun up to its
smaller rolling radius (0.244 vs 0.359 m: 32.7 m/s read at 22.2 m/s), its ABS activity kept it in the reference (the
braking outlier test judges valve-quiet wheels only), v_ref 25.2 -> 32.6 m/s in 0.3 s and the other three wheels were
held at ~1 bar for 1.6 s: the twin stopped braking and was flattered in the never-worse comparison.
"""
from __future__ import annotations

import numpy as np
import pytest

import vehicle_assist as va
from vehicle_assist.functions import esp
from vehicle_assist.verification.envelope import load_envelope
from tests.support import mean_decel

DT = 0.005  # ESP period (vehicle file esp.period_s)
FLAG = "vehicle.esp.reference_braking_rise_limit_flag"
RISE_MARGIN_MPS2 = 2.0  # the limit under test: vehicle file esp.reference_braking_rise_margin_mps2 (source there)
G = 9.80665
MU_PEAK_DRY = 1.17  # peak of the SUV's dry Burckhardt set; road.friction_mu scales it (tire_blowout envelope)
ADHESION_UTILISATION = 0.75  # UN R13-H Annex 6 (ABS category 1): epsilon >= 0.75


def _params(flag):
    from vehicle_assist.scenarios.runner import pack_records

    return pack_records([va.load_scenario("hba_snow_60kph", [f"{FLAG}={flag}"]).vehicle.flat()])[0]


@pytest.fixture(scope="module")
def params():
    return {f: _params(f) for f in (1, 0)}


def _stop(p, wheels, a_true, a_meas, v0, v_ref0, valve_quiet, n):
    """n braking periods, 1 s past the pedal onset: the true speed v0 - a_true*t, wheel i reads wheels[i](v_true),
    the accelerometer ``a_meas`` (signed). Returns (t, v_true, v_ref) arrays."""
    ctl = esp.initial_state()[0]
    ctl[esp.C_STARTED] = 1.0
    ctl[esp.C_V_REF] = v_ref0
    ctl[esp.C_BRAKED_S] = 1.0
    quiet = np.asarray(valve_quiet, dtype=float)
    out = []
    for k in range(1, n + 1):
        t = k * DT
        v = v0 - a_true * t
        vw = np.array([f(v) for f in wheels])
        ctl[esp.C_BRAKED_S] += DT
        v_plaus, changed = esp.plausible_reference(ctl, vw, True, p, DT, a_meas, quiet, quiet)
        v_ref = esp.reference_update(ctl, vw, v_plaus, changed, True, a_meas, quiet, p, DT)
        ctl[esp.C_V_REF] = v_ref
        out.append((t, v, v_ref))
    return np.array(out).T


@pytest.mark.parametrize("flag", [1, 0])
def test_one_fast_abs_active_wheel_keeps_the_reference_within_the_limit(params, flag):
    """Constant-deceleration stop (6 m/s^2 from 30 m/s, accelerometer exact), three wheels at 5 % ABS slip, FL reading
    30 % fast (a flat front spun up, a sensor fault) with ABS activity on it (valves never quiet, so the outlier test
    cannot leave it out): for 2 s the reference stays within RISE_MARGIN_MPS2 * t of the true speed. The seeded defect
    rides FL: 0.3 * v_true (7 m/s at 1 s) above it, the check fails."""
    slip = lambda v: 0.95 * v  # noqa: E731
    t, v, v_ref = _stop(params[flag], (lambda v: 1.3 * v, slip, slip, slip), 6.0, -6.0, 30.0, 30.0,
                        (0.0, 0.0, 0.0, 0.0), 400)
    excess = v_ref - v - RISE_MARGIN_MPS2 * t
    if flag:
        assert excess.max() <= 1e-9, excess.max()
    else:
        assert excess.max() > 1.0, excess.max()  # negative control: the defect fails the bound


@pytest.mark.parametrize("flag", [1, 0])
def test_two_wheels_lift_a_drifted_low_reference_at_once(params, flag):
    """Guard for the drifted-low case (ice, accelerometer over-reading deceleration): reference 10 % below the true
    speed, FL and FR back at the car's speed after a release (ABS-active), the rears slipping 30 %: two wheels agreeing
    show the car's speed, the reference is back on it after one period (with and without the rule)."""
    slip = lambda v: 0.7 * v  # noqa: E731
    true = lambda v: v  # noqa: E731
    t, v, v_ref = _stop(params[flag], (true, true, slip, slip), 1.5, -2.9, 15.0, 13.5, (0.0, 0.0, 0.0, 0.0), 10)
    assert np.allclose(v_ref, v, rtol=0, atol=1e-9), (v_ref - v).min()


def test_one_recovering_wheel_brings_a_drifted_low_reference_back(params):
    """The same drifted-low reference (1.5 m/s low) with ONE wheel back at the car's speed and the accelerometer
    over-reading deceleration by 1.4 m/s^2 (the ice60 robustness case): the rule lets the reference rise at
    a_x,meas + margin = true deceleration + 0.6 m/s^2, so it reaches the true speed within 1.5/0.6 = 2.5 s; it never
    exceeds it (it follows the wheel)."""
    slip = lambda v: 0.7 * v  # noqa: E731
    t, v, v_ref = _stop(params[1], (lambda v: v, slip, slip, slip), 1.5, -2.9, 15.0, 13.5, (0.0, 0.0, 0.0, 0.0), 540)
    assert (v_ref - v).max() <= 1e-9, (v_ref - v).max()
    assert abs(v_ref[-1] - v[-1]) <= 1e-9, v_ref[-1] - v[-1]


# G8's point: CMA-ES 2026 b200 #124 of the tire_blowout envelope (lead's history at 7242b18), FL blown, braking in the
# 650 m curve toward FL; its no-compensation twin is the system under test (the ESP/ABS alone).
P124 = {"speed": 113.40436654955622, "mu": 0.3015865312891882, "delay": 0.026428924010555487,
        "wheel_speed_noise": 0.29907701119224267, "noise_seed": 4004.0, "brake_gain": 0.8414758652864396,
        "brake.start_s": 0.7662424705649573, "brake.level_frac": 0.25007585116137115,
        "brake.rate_per_s": 5.848311888067299, "braking": "brakes", "wheel": "fl", "driver": "follow", "curve": "r650"}
T_DUMP_S = 3.2  # ABS dumps the flat FL (both variants; G8) - the runaway starts there


def _bound(point):
    """R13-H's 0.75 of the friction the 650 m curve leaves for braking at the initial speed (friction circle)."""
    mu_g = MU_PEAK_DRY * point["mu"] * G
    a_lat = (point["speed"] / 3.6) ** 2 / 650.0
    return ADHESION_UTILISATION * np.sqrt(mu_g ** 2 - a_lat ** 2)


@pytest.fixture(scope="module")
def twins():
    sc = load_envelope("tire_blowout").scenario(P124, baseline=True)
    return {f: va.simulate(sc.with_sets(f"{FLAG}={f}"), requirements=False) for f in (1, 0)}


@pytest.mark.parametrize("flag", [1, 0])
def test_g8_twin_keeps_braking_after_the_flat_front_is_dumped(twins, flag):
    """#124's twin, 0.1-1.1 s after ABS dumped the flat FL: mean deceleration >= 0.75 * sqrt((mu g)^2 - (u0^2/R)^2)
    (2.33 m/s^2). Measured 2.80 with the rule; the seeded defect 1.17 (all intact wheels at ~1 bar), the check fails."""
    a = mean_decel(twins[flag], T_DUMP_S + 0.1, T_DUMP_S + 1.1)
    if flag:
        assert a >= _bound(P124), (a, _bound(P124))
    else:
        assert a < _bound(P124), (a, _bound(P124))  # negative control


@pytest.mark.xfail(strict=True, reason="open: one over-reading wheel still holds the reference up to the margin "
                   "(2 m/s^2) above the car speed; by 5 s it reads 22.8 vs 18.1 m/s and ABS releases the intact wheels "
                   "again (measured 1.90 m/s^2 from 4.3 to 5.0 s). Needs a braked tire-size/sensor plausibility "
                   "that can leave an ABS-active wheel out (the 968b8ea ice case forbids the simple one).")
def test_g8_twin_keeps_braking_to_the_end(twins):
    a = mean_decel(twins[1], T_DUMP_S + 1.1, 5.0)
    assert a >= _bound(P124), (a, _bound(P124))


# --- review RH1 (session h): the checks above set the flag explicitly (1 and 0), so they pass whatever the vehicle
# files ship; these run the SHIPPED defaults (fail with reference_braking_rise_limit_flag = 0 in the vehicle file)
@pytest.mark.parametrize("scenario", ["hba_snow_60kph", "blowout_lf_60kph_paper"])  # sedan_1p8t, suv_bj2500
def test_shipped_vehicle_limits_one_fast_abs_active_wheel(scenario):
    from vehicle_assist.scenarios.runner import pack_records

    p = pack_records([va.load_scenario(scenario).vehicle.flat()])[0]
    slip = lambda v: 0.95 * v  # noqa: E731
    t, v, v_ref = _stop(p, (lambda v: 1.3 * v, slip, slip, slip), 6.0, -6.0, 30.0, 30.0, (0.0, 0.0, 0.0, 0.0), 400)
    assert (v_ref - v - RISE_MARGIN_MPS2 * t).max() <= 1e-9


def test_g8_twin_as_shipped_keeps_braking_after_the_flat_front_is_dumped():
    a = mean_decel(va.simulate(load_envelope("tire_blowout").scenario(P124, baseline=True), requirements=False),
                   T_DUMP_S + 0.1, T_DUMP_S + 1.1)
    assert a >= _bound(P124), (a, _bound(P124))
