"""``blowout_compensation.blown_side_front_cap_flag`` (session 2026-11-25 o, task O2; tire_blowout_findings.md "O2").

A REAR blowout detected while the driver brakes: paper 004 eqs. 26-28 balance the blown rear's drag with the opposite
rear on top of the driver's pressure p_0, on the premise that the other wheels brake alike. At the lead's rr17 #124
(RR, 109 km/h, mu 0.64, r650, follower, pedal 0.29 from 0.86 s) the blown side's FRONT (FR) carries 71.5-76 bar
against FL's 48-54 after the detection (the ESP reference leaves the TPMS-named RR out, so FR's ABS level is the
true one; the twin's reference rides the fast RR and its ABS holds FR at 47-63 bar): a moment toward the blown side the
balance does not contain; the car yawed -0.10 rad/s toward RR and lost its heading (run max 1.851 vs the twin's 1.835 m;
the sign holds at a halved plant step, the blowout 5 ms earlier/later: -0.035 / -0.131 / -0.003 m - not sampling noise).
Value 1: the blown side's front held at no more than the other front's pressure (ESP hold, dumped above it by > 1 bar,
ABS's own hold/dump win). Value 2: value 1 only while the yaw error (measured - steered reference) points toward the
blown side beyond yaw_deadband (1 deg/s). These tests run the values explicitly, so they pass whatever the TOML value:

Value 3: value 2 with the hold from 1 bar ABOVE the other front (dumped above it by 1 bar more), so equal fronts
building together at a pedal onset are not held.

* rr17 #124: never worse on the road at 3 (both cars on the road); fails at 0 (1.851 > 1.835 m).
* rr17 #124 mechanism: FR is held at 71.5 bar by the ESP from 1.2 s (the cap yields to the ESP's own hold/dump); when
  the hold ends (2.4 s), the yaw error toward RR, value 2 dumps FR to FL's level; at 0 FR stays > 15 bar above FL.
* r23 #23 (RR, straight, follower, pedal 0.35 after the blowout): the ungated value 1 over-compensates (the car yaws
  away from RR and spins, 6.48 m vs the twin's 2.99) - a control that the gate matters; at 3 never worse.
* rb13 #39 (RL, r650, follower, panic pedal after the detection): value 2's hold from equality holds FL at the pedal
  onset (3.395 m vs the twin's 1.309) - a control that the 1-bar offset matters; at 3 never worse.
* The twin (the compensation off, no detection) is the same run at 3 as at 0.
Independent references: the twin run (paper 004 Fig. 4 curve 2), the requirement rows' own metrics.
"""
from __future__ import annotations

import numpy as np
import pytest

from tests.support import envelope_point_run
from vehicle_assist.verification.envelope import load_envelope

ROAD = "blowout_lateral_deviation_road_max_m"
EARLY = "blowout_road_departure_earliness_s"
V = {v: (f"vehicle.blowout_compensation.blown_side_front_cap_flag={v}",) for v in (0, 1, 2, 3)}
SLY0 = ("vehicle.blowout_compensation.slip_limit_yaw_flag=0",)  # the code O2 measured on (findings O2, RO6)
# /tmp/lead/n/fin2/rr17/falsify.json history #124 (random 17 -n 256 -b 64 -R wheel=rl,rr)
P124 = {"speed": 108.91683364761067, "mu": 0.6436928167055318, "delay": 0.2850483437787553,
        "wheel_speed_noise": 0.0739334446844415, "noise_seed": 3410.0, "brake_gain": 0.7897214584457406,
        "brake.start_s": 0.8581671721911408, "brake.level_frac": 0.29410861954366574,
        "brake.rate_per_s": 6.362754617159936, "braking": "brakes", "wheel": "rr", "driver": "follow", "curve": "r650"}
# /tmp/lead/n/fin2/r23/falsify.json history #23 (random 23 -n 32 -b 32)
P23 = {"speed": 97.23395380500088, "mu": 0.41714060938176484, "delay": 0.38211942855281844,
       "wheel_speed_noise": 0.22408625934702156, "noise_seed": 4133.0, "brake_gain": 1.1209430949207748,
       "brake.start_s": 1.8882540510900097, "brake.level_frac": 0.3463936944657572,
       "brake.rate_per_s": 16.36105613757057, "braking": "brakes", "wheel": "rr", "driver": "follow",
       "curve": "straight"}
# /tmp/lead/n/fin2/rb13/falsify.json history #39 (random 13 -n 128 -b 64 -R braking=brakes)
P39 = {"speed": 68.4452752742673, "mu": 0.34954681864377457, "delay": 0.2951973294359801,
       "wheel_speed_noise": 0.09989329368933665, "noise_seed": 899.0, "brake_gain": 1.0636242811582959,
       "brake.start_s": 2.0131118777538703, "brake.level_frac": 0.45703530019253413,
       "brake.rate_per_s": 10.666380610683916, "braking": "brakes", "wheel": "rl", "driver": "follow", "curve": "r650"}


@pytest.fixture(scope="module")
def env():
    return load_envelope("tire_blowout")


@pytest.fixture(scope="module")
def rr17_124(env):
    runs = {v: envelope_point_run(env, P124, sets=V[v]) for v in (0, 3)}
    runs["none"] = envelope_point_run(env, P124, baseline=True)
    runs["none3"] = envelope_point_run(env, P124, baseline=True, sets=V[3])
    return runs


@pytest.fixture(scope="module")
def r23_23(env):
    # the gate controls run at slip_limit_yaw_flag 0 (the code O2 measured them on): since session o's RO6 the shipped
    # slip_limit_yaw 1 also stops value 1's over-compensation here (1.504 m < the twin's 2.989; at 0: 3.978, off the road)
    runs = {v: envelope_point_run(env, P23, sets=V[v] + SLY0) for v in (1, 3)}
    runs["none"] = envelope_point_run(env, P23, baseline=True)
    return runs


@pytest.fixture(scope="module")
def rb13_39(env):
    # at slip_limit_yaw_flag 0, as r23_23 (shipped 1: value 2 gives 0.710 m < the twin's 1.309; at 0: 3.395)
    runs = {v: envelope_point_run(env, P39, sets=V[v] + SLY0) for v in (2, 3)}
    runs["none"] = envelope_point_run(env, P39, baseline=True)
    return runs


def _front_gap_bar(run, t0, t1):
    t = np.asarray(run.trace["time_s"])
    k = (t >= t0) & (t <= t1)
    fl = np.asarray(run.trace["wheel_pressure_fl_pa"])[k]
    fr = np.asarray(run.trace["wheel_pressure_fr_pa"])[k]
    return float(np.max(fr - fl)) / 1e5


def test_rr17_124_never_worse_on_the_road_at_3(rr17_124):
    """no_worse_than_no_compensation at rr17 #124 with value 3 (both cars on the road, so not a tie at the edge)."""
    assert rr17_124[3].metrics[EARLY] == 0.0 and rr17_124["none"].metrics[EARLY] == 0.0
    on, none = rr17_124[3].metrics[ROAD], rr17_124["none"].metrics[ROAD]
    assert on <= none, (on, none)


def test_rr17_124_violation_stands_at_0(rr17_124):
    """Negative control: at 0 (the code before) the same check fails (1.851 > 1.835 m)."""
    assert rr17_124[0].metrics[ROAD] > rr17_124["none"].metrics[ROAD]


def test_rr17_124_blown_side_front_not_above_other_front(rr17_124):
    """The mechanism: FR is held at 71.5-72 bar by the ESP from 1.2 s (the rule yields to the ESP's own hold); when
    that hold ends (2.4 s) with the yaw error toward RR (the car turning less than the steered curve), value 3 dumps FR
    to within 2 bar of FL's level (value 2: 52.3 vs 53.8 bar); at 0 FR stays at 72 bar, > 15 bar above FL."""
    assert _front_gap_bar(rr17_124[3], 2.40, 2.60) < 2.0
    assert _front_gap_bar(rr17_124[0], 2.40, 2.60) > 15.0


def test_r23_23_gate(r23_23):
    """The yaw gate: ungated (1) the cap over-compensates a follower on a straight road (6.48 m, worse than the twin's
    2.99); at 3 never worse."""
    none = r23_23["none"].metrics[ROAD]
    assert r23_23[1].metrics[ROAD] > none
    assert r23_23[3].metrics[ROAD] <= none


def test_rb13_39_no_hold_at_equal_fronts(rb13_39):
    """The hold starts 1 bar above the other front: at 2 (hold from equality) a pedal onset with both fronts building
    together held FL at 0.1 bar, the GMA then kept it at 9.8 bar against FR's 19-23, the car yawed away from RL and
    spun (3.395 m vs the twin's 1.309); at 3 FL builds with FR and the point is never worse."""
    none = rb13_39["none"].metrics[ROAD]
    assert rb13_39[2].metrics[ROAD] > none
    assert rb13_39[3].metrics[ROAD] <= none


def test_twin_unchanged(rr17_124):
    """The twin has no detection: the flag does not reach it."""
    a, b = rr17_124["none"], rr17_124["none3"]
    assert a.metrics[ROAD] == b.metrics[ROAD]
    assert np.array_equal(np.asarray(a.trace["wheel_pressure_fr_pa"]), np.asarray(b.trace["wheel_pressure_fr_pa"]))
