"""The braking rule's rear pair while ABS acts on the compensating front in a curve toward the blown side
(``rear_accel_circle_flag``; docs/functions/tire_blowout_sessions.md status h item 6, tire_blowout_findings.md RH1 / I2 (session i)).

Session h (H1, ``rear_abs_limit_flag``) left the rear pair to ABS while the compensating front is ABS-active: the
panic stops got their deceleration back (3.1 -> 3.8 m/s^2), but in a low-mu curve the rear friction circle had been the
rears' only lateral protection (rear_circle_flag's reason: random 7 #15). With the blown front INSIDE the turn the
flat's diagonal load transfer unloads the OUTER rear; under the select-low pair that wheel is then run at ABS's lock slip
(RR 10-18 % slip, 0.1-0.17 kN lateral force at RH1's random 17 #24) and the car drifts out of the curve.

The rule: in a curve toward the blown side (steered reference yaw rate beyond the closed-loop dead band) the pair is
capped at the rears' friction circle (Kamm: F_x^2 + F_y^2 <= (mu*F_z)^2, spec 2.3) at the friction the car's measured
acceleration proves, mu >= |a|/g = sqrt(a_x^2 + a_y^2)/g (|sum F_i| = m*|a| <= sum mu*F_z,i = mu*m*g). Straight stops
and curves away from the blown side stay with ABS (H1).

Independent references: rigid-body statics for the wheel loads and the rear axle's lateral force (m*a_y*l_f/l, split
equally on two intact tires), the Kamm circle; the lane bound 0.978 m (requirement stay_in_lane: 3.75 m lane, JTG
B01-2014, BJ2500 width); the "braking no worse than not braking" check of tests/verification/
test_blowout_front_braking.py (+5 % assumed margin there). Each check below fails with the flag at 0 (H1's rule)."""
from __future__ import annotations

import math

import numpy as np
import pytest

FL, FR = 0, 1
G = 9.81
FLAG0 = "vehicle.blowout_compensation.rear_accel_circle_flag=0"
LANE_M = 0.978  # data/requirements/tire_blowout.toml stay_in_lane: (3.75 m lane JTG B01-2014 - 1.794 m width)/2
METRIC = "blowout_lateral_deviation_run_max_m"


def _params(*sets):
    import vehicle_assist as va
    from vehicle_assist.scenarios.runner import pack_records

    sc = va.load_scenario("blowout_lf_60kph_paper")
    return pack_records([(sc.with_sets(*sets) if sets else sc).vehicle.flat()])[0]


@pytest.fixture(scope="module")
def params():
    return _params()


def rear_cap_n(p, a_x, a_y, r_ref, abs_front=True, mu_meas=0.15, blown=FL):
    """The rear pair's cap as brake force [N] per wheel (-1 = no cap) from one braking_rule call: compensating front
    in HOLD with a measured friction, the driver braking 100 bar, the measured accelerations a_x, a_y (the steered
    lateral acceleration taken equal to the measured one), the steered reference yaw rate r_ref."""
    from vehicle_assist.functions import blowout_compensation as bc

    tg = FR if blown == FL else FL
    st = bc.initial_state()
    st[bc.S_BLOWN], st[bc.S_TARGET], st[bc.S_MODE] = blown, tg, bc.HOLD
    st[bc.S_P_REQ] = 5.0e5
    st[bc.S_MU_MEAS] = mu_meas
    st[bc.S_ABS_ACTIVE + tg] = 1.0 if abs_front else 0.0
    p_est = np.zeros(4)
    p_est[tg] = 5.0e5
    bc.braking_rule(st, blown, tg, bc.HOLD, 1.0, a_x, a_y, 0.0, 100.0e5, p_est, p, r_ref, a_y)
    cap = st[bc.S_REAR_CAP]
    return cap * p.brakes_rear_gain_nm_per_pa / p.body_wheel_radius_m if cap >= 0.0 else -1.0


def max_rear_load_n(p, a_x, a_y):
    """Upper bound of either rear wheel's load (statics, no flat-tire transfer - which only unloads the diagonal rear):
    m*g*l_f/(2*l) - m*|a_x|*h/(2*l) (braking) + m*|a_y|*h*l_f/(B_r*l) (lateral transfer onto the outer wheel)."""
    m, l, l_f, h = p.body_mass_kg, p.chassis_wheelbase_m, p.chassis_cg_to_front_axle_m, p.chassis_cg_height_m
    return (m * G * l_f / (2.0 * l) - m * abs(a_x) * h / (2.0 * l)
            + m * abs(a_y) * h * l_f / (p.chassis_rear_track_m * l))


# a left curve (r_ref > 0) toward the blown FL: 25 m/s on a 300 m radius path
R_TOWARD = 25.0 / 300.0


def test_curve_toward_the_blown_side_rears_inside_the_circle_the_acceleration_proves(params):
    """FL blown, left curve, FR ABS-active: the cap exists and its brake force with the wheel's half of the rear axle's
    lateral force fits the Kamm circle at |a|/g on the most load either rear wheel can have. Flag 0: no cap (-1)."""
    for a_x, a_y in ((-2.0, 1.5), (-3.0, 2.0), (-3.5, 1.0)):
        f_x = rear_cap_n(params, a_x, a_y, R_TOWARD)
        assert f_x > 0.0, (a_x, a_y)
        mu_acc = math.hypot(a_x, a_y) / G
        f_y = params.body_mass_kg * abs(a_y) * params.chassis_cg_to_front_axle_m / params.chassis_wheelbase_m / 2.0
        assert math.hypot(f_x, f_y) <= mu_acc * max_rear_load_n(params, a_x, a_y) + 1.0, (a_x, a_y)


def test_curve_toward_the_blown_side_uncapped_with_the_defect():
    """Negative control: rear_accel_circle_flag = 0 (H1: no cap while the front is ABS-active)."""
    assert rear_cap_n(_params(FLAG0), -3.0, 2.0, R_TOWARD) == -1.0


def test_the_cap_rises_with_the_proven_friction(params):
    """The bound rises with the stop (more deceleration proves more friction), and a higher measured friction on the
    front (S_MU_MEAS, also a lower bound) counts when it exceeds |a|/g."""
    low, high = rear_cap_n(params, -2.0, 1.0, R_TOWARD), rear_cap_n(params, -4.0, 1.0, R_TOWARD)
    assert high > low > 0.0
    assert rear_cap_n(params, -2.0, 1.0, R_TOWARD, mu_meas=0.6) > high


def test_straight_stop_and_curve_away_from_the_blown_side_left_to_abs(params):
    """A straight panic stop (decel bound 0.5 mu g, tests/verification/test_blowout_front_panic_stop.py) and a curve
    away from the blown side keep H1's rule: no cap while the front is ABS-active. Without ABS on the front the
    measured-friction circle of rear_circle_flag stands (a cap >= 0, not -1)."""
    assert rear_cap_n(params, -4.0, 0.0, 0.0) == -1.0
    assert rear_cap_n(params, -3.0, -2.0, -R_TOWARD) == -1.0  # right curve, FL blown: the blown front is outside
    assert rear_cap_n(params, -3.0, 2.0, R_TOWARD, blown=FR) == -1.0  # left curve, FR blown: outside
    assert rear_cap_n(params, -3.0, 2.0, R_TOWARD, abs_front=False) >= 0.0  # a cap (0 here: F_y > 0.15*F_z)


# --- closed loop: the two curve points of status h item 6 -------------------------------------------------------------
# lead's h3 bb29 (-R braking=brakes random 29 -n 128) #3: FL 103 km/h, mu scale 0.362, 1000 m left curve, steering fixed
BB29_3 = {"speed": 103.4318721235254, "mu": 0.36177639884711477, "delay": 0.3360465540376417,
          "wheel_speed_noise": 0.07091688755095645, "noise_seed": 9451.0, "brake_gain": 1.1367191014835991,
          "brake.start_s": 1.58912103982089, "brake.level_frac": 0.33218046072817886,
          "brake.rate_per_s": 25.041199511400457, "braking": "brakes", "wheel": "fl", "driver": "fixed", "curve": "r1000"}
# RH1's random 17 -n 32 #24: FL 104 km/h, mu scale 0.418, 650 m left curve, steering fixed, 0.18 pedal
R17_24 = {"speed": 103.6703830392677, "mu": 0.41813247899951217, "delay": 0.1724405262627183,
          "wheel_speed_noise": 0.11211859638563644, "noise_seed": 4213.0, "brake_gain": 1.1441396815350873,
          "brake.start_s": 1.7026066381291147, "brake.level_frac": 0.18280261279231214,
          "brake.rate_per_s": 7.8236155620425505, "braking": "brakes", "wheel": "fl", "driver": "fixed",
          "curve": "r650"}


@pytest.fixture(scope="module")
def env():
    from vehicle_assist.verification.envelope import load_envelope

    return load_envelope("tire_blowout")


def _run(env, point, sets=()):
    from tests.support import envelope_point_run

    return envelope_point_run(env, point, False, sets)


# The braking-vs-no-pedal comparisons below are judged over a common window: a point without a pedal runs the base
# scenario's 5 s (the car keeps ~20 m/s), a braking point runs to standstill since session n (tire_blowout envelope,
# choices.braking). The run max of a 5-s run against that of a 11-s run compares windows, not the pedal's effect, so both
# runs of such a comparison end at 5 s (an explicit run.duration_s = 5 after the braking option; N1, class A).
COMMON_WINDOW = ("run.duration_s=5",)


def _run5(env, point, sets=()):
    return _run(env, point, tuple(sets) + COMMON_WINDOW)


def _max_lane(run):
    return float(np.max(np.abs(np.asarray(run.trace["lane_offset_m"]))))


@pytest.mark.xfail(strict=True, reason="N1 (session n): random 17 #24 judged to standstill (11.3 s; stay_in_lane is "
                   "'the whole run'): the capped car leaves the lane, max |offset| 2.427 m > 0.978 m (at 5 s 0.922 m); "
                   "the twin 12.241 m, flag 0 (uncapped rears) 1.888 m: the cap's 5-s gain is a loss at standstill "
                   "(road deviation 2.423 vs flag 0 1.885 m, robustness -0.539 m), the car drifts on while braking after 5 s")
def test_r17_24_stays_in_lane(env):
    """RH1's random 17 #24: with the cap the car stays in its lane (0.922 m at I2; H1's rule 1.058 m, before H1
    0.257 m deviation; none 2.533 m): the outer rear keeps its lateral force (RR 0.4-2 % slip vs 10-18 %).
    Session n (N1, class B): an honest finding at standstill, see the xfail reason."""
    assert _max_lane(_run(env, R17_24)) <= LANE_M


def test_r17_24_leaves_the_lane_with_the_defect(env):
    """Negative control: rear_accel_circle_flag = 0 (H1's uncapped rears)."""
    assert _max_lane(_run(env, R17_24, [FLAG0])) > LANE_M


def test_r17_24_braking_no_worse_than_not_braking(env):
    """Random 17 #24: the braking compensated car goes no farther off than the same compensated car without the pedal
    (+5 %, the assumed margin of test_blowout_front_braking.py): 0.732 vs 0.819 m once the rear cap's friction is a
    lower bound (rear_accel_bound_flag, review RI2); with |a|/g (I2) 0.919 m - an open xfail until then.
    Session n (N1, class A): judged over the common 5-s window (COMMON_WINDOW); to standstill the braking car reaches
    2.423 m (stopped at 11.3 s) while the no-pedal run ends at 5 s (0.819 m, 20.3 m/s): no common horizon exists."""
    on = _run5(env, R17_24).metrics[METRIC]
    assert on <= 1.05 * _run5(env, dict(R17_24, braking="none")).metrics[METRIC]


def test_r17_24_braking_worse_than_not_braking_with_the_unbounded_reading(env):
    """Negative control: rear_accel_bound_flag = 0 (|a|/g: rim drag and resistances counted as tire friction)."""
    on = _run5(env, R17_24, ["vehicle.blowout_compensation.rear_accel_bound_flag=0"]).metrics[METRIC]
    assert on > 1.05 * _run5(env, dict(R17_24, braking="none")).metrics[METRIC]


def test_bb29_3_braking_no_worse_than_not_braking(env):
    """bb29 #3: the braking compensated car goes no farther off than the same compensated car without the pedal (+5 %,
    the assumed margin of test_blowout_front_braking.py): 1.13 vs 1.24 m at I2. Session n (N1, class A): the common
    5-s window (COMMON_WINDOW); to standstill the braking car reaches 1.889 m (stopped at 11.0 s; twin 3.682 m)."""
    assert _run5(env, BB29_3).metrics[METRIC] <= 1.05 * _run5(env, dict(BB29_3, braking="none")).metrics[METRIC]


def test_bb29_3_braking_worse_than_not_braking_with_the_defect(env):
    """Negative control: rear_accel_circle_flag = 0 - 1.821 m (none 2.405) vs 1.24 m without the pedal."""
    on = _run5(env, BB29_3, [FLAG0]).metrics[METRIC]
    assert on > 1.05 * _run5(env, dict(BB29_3, braking="none")).metrics[METRIC]


# --- status h item 6, second half: front_circle_measured_flag is not reachable in the shipped configuration -----------
CIRCLE0 = "vehicle.blowout_compensation.front_circle_measured_flag=0"
ABSLIM0 = "vehicle.blowout_compensation.front_abs_limit_flag=0"


def _front_target(p, a_y=2.0):
    """The compensating front's braking-rule target S_P_BRAKE [Pa]: FL blown, FR compensating in HOLD with a measured
    friction 0.3, the driver at 100 bar, a left curve (lateral share on FR), no yaw error."""
    from vehicle_assist.functions import blowout_compensation as bc

    st = bc.initial_state()
    st[bc.S_BLOWN], st[bc.S_TARGET], st[bc.S_MODE] = FL, FR, bc.HOLD
    st[bc.S_P_REQ] = 5.0e5
    st[bc.S_MU_MEAS] = 0.3
    bc.braking_rule(st, FL, FR, bc.HOLD, 1.0, -3.0, a_y, 0.0, 100.0e5, np.array((0.0, 5.0e5, 0.0, 0.0)), p, R_TOWARD,
                    a_y)
    return st[bc.S_P_BRAKE]


def test_front_circle_measured_flag_is_dead_with_front_abs_limit(params):
    """front_circle_measured_flag acts only in braking_rule (the driver braking) with a measured friction, and under
    exactly that condition front_abs_limit_flag (H1, shipped 1) lifts the front cap to ABS: the flag changes nothing
    in the shipped configuration (its toml text and the negative control in tests/verification/
    test_blowout_front_braking.py say so). It is reachable only with front_abs_limit_flag = 0 - there it still changes
    the cap (second assertion). This test fails if the flag becomes live again under the pedal (then its negative
    control tests shipped code once more and this note must go)."""
    assert _front_target(params) == _front_target(_params(CIRCLE0))
    assert _front_target(_params(ABSLIM0)) != _front_target(_params(ABSLIM0, CIRCLE0))
