"""A false TPMS alarm (no blowout) while the driver brakes at 100/120 km/h must not pull the car out of its lane
(issue #10: "false blowout detection (no blowout happened) must not pull the car off its lane by more than a bound you
justify"; tire_blowout_findings.md P, session 2026-11-24 e). Bound: the existing false-detection bound, the 0.978 m lane margin
of metrics/blowout.py LANE_MARGIN_M = (3.75 m lane, JTG B01-2014 - 1.794 m BJ2500 width, cite:J2500)/2, whole run, the
check of the shipped blowout_false_tpms_braking_60kph. Reference: the function off the car stays straight (0.00 m):
the driver's symmetric braking - a false alarm must not be worse than no assist.

Scenario: blowout_false_tpms_braking_60kph (no blowout; the TPMS names a wheel from 1 s; the driver brakes from
0.5 s) with the named wheel FL or RL, the pedal 80 N (8 %) or 500 N (50 %), 100 or 120 km/h.

Mechanism (measured): with a braking driver the TPMS alarm alone detects (TPMS path, single source), the named healthy
wheel is released and the same-axle one built. (1) The yaw-plausibility rule sees a rear false alarm under a light
pedal too late or never (RL 80 N: RR's counter-brake is held under the rear slip limit, < 2 deg/s): 1.76 m at
100 km/h, 2.55 m at 120 km/h. Fixed by ``tpms_confirm_flag``: a released healthy wheel, once free of the brake (pressure estimate <= 2 bar), rolls at
the car's speed without spinning up, a released flat one spins up toward ~50 % over-speed -> REJECTED
(signature_unconfirmed) after 60 ms of that evidence: 0.17 / 0.23 m. (2) Under a 500 N pedal every wheel is at its ABS
level; after the rejection ABS re-built the released wheel in pulses (front 10 -> 55 bar in 0.3 s) and the rear
select-low held a released rear at 3-9 bar for > 1 s: FL 1.33 / 2.28 m, RL 2.57 / 4.16 m. ``reject_reapply_flag``
gives it the driver's pressure back at once up to the same-axle wheel's: FL 0.54 / 0.72 m; RL 500 N 1.29 / 2.06 m
still out: the ECU's estimate of the re-applied rear jumped to the driver's (W_N) while the line filled it only to 35
of 81 bar before the rear select-low dumped the pair, and the select-low shares the request, not the pressure, so RL
stayed 25-35 bar below RR (35-63 vs 64-79 bar) for the whole stop. ``reject_pair_low_flag`` (after a rear rejection,
until the brake is released): the re-applied rear's estimate is the re-apply's line model, and the higher rear is
dumped to the lower one's pressure (select-low on the pair, Bosch Automotive Handbook): 0.19 / 0.16 m."""
from __future__ import annotations

import tempfile
from pathlib import Path

import numpy as np
import pytest

import vehicle_assist as va

LANE_MARGIN_M = 0.978  # metrics/blowout.py LANE_MARGIN_M (the false-detection bound, issue #10)
WHEEL_INDEX = {"FL": 1.0, "RL": 3.0, "RR": 4.0}  # tpms_alarm_wheel bias: 1..4 = fl, fr, rl, rr


def _run(wheel, pedal_frac, speed_kph, sets=()):
    """The shipped scenario with the TPMS naming ``wheel`` (its text with the fault's bias_index replaced)."""
    text = (Path(va.__file__).parent / "data/scenarios/blowout_false_tpms_braking_60kph.toml").read_text()
    assert text.count("bias_index = 1.0") == 1
    with tempfile.TemporaryDirectory() as d:
        path = Path(d) / f"false_tpms_{wheel.lower()}.toml"
        path.write_text(text.replace("bias_index = 1.0", f"bias_index = {WHEEL_INDEX[wheel]}"))
        sc = va.load_scenario(path, sets=(
            f"run.initial_speed_kph={speed_kph}",
            f"driver.brake_pedal={{time_s = [0.0, 0.5, 0.55], frac = [0.0, 0.0, {pedal_frac}]}}") + tuple(sets))
    r = va.simulate(sc, requirements=False)
    return float(np.max(np.abs(np.asarray(r.trace.channels["lane_offset_m"])))), r


CASES = [("FL", 0.08, 100), ("FL", 0.08, 120), ("RL", 0.08, 100), ("RL", 0.08, 120),
         ("FL", 0.5, 100), ("FL", 0.5, 120),
         ("RL", 0.5, 100), ("RL", 0.5, 120),
         # rear pair rule across pedal / speed / side (sweep 60-140 km/h x 20-100 % pedal, RL and RR: fix <= 0.61 m,
         # defect up to 2.75 m; measured fix / defect): 0.23 / 1.79, 0.61 / 1.28, 0.14 / 2.19, 0.15 / 2.06 m
         ("RL", 0.35, 120), ("RL", 0.8, 120), ("RL", 1.0, 140), ("RR", 0.5, 120)]


@pytest.mark.parametrize("wheel,pedal_frac,speed_kph", CASES)
def test_false_tpms_alarm_braking_stays_in_lane(wheel, pedal_frac, speed_kph):
    dev, r = _run(wheel, pedal_frac, speed_kph)
    assert any(e.machine == "blowout_compensation" and e.to_mode == "REJECTED" for e in r.events)
    assert dev < LANE_MARGIN_M


@pytest.mark.parametrize("wheel,pedal_frac,speed_kph,flag", [
    ("RL", 0.08, 100, "tpms_confirm_flag"), ("RL", 0.08, 120, "tpms_confirm_flag"),
    ("FL", 0.5, 100, "reject_reapply_flag"), ("FL", 0.5, 120, "reject_reapply_flag"),
    ("RL", 0.5, 100, "reject_pair_low_flag"), ("RL", 0.5, 120, "reject_pair_low_flag"),
    ("RL", 0.35, 120, "reject_pair_low_flag"), ("RR", 0.5, 120, "reject_pair_low_flag")])
def test_false_tpms_alarm_braking_leaves_lane_with_the_defect(wheel, pedal_frac, speed_kph, flag):
    """Negative control: the seeded defect (the flag 0 = the code before) takes the same case out of the lane
    (measured: RL 80 N 1.76 / 2.55 m; FL 500 N 1.33 / 2.28 m; RL 500 N 1.29 / 2.06 m; RL 350 N 120 km/h 1.79 m;
    RR 500 N 120 km/h 2.06 m)."""
    dev, _ = _run(wheel, pedal_frac, speed_kph, (f"vehicle.blowout_compensation.{flag}=0", "vehicle.blowout_compensation.reject_heading_return_flag=0"))  # (J5, session j) isolated from reject_heading_return_flag, which also rescues this defect
    assert dev > LANE_MARGIN_M
