"""A blown REAR whose side's FRONT has its inlet stuck closed (``blowout_compensation.blown_side_fault_flag``, session
2026-11-24 l, task L1; tire_blowout_findings.md "L1 (session l)", status k item 1, K1's r41 #360).

The paper releases the blown wheel (P7, eqs. 26-28: F_b = 0) and balances its drag with the opposite wheel. With the
blown side's front stuck that side then has no brake at all: a braking driver's whole braking force is on the other
side. K1's worst fault point, random 41 -n 512 #360 of tire_blowout_faults (RR blown, FR stuck, braking, straight, lane
follower, 63 km/h, mu 0.347): FL 20 bar, RL 50-67 bar, the right side 0; yaw 0.51 rad/s, 9.269 m vs the twin's 0.172 m
(the twin keeps RR braked: ABS rear select-low, RL = RR). The rule: while the driver brakes the blown rear is left to
the driver and ABS and the counter-brake rear no higher than it; limit code 6 says why.

References, independent of the function's code: the spec's stay_in_lane bound (3.75 m lane, JTG B01-2014, BJ2500
width: |offset| <= 0.978 m, data/requirements/tire_blowout.toml), the car without the function with the SAME fault (its
ABS rear select-low keeps the rear pair at one pressure), issue #10 'Faults' ("the controller limits its authority and
says why"). Flag 0 = the code before = the seeded defect: every test below but the last fails there (shown in findings
L1).
"""
from __future__ import annotations

import numpy as np
import pytest

import vehicle_assist as va
from vehicle_assist.verification.envelope import load_envelope

METRIC = "blowout_lateral_deviation_run_max_m"
ON = ("vehicle.blowout_compensation.blown_side_fault_flag=1",)
DEFECT = ("vehicle.blowout_compensation.blown_side_fault_flag=0",)  # the code before
LANE_MARGIN_M = 0.978  # stay_in_lane: (3.75 m lane - 1.794 m BJ2500 width)/2, data/requirements/tire_blowout.toml
LIMIT_BLOWN_SIDE = 6  # blowout_limit_code: the blown side's other inlet stuck (LIMIT_REASONS[6])
BAR = 1.0e5
# /tmp/lead/l/base/f_r41/falsify.json history #360 (tire_blowout_faults, random 41 -n 512 -b 64; K1's worst)
P360 = {"speed": 63.136574275141896, "mu": 0.34681190240008497, "delay": 0.16104437685029044,
        "wheel_speed_noise": 0.13613312727728766, "noise_seed": 6437.0, "brake_gain": 1.0538247572128214,
        "accumulator": 62.85697243180388, "brake.start_s": 1.3099401049183217, "brake.level_frac": 0.49237410416076977,
        "brake.rate_per_s": 5.629822385267875, "braking": "brakes", "wheel": "rr", "driver": "follow",
        "curve": "straight", "fault": "inlet_stuck_fr"}


def _run(env, baseline=False, sets=()):
    sc = env.scenario(P360, baseline=baseline)
    return va.simulate(sc.with_sets(*sets) if sets else sc, requirements=False)


@pytest.fixture(scope="module")
def runs():
    env = load_envelope("tire_blowout_faults")
    return {"on": _run(env, sets=ON), "defect": _run(env, sets=DEFECT), "none": _run(env, baseline=True)}


def _braking_window(r):
    """Samples from 0.2 s after the pedal starts (the line and ABS settled) to 3 s (the stop is well under way)."""
    t = np.asarray(r.trace["time_s"])
    return (t >= P360["brake.start_s"] + 0.2) & (t <= 3.0)


def test_360_stays_in_lane(runs):
    """stay_in_lane (spec): measured 0.193 m with the rule; the code before leaves the lane (9.269 m)."""
    assert runs["on"].metrics[METRIC] <= LANE_MARGIN_M, runs["on"].metrics[METRIC]
    assert runs["none"].metrics[METRIC] <= LANE_MARGIN_M  # the reference car with the same fault stays in too


def test_360_blown_side_braked_like_the_car_without_the_function(runs):
    """While the driver brakes the rear pair carries one pressure, as the twin's ABS select-low gives it (twin: RL - RR
    = 0 bar): mean RL - RR < 3 bar and RR braked (> 10 bar at some sample). Flag 0: RR released to 0 bar, RL 50-67."""
    r, w = runs["on"], _braking_window(runs["on"])
    rl, rr = (np.asarray(r.trace[f"wheel_pressure_{k}_pa"])[w] for k in ("rl", "rr"))
    assert np.mean(rl - rr) < 3 * BAR, np.mean(rl - rr) / BAR
    assert np.max(rr) > 10 * BAR, np.max(rr) / BAR
    tw = runs["none"]
    rl_t, rr_t = (np.asarray(tw.trace[f"wheel_pressure_{k}_pa"])[_braking_window(tw)] for k in ("rl", "rr"))
    assert abs(np.mean(rl_t - rr_t)) < 3 * BAR  # the reference: the twin's select-low


def test_360_limit_code_says_why(runs):
    """Issue #10 'Faults': the limit says why - code 6 while the rule acts (the code before: 0 until a late refusal 4)."""
    codes = np.asarray(runs["on"].trace["blowout_limit_code"])[_braking_window(runs["on"])]
    assert np.all(codes == LIMIT_BLOWN_SIDE), np.unique(codes)


def test_360_defect_leaves_the_lane(runs):
    """Negative control: the code before fails the stay_in_lane bound (9.269 m) and is far worse than the twin."""
    assert runs["defect"].metrics[METRIC] > LANE_MARGIN_M
    assert runs["defect"].metrics[METRIC] > runs["none"].metrics[METRIC] + 1.0


@pytest.mark.xfail(strict=True, reason="residual: 0.193 vs the twin's 0.172 m (the pre-pedal counter-brake; findings L1)")
def test_360_never_worse_than_without_compensation(runs):
    """no_worse_than_no_compensation with the same fault in both cars: still missed by 0.021 m (-9.096 before)."""
    assert runs["on"].metrics[METRIC] <= runs["none"].metrics[METRIC]
