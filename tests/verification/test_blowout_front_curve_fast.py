"""Front blowouts at 90-120 km/h in 650 m curves (docs/functions/tire_blowout_sessions.md, status at the end of session g, item 7;
tire_blowout_findings.md RG2 (d) and H6): RG2's targeted falsifier search ``-R wheel=fl,fr -R speed=90..120`` (random, budget 128).

Two of its four counterexamples are one mechanism: a blown INNER front (FL in the 650 m left curve), no pedal, the
lane-following driver. The paper's balance brakes the OUTER front (FR 42-49 bar at 6-7 % slip); the car yaws 0.04-0.09
rad/s short of the driver's steering reference for ~3 s and runs wide, while the car without compensation is turned in by
the flat's drag and stays closer. The understeer rule (``understeer_flag``) that lowers the outer front in exactly this
case waited for capacity evidence (S_CAP_LATCHED), which the tire-capacity rule never found at that slip.
``understeer_persist_flag`` (0 = seeded defect = the code before): a shortfall that outlasts the 2 % settling time of
the ECU's single-track yaw mode is a steady response, not the build's transient dip, and counts as the evidence; a lowering
made that way is restored on the same persistence (the swing past the reference after the dump is that transient too).

Requirement: data/requirements/tire_blowout.toml ``no_worse_than_no_compensation`` (tire_blowout.md 9.5): the largest
lateral deviation from t_b to the end of the run with compensation is no larger than without it (the envelope's baseline,
enabled_flag = 0: an independent run of the same plant, driver and blowout).

Can fail: with the flag at 0 both points (and the two neighbours) are worse than no compensation (19 #66 1.765 vs 1.113 m;
71 #49 1.582 vs 1.356 m at main 4718b3b); checked below as negative controls. With the rule: 0.535 / 0.643 m."""
from __future__ import annotations

import numpy as np
import pytest

from tests.support import envelope_point_metric, understeer_hold_state
from vehicle_assist.verification.envelope import load_envelope

METRIC = "blowout_lateral_deviation_run_max_m"
DEFECT = "vehicle.blowout_compensation.understeer_persist_flag=0"
# RG2's targeted search (tire_blowout_findings.md RG2 (d)), random seed 19 budget 128 #66: FL 116.7 km/h, mu scale 0.424, 650 m left
# curve, lane-following driver, no pedal, detection delay 0.44 s, pads 24 % below nominal
P19_66 = {"speed": 116.66458342072876, "mu": 0.4244687855430994, "delay": 0.44253677268711084,
          "wheel_speed_noise": 0.148882156747999, "noise_seed": 4425.0, "brake_gain": 0.7583798176316293,
          "brake.start_s": 2.4894480194637403, "brake.level_frac": 0.390944834020977,
          "brake.rate_per_s": 1.5376923806695595, "braking": "none", "wheel": "fl", "driver": "follow", "curve": "r650"}
# same search, random seed 71 #49: FL 108.6 km/h, mu scale 0.451, 650 m left curve, follower, no pedal
P71_49 = {"speed": 108.55088517007218, "mu": 0.45147850039247617, "delay": 0.08641597371667321,
          "wheel_speed_noise": 0.09551123661079297, "noise_seed": 6538.0, "brake_gain": 0.7369995317328288,
          "brake.start_s": 2.211065482298558, "brake.level_frac": 0.37346975025601514,
          "brake.rate_per_s": 25.110979378421447, "braking": "none", "wheel": "fl", "driver": "follow", "curve": "r650"}
# neighbours (not searched for: one parameter moved each; measured with / flag 0 / none): #66 at 119.7 km/h 0.605 / 1.894 /
# 1.064 m; #49 at mu scale 0.421 0.633 / 1.610 / 1.178 m (of 16 neighbours - noise seed, speed +-3 km/h, mu +-0.03,
# delay +0.1 s, pad gain +0.15 - 12 violate with the flag at 0, none with it; tire_blowout_findings.md H6)
POINTS = {"19_66": P19_66, "71_49": P71_49, "19_66_v+3": {**P19_66, "speed": P19_66["speed"] + 3.0},
          "71_49_mu-0.03": {**P71_49, "mu": P71_49["mu"] - 0.03}}


@pytest.fixture(scope="module")
def runs():
    env = load_envelope("tire_blowout")
    return {k: {"on": envelope_point_metric(env, pt, METRIC),
                "off": envelope_point_metric(env, pt, METRIC, baseline=True),
                "defect": envelope_point_metric(env, pt, METRIC, sets=[DEFECT])} for k, pt in POINTS.items()}


@pytest.mark.parametrize("key", sorted(POINTS))
def test_inner_front_curve_no_worse_than_no_compensation(runs, key):
    """With the persistence evidence the compensated car goes no farther off the lane than the car without
    compensation (19 #66 0.535 vs 1.113 m, 71 #49 0.643 vs 1.356 m)."""
    assert runs[key]["on"] <= runs[key]["off"]


@pytest.mark.parametrize("key", sorted(POINTS))
def test_inner_front_curve_worse_with_the_defect(runs, key):
    """Negative control: understeer_persist_flag = 0 (capacity evidence required) is worse than no compensation."""
    assert runs[key]["defect"] > runs[key]["off"]


def _rule_state(params_flag):
    """A compensation in HOLD on FR for a blown FL, no capacity evidence, the reference 0.1 rad/s into the curve
    (toward FL) and the measured yaw 0.05 rad/s: a shortfall of 0.05 rad/s, well beyond the 1 deg/s dead band."""
    return understeer_hold_state(f"vehicle.blowout_compensation.understeer_persist_flag={params_flag}")


def _hold_shortfall(bc, st, p, seconds, v_ref, yaw=0.05, r_ref=0.1, dt=0.005):
    p_est = np.array([0.0, 40.0e5, 0.0, 0.0])
    req = np.zeros(4, dtype=np.int64)
    lowered_at = -1.0
    for k in range(int(round(seconds / dt))):
        req[:] = bc.Q_HOLD
        bc.understeer_rule(st, 0, 1, bc.HOLD, 0.0, r_ref, yaw, p_est, req, p, dt, v_ref)
        if lowered_at < 0 and st[bc.S_US_LIMITED] > 0.5:
            lowered_at = (k + 1) * dt
    return lowered_at


def test_short_shortfall_is_not_evidence():
    """The build's transient dip (shorter than the yaw mode's 2 % settling time, 0.84 s at 100 km/h by 8/a_1 of the
    nominal single-track model, Rajamani 2012 ch. 2) does not lower the outer front without capacity evidence; a
    shortfall lasting longer does - and with the flag at 0 it never does (the code before)."""
    v = 100.0 / 3.6
    bc, st, p = _rule_state(1)
    assert _hold_shortfall(bc, st, p, 0.5, v) < 0.0
    bc, st, p = _rule_state(1)
    t_low = _hold_shortfall(bc, st, p, 2.0, v)
    assert 0.7 <= t_low <= 1.0  # the settling time at 100 km/h (0.84 s, settling_time_s docstring)
    bc, st, p = _rule_state(0)
    assert _hold_shortfall(bc, st, p, 2.0, v) < 0.0
