"""A blown FRONT whose side's REAR has its inlet stuck closed (``blowout_compensation.blown_side_front_flag``, session
2026-11-24 m, task M2; tire_blowout_findings.md "M2 (session m)") - the mirror of L1's blown rear with its side's front
stuck (``blown_side_fault_flag``).

The paper releases the blown front (P7, eqs. 26-28: F_b = 0) and balances its drag with the other front. With the blown
side's rear stuck the blown side has no brake while the driver brakes; the free rear (the other side) carries the
driver's proportioned pressure alone, a yaw moment b_r*F_rr away from the blown side that the front balance does not
contain (its premise: the rears brake alike). Value 2: the rear pair select-low on pressure (the free rear held at the
stuck rear's trapped pressure + 1 bar) while the yaw error points away from the blown side beyond the dead band; the
front balance stays the paper's. Value 1 (the stand-down L1 applies to a blown rear: blown front to the driver, no
counter-brake) is the measured bad candidate (findings M2).

Points: /tmp/m2/ownbase/o7/falsify.json (faults_t0 = tire_blowout_faults with the fault from t = 0; random seed 7,
-R wheel=fl,fr -R fault=inlet_stuck_rl,inlet_stuck_rr -R braking=brakes). #90: FL blown, RL stuck, 111 km/h, mu 0.436,
left curve r650, lane follower, pedal 1.22 s after the two-source detection 1.11 s: flag 0 0.926 m (RR 18-25 bar alone),
twin 0.732. #17: FR blown, RR stuck, pedal 0.76 s BEFORE a TPMS-only detection (1.415 s) - RL4's source gate keeps the
paper's release there (without it: +0.289 -> -0.335 m, the rule kept alive a detection the pedal's yaw would reject).

References, independent of the function's code: the car without the function with the SAME fault (never worse), the
ESP's rear select-low (Bosch Automotive Handbook: the rear axle braked at the lower wheel's level), issue #10 'Faults'
("the controller limits its authority and says why"). Flag 0 = the code before = the seeded defect (findings M2 shows
which tests fail there).
"""
from __future__ import annotations

import numpy as np
import pytest

from vehicle_assist.verification.envelope import load_envelope
from tests.support import envelope_point_run

METRIC = "blowout_lateral_deviation_run_max_m"
FLAG = "vehicle.blowout_compensation.blown_side_front_flag"
ON = (f"{FLAG}=2",)
DEFECT = (f"{FLAG}=0",)  # the code before
LIMIT_BLOWN_SIDE = 6  # blowout_limit_code: the blown side's other inlet stuck (LIMIT_REASONS[6])
BAR = 1.0e5
P90 = {"speed": 111.4817310086122, "mu": 0.4361653244764513, "delay": 0.07043253775692655,
       "wheel_speed_noise": 0.18608033829235668, "noise_seed": 1270.0, "brake_gain": 1.1458106615650756,
       "accumulator": 49.796545306086244, "brake.start_s": 1.2237409675705486, "brake.level_frac": 0.26249010116872623,
       "brake.rate_per_s": 3.5600016159728365, "braking": "brakes", "wheel": "fl", "driver": "follow",
       "curve": "r650", "fault": "inlet_stuck_rl", "fault_time": 0.0}
P17 = {"speed": 76.59405585105739, "mu": 0.3313080807561882, "delay": 0.3813114254561627,
       "wheel_speed_noise": 0.17371637232877626, "noise_seed": 2997.0, "brake_gain": 0.7387732861755014,
       "accumulator": 101.0544761121185, "brake.start_s": 0.7621579765826414, "brake.level_frac": 0.09260712190434878,
       "brake.rate_per_s": 3.9439988995815036, "braking": "brakes", "wheel": "fr", "driver": "fixed",
       "curve": "straight", "fault": "inlet_stuck_rr", "fault_time": 0.0}


_run = envelope_point_run  # tests/support.py


@pytest.fixture(scope="module")
def runs():
    env = load_envelope("tire_blowout_faults")
    return {"on": _run(env, P90, sets=ON), "defect": _run(env, P90, sets=DEFECT), "none": _run(env, P90, baseline=True),
            "17on": _run(env, P17, sets=ON), "17defect": _run(env, P17, sets=DEFECT)}


def _window(r, t0=1.4, t1=3.5):
    t = np.asarray(r.trace["time_s"])
    return (t >= t0) & (t <= t1)


def test_90_never_worse(runs):
    """Never worse than the car without the function with the same fault: 0.501 m vs the twin's 0.732 (flag 0:
    0.926 m, a violation)."""
    on, none = runs["on"].metrics[METRIC], runs["none"].metrics[METRIC]
    assert on <= none, (on, none)


def test_90_rear_pair_select_low(runs):
    """The free rear (RR) is not left braking alone: mean RR - RL over the braking window below 8 bar (flag 0: the
    braking rule's friction cap left RR at 18-25 bar against the stuck RL's 1 bar)."""
    r, w = runs["on"], _window(runs["on"])
    rl, rr = (np.asarray(r.trace[f"wheel_pressure_{k}_pa"])[w] for k in ("rl", "rr"))
    assert np.mean(rr - rl) < 8 * BAR, np.mean(rr - rl) / BAR
    assert np.max(rl) < 2 * BAR  # the premise: the stuck rear is unbraked (reads the plant, not the rule)


def test_90_limit_code_says_why(runs):
    """Issue #10 'Faults': code 6 while the rule acts (flag 0: code 0 throughout)."""
    codes = np.asarray(runs["on"].trace["blowout_limit_code"])[_window(runs["on"])]
    assert np.all(codes == LIMIT_BLOWN_SIDE), np.unique(codes)


def test_17_single_source_detection_untouched(runs):
    """RL4's source gate holds for a blown front too: a TPMS-only detection (pedal first) keeps the paper's release, the
    run equals flag 0 (a mutant without the gate: 0.945 m vs the twin's 0.610, a new violation)."""
    a, b = runs["17on"], runs["17defect"]
    assert a.metrics[METRIC] == b.metrics[METRIC]
    assert np.array_equal(np.asarray(a.trace["wheel_pressure_rr_pa"]), np.asarray(b.trace["wheel_pressure_rr_pa"]))


def test_90_defect_is_a_violation(runs):
    """Negative control: the code before (flag 0) is worse than the twin at #90 (0.926 vs 0.732 m)."""
    assert runs["defect"].metrics[METRIC] > runs["none"].metrics[METRIC]
