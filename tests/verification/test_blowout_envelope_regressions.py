"""Former counterexamples of tire_blowout.no_worse_than_no_compensation found over the extended envelope
(data/envelopes/tire_blowout.toml with wheel-speed noise, the noise seed and the brake-gain error; CMA-ES seed 2026
budget 64 --keep-going at bffdbd8, findings F7/F8 of the #10 envelope campaign). Rear blowouts at 116-120 km/h on
mu scale 0.30-0.35 with a lane-following driver; no pedal; the plant's pad friction 75-95 % of the ECU's nominal.

Reference: the same blowout without compensation (paper 004 Fig. 4 curve 2; conventions.md 'Evidence'), compared as
the requirement does (largest lateral deviation from t_b to the end of the run).
Can fail: on the code before the fixes (bffdbd8, checked in a git worktree) all three were worse than none
(4.06 vs 2.09 m, 3.05 vs 1.57 m, 2.85 vs 0.89 m); fixed by the filtered limits (7d6f650: #19, #41) and the ECU's
pressure estimate (787c4a6: #32). In-tree negative control: the seeded defect tire_capacity_flag = 0 makes each worse
than none again (4.30 / 3.69 / 3.52 m at 787c4a6)."""
from __future__ import annotations

import pytest

from tests.support import envelope_point_metric
from vehicle_assist.verification.envelope import load_envelope

METRIC = "blowout_lateral_deviation_run_max_m"
NO_CAPACITY = "vehicle.blowout_compensation.tire_capacity_flag=0"
_PEDAL = {"brake.start_s": 2.0, "brake.level_frac": 0.2, "brake.rate_per_s": 20.0, "braking": "none"}  # no pedal
CASES = {
    # F8: found with gain 0.946 and noise 0.033; also worse with noise 0 and gain 1.0 before the fix (4.19 vs 2.09 m)
    "cma2026_19_rr_r1000": dict(speed=119.71332063997775, mu=0.35191197346913516, delay=0.38913169736479997,
                                wheel_speed_noise=0.03323929330026863, noise_seed=6019, brake_gain=0.9459724333761543,
                                wheel="rr", driver="follow", curve="r1000", **_PEDAL),
    # F7: pad friction 25 % below nominal (SAE J866 hot, assumed one code lower)
    "cma2026_32_rr_gain075": dict(speed=115.55105036880433, mu=0.3026839865775358, delay=0.4482244554762499,
                                  wheel_speed_noise=0.09429576131708062, noise_seed=6272, brake_gain=0.7490956356317058,
                                  wheel="rr", driver="follow", curve="r1000", **_PEDAL),
    # F7: pad friction 16 % below nominal; with gain 1.0 the old code helped (0.45 vs 0.89 m)
    "cma2026_41_rr_gain084": dict(speed=117.80736924001569, mu=0.30073131304960815, delay=0.34201157263214377,
                                  wheel_speed_noise=0.04468890692070477, noise_seed=4189, brake_gain=0.8409396466300803,
                                  wheel="rr", driver="follow", curve="r650", **_PEDAL),
}


@pytest.fixture(scope="module")
def env():
    return load_envelope("tire_blowout")


def _dev(env, point, baseline=False, sets=()):
    return envelope_point_metric(env, point, METRIC, baseline, sets)


@pytest.fixture(scope="module", params=list(CASES), ids=list(CASES))
def case(request, env):
    p = CASES[request.param]
    return {"on": _dev(env, p), "off": _dev(env, p, baseline=True), "defect": _dev(env, p, sets=[NO_CAPACITY])}


def test_former_counterexample_no_worse(case):
    assert case["on"] < case["off"]


def test_former_counterexample_worse_with_the_defect(case):
    """Negative control: without the measured tyre-capacity limit the point is a counterexample again."""
    assert case["defect"] > case["off"]
