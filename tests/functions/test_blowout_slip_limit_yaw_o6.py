"""O6 (session o): the rear slip limit's driver's-pressure floor must not override the over-compensation limiter's dump
(``blowout_compensation.slip_limit_yaw_flag``; tire_blowout_findings.md "O6").

Point rrL #43 (O5's targeted search: tire_blowout, random seed 102 -n 256 -b 64 -R wheel=rl,rr -R mu=0.3..0.55
-R speed=90..120; /tmp/o5/s/rrL/shp_worse): RL blown, 90.8 km/h, mu scale 0.361, 1000 m LEFT curve (toward RL),
following driver, pedal 0.22 at 23 /s from 1.91 s (HBA: master 134 bar). The compensation brakes RR to 52 bar before
the pedal (the paper's opposite rear, eqs. 26-30). With the pedal RL stays released (the paper's blown wheel), FL is
held at 2 bar by the GMA, RR rises to 64 bar: every brake on the right side, the car yaws right 0.08 -> 0.48 rad/s.
The feed-forward over-compensation limiter asks to dump RR (yaw away from the blown side beyond esp.yaw_dump_rate,
5 deg/s) from ~2.25 s, but the slip limit's floor (the driver's proportioned pressure, 70 bar) replaces the request by
HOLD: RR held at 64 bar until the yaw bound refuses the compensation (2.655 s); the car leaves the road at earliness
26.145 s; the twin stays on (2.562 m). With the flag: RR dumped 64 -> 1.4 bar at 2.5-2.8 s, the car stays on the road,
1.729 m (both rows >= 0).

Independent reference: the twin (the same car, compensation off) on the same point. The check fails at flag 0: the
*_at_0 test keeps that proof in the suite, and the module run with RULE_SETS = FLAG0 fails test_rule_on_never_worse
(findings O6).
"""
from __future__ import annotations

import numpy as np
import pytest

from tests.support import envelope_point_run, never_worse_rows
from vehicle_assist.verification.envelope import load_envelope

ROW1, ROW2 = "no_worse_than_no_compensation", "no_earlier_road_departure"
FLAG1 = ("vehicle.blowout_compensation.slip_limit_yaw_flag=1",)
FLAG0 = ("vehicle.blowout_compensation.slip_limit_yaw_flag=0",)
RULE_SETS: tuple = FLAG1  # the proof of failure at 0 sets this to FLAG0 (findings O6)
RRL_43 = {"speed": 90.77271296590422, "mu": 0.36141046272018323, "delay": 0.4015046233517685,
          "wheel_speed_noise": 0.1734490956284859, "noise_seed": 1748.0, "brake_gain": 0.8175536441672386,
          "brake.start_s": 1.9110543789147563, "brake.level_frac": 0.2247847261836685,
          "brake.rate_per_s": 23.254339942733292, "braking": "brakes", "wheel": "rl", "driver": "follow",
          "curve": "r1000"}


@pytest.fixture(scope="module")
def runs():
    env = load_envelope("tire_blowout")
    return {"rule": envelope_point_run(env, RRL_43, sets=RULE_SETS),
            "flag0": envelope_point_run(env, RRL_43, sets=FLAG0),
            "twin": envelope_point_run(env, RRL_43, baseline=True)}


def _at(r, ch, t0, t1):
    t = np.asarray(r.trace["time_s"])
    return np.asarray(r.trace[ch])[(t >= t0) & (t <= t1)]


def test_premise_yaw_away_while_held(runs):
    """The premise, at flag 0: in HOLD with the pedal on, the car yaws away from RL (right, -) faster than the ESP's
    yaw dump rate (5 deg/s = 0.087 rad/s) at 2.4-2.6 s while RR stays above 60 bar."""
    r = runs["flag0"]
    assert np.max(_at(r, "yaw_rate_radps", 2.4, 2.6)) < -0.087
    assert np.min(_at(r, "wheel_pressure_rr_pa", 2.4, 2.6)) > 60e5


def test_rule_on_never_worse(runs):
    """Both rows >= 0 against the twin (measured 1.729 m vs 2.562 m, 0 s) and on the road with a margin of 1 m."""
    rows = never_worse_rows(runs["rule"], runs["twin"])
    assert rows[ROW1] >= 0.0 and rows[ROW2] >= 0.0, rows
    assert runs["rule"].metrics["blowout_lateral_deviation_road_max_m"] <= 3.978 - 1.0


def test_rule_on_limiter_dumps(runs):
    """With the rule the limiter's dump acts: RR below 20 bar by 2.8 s (flag 0: 54 bar)."""
    assert np.min(_at(runs["rule"], "wheel_pressure_rr_pa", 2.4, 2.8)) < 20e5


def test_flag0_is_worse_than_the_twin_at_0(runs):
    """The defect (flag 0, the code before): off the road where the twin stays on - row 1 -1.416 m, row 2 -26.145 s.
    This is what test_rule_on_never_worse would meet with RULE_SETS = FLAG0."""
    rows = never_worse_rows(runs["flag0"], runs["twin"])
    assert rows[ROW1] < -1.0 and rows[ROW2] < -20.0, rows
