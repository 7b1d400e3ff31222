"""A false TPMS alarm on a SPLIT-mu road while the driver brakes (review RH1, session h; functions/esp.py GMA,
``gma_rejected_flag`` / ``gma_rejected_pre_flag``). Neither the tire_blowout nor the false-alarm envelope varies the
friction left/right, so the falsifier cannot reach this case.

Point: the shipped false-alarm scenario (blowout_false_tpms_braking_60kph) on the SUV's split surface (left dry, right
snow), 80 km/h, pedal 0.3 from 0.55 s, the lane keeper following, the TPMS naming FR (the snow side) from 1.0 s. The car
without the function stops on split-mu with the ESP's yaw-moment build-up delay (GMA) on the dry FL (Bosch Automotive
Handbook: the GMA delays the high-mu front of a split-mu stop): FL ~9-11 bar in 1.1-1.8 s. The function detects FR
(1.05 s), which ends that GMA (gma_blown_front_flag), and rejects the detection at 1.125 s (yaw_implausible). H2's
gma_rejected_flag then ignored FR's ABS activity for the GMA - activity that had started the GMA before the function
acted: FL went to 47 bar against FR's 7-13 bar, 3.503 m (before gma_rejected_flag 2.624 m; none 1.888 m).

References: the car without the function (its GMA on FL, its deviation) - not the code's own formula."""
from __future__ import annotations

import numpy as np
import pytest

import vehicle_assist as va

B = "vehicle.blowout_compensation."
DEV = "blowout_lateral_deviation_run_max_m"
POINT = ["vehicle.surface.left=dry", "vehicle.surface.right=snow", "run.initial_speed_kph=80",
         "driver.brake_pedal.frac=[0.0, 0.0, 0.3]", "vehicle.lane_keeper.steering_mode=follow",
         'events=[{at_s=1.0, action="sensor_fault", sensor="tpms_alarm_wheel", fault="bias", bias_index=2.0}]']


def _run(*extra):
    sc = va.load_scenario("blowout_false_tpms_braking_60kph").with_sets(*POINT, *extra)
    return va.simulate(sc, requirements=False)


@pytest.fixture(scope="module")
def runs():
    # the defect row isolated from I12's gma_rejected_split_flag (session i), which alone takes the pre-defect's 3.503 m to
    # 2.893 m here (FR's lock level ~1/4 of FL's after the rejection also starts the GMA, later than the pre rule)
    # and from J6's rejected_hold_limit_flag (session j: with the counter-steer the steered reference is a curve, its hold
    # limit dumps the defect's held FL: 46.5 -> 44.3 bar; the shipped row is unchanged, 29.3 bar)
    return {"on": _run(), "defect": _run(B + "gma_rejected_pre_flag=0", B + "gma_rejected_split_flag=0",
                                         B + "rejected_hold_limit_flag=0"),
            "none": _run(B + "enabled_flag=0")}


def _t_rejected(res):
    ts = [x.time_s for x in res.events if x.machine == "blowout_compensation" and x.to_mode == "REJECTED"]
    return ts[0] if ts else None


def _mean_fl_bar(res, t0, t1):
    df = res.to_pandas()
    w = df[(df.time_s >= t0) & (df.time_s <= t1)]
    return float(np.mean(w.wheel_pressure_fl_pa)) / 1e5


def test_point_exercises_a_rejected_detection(runs):
    for key in ("on", "defect"):
        assert _t_rejected(runs[key]) is not None, key
    assert _t_rejected(runs["none"]) is None


def test_dry_front_held_as_without_the_function_after_the_rejection(runs):
    """In the second after the rejection the dry FL's mean pressure is nearer the car without the function's (its GMA
    on FL) than the seeded defect's (gma_rejected_pre_flag 0: no GMA, FL at the driver's ~47 bar). Fails with the
    flag at 0 (the defect is the code under test then). Measured: 29.3 bar vs none 13.7, defect 46.5."""
    t0 = _t_rejected(runs["on"])
    on, defect, none = (_mean_fl_bar(runs[k], t0, t0 + 1.0) for k in ("on", "defect", "none"))
    assert abs(on - none) < abs(defect - none) / 2, (on, defect, none)


def test_rejection_on_split_mu_no_worse_than_before_the_gma_rejected_rule(runs):
    """Deviation: with the rule 2.624 m; the seeded defect 3.503 m (none 1.888)."""
    assert runs["on"].metrics[DEV] < runs["defect"].metrics[DEV] - 0.3, (runs["on"].metrics[DEV],
                                                                          runs["defect"].metrics[DEV])


@pytest.mark.xfail(strict=True, reason="open (review RH1): the false FR detection on split-mu still costs 2.624 m vs "
                   "1.888 m without the function - the 35 ms release of FR / build of FL before the rejection and the "
                   "GMA ended at the detection (FL 40 bar at 1.3-1.5 s vs the twin's 9); not fixed here")
def test_false_alarm_on_split_mu_no_worse_than_none(runs):
    assert runs["on"].metrics[DEV] <= runs["none"].metrics[DEV]
