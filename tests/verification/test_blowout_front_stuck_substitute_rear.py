"""A FRONT blowout whose opposite front's inlet is stuck closed: LIMITED on the substitute REAR and the blown side's
rear held at no more than the substitute (``blowout_compensation.front_substitute_rear_flag``, session 2026-11-24 l,
task L2; tire_blowout_findings.md "L2 (session l)", status k item 1; K2's rule for a blown rear, mirrored).

With the opposite front's inlet stuck the compensation brakes the rear on the other side of the car (``_substitute``:
FL blown -> RR; limit code 1). Both fronts are then unbraked (the blown one released, the other stuck) and the car
brakes on its rears alone. Without the function the ESP's rear select-low keeps both rears at one pressure; with it the
substitute is the compensation's wheel and bypasses the select-low, and the blown side's rear took the driver's / HBA
pump pressure above the substitute. K1's fault envelope, lead's set f_r3 (random 3 -n 64) #24: FL blown, FR stuck,
braking (panic pedal at 1.57 s), straight, lane follower, 117 km/h, mu 0.668: RL 80 bar against the substitute RR's 65,
yaw toward FL 0.29 rad/s, refused at 2.4 s (limit code 3) and spun: 19.585 m against the twin's 13.684 m.

References, independent of the function's code: requirement tire_blowout.no_worse_than_no_compensation with the SAME
fault in both cars (the twin: the car without compensation, paper 004 Fig. 4 curve 2); the ESP's rear select-low (the
twin's rears carry one pressure: no rear-axle yaw moment). Flag 0 = the code before = the seeded defect.
"""
from __future__ import annotations

import numpy as np
import pytest

from vehicle_assist.verification.envelope import load_envelope
from tests.support import envelope_point_run

METRIC = "blowout_lateral_deviation_run_max_m"
DEFECT = ("vehicle.blowout_compensation.front_substitute_rear_flag=0",)  # the code before
LIMIT_OTHER_AXLE = 1  # blowout_limit_code: the opposite inlet stuck, the other axle's wheel brakes (issue #10 'Faults')
# /tmp/lead/l/base/f_r3/falsify.json history #24 (tire_blowout_faults, random 3 -n 64 -b 64)
P24 = {"speed": 116.9448308991426, "mu": 0.6678977319661067, "delay": 0.2199934626891463,
       "wheel_speed_noise": 0.14086904803366992, "noise_seed": 2723.0, "brake_gain": 0.9937423289360476,
       "accumulator": 56.41183888047423, "brake.start_s": 1.569214634733117, "brake.level_frac": 0.45503709798857306,
       "brake.rate_per_s": 15.19880565202063, "braking": "brakes", "wheel": "fl", "driver": "follow",
       "curve": "straight", "fault": "inlet_stuck_fr"}
PAIR_MARGIN_PA = 3.0e5  # the rule's 1-bar dump margin plus one period of the pump's build (plant pressure, not the ECU's)


_run = envelope_point_run  # tests/support.py


@pytest.fixture(scope="module")
def runs():
    env = load_envelope("tire_blowout_faults")
    return {"on": _run(env, P24), "defect": _run(env, P24, sets=DEFECT), "none": _run(env, P24, baseline=True)}


def test_24_goes_limited_on_the_substitute_rear(runs):
    """The case this file is about: LIMITED on the other axle (limit code 1) in both variants."""
    for k in ("on", "defect"):
        codes = np.asarray(runs[k].trace["blowout_limit_code"])
        assert np.any(codes == LIMIT_OTHER_AXLE), k


def test_24_front_stuck_never_worse_than_without_compensation(runs):
    """Requirement no_worse_than_no_compensation with the same fault in both cars (rollback_floor_m 0: the function's run
    max <= the twin's; measured 3.041 vs 13.684 m)."""
    on, none = runs["on"].metrics[METRIC], runs["none"].metrics[METRIC]
    assert on <= none, (on, none)


# Session o (O3): the strict xfail test_24_defect_is_worse_than_without_compensation (N5 class C: judged to standstill
# the code before and the twin both spin off the road, the code before 0.175 s AFTER the twin, earliness 27.855 vs
# 28.030 s) is replaced by the negative control at f_r11 #36 below (tests test_36_*), where the code before leaves the
# road and the twin does not.


def _rear_pair_excess(r):
    """Largest plant pressure of the blown side's rear (RL) above the substitute (RR) over the LIMITED code-1 samples
    while the pedal is applied: the rear axle's brake moment toward the blown side (the select-low keeps it <= 0)."""
    code = np.asarray(r.trace["blowout_limit_code"])
    pedal = np.asarray(r.trace["brake_pedal_frac"])
    k = (code == LIMIT_OTHER_AXLE) & (pedal > 0.0)
    assert k.any(), "no braking LIMITED sample"
    return float(np.max(np.asarray(r.trace["wheel_pressure_rl_pa"])[k] - np.asarray(r.trace["wheel_pressure_rr_pa"])[k]))


def test_24_blown_side_rear_not_above_the_substitute(runs):
    """The mechanism: in LIMITED on the substitute RR while the driver brakes, RL never carries more than RR (+ the
    rule's 1-bar margin and one pump period); at flag 0 RL was pumped 15 bar above RR (80 vs 65 bar)."""
    on = _rear_pair_excess(runs["on"])
    assert on <= PAIR_MARGIN_PA, on / 1e5
    defect = _rear_pair_excess(runs["defect"])
    assert defect > PAIR_MARGIN_PA, defect / 1e5


# Review RL3 (session l): the four tests above pin only the select-low cap. Mutants of front_substitute_rear that all
# passed them (measured, tire_blowout_findings.md RL3): the release removed (cap only), the release's yaw sign flipped,
# the curve gate's sign flipped, the phase-plane gate removed. The points below (the lead's fault sets, same envelope,
# fault from t = 0) check the same requirement (never worse than the twin with the same fault) where the release and its
# gates decide it. Robustness = twin - function (m).
# /tmp/lead/l/base/f_r3 #54: FL blown, FR stuck, straight, follower, 115 km/h, mu 0.496, pedal 1.19 s.
# function 2.886, twin 11.098; flag 0 16.621; cap only / release sign flipped 14.623.
P54 = {"speed": 114.77901331020196, "mu": 0.49620532691536845, "delay": 0.41217318486205834,
       "wheel_speed_noise": 0.19436911490554884, "noise_seed": 5142.0, "brake_gain": 0.9516392694334314,
       "accumulator": 119.35489890948396, "brake.start_s": 1.1914718996572977, "brake.level_frac": 0.2295889228305815,
       "brake.rate_per_s": 14.248644218260972, "braking": "brakes", "wheel": "fl", "driver": "follow",
       "curve": "straight", "fault": "inlet_stuck_fr"}
# /tmp/lead/l/base/f_r41 #309: FR blown, FL stuck, LEFT curve r1000 (steered AWAY from the blown side: the curve gate
# must let the release act), fixed steering, 103 km/h, mu 0.346. function 10.159, twin 10.930; flag 0 13.690; cap only /
# release sign flipped / curve gate's sign flipped 14.255.
P309 = {"speed": 102.89808906865272, "mu": 0.34636769643824644, "delay": 0.10000285925191393,
        "wheel_speed_noise": 0.268374503562595, "noise_seed": 3463.0, "brake_gain": 1.1776525537535614,
        "accumulator": 73.32034036713664, "brake.start_s": 0.8633359241460539, "brake.level_frac": 0.22241549299725005,
        "brake.rate_per_s": 1.4101702693199711, "braking": "brakes", "wheel": "fr", "driver": "fixed",
        "curve": "r1000", "fault": "inlet_stuck_fl"}
# /tmp/lead/l/base/f_r41 #459: FR blown, FL stuck, r650, fixed, 110 km/h, mu 0.303 (L2's phase-plane gate point).
# function 13.373, twin 13.456 (margin 0.083 m); without the phase-plane gate 14.223; flag 0 13.343 (passes: this one
# guards the gate, it is not a flag-0 negative control).
P459 = {"speed": 110.47107304299398, "mu": 0.3025390669435406, "delay": 0.33770351071126803,
        "wheel_speed_noise": 0.1620515628980955, "noise_seed": 5861.0, "brake_gain": 0.8225244736553101,
        "accumulator": 113.93599389892722, "brake.start_s": 0.6948995801046896, "brake.level_frac": 0.1624648777712299,
        "brake.rate_per_s": 28.40120964129963, "braking": "brakes", "wheel": "fr", "driver": "fixed",
        "curve": "r650", "fault": "inlet_stuck_fl"}


@pytest.fixture(scope="module")
def env():
    return load_envelope("tire_blowout_faults")


@pytest.mark.parametrize("point", [P54, P309, P459], ids=["f_r3_54", "f_r41_309", "f_r41_459"])
def test_release_and_gates_never_worse_than_without_compensation(env, point):
    """The yaw limitation (the blown side's rear released beyond esp.yaw_dump_rate toward the blown side) and its two
    gates, through the requirement: the function's run max <= the twin's (same fault). Session n (N1): both rows of
    the requirement (never_worse_rows), the run judged to standstill."""
    from tests.support import never_worse_rows

    rows = never_worse_rows(_run(env, point), _run(env, point, baseline=True))
    assert min(rows.values()) >= 0.0, rows


@pytest.mark.parametrize("point", [P54, P309], ids=["f_r3_54", "f_r41_309"])
def test_release_points_defect_is_worse_than_without_compensation(env, point):
    """Negative control: the code before (flag 0) fails the same check at these two points (16.621 > 11.098,
    13.690 > 10.930). Session n (N1, class C corrected): judged to standstill every car at #309 and the code before and
    the twin at #54 leave the road (run max #309 48.190 vs 50.688 m, beyond the road edge: not ranked), so the same
    check is both rows (never_worse_rows): the code before leaves the road 0.015 s (#54) / 0.050 s (#309) before the
    twin - worse in row no_earlier_road_departure."""
    from tests.support import never_worse_rows

    rows = never_worse_rows(_run(env, point, sets=DEFECT), _run(env, point, baseline=True))
    assert min(rows.values()) < 0.0, rows


# ---- Session o (O3): the negative control under both rows, judged to standstill (tire_blowout_findings.md O3) ------
# The lead's f_r11 #36 (/tmp/lead/n/fin2 and fin2d; faults_t0 = tire_blowout_faults at fault_time 0, random 11 -n 64):
# FL blown, FR inlet stuck from t = 0, 49 km/h, mu 0.472, LEFT curve r650 (steered toward the blown side: the curve
# gate keeps the cap, no release), fixed steering, pedal 0.08 from 1.08 s. Measured at main 8594568 (pt.py):
#   flag 0 (the code before): RL 75.6 / 64.1 / 90.1 bar at 2 / 3 / 4 s against the substitute RR's 35.3 / 30.0 / 39.5,
#     yaw 0.22-0.25 rad/s toward FL, off the road 2.63 s after the blowout (earliness 27.370 s; unclipped 7.479 m),
#   shipped (2): RL 38.6 vs RR 36.7 bar, yaw 0.06 rad/s, on the road, stopped at 7.4 s: road deviation 3.419 m,
#   twin (no compensation, same fault): rear pair 39.5 / 39.5 bar (select-low), on the road: 3.028 m.
# Rows (robustness, twin - car): flag 0 row 1 -0.950 m (3.978 clipped vs 3.028), row 2 -27.370 s;
# shipped row 1 -0.391 m (an OPEN violation of the lead's baseline, fin2 f_r11), row 2 0.
P36 = {"speed": 48.61740545445764, "mu": 0.4721419073362476, "delay": 0.25053936709436814,
       "wheel_speed_noise": 0.14048247633898747, "noise_seed": 6193.0, "brake_gain": 0.8364015188479235,
       "accumulator": 110.4314499140652, "brake.start_s": 1.076657532163613, "brake.level_frac": 0.08032469512861332,
       "brake.rate_per_s": 10.486333006074556, "braking": "brakes", "wheel": "fl", "driver": "fixed", "curve": "r650",
       "fault": "inlet_stuck_fr", "fault_time": 0.0}


@pytest.fixture(scope="module")
def runs36(env):
    return {"on": _run(env, P36), "defect": _run(env, P36, sets=DEFECT), "none": _run(env, P36, baseline=True)}


def test_36_defect_leaves_the_road_the_twin_stays_on(runs36):
    """Negative control (replaces N5's strict xfail at #24): the code before (flag 0) fails row
    no_earlier_road_departure - it leaves the road 2.63 s after the blowout where the twin, with the same fault, stays on
    it (row 2 -27.370 s; row 1 -0.950 m). Both rows of the requirement (tests/support.never_worse_rows)."""
    from tests.support import never_worse_rows

    rows = never_worse_rows(runs36["defect"], runs36["none"])
    assert rows["no_earlier_road_departure"] < 0.0, rows
    assert rows["no_worse_than_no_compensation"] < 0.0, rows


def test_36_rule_keeps_the_car_on_the_road(runs36):
    """The rule passes the row its defect fails: no earlier road departure than the twin (0: both on the road; flag 0:
    -27.370 s, so this assertion fails at the defect value). Row 1 is NOT claimed: the shipped car deviates 3.419 m
    against the twin's 3.028 m (-0.391 m, an open violation of the lead's baseline); asserted only that the rule is
    better than its defect there (-0.391 vs -0.950 m: the defect is off the road)."""
    from tests.support import never_worse_rows

    on = never_worse_rows(runs36["on"], runs36["none"])
    defect = never_worse_rows(runs36["defect"], runs36["none"])
    assert on["no_earlier_road_departure"] >= 0.0, on
    assert on["no_worse_than_no_compensation"] > defect["no_worse_than_no_compensation"], (on, defect)


LIMITED_MODE = 3  # blowout_mode_index of LIMITED (functions/blowout_compensation.py: IDLE, BUILD, HOLD, LIMITED, ...)


def _rear_pair_excess_limited(r):
    """MEDIAN plant pressure of the blown side's rear (RL) above the substitute (RR) over the samples in mode LIMITED,
    limit code 1, pedal applied. Mode LIMITED only: at #36 the limit code stays 1 after the compensation has ENDED
    (vehicle slow, the last second before standstill), where the rule no longer acts. The median, not the max: at #36
    the rule's 1-bar dump and the pump's build alternate in a 25-ms sawtooth on RL (38.6, 39.4, 44.4, 37.7, 38.2 bar
    against RR's 36.7 for 3.8 s; peak 7.7 bar above RR, one pump period's build here ~5 bar where #24's was < 2); the
    median is the level the rule holds (measured +1.9 bar; flag 0: RL at the pump's 64-90 bar)."""
    code = np.asarray(r.trace["blowout_limit_code"])
    mode = np.asarray(r.trace["blowout_mode_index"])
    pedal = np.asarray(r.trace["brake_pedal_frac"])
    k = (code == LIMIT_OTHER_AXLE) & (mode == LIMITED_MODE) & (pedal > 0.0)
    assert k.any(), "no braking LIMITED sample"
    return float(np.median(np.asarray(r.trace["wheel_pressure_rl_pa"])[k]
                           - np.asarray(r.trace["wheel_pressure_rr_pa"])[k]))


def test_36_blown_side_rear_not_above_the_substitute(runs36):
    """The mechanism at #36 is the rule's reason: in LIMITED code 1 with the pedal the blown side's rear (RL) is held at
    no more than the substitute RR (+ the 1-bar margin and one pump period; median, see the helper); at flag 0 it took
    the pump's pressure, ~50 bar above RR (90.1 vs 39.5 bar at 4 s), and yawed the car toward FL off the road."""
    on = _rear_pair_excess_limited(runs36["on"])
    assert on <= PAIR_MARGIN_PA, on / 1e5
    defect = _rear_pair_excess_limited(runs36["defect"])
    assert defect > PAIR_MARGIN_PA, defect / 1e5


# O3's targeted search on the rule's premise, right-hand curves (a FRONT blown, the other front's inlet stuck, braking):
# falsify tire_blowout_faults_right -r <row> --optimizer random --seed 613 -n 128 -b 64 -R wheel=fl,fr
# -R fault=inlet_stuck_fl,inlet_stuck_fr -R braking=brakes -R fault_time=0..1, #23: FL blown, FR stuck at 0.13 s,
# RIGHT curve rr1000 (steered AWAY from the blown side: the release acts), lane follower, 53 km/h, mu 0.345, pedal 0.10
# from 0.76 s. Measured at main 8594568 (pt.py): flag 0: RL 59.8-79.2 bar against the substitute RR's 36-42 bar from
# 1.5 s to 5.5 s, 1.374 m; shipped: RL released to 1.9 bar at 1.5 s, then <= RR (26.7 vs 35.8 bar at 2 s), 0.595 m;
# twin (same fault, rear select-low 32-43 bar): 1.211 m. All on the road. Rows (twin - car): flag 0 row 1 -0.164 m,
# row 2 0; shipped row 1 +0.615 m, row 2 0 - a control where the shipped rule passes BOTH rows.
P23R = {"speed": 53.1719253025549, "mu": 0.3452102892403405, "delay": 0.3509857197166382,
        "wheel_speed_noise": 0.22975422421378303, "noise_seed": 9687.0, "brake_gain": 0.8277590146746252,
        "accumulator": 61.594901424201005, "fault_time": 0.1303385246488744, "brake.start_s": 0.7564491989150415,
        "brake.level_frac": 0.09539235681725507, "brake.rate_per_s": 12.090429360039037, "braking": "brakes",
        "wheel": "fl", "driver": "follow", "curve": "rr1000", "fault": "inlet_stuck_fr"}


@pytest.fixture(scope="module")
def runs23r():
    e = load_envelope("tire_blowout_faults_right")
    return {"on": _run(e, P23R), "defect": _run(e, P23R, sets=DEFECT), "none": _run(e, P23R, baseline=True)}


def test_23r_defect_is_worse_than_without_compensation(runs23r):
    """Negative control, right-hand curve: the code before (flag 0) is worse than the twin with the same fault in row
    no_worse_than_no_compensation, all cars on the road (1.374 vs 1.211 m, -0.164 m)."""
    from tests.support import never_worse_rows

    rows = never_worse_rows(runs23r["defect"], runs23r["none"])
    assert min(rows.values()) < 0.0, rows


def test_23r_never_worse_than_without_compensation(runs23r):
    """The rule passes both rows there (0.595 vs 1.211 m, no departure; flag 0: row 1 -0.164 m, so this assertion
    fails at the defect value)."""
    from tests.support import never_worse_rows

    rows = never_worse_rows(runs23r["on"], runs23r["none"])
    assert min(rows.values()) >= 0.0, rows


def test_23r_blown_side_rear_not_above_the_substitute(runs23r):
    """Mechanism: in LIMITED code 1 with the pedal the blown side's rear (RL) is held at no more than the substitute RR
    (median, + the 1-bar margin and one pump period); at flag 0 the pump lifts it 20-37 bar above RR."""
    on = _rear_pair_excess_limited(runs23r["on"])
    assert on <= PAIR_MARGIN_PA, on / 1e5
    defect = _rear_pair_excess_limited(runs23r["defect"])
    assert defect > PAIR_MARGIN_PA, defect / 1e5
