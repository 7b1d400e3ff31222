"""Paper 004's false-alarm ``reproduce`` campaign (procedures/blowout_study.py falsify_extra: CMA-ES seed 2026, budget 48,
batch 8, ``tire_blowout.stay_in_lane`` over data/envelopes/tire_blowout_false_alarm.toml; issue #10 'Faults': a false
blowout detection must not pull the car off its lane). Session i, I7 (tire_blowout_findings.md "I7 (session i)").

At main cc64ff5 the campaign FAILs with 16 violations in 48 points; at EVERY one of them the same false alarm without
the function (the envelope's twin, enabled_flag=0) leaves the lane as well, and by more (campaign #10, its first
counterexample: 1.285 m vs the twin's 1.481 m; #35, its worst: 2.143 vs 2.560 m). The points are braking at 96-120 km/h on
mu 0.30-0.49 in the 650 / 1000 m curve with the steering held: the car without the function drifts out of the curve -
physics of the scenario, not the false detection's doing. These checks hold the function to never worse than the twin
at those points (conventions.md 'Evidence'), and keep the absolute lane breach visible (the twin out of the lane).

References: the car without the function (same point, same false alarm) and the lane bound 0.978 m = (3.75 m lane,
JTG B01-2014 - 1.794 m BJ2500 width)/2 (data/requirements/tire_blowout.toml stay_in_lane) - not the code's formulas.
The seeded defect: gma_rejected_flag 0 (H2, session h: the re-applied front's ABS starts the GMA on the compensating
front after the rejection), as tests/verification/test_blowout_false_alarm_envelope.py."""
from __future__ import annotations

import numpy as np
import pytest

import vehicle_assist as va
from vehicle_assist.verification.envelope import load_envelope

LANE_BOUND_M = (3.75 - 1.794) / 2  # JTG B01-2014 lane, BJ2500 width (cite:J2500)
B = "vehicle.blowout_compensation."
# the campaign's points as the search wrote them (main cc64ff5, falsify ... --optimizer cma --seed 2026 -n 48 -b 8)
CMA8_10 = {"speed": 114.39976126715021, "mu": 0.4401978654716151, "brake.start_s": 2.1419487727391546,
           "brake.level_frac": 0.33201619689205286, "brake.rate_per_s": 4.117975668537231, "braking": "brakes",
           "wheel": "fr", "driver": "fixed", "curve": "r650"}
CMA8_35 = {"speed": 111.77001221134172, "mu": 0.3055391651557799, "brake.start_s": 1.8567357614727662,
           "brake.level_frac": 0.2600314374392143, "brake.rate_per_s": 11.56794617397983, "braking": "brakes",
           "wheel": "fr", "driver": "fixed", "curve": "r650"}
DEFECT = (B + "gma_rejected_flag=0", B + "reject_heading_return_flag=0")  # (J5, session j) isolated from reject_heading_return_flag, which also rescues this defect


@pytest.fixture(scope="module")
def env():
    return load_envelope("tire_blowout_false_alarm")


def _lane(res):
    return float(np.max(np.abs(res.to_pandas().lane_offset_m)))


def _runs(env, point):
    sc = env.scenario(point)
    return {"on": va.simulate(sc, requirements=False), "defect": va.simulate(sc.with_sets(*DEFECT), requirements=False),
            "none": va.simulate(env.scenario(point, baseline=True), requirements=False)}


@pytest.fixture(scope="module")
def first(env):
    return _runs(env, CMA8_10)


@pytest.fixture(scope="module")
def worst(env):
    return _runs(env, CMA8_35)


def _rejected(res):
    return [x for x in res.events if x.machine == "blowout_compensation" and x.to_mode == "REJECTED"]


@pytest.mark.parametrize("which", ["first", "worst"])
def test_campaign_point_is_a_rejected_false_detection(which, request):
    """The points exercise the false alarm: a TPMS-only detection of the healthy FR under the driver's brake, rejected."""
    runs = request.getfixturevalue(which)
    assert _rejected(runs["on"]), which
    assert not [x for x in runs["none"].events if x.machine == "blowout_compensation"]


@pytest.mark.parametrize("which", ["first", "worst"])
def test_campaign_breach_is_the_twins_too(which, request):
    """The absolute lane bound is broken by the car WITHOUT the function at the campaign's counterexamples (measured
    1.481 / 2.560 m): the campaign's FAIL is the scenario's physics (braking, steering held, low mu, 650 m curve)."""
    runs = request.getfixturevalue(which)
    assert _lane(runs["none"]) > LANE_BOUND_M, _lane(runs["none"])


@pytest.mark.parametrize("which", ["first", "worst"])
def test_false_detection_does_not_pull_the_car_further_off_its_lane(which, request):
    """Never worse than the same false alarm without the function (conventions.md 'Evidence'; issue #10 'Faults': the
    false detection must not pull the car off its lane): measured 1.285 vs 1.481 m (#10), 2.143 vs 2.560 m (#35).
    Fails with the seeded defect (gma_rejected_flag 0) - see test_seeded_defect_is_worse_than_the_twin."""
    runs = request.getfixturevalue(which)
    assert _lane(runs["on"]) <= _lane(runs["none"]), (_lane(runs["on"]), _lane(runs["none"]))


def test_seeded_defect_is_worse_than_the_twin(first, worst):
    """The never-worse check can fail: with gma_rejected_flag 0 the false detection pulls the car further off its lane
    than the twin at at least one of the two points."""
    assert max(_lane(r["defect"]) - _lane(r["none"]) for r in (first, worst)) > 0.0, \
        [(_lane(r["defect"]), _lane(r["none"])) for r in (first, worst)]
