"""Known limits of two ESP rules, recorded as strict xfails (each turns into an XPASS failure once fixed).

1. GMA follow during HBA (``vehicle.esp.gma_follow_flag``, 773586b) on a dry/wet split (80/100 km/h pass since the rear
   select-low on pressure, ``vehicle.esp.hba_rear_select_low_flag``; 140 km/h still a strict xfail). Criterion: the
   ``brake_assist.no_worse_heading`` requirement (src/vehicle_assist/data/requirements/brake_assist.toml; source:
   issue #9 and conventions.md 'Evidence', never worse than no assist): largest heading deviation with HBA <= that of
   the same stop with HBA off (``vehicle.brake_assist.enabled_flag=0``, as the shipped twin comparisons), floor 0.1 deg.
2. (fixed, now a passing test with its seeded defect) Reference-speed plausibility while braking (``vehicle.esp.reference_braking_plausibility_flag``, 968b8ea) with a
   longitudinal accelerometer that over-reads deceleration by 1.4 m/s^2 (stands in for a downhill: the sedan plant
   ignores road.slope_deg) on an ice-like road. Criterion: brake_assist.md 8 criterion 5 (no wheel lock: every wheel
   slip < 0.5 for v > 15 km/h except transients shorter than 0.15 s; metric ``wheel_lock_time_max_s``).

The bounds come from the requirement row and the spec, never from these runs; the measured numbers are in the reasons.
"""
from __future__ import annotations

import pytest

import vehicle_assist as va

SPLIT = "hba_split_mu_80kph"
HEADING_FLOOR_DEG = 0.1  # brake_assist.toml no_worse_heading: floor 0.1 deg (one GMA step, issue #9 review)
LOCK_TRANSIENT_MAX_S = 0.15  # brake_assist.md 8 criterion 5: lock transients shorter than 0.15 s

GMA_REASON = (
    "known limit of GMA follow (esp.gma_follow_flag, 773586b) on dry/wet split, no noise: heading max with HBA vs "
    "without 8.19 vs 0.18 deg at 140 km/h (steering 58 vs 1.5 deg; 80 km/h fixed by the rear select-low, test below); "
    "without HBA the driver's 60 bar never reaches the wet front's ABS level (no ABS, no yaw); with HBA both fronts are "
    "pumped to ~72-76 bar, the dry front follows the wet one up and is held at 74 bar (R_GMA_HOLD ratchet) while the wet "
    "one cycles at 49-76 bar: heading +4.1 deg at 2.25 s, then the driver model's counter-steer (-33 deg) overshoots "
    "to -8.1 deg at 4 s; the rears are equal there (70-83 bar, both pumped), so the rear select-low does not change it; "
    "HBA was already worse than no HBA here before gma_follow (6.43 deg at 140 km/h)")


def _dry_wet_split_pair(speed_kph: float):
    sets = ['vehicle.surface.left="dry"', 'vehicle.surface.right="wet"', f"run.initial_speed_kph={speed_kph}"]
    on, off = va.simulate_batch([va.load_scenario(SPLIT, sets=sets),
                                 va.load_scenario(SPLIT, sets=[*sets, "vehicle.brake_assist.enabled_flag=0"])]).metrics
    return on, off


@pytest.mark.xfail(strict=True, reason=GMA_REASON)
@pytest.mark.parametrize("speed_kph", [140])
def test_gma_follow_dry_wet_split_hba_heading_not_worse(speed_kph):
    on, off = _dry_wet_split_pair(speed_kph)
    assert on["hba_activated_flag"] == 1.0  # the assist ran (else the comparison says nothing)
    assert on["heading_max_deg"] <= max(HEADING_FLOOR_DEG, off["heading_max_deg"]), (
        on["heading_max_deg"], off["heading_max_deg"])


REAR_DEFECT = "vehicle.esp.hba_rear_select_low_flag=0"  # seeded defect: each rear pumped with its circuit's front
# the ABS hold's time limit (esp.abs_hold_limit_flag, session i I5) steps the over-pumped dry rear down and hides the
# defect (80 km/h: 1.79 vs 2.27 deg with it, 3.15 without): the negative control runs on the ABS before that rule
HOLD_RULE_OFF = "vehicle.esp.abs_hold_limit_flag=0"


@pytest.mark.parametrize("speed_kph", [80, 100])
def test_dry_wet_split_hba_heading_not_worse_with_rear_select_low(speed_kph):
    """Dry/wet split at 80 and 100 km/h: with the rear select-low on pressure during the pump build
    (``esp.hba_rear_select_low_flag``) the HBA stop's heading is not worse than without HBA (no_worse_heading, floor
    0.1 deg; measured 80 km/h 1.36 vs 2.27 deg, 100 km/h 2.37 vs 4.48). With the seeded defect the X-split pumps the
    dry rear (RL, the wet front's circuit) to 86-89 bar against 65-75 on the wet rear and the 80 km/h stop is worse
    than none (3.15 vs 2.27 deg), so the check can fail there."""
    on, off = _dry_wet_split_pair(speed_kph)
    assert on["hba_activated_flag"] == 1.0
    assert on["heading_max_deg"] <= max(HEADING_FLOOR_DEG, off["heading_max_deg"]), (
        on["heading_max_deg"], off["heading_max_deg"])
    if speed_kph == 80:  # negative control
        sets = ['vehicle.surface.left="dry"', 'vehicle.surface.right="wet"', f"run.initial_speed_kph={speed_kph}",
                REAR_DEFECT, HOLD_RULE_OFF]
        bad = va.simulate(va.load_scenario(SPLIT, sets=sets)).metrics
        assert bad["heading_max_deg"] > max(HEADING_FLOOR_DEG, off["heading_max_deg"]), (
            bad["heading_max_deg"], off["heading_max_deg"])


# Was a strict xfail (known limit of 968b8ea): a wheel locked 0.49 s with the rule vs 0.0 s without (bound 0.15 s); a
# reference drifted low could not rise back (rise limit a_x,meas + 2 m/s^2 while braking) and RL, the wheel nearest the
# true speed, was left out (its own ABS mode off while the rear select-low released it), so the other three locked.
# Fixed by esp.braking_outlier (reference_braking_outlier_flag): only a lone (> 8 % above the second fastest),
# valve-quiet fast wheel is rise-bounded and left out; 0 = the seeded defect (the 968b8ea rule).
OUTLIER_DEFECT = "vehicle.esp.reference_braking_outlier_flag=0"


def _ice60(flag: int):
    sets = ['vehicle.surface.left="dry"', 'vehicle.surface.right="dry"', "road.friction_mu=0.15",
            "sensors.longitudinal_accel.bias_mps2=-1.4", "run.seed=1",
            f"vehicle.esp.reference_braking_plausibility_flag={flag}"]
    sets += [f"sensors.wheel_speed_{w}.noise_std_radps=0.2" for w in ("fl", "fr", "rl", "rr")]
    return va.load_scenario("hba_snow_60kph", sets=sets)


def test_braking_plausibility_ice_with_accel_bias_no_wheel_lock():
    """ice60 with the a_x sensor over-reading deceleration by 1.4 m/s^2: with the braking plausibility on, no wheel
    locks longer than criterion 5 allows (measured 0.0 s); with the seeded defect (the 968b8ea rule) a wheel locks
    (measured 0.49 s), so the check can fail."""
    on, defect = va.simulate_batch([_ice60(1), _ice60(1).with_sets(OUTLIER_DEFECT)]).metrics
    assert on["wheel_lock_time_max_s"] <= LOCK_TRANSIENT_MAX_S, on["wheel_lock_time_max_s"]
    assert on["wheel_stopped_moving_flag"] == 0.0
    assert defect["wheel_lock_time_max_s"] > LOCK_TRANSIENT_MAX_S, defect["wheel_lock_time_max_s"]  # negative control


def test_ice_with_accel_bias_without_braking_plausibility_no_wheel_lock():
    """Control for the xfail above: the same run with the rule off keeps lock within criterion 5 (measured 0.0 s),
    so the rule, not the road or the sensor bias alone, causes the lock."""
    m = va.simulate(_ice60(0)).metrics
    assert m["wheel_lock_time_max_s"] <= LOCK_TRANSIENT_MAX_S, m["wheel_lock_time_max_s"]
    assert m["wheel_stopped_moving_flag"] == 0.0
