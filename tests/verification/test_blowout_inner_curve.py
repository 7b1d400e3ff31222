"""Front blowout on the INSIDE of a low-friction curve, no pedal (docs/functions/tire_blowout_sessions.md "Open at the end of
session 2026-11-24 e" item 1; tire_blowout_findings.md R3 and X): the blown inner front's drag turns the car into the curve, the
paper's feed-forward balance brakes the OUTER front, which carries most of the front axle's lateral force, and the car
understeers out of the curve. The understeer rule (``understeer_flag``, functions/blowout_compensation.py
``understeer_rule``) lowers the compensating outer front while the measured yaw rate falls short of the steering
reference toward the blown side (ESP practice: understeer is not answered on the outer front wheel; van Zanten, Bosch
ESP Systems: 5 Years of Experience, SAE 2000-01-1633).

Requirement: data/requirements/tire_blowout.toml ``no_worse_than_no_compensation`` (tire_blowout.md 9.5; conventions.md
'Evidence'): the largest lateral deviation from t_b to the end of the run with compensation is no larger than the same
blowout without compensation (paper 004 Fig. 4 curve 2; the envelope's baseline enabled_flag = 0).

Can fail: with the seeded defect understeer_flag = 0 (the code before) the point is worse than no compensation
(1.31 vs 0.66 m at 0b41466); checked below as the negative control."""
from __future__ import annotations

import pytest

from tests.support import envelope_point_metric
from vehicle_assist.verification.envelope import load_envelope

METRIC = "blowout_lateral_deviation_run_max_m"
DEFECT = "vehicle.blowout_compensation.understeer_flag=0"
# lead's falsifier random seed 41 budget 512 #336 (session e, /tmp/lead/m_r41): FL 119.6 km/h, mu scale 0.322,
# 0.071 rad/s wheel-speed noise, pads 27 % below nominal, no pedal, lane-following driver, 650 m left curve
P336 = {"speed": 119.55148713880769, "mu": 0.32198842450556386, "delay": 0.054589311706745886,
        "wheel_speed_noise": 0.07092781688686324, "noise_seed": 1695, "brake_gain": 0.7340052921278769,
        "brake.start_s": 2.4843976336851883, "brake.level_frac": 0.2499865491798822,
        "brake.rate_per_s": 14.961934578149188, "braking": "none", "wheel": "fl", "driver": "follow", "curve": "r650"}


@pytest.fixture(scope="module")
def p336():
    env = load_envelope("tire_blowout")
    return {"on": envelope_point_metric(env, P336, METRIC),
            "off": envelope_point_metric(env, P336, METRIC, baseline=True),
            "defect": envelope_point_metric(env, P336, METRIC, sets=[DEFECT])}


def test_inner_blowout_low_friction_curve_no_worse(p336):
    """#336: with the understeer rule the compensated car goes no farther off the lane than the car without
    compensation (0.18 vs 0.66 m at the rule's commit)."""
    assert p336["on"] <= p336["off"]


def test_inner_blowout_low_friction_curve_worse_with_the_defect(p336):
    """Negative control: understeer_flag = 0 (the paper's balance held on the outer front through the understeer) is
    worse than no compensation (1.31 vs 0.66 m)."""
    assert p336["defect"] > p336["off"]
