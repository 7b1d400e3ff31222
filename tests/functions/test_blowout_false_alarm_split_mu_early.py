"""A FALSE TPMS alarm BEFORE the driver brakes, on a SPLIT-mu road (review RI1, session i; fixed by I12's
gma_rejected_split_flag for the snow-side named front; the dry-side named front still open).

The shipped split-mu false-alarm case (tests/functions/test_blowout_false_alarm_split_mu.py) names FR 0.45 s after the
pedal, when the ESP's GMA already runs on the dry FL; gma_rejected_pre_flag restores it after the rejection. Here the
faulty TPMS names the snow-side FR at 0.3 s, while cruising (a driver braking BECAUSE of the warning), and the 0.3
pedal (HBA, 150 bar) comes at 0.5-0.55 s. Measured at main a1878ef: the compensation detects FR at 0.555 s (TPMS path
under the pedal) - before any one-sided ABS activity, so no GMA ran before it - builds FL, and rejects at 0.615 s.
Then C_GMA_BLOCK stays on FL for the rest of the stop (FL, on dry at the driver's 150 bar, never leaves ABS) and
gma_rejected_flag masks the rejected FR's ABS activity (genuine: FR is on snow): no front's activity counts, the GMA
never starts. FL 41-47 bar against FR 8-11 bar, yaw 0.05 -> 0.32 rad/s toward the dry side: 14.635 m vs 1.888 m
without the function (its GMA holds FL at ~8 bar from 1.0 s). With gma_rejected_flag = 0: 2.456 m.
The mirror (FL named, left on snow) gives the same 14.635 m. esp.named_front_gma_flag does not change either (the
named window under the pedal is 5 ms). Neither envelope varies friction left/right: the falsifier cannot reach it.

Reference: the same car without the function (the requirement tire_blowout.no_worse_than_no_compensation)."""
from __future__ import annotations

import pytest

import vehicle_assist as va

B = "vehicle.blowout_compensation."
DEV = "blowout_lateral_deviation_run_max_m"
POINT = ["vehicle.surface.left=dry", "vehicle.surface.right=snow", "run.initial_speed_kph=80",
         "driver.brake_pedal.frac=[0.0, 0.0, 0.3]", "vehicle.lane_keeper.steering_mode=follow",
         'events=[{at_s=0.3, action="sensor_fault", sensor="tpms_alarm_wheel", fault="bias", bias_index=2.0}]']


def _dev(*extra):
    sc = va.load_scenario("blowout_false_tpms_braking_60kph").with_sets(*POINT, *extra)
    return va.simulate(sc, requirements=False).metrics[DEV]


@pytest.fixture(scope="module")
def none_m():
    return _dev(B + "enabled_flag=0")


def test_the_gma_rejected_mask_is_the_cause(none_m):
    """Diagnostic (code before I12's rule, gma_rejected_split_flag = 0): without gma_rejected_flag's mask the GMA
    starts on FL and the car does not spin (2.456 m; with the mask 14.635 m): the mask, not the detection or the build."""
    S0 = B + "gma_rejected_split_flag=0"  # before I12's rule (with it the GMA starts on FL: 1.639 m)
    J0 = B + "reject_heading_return_flag=0"  # (J5, session j) isolated from reject_heading_return_flag, which also rescues this defect
    assert _dev(B + "gma_rejected_flag=0", S0, J0) < 0.5 * _dev(S0, J0)


def test_false_alarm_before_braking_on_split_mu_no_worse_than_none(none_m):
    """Requirement no_worse_than_no_compensation (the same car without the function), RI1's point. I12's rule
    gma_rejected_split_flag: after the rejection the fronts' ABS lock levels (FL ~53-58 bar, FR ~14-17 bar: ratio >= 2,
    UN R13-H Annex 6 split surface) let the snow-side FR's activity count, the GMA starts on FL: 1.639 m (none 1.888);
    with gma_rejected_hold_dump_flag too 1.456 m."""
    assert _dev() <= none_m


def test_mirror_fl_on_snow_no_worse_than_none():
    """The mirror road (left on snow, FL named): the rule is side-symmetric (same 1.456 m against 1.888 m)."""
    mirror = ["vehicle.surface.left=snow", "vehicle.surface.right=dry",
              'events=[{at_s=0.3, action="sensor_fault", sensor="tpms_alarm_wheel", fault="bias", bias_index=1.0}]']
    assert _dev(*mirror) <= _dev(*mirror, B + "enabled_flag=0")


def test_seeded_defect_split_flag_zero_fails(none_m):
    """The same check with the rule off (gma_rejected_split_flag = 0, the code before: both fronts masked, no GMA,
    14.635 m) must fail - the check can catch the defect."""
    assert not (_dev(B + "gma_rejected_split_flag=0", B + "reject_heading_return_flag=0") <= none_m)  # (J5: isolated)


def test_dry_side_named_no_worse_than_none(none_m):
    """Was a strict xfail (I12, session i: FL named on the DRY side, FR built and rejected 0.715 s, 2.300 m vs 1.888 m
    without the function). Since session j (J5) reject_heading_return_flag gives back the heading the rejected
    detection's release + build made; with that flag at 0 it is 2.300 m again (the second assert: the check can fail)."""
    dry = ['events=[{at_s=0.3, action="sensor_fault", sensor="tpms_alarm_wheel", fault="bias", bias_index=1.0}]']
    assert _dev(*dry) <= none_m
    assert not (_dev(*dry, B + "reject_heading_return_flag=0") <= none_m)


def _at(speed_kph, frac, *extra):
    return _dev(f"run.initial_speed_kph={speed_kph}", f"driver.brake_pedal.frac=[0.0, 0.0, {frac}]", *extra)


@pytest.mark.parametrize("speed_kph,frac", [(80, 0.5), (100, 0.2)])
def test_faster_or_firmer_no_worse_than_none(speed_kph, frac):
    """The same false FR alarm at 80 km/h pedal 0.5 and 100 km/h pedal 0.2: the GMA (gma_rejected_split_flag) starts on
    FL but ABS HOLDS FL at its dry lock level (48 bar at 100 km/h), so the GMA's yaw limitation (OFF/BUILD only) never
    acts: 14.626 / 15.854 m vs 2.211 / 4.823 m without the function. gma_rejected_hold_dump_flag lets its yaw dump
    outrank the hold after a front rejection: 1.425 / 3.859 m."""
    assert _at(speed_kph, frac) <= _at(speed_kph, frac, B + "enabled_flag=0")


def test_seeded_defect_hold_dump_flag_zero_fails():
    """gma_rejected_hold_dump_flag = 0 (the code before that rule): 80 km/h pedal 0.5 is 14.626 m vs 2.211 m."""
    assert not (_at(80, 0.5, B + "gma_rejected_hold_dump_flag=0", B + "reject_heading_return_flag=0") <= _at(80, 0.5, B + "enabled_flag=0"))  # (J5)


def test_100kph_pedal_03_no_worse_than_none():
    """Was a strict xfail (I12, session i: 100 km/h pedal 0.3, FR on snow named, 3.736 m vs 2.633 m without the
    function); met since session j by reject_heading_return_flag (J5), which at 0 fails it again."""
    none = _at(100, 0.3, B + "enabled_flag=0")
    assert _at(100, 0.3) <= none
    assert not (_at(100, 0.3, B + "reject_heading_return_flag=0") <= none)
