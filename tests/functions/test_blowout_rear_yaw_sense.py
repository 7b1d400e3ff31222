"""The rear-pair yaw hold (``rear_oversteer_yaw_flag``, functions/blowout_compensation.py ``rear_oversteer_cap``) only
while the car itself turns toward the blown side beyond the dead band (``rear_oversteer_yaw_sense_flag``; independent
review RG2, session 2026-11-24 g).

Reference, independent of the rule's code: the ESP yaw-rate oversteer criterion the rule cites (van Zanten, SAE
2000-01-1633) - a car rotating toward the blown side faster than the steering asks; a yaw rate inside the closed-loop
dead band (1 deg/s, the toml's assumed value) is a car that is not turning. In a curve steered AWAY from the blown side
such a car is short of the steered turn (understeer), and its yaw error points toward the blown side only because the
reference points away. The no-compensation twin and the code before (seeded defect rear_oversteer_yaw_sense_flag = 0,
the G6 code: any yaw > 0 toward the blown side) are the system-level references."""
from __future__ import annotations

import numpy as np
import pytest

import vehicle_assist as va
from vehicle_assist.functions import blowout_compensation as bc
from vehicle_assist.scenarios.runner import pack_records

BAR = 1.0e5
FL, FR = 0, 1
B = "vehicle.blowout_compensation."
METRIC = "blowout_lateral_deviation_run_max_m"


@pytest.fixture(scope="module")
def params():
    return pack_records([va.load_scenario("blowout_lf_60kph_paper").vehicle.flat()])[0]


def _cap(p, blown, tg, yaw_err, r_ref, periods=5):
    """``periods`` ESP periods of the braking rule in HOLD, the driver braking, the phase-plane state at rest, rears at
    48 bar: the rear cap the rule writes (-1 = not acting)."""
    st = bc.initial_state()
    st[bc.S_P_REQ] = 20.0 * BAR
    p_est = np.array([45.0, 45.0, 48.0, 48.0]) * BAR
    p_est[blown] = 1.0 * BAR
    for _ in range(periods):
        bc.braking_rule(st, blown, tg, bc.HOLD, 1.0, -6.0, 0.0, yaw_err, 159.0 * BAR, p_est, p, r_ref)
    return st[bc.S_REAR_CAP], st[bc.S_OS_YAW_SEEN]


@pytest.mark.parametrize("blown, tg, sign", [(FL, FR, 1.0), (FR, FL, -1.0)])
def test_steered_away_from_the_blown_side_is_not_an_oversteer(params, blown, tg, sign):
    """Steering away from the blown side (reference 0.042 rad/s away), the car yawing 0.0045 rad/s toward it (error
    0.046 rad/s toward the blown side): a car that hardly turns (inside the 1 deg/s dead band), short of the steered
    turn - no rear hold, no confirmation. With the defect (sense flag 0) the rule held the pair and latched the
    confirmation (mirror for FR)."""
    r_ref = -0.042 * sign
    yaw_meas = 0.0045 * sign
    cap, seen = _cap(params, blown, tg, yaw_meas - r_ref, r_ref)
    assert cap < 0.0 and seen < 0.5
    p0 = params.copy()
    p0.blowout_compensation_rear_oversteer_yaw_sense_flag = 0.0
    cap0, seen0 = _cap(p0, blown, tg, yaw_meas - r_ref, r_ref)
    assert cap0 == pytest.approx(48.0 * BAR, abs=1.0) and seen0 > 0.5


@pytest.mark.parametrize("blown, tg, sign", [(FL, FR, 1.0), (FR, FL, -1.0)])
@pytest.mark.parametrize("r_ref", [0.0, 0.01, 0.04])
def test_straight_or_toward_the_blown_side_still_held(params, blown, tg, sign, r_ref):
    """The rule's own case is kept: a straight road (or a reference inside the dead band) and a turn toward the blown
    side, the yaw beyond the reference toward the blown side by 0.10 rad/s: the pair is held at its 48 bar."""
    cap, seen = _cap(params, blown, tg, 0.10 * sign, r_ref * sign)
    assert cap == pytest.approx(48.0 * BAR, abs=1.0) and seen > 0.5


@pytest.mark.parametrize("blown, tg, sign", [(FL, FR, 1.0), (FR, FL, -1.0)])
def test_counter_steered_rotation_toward_the_blown_side_still_held(params, blown, tg, sign):
    """The driver counter-steering (reference 0.04 rad/s away from the blown side), the car rotating toward the blown
    side at 0.06 rad/s (beyond the dead band): the rotation against the steering is the rule's oversteer - held."""
    r_ref = -0.04 * sign
    cap, seen = _cap(params, blown, tg, 0.06 * sign - r_ref, r_ref)
    assert cap == pytest.approx(48.0 * BAR, abs=1.0) and seen > 0.5


# Session i (I11): esp.pressure_estimate_line_flag = 2 shipped (the ABS dump's stored lock level S_P_PREDUMP reads the
# ECU's line-lag estimate, not the source step). At 1000 m the sense defect's loss came through that lock level: with
# the flag at 2 the defect run (rear_oversteer_yaw_sense_flag=0, gma_rejected_flag=0) is 0.611 m vs none 1.514 (2.786 m
# at 0) - its mechanism needs the source-step estimate, so the 1000-m negative controls (and the isolated row's three
# runs, compared with each other) are pinned at the code before (flag 0). 650 m still shows the defect at 2: not pinned.
PEST_PIN = {1000: ("vehicle.esp.pressure_estimate_line_flag=0",)}


def _false_fr_alarm(extra=(), radius_m=650):
    """Shipped blowout_false_tpms_braking_60kph with the FR named (faulty alarm, no blowout) in a LEFT curve
    at mu 0.4, 100 km/h, pedal 0.3, fixed steering."""
    sets = ["road.friction_mu=0.4", "run.initial_speed_kph=100", f"vehicle.lane_keeper.lane_radius_m={radius_m}",
            "vehicle.lane_keeper.steering_mode=fixed", "driver.brake_pedal.frac=[0.0, 0.0, 0.3]",
            'events=[{at_s=1.0, action="sensor_fault", sensor="tpms_alarm_wheel", fault="bias", bias_index=2.0}]']
    sc = va.load_scenario("blowout_false_tpms_braking_60kph").with_sets(*sets, *extra)
    return va.simulate(sc, requirements=False).metrics[METRIC]


@pytest.mark.parametrize("radius_m, why", [
    (650, "3.641 m with the defect vs 3.044 before rear_oversteer_yaw_flag (none 2.445)"),
    (1000, "2.786 m with the defect - out of the 0.978 m lane bound and worse than none 1.514 - vs 0.567 before"),
])
def test_false_fr_alarm_in_a_left_curve_not_made_worse(radius_m, why):
    """False FR alarm in a left curve: the understeering car (at 650 m: yaw -0.0045..-0.0008 rad/s against a +0.042
    rad/s reference at 1.08-1.10 s) is not an oversteer toward FR. With the defect the rear pair was held and the
    detection counted as confirmed (tire_blowout_findings.md RG2: 11 of 640 false-alarm grid points worse by > 0.05 m, all FR
    named in a left curve)."""
    # run isolated from gma_rejected_flag (session h, H2): that rule removes the GMA the rejected FR's re-apply started on
    # FL, which is where most of this defect's loss went (with it: 650 m before G6 3.044 -> 1.593 m, the G6 defect
    # 1.544 m; 1000 m 0.567 -> 0.698, defect 0.725) - so the sense rule's own check runs on the code it was written on
    iso = (B + "gma_rejected_flag=0", B + "reject_heading_return_flag=0") + PEST_PIN.get(radius_m, ())  # (J5, session j) isolated from reject_heading_return_flag, which also rescues this defect
    fixed = _false_fr_alarm(iso, radius_m=radius_m)
    before_g6 = _false_fr_alarm(iso + (B + "rear_oversteer_yaw_flag=0",), radius_m)
    defect = _false_fr_alarm(iso + (B + "rear_oversteer_yaw_sense_flag=0",), radius_m)
    assert fixed <= before_g6 + 1.0e-6, why
    assert defect > before_g6 + 0.3, why


@pytest.mark.parametrize("radius_m", [650, 1000])
def test_false_fr_alarm_in_a_left_curve_as_shipped_no_worse_than_none(radius_m):
    """Review RH1 (session h): the check above runs isolated from gma_rejected_flag, i.e. on code that is not shipped;
    this one holds the shipped code to the requirement the test name states - the false FR alarm in the left curve
    no worse than the same car without the function (tire_blowout.no_worse_than_no_compensation). Measured at 1275827:
    650 m 1.593 m vs none 2.445; 1000 m 0.698 vs 1.514. Can fail: with rear_oversteer_yaw_sense_flag and
    gma_rejected_flag both 0 (the code before G6's sense rule and H2) 3.641 / 2.786 m."""
    shipped = _false_fr_alarm(radius_m=radius_m)
    none = _false_fr_alarm((B + "enabled_flag=0",), radius_m)
    assert shipped <= none, (shipped, none)


@pytest.mark.parametrize("radius_m", [650, 1000])
def test_false_fr_alarm_as_shipped_check_fails_with_both_defects(radius_m):
    """Negative control of the check above: sense rule and gma_rejected rule both off -> worse than none."""
    defect = _false_fr_alarm((B + "rear_oversteer_yaw_sense_flag=0", B + "gma_rejected_flag=0", B + "reject_heading_return_flag=0",  # (J5)
                              *PEST_PIN.get(radius_m, ())), radius_m)
    none = _false_fr_alarm((B + "enabled_flag=0",), radius_m)
    assert defect > none, (defect, none)
