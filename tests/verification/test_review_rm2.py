"""Review RM2 (session 2026-11-24 m) of M2's ``blowout_compensation.blown_side_front_flag`` = 2 (a blown FRONT whose
side's REAR inlet is stuck closed: the free rear held select-low - at most 1 bar above the pressure trapped in the stuck
rear - while the yaw error points AWAY from the blown side beyond the braking rule's dead band).

M2's tests use one acting point (#90, FL blown, RL stuck, left curve) and one untouched point (#17). Mutants of the rule
that survived them (tire_blowout_findings.md RM2): the gate's sign taken from the yaw error alone (right for FL, wrong
for FR), the gate or its dead band dropped, the cap latched once set. Points added here:

* #137 of RM2's search (faults_t0, random seed 23, -R wheel=fl,fr -R fault=inlet_stuck_rl,inlet_stuck_rr -R
  braking=brakes): FL blown, RL stuck, STRAIGHT road, fixed steering (the steered reference is 0, so the yaw error is
  the yaw rate), 108 km/h, mu 0.40, panic pedal 0.47 from 1.17 s. Flag 0: 2.579 m vs the twin's 1.559 (RR 41-54 bar
  alone against RL 0.7 bar). Its MIRROR (FR blown, RR stuck, everything else equal) is the independent reference for the
  other side: the plant, the X-split circuits and the straight road are mirror-symmetric, so the rule must do the
  mirrored thing (flag 0: 2.693 m vs twin 1.636; flag 2: 1.119 / 1.114 m for the two sides).
* #95 of M2's own set (faults_t0 seed 7): FL blown, RL stuck, left curve r1000, pedal 2.02 s; the ungated rule (M2's
  variant, = mutant 'no gate') made it a NEW violation, +0.293 -> -0.176 m.

References: the twin with the same fault (never worse), mirror symmetry, the rule's own statement (the ESP's rear
select-low level = the stuck rear's pressure + 1 bar, Bosch Automotive Handbook ABS select-low; released when the yaw
error no longer points away from the blown side - the braking rule's dead band, yaw_deadband_deg_per_s). No bound is
taken from the function's output.
"""
from __future__ import annotations

import numpy as np
import pytest

from vehicle_assist.verification.envelope import load_envelope
from tests.support import envelope_point_run

METRIC = "blowout_lateral_deviation_run_max_m"
FLAG = "vehicle.blowout_compensation.blown_side_front_flag"
BAR = 1.0e5
DEADBAND = np.deg2rad(1.0)  # suv_bj2500 blowout_compensation.yaw_deadband_deg_per_s (the rule's gate)
LIMIT_BLOWN_SIDE = 6
P137 = {"speed": 107.88547227990549, "mu": 0.39587181487179507, "delay": 0.1390145640381683,
        "wheel_speed_noise": 0.05989837280799076, "noise_seed": 7312.0, "brake_gain": 0.8614811935741586,
        "accumulator": 79.45826501242345, "brake.start_s": 1.172291511067692, "brake.level_frac": 0.4719536490265265,
        "brake.rate_per_s": 28.995197032457792, "braking": "brakes", "wheel": "fl", "driver": "fixed",
        "curve": "straight", "fault": "inlet_stuck_rl", "fault_time": 0.0}
P137_MIRROR = dict(P137, wheel="fr", fault="inlet_stuck_rr")
P95 = {"speed": 118.72368377813987, "mu": 0.38364493322955673, "delay": 0.26378980578550265,
       "wheel_speed_noise": 0.027755604672762967, "noise_seed": 3928.0, "brake_gain": 1.1751757825765714,
       "accumulator": 46.87362409737596, "brake.start_s": 2.0154455568541563, "brake.level_frac": 0.43675405363342157,
       "brake.rate_per_s": 15.281643987008852, "braking": "brakes", "wheel": "fl", "driver": "fixed",
       "curve": "r1000", "fault": "inlet_stuck_rl", "fault_time": 0.0}
# blown wheel -> (stuck rear, free rear, sign making a CCW+ yaw rate 'toward the blown side')
SIDES = {"fl": ("rl", "rr", 1.0), "fr": ("rr", "rl", -1.0)}


def _run(env, point, flag=None, baseline=False):
    return envelope_point_run(env, point, baseline, (f"{FLAG}={flag}",) if flag is not None else ())


@pytest.fixture(scope="module")
def runs():
    env = load_envelope("tire_blowout_faults")
    out = {}
    for name, pt in (("137", P137), ("137m", P137_MIRROR), ("95", P95)):
        out[name] = {"on": _run(env, pt, 2), "none": _run(env, pt, baseline=True)}
    for name, pt in (("137", P137), ("137m", P137_MIRROR)):
        out[name]["defect"] = _run(env, pt, 0)
    return out


_N1_RM2 = (
    "N1 (session n): judged to standstill blown_side_front_flag = 2 is worse than the twin with the same fault: #137 the "
    "function's car leaves the road (run max 4.646 m, departure at t_b + 7.6 s) where the twin stays on (2.229 m): "
    "robustness -1.749 m / -22.420 s; mirror -1.615 m / -22.390 s (4.625 vs 2.363 m); #95 2.971 vs 0.625 m (-2.346 m, "
    "both on the road; flag 0 2.902 m); the function's car stops 11.4 / 16.1 s after the start against the twin's "
    "8.2 / 9.6 s and drifts on (at 5 s no worse)")


# (session o, O4) #95 passes with blown_side_stop_flag 1 (the counter-brake front takes its share inside the dead band
# while code 6): value 2 0.460 m vs the twin's 0.625 (blown_side_stop 0: 2.971); #137 / #137m stay N1's losses
@pytest.mark.parametrize("name", [pytest.param("137", marks=pytest.mark.xfail(strict=True, reason=_N1_RM2)),
                                  pytest.param("137m", marks=pytest.mark.xfail(strict=True, reason=_N1_RM2)),
                                  "95"])
def test_never_worse_both_sides_and_the_gated_curve_point(runs, name):
    """Never worse than the car without the function with the same fault, on #137 (FL), its mirror (FR) and #95
    (left curve, late pedal: the gate's point). Flag 0: #137 2.579 vs 1.559 m, mirror 2.693 vs 1.636 m. Session n
    (N1, class B): both rows of the requirement (never_worse_rows); an honest finding at standstill (xfail reason)."""
    from tests.support import never_worse_rows

    rows = never_worse_rows(runs[name]["on"], runs[name]["none"])
    assert min(rows.values()) >= 0.0, (name, rows)


@pytest.mark.parametrize("name", ["137", "137m"])
def test_defect_is_a_violation_on_both_sides(runs, name):
    """Negative control: flag 0 (the code before) is worse than the twin at #137 and its mirror."""
    assert runs[name]["defect"].metrics[METRIC] > runs[name]["none"].metrics[METRIC]


@pytest.mark.parametrize("name", ["137", "137m"])
def test_free_rear_select_low_while_yawing_away_and_released_after(runs, name):
    """The rule's statement, per side, read from the plant (straight road, fixed steering: the yaw error is the yaw
    rate). (1) While the car has yawed AWAY from the blown side beyond the dead band for 50 ms (the gate on, time for
    the dump), the free rear comes down to the stuck rear's level + 1 bar (+ 1 bar for the hold's and the estimate's
    lag): its minimum over such samples. (2) The cap is not latched: while the yaw rate no longer points away beyond the
    dead band (gate off) after the first cap, the free rear is back on the driver's pressure at some sample (> 10 bar, the
    driver's proportioned pressure is 40-54 bar here). (3) The whole braking window says code 6."""
    wheel = {"137": "fl", "137m": "fr"}[name]
    stuck, free, sgn = SIDES[wheel]
    r = runs[name]["on"]
    t = np.asarray(r.trace["time_s"])
    toward = sgn * np.asarray(r.trace["yaw_rate_radps"])
    p_stuck = np.asarray(r.trace[f"wheel_pressure_{stuck}_pa"])
    p_free = np.asarray(r.trace[f"wheel_pressure_{free}_pa"])
    dt = t[1] - t[0]
    n = int(round(0.05 / dt))
    away = toward < -DEADBAND
    held = np.array([k >= n and away[k - n:k + 1].all() for k in range(len(t))])
    assert held.sum() > 0, "premise: the car yaws away from the blown side (flag 0 does, the twin too)"
    assert np.min(p_free[held] - p_stuck[held]) < 2 * BAR, np.min(p_free[held] - p_stuck[held]) / BAR
    first = t[np.argmax(held)]
    after_toward = (t > first) & (toward > -DEADBAND) & (t < 4.0)
    assert after_toward.any() and np.max(p_free[after_toward]) > 10 * BAR, np.max(p_free[after_toward]) / BAR
    w = (t >= 1.4) & (t <= 3.5)
    codes = np.asarray(r.trace["blowout_limit_code"])[w]
    assert np.all(codes == LIMIT_BLOWN_SIDE), np.unique(codes)


def test_mirror_symmetry_of_the_gain(runs):
    """Mirror symmetry (independent of the rule): the straight point and its mirror differ only by the side (and by the
    sensor-noise realisation, which the twins show: 1.559 vs 1.636 m). The rule's gain over flag 0 must be the same on
    both sides to within that spread: a rule that acts on one side only gains ~0 there. Bound: each side's gain is
    at least half of the other's."""
    g = {k: runs[k]["defect"].metrics[METRIC] - runs[k]["on"].metrics[METRIC] for k in ("137", "137m")}
    assert g["137"] > 0.5 * g["137m"] and g["137m"] > 0.5 * g["137"], g


def test_limit_code_6_says_what_the_front_rule_does():
    """(c) Issue #10 'Faults' ('says why'): code 6's reason said 'the blown wheel is left to the driver and ABS (not
    released) and no counter-brake is added' - false for a blown front (M2: released, counter-brake kept, the free rear
    held select-low). The reason names both cases."""
    from vehicle_assist.functions.blowout_compensation import LIMIT_BLOWN_SIDE, LIMIT_REASONS

    why = LIMIT_REASONS[LIMIT_BLOWN_SIDE]
    assert "front blown" in why and "select-low" in why and "blown_side_front_flag" in why, why


P61T = {"speed": 84.90912784968877, "mu": 0.31295992770956355, "delay": 0.45320438626887666,
        "wheel_speed_noise": 0.11673692360032095, "noise_seed": 2939.0, "brake_gain": 0.8221361681127359,
        "accumulator": 46.225079390927164, "fault_time": 1.683003909343571, "brake.start_s": 0.9678204181279444,
        "brake.level_frac": 0.40067602664282687, "brake.rate_per_s": 23.379350647506904, "braking": "brakes",
        "wheel": "fl", "driver": "fixed", "curve": "r650", "fault": "inlet_stuck_rl"}


def test_rear_stuck_while_braked_keeps_the_code_before():
    """The premise 'the stuck wheel is unbraked at its diagnosis' (blown_side_fault_flag 3, esp.plausibility_pressure)
    holds for a blown front too. RM2's search on the shipped tire_blowout_faults (fault_time; random seed 29) #61: FL
    blown, RL stuck at 1.68 s with the pedal on since 0.97 s (pressure trapped in RL): value 2 must run as flag 0 (the
    code before), bit for bit. A mutant without that premise for fronts: -0.031 -> -0.203 m (already a violation at
    flag 0: the point tests the gate, not never-worse)."""
    env = load_envelope("tire_blowout_faults")
    a, b = _run(env, P61T, 2), _run(env, P61T, 0)
    assert np.max(np.asarray(a.trace["wheel_pressure_rl_pa"])) > 2 * BAR  # premise: RL was braked when it stuck
    assert a.metrics[METRIC] == b.metrics[METRIC]
    for w in ("fl", "fr", "rl", "rr"):
        assert np.array_equal(np.asarray(a.trace[f"wheel_pressure_{w}_pa"]), np.asarray(b.trace[f"wheel_pressure_{w}_pa"])), w
