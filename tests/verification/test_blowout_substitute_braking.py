"""N3 (session 2026-11-25 n): ``blowout_compensation.substitute_braking_flag`` (tire_blowout_findings.md N3).

A REAR blowout whose opposite rear's inlet is diagnosed stuck closed: the compensation goes LIMITED (limit code 1) and
counter-brakes on the SUBSTITUTE front (the front on the other side). With a braking driver that front takes the
driver's pressure and ABS guards it - but its re-build after an ABS dump stopped at the compensation's plan (lowered
before the pedal by the rear slip limit / capacity rule), so every dump lowered it for good. rear_braking_flag's
re-build (to the highest driver's level it reached, never above the dump's start) is applied to that front.

* The lead's f_r41 #184 (faults_t0 = tire_blowout_faults at fault_time 0): RL blown, RR stuck from t = 0, 54 km/h,
  mu 0.39, 650 m left curve, fixed steering, pedal 0.25 from 1.74 s. Flag 0: FR 31 bar at the pedal, 6.7 bar from
  2.4 s to the stop (9.3 s), the twin's ABS-cycled FR 20-25 bar; the function's car leaves the road (road-clipped
  deviation 3.978 m), the twin stops on it (3.056 m): no_earlier_road_departure -26.045 s.

References: the twin with the same fault (the car without the function; its FR is what ABS gives that wheel) and the
road edge of the requirement (lane margin + 3.0 m shoulder). No bound taken from the function's own output.
"""
from __future__ import annotations

import numpy as np
import pytest

from vehicle_assist.verification.envelope import load_envelope
from tests.support import envelope_point_run

ROAD = "blowout_lateral_deviation_road_max_m"
EARLY = "blowout_road_departure_earliness_s"
P184 = {"speed": 53.51858866794322, "mu": 0.38940304617064486, "delay": 0.14620579803477005,
        "wheel_speed_noise": 0.25791543213718915, "noise_seed": 8906.0, "brake_gain": 1.1024999720839241,
        "accumulator": 84.29195478977583, "brake.start_s": 1.7365634334131352,
        "brake.level_frac": 0.2516823282086723, "brake.rate_per_s": 26.434723594027552, "braking": "brakes",
        "wheel": "rl", "driver": "fixed", "curve": "r650", "fault": "inlet_stuck_rr", "fault_time": 0.0}


@pytest.fixture(scope="module")
def runs():
    env = load_envelope("tire_blowout_faults")
    return {"on": envelope_point_run(env, P184),  # the shipped flags
            "none": envelope_point_run(env, P184, True)}


def test_184_no_earlier_road_departure(runs):
    """Row no_earlier_road_departure: the twin stays on the road, so must the function's car (earliness 0). Flag 0:
    26.045 s (FAILS)."""
    assert runs["none"].metrics[EARLY] == 0.0
    assert runs["on"].metrics[EARLY] <= runs["none"].metrics[EARLY], runs["on"].metrics[EARLY]


def test_184_never_worse_on_the_road(runs):
    """Row no_worse_than_no_compensation (road-clipped): flag 0 3.978 m (off the road) vs the twin's 3.056 (FAILS)."""
    assert runs["on"].metrics[ROAD] <= runs["none"].metrics[ROAD], (runs["on"].metrics[ROAD], runs["none"].metrics[ROAD])


def _window(r, t0, t1):
    tr = r.trace
    t = np.asarray(tr["time_s"])
    return (t >= t0) & (t <= t1)


def test_184_substitute_front_keeps_the_brake_abs_gives_it(runs):
    """The mechanism: while LIMITED (code 1) and the driver brakes, the substitute FR carries the brake that ABS gives
    that wheel in the car without the function, not a level ratcheted down by dumps. Window: 0.5 s after the pedal
    to 1 s before the twin stops (both cars braking, the twin's FR ABS-cycled). Flag 0: FR mean 5.6 bar vs the twin's
    23.1 (ratio 0.24, FAILS); 0.5 = half of the twin's - the test's margin, not a model number."""
    on, none = runs["on"], runs["none"]
    v = np.asarray(none.trace["speed_mps"])
    t = np.asarray(none.trace["time_s"])
    t_stop = float(t[np.argmax(v < 0.1)])
    t0, t1 = P184["brake.start_s"] + 0.5, t_stop - 1.0
    m_on = _window(on, t0, t1)
    m_none = _window(none, t0, t1)
    mode = np.asarray(on.trace["blowout_mode_index"])[m_on]
    code = np.asarray(on.trace["blowout_limit_code"])[m_on]
    assert np.all(mode == 3) and np.all(code == 1)  # LIMITED, opposite inlet stuck: the rule's premise holds
    fr_on = float(np.mean(np.asarray(on.trace["wheel_pressure_fr_pa"])[m_on]))
    fr_none = float(np.mean(np.asarray(none.trace["wheel_pressure_fr_pa"])[m_none]))
    assert fr_on >= 0.5 * fr_none, (fr_on / 1e5, fr_none / 1e5)
