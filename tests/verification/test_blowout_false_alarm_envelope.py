"""The false-TPMS-alarm envelope (issue #10 'Faults': a false blowout detection must not pull the car off its
lane; data/envelopes/tire_blowout_false_alarm.toml). References: the overrides written out by hand from the
envelope file and the base scenario, and the lane bound 0.978 m = (3.75 m lane, JTG B01-2014 - 1.794 m BJ2500
width)/2 (data/requirements/tire_blowout.toml stay_in_lane, the shipped false-alarm check's bound). The known
breach is review RG2's grid point k=664 (tire_blowout_findings.md 'RG2 (session g)', /tmp/rg2/ftp2.py): FR named, 120 km/h,
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


# --- H2 (session h): the GMA started on the compensating front by the rejected front's re-apply -------------------
# CMA-ES seed 2026 (reproduce 004's fifth campaign, --keep-going) #25, the point as the search wrote it
# (/tmp/h2/b_fc2026/falsify.json; tire_blowout_findings.md 'H2 (session h)'): FR named, 107.2 km/h, mu 0.527, 650 m left curve,
# steering held, pedal 0.25 (250 N) from 2.07 s at 2.53 /s. At main 4718b3b the compensated car left the lane
# (2.131 m) while the same false alarm without the function stayed inside (0.346 m).
CMA25 = {"speed": 107.1759783711669, "mu": 0.5273353045859637, "brake.start_s": 2.067207842978096,
         "brake.level_frac": 0.25018473421253884, "brake.rate_per_s": 2.533172798691344, "braking": "brakes",
         "wheel": "fr", "driver": "fixed", "curve": "r650"}
DEV = "blowout_lateral_deviation_run_max_m"
GMA_REJECTED_OFF = "vehicle.blowout_compensation.gma_rejected_flag=0"


@pytest.fixture(scope="module")
def cma25(env):
    import vehicle_assist as va

    def dev(sets=(), baseline=False):
        sc = env.scenario(CMA25, baseline=baseline)
        return va.simulate(sc.with_sets(*sets) if sets else sc, requirements=False)
    return {"on": dev(), "defect": dev((GMA_REJECTED_OFF, "vehicle.blowout_compensation.reject_heading_return_flag=0")), "none": dev(baseline=True)}


def test_cma25_false_alarm_is_rejected_while_braking(cma25):
    """The point exercises the rule: a TPMS-only detection of the healthy FR under the driver's brake, rejected
    (not a run where the function never acts)."""
    for key in ("on", "defect"):
        ev = [(x.to_mode, x.reason) for x in cma25[key].events if x.machine == "blowout_compensation"]
        assert ("BUILD", "blowout_detected") in ev, (key, ev)
        assert any(m == "REJECTED" for m, _ in ev), (key, ev)


def test_cma25_stays_in_lane_with_gma_rejected_rule(env):
    """gma_rejected_flag: after the rejection the re-applied FR's ABS activity does not start the GMA on FL (the
    compensating front); the car stays inside the lane bound (JTG B01-2014 lane, BJ2500 width), as the car without
    the function does. Fails with the flag at 0 (the GMA dumps FL to ~16 bar and holds it against FR's ~46 bar).
    Judged over the first 5 s, the window H2 judged (session n runs braking points to standstill: see the xfail
    below; review R0)."""
    import vehicle_assist as va

    def dev(baseline):
        sc = env.scenario(CMA25, baseline=baseline).with_sets("run.duration_s=5")
        return va.simulate(sc, requirements=False).metrics[DEV]
    none = dev(True)
    assert none <= LANE_BOUND_M, none  # the twin meets the bound here (0.346 m)
    on = dev(False)
    assert on <= LANE_BOUND_M, on  # 0.643 m


@pytest.mark.xfail(strict=True, reason="review R0 (session n): judged to standstill (the braking option's run, "
                   "8.3 s) the false alarm with the function leaves the lane at 6.29 s (1.047 m > 0.978 m) while the "
                   "twin stays inside (0.615 m): no_lane_departure_caused +0.300 at 5 s -> -0.104 to standstill")
def test_cma25_stays_in_lane_to_standstill(cma25):
    assert cma25["none"].metrics[DEV] <= LANE_BOUND_M
    on = cma25["on"].metrics[DEV]
    assert on <= LANE_BOUND_M, on


def test_cma25_seeded_defect_leaves_the_lane(cma25):
    """The check can fail: with gma_rejected_flag 0 (the code before) the same point leaves the lane (2.13 m)."""
    assert cma25["defect"].metrics[DEV] > LANE_BOUND_M


def test_cma25_front_braking_difference_after_rejection(cma25):
    """Mechanism (plant pressures, not the controller's formula): in the second after the rejection the mean
    |p_FR - p_FL| of the car with the function is nearer the car without the function's (both fronts under ABS:
    3.4 bar) than the seeded defect's (the GMA holds FL ~20-30 bar below FR: 18.9 bar); measured 4.4 bar."""
    import numpy as np

    def mean_diff(res, t0):
        df = res.to_pandas()
        w = df[(df.time_s >= t0) & (df.time_s <= t0 + 1.0)]
        return float(np.mean(np.abs(w.wheel_pressure_fr_pa - w.wheel_pressure_fl_pa))) / 1e5
    t_rej = [x.time_s for x in cma25["on"].events if x.machine == "blowout_compensation" and x.to_mode == "REJECTED"][0]
    none, on, defect = (mean_diff(cma25[k], t_rej) for k in ("none", "on", "defect"))
    assert on - none < (defect - none) / 2, (on, none, defect)
