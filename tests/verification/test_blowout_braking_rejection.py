"""The yaw-implausibility rejection with a driver braking through a blowout (issue #10 independent review d, falsifier
random search budget 32 --keep-going, seeds 23 and 3, envelope data/envelopes/tire_blowout.toml).

With the pedal applied around t_b the detection comes from the TPMS path (a braked blown wheel shows no over-speed),
i.e. from one source, and the function releases the blown wheel from the driver's pressure (paper 004 P7: the blown
wheel is not braked). That release is itself a yaw moment away from the blown side, on top of the counter-brake. The
car then yaws away from the blown side and the single-source rule (BUILD/HOLD/LIMITED -> REJECTED, yaw_implausible)
takes the real blowout for a false alarm. Two points of the envelope pull in opposite directions:

* RL at 119 km/h (seed 23 #4): the rejection at t_b + 1.05 s re-brakes the blown wheel with the driver's pressure and the
  car ends 1.39 m off vs 1.19 m without compensation; without the rejection (abort_yaw_rate 8 deg/s) 0.64 m. Honest
  FAIL (strict xfail).
* FL at 120 km/h (seed 3 #12, reached when the TPMS-path detection was promoted to two sources once the released
  wheel showed its over-speed - the fix tried in the review and withdrawn): the rejection at t_b + 0.54 s is what
  keeps the car near the lane (0.87 m vs 1.26 m without compensation); holding the compensation, the car keeps yaw
  ~0 in a 1000 m left curve with the steering held and ends 3.72 m off. Guard: a fix of the first point must not
  lose this one.

Reference: the same blowout without compensation (paper 004 Fig. 4 curve 2; conventions.md 'Evidence'), largest
lateral deviation from t_b to the end of the run, as the requirement tire_blowout.no_worse_than_no_compensation.
Fixed by ``yaw_net_flag`` (functions/blowout_compensation.py, review finding A): the yaw is judged net of the
function's own release of the blown wheel from the driver's pressure (b * K_b * dp / R through the ECU's single-track
model) once the released wheel shows the blowout's over-speed; the compensation pressure stays in the judged yaw, so a
false detection is still rejected (tests/functions/test_blowout_yaw_net.py, false TPMS alarms under 80-150 N;
tests/functions/test_blowout_compensation.py::test_false_tpms_alarm_while_braking_stays_in_lane). Measured: RL 1.39 ->
0.64 m (none 1.19 m), FL unchanged 0.87 m (none 1.26 m; still rejected at t_b + 0.54 s)."""
from __future__ import annotations

import pytest

from tests.support import envelope_point_metric
from vehicle_assist.verification.envelope import load_envelope

METRIC = "blowout_lateral_deviation_run_max_m"
ROAD = "blowout_lateral_deviation_road_max_m"  # row no_worse_than_no_compensation (session n)
RL_SEED23 = {"speed": 119.39563563443807, "mu": 0.4186664885826914, "delay": 0.39560516807119134,
             "wheel_speed_noise": 0.049908390411532756, "noise_seed": 5936, "brake_gain": 0.8733545627851009,
             "brake.start_s": 0.9847597428997881, "brake.level_frac": 0.21453458675326495,
             "brake.rate_per_s": 28.031617768272152, "braking": "brakes", "wheel": "rl", "driver": "follow",
             "curve": "r1000"}
FL_SEED3 = {"speed": 119.98424226281585, "mu": 0.3551565873975112, "delay": 0.2779029077251118,
            "wheel_speed_noise": 0.26436015861764756, "noise_seed": 530, "brake_gain": 0.994146577927896,
            "brake.start_s": 0.8478226987765873, "brake.level_frac": 0.3908802232177515,
            "brake.rate_per_s": 28.13061500386974, "braking": "brakes", "wheel": "fl", "driver": "fixed",
            "curve": "r1000"}
# falsifier random search seed 11, budget 512, on the braking-only part of the envelope (braking = brakes), point #219
FL_SEED11 = {"speed": 111.03662190443559, "mu": 0.34607360245082186, "delay": 0.04467767430050759,
             "wheel_speed_noise": 0.009833120167830056, "noise_seed": 751, "brake_gain": 0.748048606846051,
             "brake.start_s": 0.9694710298450024, "brake.level_frac": 0.1653419260981332,
             "brake.rate_per_s": 29.083997570533768, "braking": "brakes", "wheel": "fl", "driver": "fixed",
             "curve": "r650"}


@pytest.fixture(scope="module")
def env():
    return load_envelope("tire_blowout")


def _dev(env, point, baseline=False, sets=()):
    return envelope_point_metric(env, point, METRIC, baseline, sets)


def test_rl_blowout_braking_not_rejected_into_worse(env):
    """Requirement tire_blowout.no_worse_than_no_compensation (paper 004 Fig. 4 curve 2; conventions.md 'Evidence'):
    run max lateral deviation with compensation below the same blowout without it (0.64 vs 1.19 m)."""
    assert _dev(env, RL_SEED23) < _dev(env, RL_SEED23, baseline=True)


@pytest.mark.xfail(strict=True, reason=(
    "N1 (session n): judged to standstill the defect (yaw_net_flag = 0) is no longer worse than no compensation: "
    "1.469 m (stopped 9.2 s) vs the twin's 1.661 m (stopped 10.6 s; both on the road): the twin, still moving at 5 s "
    "(1.19 m then), drifts on; the defect's 5-s loss (1.39 vs 1.19 m) was the window. The rule still beats the defect "
    "(0.640 vs 1.469 m: next test)"))
def test_rl_blowout_braking_defect_rejects_into_worse(env):
    """Negative control: with the seeded defect (yaw_net_flag = 0, the raw yaw as before) the same point is rejected
    at t_b + 1.05 s and is worse than no compensation (1.39 vs 1.19 m) - the test above fails with the defect.
    Session n (N1, class C): a 5-s artefact, xfail(strict) with the numbers; the control that still separates the rule
    from its defect at standstill is the next test."""
    assert _dev(env, RL_SEED23, sets=("vehicle.blowout_compensation.yaw_net_flag=0",)) > _dev(env, RL_SEED23,
                                                                                              baseline=True)


def test_rl_blowout_braking_rule_beats_the_defect_to_standstill(env):
    """Session n (N1, class C, the replacement control): judged to standstill the rule (yaw_net_flag shipped) is better
    than its seeded defect at the same point in the requirement's metric: road deviation 0.640 m vs 1.469 m (both on
    the road). Fails at flag 0 (the run is the defect's: equal)."""
    rule = envelope_point_metric(env, RL_SEED23, ROAD)
    defect = envelope_point_metric(env, RL_SEED23, ROAD, sets=("vehicle.blowout_compensation.yaw_net_flag=0",))
    assert rule < defect, (rule, defect)


def test_fl_blowout_braking_rejection_still_guards(env):
    """The rejection keeps this braking FL point no worse than none (0.87 vs 1.26 m, with and without yaw_net_flag);
    holding the compensation through it gave 3.72 m."""
    assert _dev(env, FL_SEED3) < _dev(env, FL_SEED3, baseline=True)


def test_fl_blowout_braking_saturated_opposite_still_rejected(env):
    """Second guard, for the linear-region condition of yaw_net_flag: FL at 111 km/h on mu 0.35, steering held in a
    650 m curve, the driver brakes from t_b - 31 ms; the opposite front runs at 8-10 % slip (past its linear region),
    the car yaws away 5 deg/s and runs wide. Rejected (raw yaw) 0.75 m vs 2.98 m without compensation; netting the
    release out there (commit 8822170, no linear-region condition) held the compensation: 4.35 m."""
    assert _dev(env, FL_SEED11) < _dev(env, FL_SEED11, baseline=True)
