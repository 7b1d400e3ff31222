"""The false-TPMS-alarm envelope (issue #10 'Faults': a false blowout detection must not pull the car off its
lane; data/envelopes/tire_blowout_false_alarm.toml). References: the overrides written out by hand from the
envelope file and the base scenario, and the lane bound 0.978 m = (3.75 m lane, JTG B01-2014 - 1.794 m BJ2500
width)/2 (data/requirements/tire_blowout.toml stay_in_lane, the shipped false-alarm check's bound). The known
breach is review RG2's grid point k=664 (findings_F.md 'RG2 (session g)', /tmp/rg2/ftp2.py): FR named, 120 km/h,
mu 0.55, left curve 1000 m, steering held, 300 N pedal from 0.5 s in 0.05 s; RG2 measured 1.483 m with the
compensation vs 0.401 m without."""
from __future__ import annotations

import pytest

from vehicle_assist.cli_verify import SHIPPED_ENVELOPES
from vehicle_assist.verification.envelope import load_envelope, shipped_envelopes
from vehicle_assist.verification.falsify import evaluate_points, twin_robustness
from vehicle_assist.verification.requirements import load_requirement_file

LANE_BOUND_M = (3.75 - 1.794) / 2  # JTG B01-2014 lane, BJ2500 width (cite:J2500)
RG2_664 = {"speed": 120, "mu": 0.55, "wheel": "fr", "curve": "r1000", "driver": "fixed", "braking": "brakes",
           "brake.start_s": 0.5, "brake.level_frac": 0.3, "brake.rate_per_s": 6.0}


@pytest.fixture(scope="module")
def env():
    return load_envelope("tire_blowout_false_alarm")


@pytest.fixture(scope="module")
def lane_req():
    return load_requirement_file("tire_blowout")["tire_blowout.stay_in_lane"]


@pytest.fixture(scope="module")
def rg2_point(env, lane_req):
    robs, _, _ = evaluate_points(env, lane_req, [RG2_664], workers=1)
    return robs[0], twin_robustness(env, lane_req, RG2_664)


def test_envelope_loads_with_sources_and_is_listed(env):
    assert env.model.base == "blowout_false_tpms_braking_60kph"
    assert "tire_blowout.stay_in_lane" in env.model.requirements
    for d in env.dims:
        assert len(d.source) > 20, d.name
    assert set(env.dim("wheel").options) == {"fl", "fr"}
    assert (env.dim("speed").lo, env.dim("speed").hi) == (40, 120)
    assert "tire_blowout_false_alarm" in shipped_envelopes()
    assert "tire_blowout_false_alarm" in [s.strip() for s in SHIPPED_ENVELOPES.split(",")]


def test_wheel_choice_names_the_wheel_and_no_blowout_happens(env):
    for wheel, index in (("fl", 1.0), ("fr", 2.0)):
        sc = env.scenario(dict(RG2_664, wheel=wheel))
        (ev,) = sc.model.events
        assert (ev.at_s, ev.sensor, ev.fault, ev.bias_index) == (1.0, "tpms_alarm_wheel", "bias", index)
        assert sc.model.vehicle.blowout["wheel_index"] == -1  # the base scenario's "no blowout"
    sets = env.sets(RG2_664, baseline=True)
    assert "driver.brake_pedal={time_s = [0.5, 0.55], frac = [0.0, 0.3]}" in sets  # RG2's pedal, by hand
    assert "vehicle.blowout_compensation.enabled_flag=0" in sets


def test_lane_requirement_can_fail_at_rg2_breach_and_the_twin_meets_it(rg2_point, lane_req):
    """The check can fail: at RG2 k=664 the compensated car leaves the lane (RG2: 1.483 m > 0.978 m) while the
    same false alarm without the function stays inside (0.401 m)."""
    assert "0.978" in lane_req.formula and abs(LANE_BOUND_M - 0.978) < 1e-3
    on, off = rg2_point
    assert on < 0, on
    assert off > 0, off


@pytest.mark.xfail(strict=True, reason="issue #10 Faults, review RG2 k=664: a false FR alarm at 120 km/h, mu 0.55, "
                   "1000 m curve, 300 N pedal pulls the compensated car 1.48 m off its lane; without the function "
                   "0.40 m (the function does not meet the false-alarm lane bound on this envelope)")
def test_false_alarm_keeps_the_car_in_its_lane_at_rg2_breach(rg2_point):
    on, _ = rg2_point
    assert on >= 0, on
