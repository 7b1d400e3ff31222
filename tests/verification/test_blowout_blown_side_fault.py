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

from vehicle_assist.verification.envelope import load_envelope
from tests.support import envelope_point_run

METRIC = "blowout_lateral_deviation_run_max_m"
ON = ("vehicle.blowout_compensation.blown_side_fault_flag=1",)
DEFECT = ("vehicle.blowout_compensation.blown_side_fault_flag=0",  # the code before
          # since session o the shipped slip_limit_yaw 1 (RO6) also catches this defect's spin: the over-compensation
          # limiter's dump of RL is no longer vetoed by the slip limit's floor (defect 0.745 m, in the lane; with
          # slip_limit_yaw 0: 13.237 m), so the control runs with that second guard off
          "vehicle.blowout_compensation.slip_limit_yaw_flag=0")
DEFECT_SLY = ("vehicle.blowout_compensation.blown_side_fault_flag=0",)  # the defect with slip_limit_yaw as shipped
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
    return envelope_point_run(env, P360, baseline, sets)


@pytest.fixture(scope="module")
def runs():
    env = load_envelope("tire_blowout_faults")
    return {"on": _run(env, sets=ON), "defect": _run(env, sets=DEFECT), "none": _run(env, baseline=True),
            "defect_sly": _run(env, sets=DEFECT_SLY)}


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


def test_360_defect_caught_by_slip_limit_yaw(runs):
    """Defence in depth (session o): with blown_side_fault OFF, the shipped slip_limit_yaw 1 still keeps the car in the
    lane (0.745 m; 13.237 m with both off): the yaw limit's dump of the counter-brake rear is no longer vetoed. Fails
    with slip_limit_yaw 0 (then runs["defect_sly"] == runs["defect"])."""
    assert runs["defect_sly"].metrics[METRIC] <= LANE_MARGIN_M


@pytest.mark.xfail(strict=True, reason="residual: 0.193 vs the twin's 0.172 m (the pre-pedal counter-brake; findings L1)")
def test_360_never_worse_than_without_compensation(runs):
    """no_worse_than_no_compensation with the same fault in both cars: still missed by 0.021 m (-9.096 before)."""
    assert runs["on"].metrics[METRIC] <= runs["none"].metrics[METRIC]


# ---- value 2/3 (session l L6, tire_blowout_findings.md L6) -------------------------------------------------------------
# Value 2: the counter-brake rear is compared with the blown rear on the ECU's line-lag estimate (A_P_LINE): A_P_EST of
# the re-braked blown rear (W_N) takes the driver's pressure at once, so value 1 stopped the dump with RL 4-5 bar above
# RR and the pair's common ABS modulation carried the offset (0.193 vs the twin's 0.172 m). Value 3 = value 2 and the
# rule's premise checked: the blown side's stuck front is unbraked (the pressure the fault trapped in it, the ECU's line
# estimate at the diagnosis, below esp.plausibility_pressure); a front stuck while braked keeps its brake and the paper's
# release stands. Seeded defects: value 1 (the A_P_EST compare) for the never-worse test, value 2 (no premise check)
# for the trapped-pressure test; value 0 (the code before L1) fails the first one too.
ON3 = ("vehicle.blowout_compensation.blown_side_fault_flag=4",)  # RL4: the shipped value 4 (= 3 on these two-source / trapped points)
# /tmp/lead/l/baseT/t_r7/falsify.json history #219 (tire_blowout_faults with L3's fault_time, random 7 -n 256 -b 64
# -R fault_time=1..2.5 -R braking=brakes): FR sticks at 1.36 s while the driver brakes - 52.8 bar trapped in it
P219 = {"speed": 72.88106304974644, "mu": 0.5857436703468413, "delay": 0.42725105074230685,
        "wheel_speed_noise": 0.05917129653661631, "noise_seed": 9694.0, "brake_gain": 0.7507054323914648,
        "accumulator": 92.61743754712857, "fault_time": 1.3585512149795187, "brake.start_s": 0.9300039897175358,
        "brake.level_frac": 0.09450780226387853, "brake.rate_per_s": 28.264871300092565, "braking": "brakes",
        "wheel": "rr", "driver": "fixed", "curve": "straight", "fault": "inlet_stuck_fr"}


_run_pt = envelope_point_run  # tests/support.py


@pytest.fixture(scope="module")
def runs3():
    env = load_envelope("tire_blowout_faults")
    return {"on": _run_pt(env, P360, sets=ON3), "none": _run_pt(env, P360, baseline=True),
            "219": _run_pt(env, P219, sets=ON3), "219_none": _run_pt(env, P219, baseline=True)}


def test_360_value3_never_worse_than_without_compensation(runs3):
    """no_worse_than_no_compensation at #360 with the same fault in both cars (measured 0.169 vs 0.172 m; value 1:
    0.193 m, value 0: 9.269 m - both fail)."""
    assert runs3["on"].metrics[METRIC] <= runs3["none"].metrics[METRIC], runs3["on"].metrics[METRIC]


def test_360_value3_rear_pair_one_pressure(runs3):
    """The twin's ABS rear select-low keeps the rear pair at one pressure (RL - RR = 0): with the rule the pair differs
    by less than 1 bar on average over the braking window (value 1: the dump stopped on A_P_EST, RL above RR)."""
    r, w = runs3["on"], _braking_window(runs3["on"])
    rl, rr = (np.asarray(r.trace[f"wheel_pressure_{k}_pa"])[w] for k in ("rl", "rr"))
    assert np.mean(rl - rr) < 1 * BAR, np.mean(rl - rr) / BAR


def test_219_stuck_front_holding_a_brake_keeps_the_release(runs3):
    """FR stuck while braked (52.8 bar trapped): the blown side is not unbraked, the rule does not act (no limit code 6)
    and the car stays no worse than without the function (1.223 vs 2.084 m; value 2 re-braked the blown rear: 2.213 m)."""
    r = runs3["219"]
    assert not np.any(np.asarray(r.trace["blowout_limit_code"]) == LIMIT_BLOWN_SIDE)
    assert r.metrics[METRIC] <= runs3["219_none"].metrics[METRIC], r.metrics[METRIC]


# ---- value 4 (session l RL4, tire_blowout_findings.md RL4) -------------------------------------------------------------
# Value 4 = value 3 for a detection both sources agree on; a single-source (TPMS-path) detection keeps the paper's
# release. With the pedal before the detection the detection is TPMS-only; its release is the function's confirmation
# probe (tpms_confirm: the freed flat spins up) and its yaw is judged net of that release (yaw_net). With the blown
# side's front stuck the driver's pedal itself yaws the car away from the blown side, so such a detection is rejected
# (yaw_implausible) in its first judged period: value 3 then only suppressed the 5 ms release and the rejection's
# re-apply, and stood the blown side down to the ESP on the function's reference - 3.1 / 2.2 cm worse than flag 0
# (the two new never-worse violations of L6) and, over +-2 % speed around them, worse in 16 / 21 and 21 / 21 points.
# Seeded defect: value 3 (fails both tests). References: the twin with the same fault (never-worse), LIMIT_REASONS.
ON4 = ("vehicle.blowout_compensation.blown_side_fault_flag=4",)
DEFECT3 = ("vehicle.blowout_compensation.blown_side_fault_flag=3",)
# /tmp/lead/l/base2/f_r41 #134 (faults from t = 0) and /tmp/lead/l/baseT/t_r41 #470 (fault_time 0.68 s): pedal BEFORE
# the detection (0.70 / 0.87 s vs 1.18 / 1.47 s), blown rear, its side's front stuck with 0 bar
P134 = {"speed": 55.37411041792652, "mu": 0.31436767903368246, "delay": 0.14654345157551255,
        "wheel_speed_noise": 0.061261524218180284, "noise_seed": 4312.0, "brake_gain": 0.8769823826056804,
        "accumulator": 115.08151986487374, "brake.start_s": 0.6998815672835486, "brake.level_frac": 0.4660023552333338,
        "brake.rate_per_s": 27.935206291332698, "braking": "brakes", "wheel": "rl", "driver": "follow",
        "curve": "straight", "fault": "inlet_stuck_fl"}
P470 = {"speed": 92.23590127310547, "mu": 0.4278474251947866, "delay": 0.4365015045708305,
        "wheel_speed_noise": 0.14433883247559784, "noise_seed": 8265.0, "brake_gain": 0.7311696019922223,
        "accumulator": 118.55216219921661, "fault_time": 0.680017994913876, "brake.start_s": 0.8741422384961437,
        "brake.level_frac": 0.48869039428355787, "brake.rate_per_s": 1.406736556936166, "braking": "brakes",
        "wheel": "rr", "driver": "follow", "curve": "straight", "fault": "inlet_stuck_fr"}


@pytest.fixture(scope="module")
def runs4():
    env = load_envelope("tire_blowout_faults")
    out = {}
    for k, pt in (("134", P134), ("470", P470)):
        out[k] = _run_pt(env, pt, sets=ON4)
        out[k + "_none"] = _run_pt(env, pt, baseline=True)
    return out


@pytest.mark.parametrize("k", ["134", "470"])
def test_single_source_detection_never_worse_than_without_compensation(runs4, k):
    """no_worse_than_no_compensation (same fault in both cars): #134 0.726 vs 0.736 m, #470 0.690 vs 0.693 m at value 4;
    value 3: 0.757 / 0.713 m (fail)."""
    assert runs4[k].metrics[METRIC] <= runs4[k + "_none"].metrics[METRIC], runs4[k].metrics[METRIC]


@pytest.mark.parametrize("k", ["134", "470"])
def test_single_source_detection_no_blown_side_code(runs4, k):
    """The rule does not act on a single-source detection: no limit code 6 (value 3 set it from the detection on, also
    through the REJECTED mode that followed 5 ms later, where nothing was limited)."""
    assert not np.any(np.asarray(runs4[k].trace["blowout_limit_code"]) == LIMIT_BLOWN_SIDE)


# /tmp/lead/l/baseT/t_r7 #208: FR sticks at 1.85 s, 0.06 s after the pedal (1.79 s) - a brake trapped in it. At value 4
# #219 above is a single-source detection (the source gate already keeps the release), so this two-source point is the
# one that exercises value 3's trapped-pressure premise at the shipped value (RL4: without that gate robustness
# 4.067 -> 0.641 m here, 14 faultsT points worse by > 0.05 m).
P208 = {"speed": 99.27539058320818, "mu": 0.42819425532026134, "delay": 0.3696206133025876,
        "wheel_speed_noise": 0.2312880160591726, "noise_seed": 1350.0, "brake_gain": 1.0782534077144796,
        "accumulator": 115.64965623023723, "fault_time": 1.8505789608362069, "brake.start_s": 1.7898682999358615,
        "brake.level_frac": 0.18161535358006173, "brake.rate_per_s": 5.256750711964737, "braking": "brakes",
        "wheel": "rr", "driver": "fixed", "curve": "straight", "fault": "inlet_stuck_fr"}


def test_208_stuck_front_holding_a_brake_rule_does_not_act():
    """Premise (value 3/4): a stuck front that holds a brake leaves the blown side braked, the rule must not act - the
    run is the code before's (flag 0) to the bit, and no limit code 6. Seeded defect: the trapped-pressure gate dropped
    (the rule re-brakes the blown rear: code 6, 4.067 -> 0.641 m robustness)."""
    env = load_envelope("tire_blowout_faults")
    r4, r0 = (_run_pt(env, P208, sets=s) for s in (ON4, DEFECT_SLY))
    assert not np.any(np.asarray(r4.trace["blowout_limit_code"]) == LIMIT_BLOWN_SIDE)
    for k in ("wheel_pressure_rl_pa", "wheel_pressure_rr_pa", "lane_offset_m"):
        np.testing.assert_array_equal(np.asarray(r4.trace[k]), np.asarray(r0.trace[k]))
