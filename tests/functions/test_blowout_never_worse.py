"""Never worse than no compensation (requirement tire_blowout.no_worse_than_no_compensation; conventions.md
'Evidence'): the points the falsifier found (issue #10, random search budget 32 seeds 3/7/2026, CMA-ES seed 2026
budget 64, envelope data/envelopes/tire_blowout.toml) as regression variants of the paper scenario. Reference: the
same blowout without compensation (paper 004 Fig. 4 curve 2), compared as the largest lateral deviation from the
blowout to the end of the run. Each case also runs with the seeded defect ``slip_limit_flag = 0`` (the rear
compensating wheel braked past the tire's linear region, the code before the fix) and must then be worse: the
test can fail."""
from __future__ import annotations

import pytest

import vehicle_assist as va

BASE_ON, BASE_OFF = "blowout_lf_60kph_paper", "blowout_lf_60kph_off"
METRIC = "blowout_lateral_deviation_run_max_m"
# (name, speed km/h, road friction scale, detection delay s, blown wheel, driver, lane radius m) as found
CASES = [
    ("random_seed3", 94.39073337792571, 0.44142022469340714, 0.30305613765401995, 2, "follow", 1000),
    ("random_seed7", 113.06838892248363, 0.6079820459509571, 0.44129185599177606, 2, "follow", 0),
    ("random_seed2026", 113.47174862964775, 0.3722907498633082, 0.4722180173458564, 3, "follow", 1000),
    ("cma_seed2026", 48.96074298666105, 0.3604975040417582, 0.11195266110062706, 3, "fixed", 650),
]


def _sets(speed, mu, delay, wheel, driver, radius):
    return [f"run.initial_speed_kph={speed}", f"road.friction_mu={mu}",
            f"vehicle.blowout_compensation.detection_delay_s={delay}", f"vehicle.blowout.wheel_index={wheel}",
            f'vehicle.lane_keeper.steering_mode="{driver}"', f"vehicle.lane_keeper.lane_radius_m={radius}"]


def _dev(name, sets):
    return va.simulate(va.load_scenario(name, sets=sets)).metrics[METRIC]


@pytest.fixture(scope="module", params=CASES, ids=[c[0] for c in CASES])
def case(request):
    sets = _sets(*request.param[1:])
    return {"on": _dev(BASE_ON, sets), "off": _dev(BASE_OFF, sets),
            "defect": _dev(BASE_ON, sets + ["vehicle.blowout_compensation.slip_limit_flag=0"])}


def test_former_counterexample_no_worse(case):
    """With the fix the compensation goes less far off the lane than no compensation."""
    assert case["on"] < case["off"]


def test_former_counterexample_fails_with_the_defect(case):
    """Negative control: with the seeded defect the same point is a counterexample again."""
    assert case["defect"] > case["off"]
