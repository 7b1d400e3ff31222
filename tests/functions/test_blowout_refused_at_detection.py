"""A blowout refused AT its detection (refused_blown_driver_flag, session k K6; tire_blowout_findings.md K6).

Reference: the spec's never-worse requirement (tire_blowout.no_worse_than_no_compensation) - the same car, same
point, with the function disabled (the twin: ESP/ABS alone). The point is K1's r41 #264 without its valve fault, a
real blowout found by the falsifier: FL blown at 107 km/h on mu 0.577, straight road, fixed steering, the driver
braking (481 N pedal reached at the blowout), brake gain 0.735, wheel-speed noise 0.203 rad/s (seed 8220). The car is
already beyond Rajamani's mu-0.8 yaw bound when the blowout is detected (1.365 s): the function refuses (code 3).
Before the flag the refusal still released the flat FL (27 -> 1 bar): the spin was slowed, not stopped, and the car
slid on faster: 20.933 m vs the twin's 10.864 m. Flag 0 (the code before) must show that violation."""
from __future__ import annotations

import pytest

import vehicle_assist as va
from vehicle_assist.verification.envelope import load_envelope

M = "blowout_lateral_deviation_run_max_m"
POINT_264 = {"speed": 106.96056507654363, "mu": 0.5768190611065651, "delay": 0.3328451066276063,
             "wheel_speed_noise": 0.20348200630878002, "noise_seed": 8220.0, "brake_gain": 0.7347401516667832,
             "brake.start_s": 0.7507262631979383, "brake.level_frac": 0.4810955398275575,
             "brake.rate_per_s": 1.9192460077599338, "braking": "brakes", "wheel": "fl", "driver": "fixed",
             "curve": "straight"}


@pytest.fixture(scope="module")
def env():
    return load_envelope("tire_blowout")


def _run(env, baseline, *sets):
    sc = env.scenario(POINT_264, baseline=baseline)
    if sets:
        sc = sc.with_sets(*sets)
    return va.simulate(sc, requirements=False)


@pytest.mark.parametrize("flag", [1, pytest.param(0, marks=pytest.mark.xfail(
    strict=True, reason="refused_blown_driver_flag = 0, the code before: 20.93 m vs the twin's 10.86 m"))])
def test_refused_at_detection_is_no_worse_than_no_function(env, flag):
    """Refused at the detection (limit code 3), the function's run deviates no more than the twin's; flag 0 (the flat
    FL released after the refusal) is the 10 m violation it fixes - the test must fail there (strict xfail)."""
    sets = (f"vehicle.blowout_compensation.refused_blown_driver_flag={flag}",)
    on = _run(env, False, *sets)
    off = _run(env, True, *sets)
    assert any(e.to_mode == "REFUSED" and e.reason == "beyond_stable_region" for e in on.events)
    assert on.metrics["blowout_limit_code"] == 3
    assert on.metrics[M] <= max(off.metrics[M], 0.0)
