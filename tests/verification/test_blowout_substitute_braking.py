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


# --- review R3 (session n): the mirror side and the other curve direction ----------------------------------------------
# N3's three tests use one point (RL blown, RR stuck from t = 0, left curve). A mutant that applies the rule to a blown
# RL only (b == 2) passed all three; on R3's targeted search (tire_blowout_faults, -R wheel=rl,rr -R
# fault=inlet_stuck_rl,inlet_stuck_rr -R braking=brakes, seed 613, 256 points) it made #115 a NEW violation in both rows.
# #115: RR blown, RL's inlet stuck from 0.89 s, 650 m LEFT curve (RR the outer rear), 64 km/h, mu 0.51, pedal 1.67 s.
# #98 of the same search on RIGHT-hand curves (tire_blowout_faults_right, lead's f326f04 = the curve's radius negative):
# RL blown, RR stuck from 1.57 s (after the detection: BUILD/HOLD on RR, then LIMITED on the substitute FR), 650 m right
# curve, 55 km/h, mu 0.44, pedal 2.10 s. References: the twin with the same fault and the road edge (as above).
P115 = {"speed": 63.65789269179121, "mu": 0.5085887279554567, "delay": 0.10843909832530703,
        "wheel_speed_noise": 0.18766956833127674, "noise_seed": 4159.0, "brake_gain": 1.1263230375822375,
        "accumulator": 70.03392537358765, "fault_time": 0.8895616547657728, "brake.start_s": 1.6701598241372202,
        "brake.level_frac": 0.15917374526209346, "brake.rate_per_s": 11.007861245842939, "braking": "brakes",
        "wheel": "rr", "driver": "fixed", "curve": "r650", "fault": "inlet_stuck_rl"}
P98R = {"speed": 54.83411736029418, "mu": 0.4380105775584465, "delay": 0.10132898845261192,
        "wheel_speed_noise": 0.28989212001859294, "noise_seed": 7036.0, "brake_gain": 0.8736321390137991,
        "accumulator": 51.045592631348924, "fault_time": 1.5696262376994534, "brake.start_s": 2.0972853229314032,
        "brake.level_frac": 0.300281991556663, "brake.rate_per_s": 18.854096850304792, "braking": "brakes",
        "wheel": "rl", "driver": "fixed", "curve": "r650", "fault": "inlet_stuck_rr"}
RIGHT = ("vehicle.lane_keeper.lane_radius_m=-650",)  # tire_blowout_faults_right's rr650


@pytest.fixture(scope="module")
def mirror_runs():
    env = load_envelope("tire_blowout_faults")
    return {"115": (envelope_point_run(env, P115), envelope_point_run(env, P115, True)),
            "98R": (envelope_point_run(env, P98R, sets=RIGHT), envelope_point_run(env, P98R, True, sets=RIGHT))}


@pytest.mark.parametrize("name", ["115", "98R"])
def test_mirror_no_earlier_road_departure(mirror_runs, name):
    """Row no_earlier_road_departure on the mirror side (#115, RR blown) and on a right-hand curve (#98R). Flag 0:
    #115 25.345 s, #98R 23.670 s (FAIL); the RL-only mutant: #115 25.345 s (FAILS)."""
    on, none = mirror_runs[name]
    assert on.metrics[EARLY] <= none.metrics[EARLY], (on.metrics[EARLY], none.metrics[EARLY])


@pytest.mark.parametrize("name", ["115", "98R"])
def test_mirror_never_worse_on_the_road(mirror_runs, name):
    """Row no_worse_than_no_compensation (road-clipped) on the same two points. Flag 0: #115 robustness -0.131,
    #98R -0.355 (FAIL); the RL-only mutant: #115 -0.131 (FAILS)."""
    on, none = mirror_runs[name]
    assert on.metrics[ROAD] <= none.metrics[ROAD], (on.metrics[ROAD], none.metrics[ROAD])
