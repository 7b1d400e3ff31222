"""A SINGLE-source detection of a blown REAR whose side's FRONT inlet is stuck unbraked, the driver braking
(``blowout_compensation.blown_side_single_flag``, session 2026-11-25 n, task N2; tire_blowout_findings.md "N2").

Paper 004's balance (eqs. 9, 22-28) with the stuck front's force gone: the release of the blown rear (P7) leaves the
blown side with no brake, the pedal's front brake acts on the other side alone and the counter-brake adds to it (L1).
For a two-source detection ``blown_side_fault_flag`` 4 stands the brakes down; a single-source (pedal-first, TPMS path)
detection kept the paper's release until ``yaw_implausible`` rejected it (M5). The rule stands the function down as a
rejection does, at the first judged period (REJECTED, guard ``blown_side_unbraked``).

References, independent of the function's code: the requirement rows themselves (data/requirements/tire_blowout.toml:
``no_earlier_road_departure`` - the function's car must not leave the road where the twin stays on it), the car without
the function with the SAME fault (its ABS rear select-low keeps the rear pair at one pressure), and the source gate
(a two-source detection is not this rule's: bitwise). Flag 0 = the code before = the seeded defect: the first three
tests fail there (shown in findings N2).
"""
from __future__ import annotations

import numpy as np
import pytest

from vehicle_assist.verification.envelope import load_envelope
from tests.support import envelope_point_run

ROAD = "blowout_lateral_deviation_road_max_m"
EARLY = "blowout_road_departure_earliness_s"
ON = ("vehicle.blowout_compensation.blown_side_single_flag=1",)
DEFECT = ("vehicle.blowout_compensation.blown_side_single_flag=0",)  # the code before
BAR = 1.0e5
COMMON = {"braking": "brakes", "driver": "fixed"}
# the lead's session-n fault sets (fault from t = 0: tire_blowout_faults with fault_time pinned 0 = /tmp/lead/n/faults_t0
# .toml); f_r3 (random 3 -n 64) #22: RL blown, FL stuck, pedal 1.02 s, TPMS-only detection 1.16 s - row 2's worst point
P22 = {"speed": 73.29901677907426, "mu": 0.39449420327105844, "delay": 0.12678198851789615,
       "wheel_speed_noise": 0.19527580931495395, "noise_seed": 478.0, "brake_gain": 0.8222270954973201,
       "accumulator": 64.31338178696205, "brake.start_s": 1.016983614424564, "brake.level_frac": 0.373384990598679,
       "brake.rate_per_s": 17.784128712934198, "wheel": "rl", "curve": "straight", "fault": "inlet_stuck_fl", **COMMON}
# f_c2026 (CMA 2026 -n 64 -b 8) #50: RR blown, FR stuck, r1000, pedal 0.85 s, detection 1.41 s - row 1's worst point
P50 = {"speed": 54.98320558500792, "mu": 0.30509922231282366, "delay": 0.3776971471217396,
       "wheel_speed_noise": 0.28999805286905533, "noise_seed": 9414.0, "brake_gain": 0.8923721105190445,
       "accumulator": 41.689316114860844, "brake.start_s": 0.8456503607136748, "brake.level_frac": 0.3680653897779955,
       "brake.rate_per_s": 29.790295255829196, "wheel": "rr", "curve": "r1000", "fault": "inlet_stuck_fr", **COMMON}
# f_c2026 #31: RR blown, FR stuck, r650, a TWO-source detection (blown_side_fault 4 acts, code 6) - not this rule's
P31 = {"speed": 50.50894007818954, "mu": 0.48193948160213695, "delay": 0.34948591390921246,
       "wheel_speed_noise": 0.2998445945659179, "noise_seed": 7544.0, "brake_gain": 0.8857776045408402,
       "accumulator": 45.182897335022474, "brake.start_s": 0.758090435058882, "brake.level_frac": 0.29194728539545733,
       "brake.rate_per_s": 16.493436524018158, "wheel": "rr", "curve": "r650", "fault": "inlet_stuck_fr", **COMMON}


@pytest.fixture(scope="module")
def env():
    """The shipped fault envelope; these points carry no fault_time, so the fault is present from t = 0 (the envelope's
    rule for points of older sets - the lead's faults_t0 group)."""
    return load_envelope("tire_blowout_faults")


@pytest.fixture(scope="module")
def r22(env):
    return {"on": envelope_point_run(env, P22, sets=ON), "defect": envelope_point_run(env, P22, sets=DEFECT),
            "none": envelope_point_run(env, P22, baseline=True)}


@pytest.fixture(scope="module")
def r50(env):
    return {"on": envelope_point_run(env, P50, sets=ON), "none": envelope_point_run(env, P50, baseline=True)}


def _bc_events(r):
    return [(e.time_s, e.to_mode, e.reason) for e in r.events if e.machine == "blowout_compensation"]


def _rear_gap_bar(r, t_from, t_to=3.0):
    t = np.asarray(r.trace["time_s"])
    w = (t >= t_from) & (t <= t_to)
    rl, rr = (np.asarray(r.trace[f"wheel_pressure_{k}_pa"]) for k in ("rl", "rr"))
    return float(np.mean(np.abs(rl - rr)[w])) / BAR


def test_22_no_earlier_road_departure(r22):
    """Row no_earlier_road_departure (requirement text): the twin stays on the road (0 s), so must the function's car.
    Measured: 0 s with the rule; the code before leaves the road (24.655 s early, 3.978 m = the road edge)."""
    assert r22["none"].metrics[EARLY] == 0.0  # the reference: the car without the function stays on the road
    assert r22["on"].metrics[EARLY] <= 0.0, r22["on"].metrics[EARLY]


def test_22_stands_down_at_the_first_judged_period(r22):
    """REJECTED with guard blown_side_unbraked one ESP period (5 ms) after the detection - no release period of the
    blown side beyond it. The code before: BUILD -> HOLD, rejected yaw_implausible 0.57 s later (1.73 s)."""
    ev = _bc_events(r22["on"])
    assert ev[0][1] == "BUILD"
    assert ev[1][1:] == ("REJECTED", "blown_side_unbraked"), ev
    assert ev[1][0] - ev[0][0] <= 0.005 + 1e-9, ev


def test_rear_pair_braked_as_without_the_function(r22, r50):
    """From 0.2 s after the detection to 3 s the rear pair carries one pressure, as the twin's ABS select-low gives it
    (twin: 0 bar): mean |RL - RR| < 3 bar, both sides (RL blown #22, RR blown #50). Measured 1.44 / 0.0 bar; the code
    before 17.1 / 29.9 bar (the blown rear released while the other rear carries the driver's and the counter-brake)."""
    for r, p in ((r22, P22), (r50, P50)):
        t0 = _bc_events(r["on"])[0][0]
        assert _rear_gap_bar(r["none"], t0 + 0.2) < 3.0  # the reference
        assert _rear_gap_bar(r["on"], t0 + 0.2) < 3.0, (p["wheel"], _rear_gap_bar(r["on"], t0 + 0.2))


def test_22_defect_leaves_the_road(r22):
    """Negative control: the code before leaves the road where the twin stays on it (earliness 24.655 s)."""
    assert r22["defect"].metrics[EARLY] > 0.0


def test_31_two_source_detection_untouched(env):
    """Source gate: a detection both sources agree on is blown_side_fault's (value 4, code 6) - the run is bitwise the
    code before's (flag 0), measured at f_c2026 #31."""
    a = envelope_point_run(env, P31, sets=ON)
    b = envelope_point_run(env, P31, sets=DEFECT)
    assert "blown_side_unbraked" not in [e[2] for e in _bc_events(a)]
    for ch in ("wheel_pressure_rl_pa", "wheel_pressure_rr_pa", "lane_offset_m", "blowout_mode_index"):
        assert np.array_equal(np.asarray(a.trace[ch]), np.asarray(b.trace[ch])), ch
