"""A REAR blowout whose opposite rear's inlet is stuck closed: LIMITED on the substitute front and the OTHER front's
yaw limitation (``blowout_compensation.substitute_yaw_limit_flag``, session 2026-11-24 k, task K2;
tire_blowout_findings.md "K2 (session k)", status j item 6).

With the opposite rear's inlet stuck the compensation brakes the front on the other side of the car (``_substitute``:
RL blown -> FR; limit code 1). The front on the BLOWN side is then the driver's and HBA's alone - and its brake force
is a yaw moment toward the blown side, the direction the flat tire already pulls. Without the function the ESP's
yaw-moment limitation (GMA: a front held above esp.yaw_hold_rate and dumped above esp.yaw_dump_rate of yaw toward its
side) governs that wheel as soon as the other front's ABS cycles alone; with the function the compensation's GMA block
masks the substitute's ABS activity (no GMA starts) and ends a GMA already running on the blown side's front, so that
front went to the full driver's / pump pressure. lead's random 61 -n 32 #22 (RL, 106 km/h, mu 0.66, 1000 m left curve,
blowout detected at 1.31 s before the pedal at 1.40 s): the twin's GMA dumps FL to 1 bar (FR 30 bar), the function's
FL rises to 30-36 bar against the substitute FR's 25-30 bar: yaw toward RL 0.30 rad/s, refused at 2.79 s (limit code 3),
19.578 m vs the twin's 11.507 m.

The rule: in LIMITED (limit code 1, rear blown) the blown side's front is released while the yaw error toward the blown
side (net of the steered reference) exceeds esp.yaw_dump_rate, and while it exceeds esp.yaw_hold_rate with that front more
than 1 bar above the substitute (the GMA's two thresholds; no new threshold). Review RK1 (session k): with the hold branch
the blown side's front is not held between the two rates (the GMA holds it there): its own ABS pulsed re-build (HBA pump)
lifts it again after each release - P22's LIMITED 1.45-3.0 s: FL 21-30 bar sawtooth every ~40 ms, FL - FR -5.9 bar mean
(twin, GMA: -27.3 bar); hence the thin margin of the never-worse row (0.065 m).

References, independent of the function's code: requirement tire_blowout.no_worse_than_no_compensation with the SAME
fault in both cars (the twin: the car without compensation, paper 004 Fig. 4 curve 2); the ESP's own yaw-dump rate
(5 deg/s, data/vehicles/suv_bj2500.toml esp table). Flag 0 = the code before = the seeded defect.
"""
from __future__ import annotations

import copy

import numpy as np
import pytest

import vehicle_assist as va
from vehicle_assist.verification.envelope import load_envelope

METRIC = "blowout_lateral_deviation_run_max_m"
# (session n, N3) substitute_braking_flag (shipped 1) re-builds the substitute FR after its ABS dumps and moves #22 on
# its own (the twin at standstill 22.19 m: K2's flag 0 with it 19.04 m, no longer worse); K2's and K7's statements are
# about the blown side's front and are tested with it at 0, as at 2012a18 (the shipped "on" run keeps every flag)
N3_OFF = ("vehicle.blowout_compensation.substitute_braking_flag=0",)
DEFECT = ("vehicle.blowout_compensation.substitute_yaw_limit_flag=0",) + N3_OFF  # the code before
LIMIT_OTHER_AXLE = 1  # blowout_limit_code: the opposite inlet stuck, the other axle's wheel brakes (issue #10)
# /tmp/lead/i/end/r61/falsify.json history #22 (random 61 -n 32 -b 32), + RR's inlet stuck closed from 0 s
P22 = {"speed": 105.64040531450647, "mu": 0.6556705730966937, "delay": 0.27866973963406677,
       "wheel_speed_noise": 0.29837619035252333, "noise_seed": 8716.0, "brake_gain": 1.1192417562560197,
       "brake.start_s": 1.4018381522506136, "brake.level_frac": 0.18837601528314624,
       "brake.rate_per_s": 13.988655380368476, "braking": "brakes", "wheel": "rl", "driver": "fixed",
       "curve": "r1000"}
STUCK_RR = {"at_s": 0.0, "action": "actuator_fault", "actuator": "inlet_valve_rr", "fault": "stuck_energized"}
CURVE_RADIUS_M = 1000.0  # P22's curve r1000 (left: CCW, the blown RL's side)
MARGIN_RADPS = 0.01
YAW_DUMP_RADPS = np.radians(5.0)  # esp.yaw_dump_rate_deg_per_s (suv_bj2500.toml, the ESP's GMA yaw dump)


def _stuck_run(env, point, baseline=False, sets=()):
    from vehicle_assist.scenarios.loader import scenario_from_raw

    sc = env.scenario(point, baseline=baseline)
    raw = copy.deepcopy(sc.raw)
    raw["events"] = list(raw.get("events", [])) + [dict(STUCK_RR)]
    sc = scenario_from_raw(raw, sc.path, sc.sets)
    return va.simulate(sc.with_sets(*sets) if sets else sc, requirements=False)


@pytest.fixture(scope="module")
def runs():
    env = load_envelope("tire_blowout")
    return {"on": _stuck_run(env, P22), "defect": _stuck_run(env, P22, sets=DEFECT),
            "none": _stuck_run(env, P22, baseline=True)}


def test_22_goes_limited_on_the_substitute(runs):
    """The case this file is about: the compensation runs LIMITED on the other axle (limit code 1) in both variants."""
    for k in ("on", "defect"):
        codes = np.asarray(runs[k].trace["blowout_limit_code"])
        assert np.any(codes == LIMIT_OTHER_AXLE), k


def test_22_stuck_rr_never_worse_than_without_compensation(runs):
    """Requirement no_worse_than_no_compensation with the same fault in both cars (rollback_floor_m 0: the function's run
    max <= the twin's; measured at main 3668eaf 11.442 vs 11.507 m, a margin of 0.065 m). Session n (N1, class B,
    corrected): judged to standstill both cars leave the road (run max 25.625 vs 22.189 m, beyond the road edge: not
    ranked by the requirement), so both rows of the requirement: road deviation tie 3.978 m, the function's car leaves
    the road 0.310 s after the twin."""
    from tests.support import never_worse_rows

    rows = never_worse_rows(runs["on"], runs["none"])
    assert min(rows.values()) >= 0.0, rows


@pytest.mark.xfail(strict=True, reason=(
    "N1 (session n, class C): judged to standstill (both rows) the code before is no longer worse than the twin: both "
    "leave the road (tie 3.978 m), the code before 0.115 s AFTER the twin (earliness 27.855 vs 27.970 s; run max "
    "125.1 vs 22.2 m, beyond the road edge); the rule leaves it 0.195 s after the code before"))
def test_22_defect_is_worse_than_without_compensation(runs):
    """Negative control: the code before (flag 0) fails the same check - 19.578 vs 11.507 m. Session n (N1): the same
    check is both rows (never_worse_rows); a 5-s-window control, xfail(strict) with the numbers."""
    from tests.support import never_worse_rows

    rows = never_worse_rows(runs["defect"], runs["none"])
    assert min(rows.values()) < 0.0, rows


def test_22_blown_side_front_released_beyond_the_yaw_dump_rate(runs):
    """The mechanism: in LIMITED on the substitute, while the car has yawed toward the blown side (RL: CCW +) beyond the
    curve's yaw by more than the ESP's dump rate for 50 ms (the ESP's 5 ms period x 10: the release has had time to act), FL's plant pressure is
    not rising - at flag 0 it is built to the driver's / pump level (30-36 bar) there."""
    def rises(r):
        t = np.asarray(r.trace["time_s"])
        # yaw rate toward RL (CCW +) net of the 1000 m curve's own u/R (kinematic path yaw, not the ECU's model) and
        # of a 0.01 rad/s margin for the ECU's steered reference (single-track model of the held steering)
        yaw = np.asarray(r.trace["yaw_rate_radps"]) - np.asarray(r.trace["speed_mps"]) / CURVE_RADIUS_M - MARGIN_RADPS
        code = np.asarray(r.trace["blowout_limit_code"])
        p_fl = np.asarray(r.trace["wheel_pressure_fl_pa"])
        dt = float(t[1] - t[0])
        n = max(int(round(0.05 / dt)), 1)
        over = yaw > YAW_DUMP_RADPS
        k = [i for i in range(n, len(t) - 1)
             if code[i] == LIMIT_OTHER_AXLE and over[i - n:i + 1].all()]
        assert k, "no LIMITED sample beyond the yaw dump rate"
        return sum(1 for i in k if p_fl[i + 1] > p_fl[i - n] + 1.0e5), len(k)

    on_rise, on_n = rises(runs["on"])
    assert on_rise == 0, (on_rise, on_n)
    d_rise, d_n = rises(runs["defect"])
    assert d_rise > 0, (d_rise, d_n)


# --- substitute_yaw_limit_flag 2 (session k, task K7; RK1's latched hold) - measured, NOT shipped ---------------------
# The GMA HOLDS the front between esp.yaw_hold_rate and esp.yaw_dump_rate (its pressure does not rise there); value 1
# only releases the blown side's front while it is > 1 bar above the substitute, so FL's own ABS/HBA pulsed re-build
# lifts it again after every release (RK1: P22 FL 21-30 bar sawtooth, twin ~1 bar). Value 2 latches FL's level on
# entering the band and releases it while it is > 1 bar above that level. Value 2 is not shipped (444 stuck rear points:
# 2 new never-worse violations, findings K7), so these tests set it explicitly; K2's value 1 is the reference it must
# improve on - they fail with LATCH = 1 (shown in findings K7).
LATCH = ("vehicle.blowout_compensation.substitute_yaw_limit_flag=2",) + N3_OFF
K2_RULE = ("vehicle.blowout_compensation.substitute_yaw_limit_flag=1",) + N3_OFF
YAW_HOLD_RADPS = np.radians(2.0)  # esp.yaw_hold_rate_deg_per_s (suv_bj2500.toml, the ESP's GMA yaw hold)
RULE_MARGIN_PA = 1.0e5  # the rule's 1-bar margin (substitute_yaw_limit, both values)


@pytest.fixture(scope="module")
def latch_runs():
    env = load_envelope("tire_blowout")
    return {"latch": _stuck_run(env, P22, sets=LATCH), "k2": _stuck_run(env, P22, sets=K2_RULE),
            "none": _stuck_run(env, P22, baseline=True)}


def _fl_mean_in_hold_band(r):
    """FL's mean plant pressure over the LIMITED (code 1) samples whose yaw rate toward RL, net of the 1000 m curve's
    kinematic u/R and of the 0.01 rad/s reference margin, exceeds the ESP's yaw hold rate (independent of the ECU)."""
    yaw = np.asarray(r.trace["yaw_rate_radps"]) - np.asarray(r.trace["speed_mps"]) / CURVE_RADIUS_M - MARGIN_RADPS
    code = np.asarray(r.trace["blowout_limit_code"])
    band = (code == LIMIT_OTHER_AXLE) & (yaw > YAW_HOLD_RADPS)
    assert band.any(), "no LIMITED sample beyond the yaw hold rate"
    return float(np.asarray(r.trace["wheel_pressure_fl_pa"])[band].mean())


def test_22_latched_hold_lowers_the_blown_side_front(latch_runs):
    """With the hold, FL's level where the GMA would hold it is lower than with K2's release-only rule by more than the
    rule's 1-bar margin (measured: 15.30 vs 23.07 bar; the twin's GMA keeps FL at ~1 bar). Fails at LATCH = 1 (equal)."""
    latch, k2 = _fl_mean_in_hold_band(latch_runs["latch"]), _fl_mean_in_hold_band(latch_runs["k2"])
    assert latch < k2 - RULE_MARGIN_PA, (latch / 1e5, k2 / 1e5)


def test_22_latched_hold_never_worse_and_not_worse_than_k2(latch_runs):
    """Requirement no_worse_than_no_compensation with the same fault in both cars (9.253 vs the twin's 11.507 m), and no
    worse than K2's rule on its own test point (11.442 m)."""
    latch, k2, none = (latch_runs[k].metrics[METRIC] for k in ("latch", "k2", "none"))
    assert latch <= none, (latch, none)
    assert latch <= k2, (latch, k2)
