"""Whole-vehicle closed-form checks of the ESP sedan (vehicles/sedan_esp.py) through the scenario API.

References: the friction limit (all four wheels locked -> deceleration mu_locked*g whatever the load
transfer, since the loads sum to m*g; stopping distance v^2/(2a)); the statics of common.md 9 worked by hand;
mirror symmetry of the two-track model (ISO 8855: positive steer -> positive yaw rate).
"""
from __future__ import annotations

import numpy as np
import pytest

import vehicle_assist as va

BASE = "hba_paper_110kph_dry"
NO_RESIST = ["vehicle.body.drag_area_m2=0", "vehicle.body.rolling_resistance_coeff=0"]
ABS_FAILED = 'events=[{at_s=0, action="actuator_fault", actuator="esp_valves", fault="unpowered"}]'
MU_LOCKED_DRY = 1.2801 * (1 - np.exp(-23.99)) - 0.52  # Burckhardt dry at s = 1 (brake_assist.md 4.4: 0.76)


def run(*sets):
    return va.simulate(va.load_scenario(BASE, list(sets)))


MU_PEAK_DRY = 1.1700  # Burckhardt dry peak (brake_assist.md 4.4), the Dugoff model's mu at the same surface


@pytest.mark.parametrize("scale, model, mu_locked", [(1.0, "burckhardt", MU_LOCKED_DRY), (0.5, "burckhardt", MU_LOCKED_DRY),
                                                     (1.0, "dugoff", MU_PEAK_DRY)])
def test_locked_wheels_decelerate_at_mu_g(scale: float, model: str, mu_locked: float) -> None:
    """ABS failed, full pedal (210 bar): every wheel locks; then m*a = -sum mu(1)*F_z = -mu(1)*m*g exactly
    (drag and rolling resistance off), whatever the load transfer; with the Dugoff model the locked force is
    mu*F_z with mu the surface's peak (tire_blowout.md 2.3, s = 1 limit). Tolerance 0.5 %: the loads lag one 0.5 ms
    step behind the acceleration, nothing else. Stopping distance from the lock instant: v_lock^2/(2*mu*g)
    within 0.5 m (one record period of travel at the lock speed plus the stop regularisation at 0.05 m/s)."""
    r = run(*NO_RESIST, ABS_FAILED, f"road.friction_mu={scale}",
            'driver.brake_pedal={time_s=[0.0, 0.1, 0.11], frac=[0.0, 0.0, 1.0]}', "run.duration_s=12",
            f'vehicle.tires.model="{model}"')
    tr = r.trace
    locked = np.all([tr[f"wheel_slip_{w}_frac"] >= 1.0 for w in ("fl", "fr", "rl", "rr")], axis=0) & (tr["speed_mps"] > 1)
    assert locked.sum() > 100
    a = tr["accel_mps2"][locked]
    expected = -mu_locked * scale * 9.81
    assert np.all(np.abs(a - expected) <= 0.005 * abs(expected))
    k = np.flatnonzero(locked)[0]
    v_lock = tr["speed_mps"][k]
    distance = r.metrics["stopping_distance_m"] - (tr["position_m"][k] - tr["position_m"][np.flatnonzero(tr["pedal_force_n"] >= 20)[0]])
    assert distance == pytest.approx(v_lock**2 / (2 * abs(expected)), abs=0.5)
    assert r.metrics["hba_activated_flag"] == 0.0  # ABS failed -> HBA unavailable (paper P2)


def test_static_wheel_loads_in_the_trace() -> None:
    """First sample (no acceleration yet): FL = FR = 9440.7/2 N, RL = RR = 6255.3/2 N (by hand, as in
    tests/plant/test_chassis_tires.py)."""
    tr = run(*NO_RESIST, "run.duration_s=0.05").trace
    assert tr["wheel_load_fl_n"][0] == pytest.approx(4720.35, abs=0.5)
    assert tr["wheel_load_rr_n"][0] == pytest.approx(3127.65, abs=0.5)


@pytest.mark.parametrize("angle_deg", [1.0, 3.0])
def test_symmetric_steer_gives_antisymmetric_yaw(angle_deg: float) -> None:
    """Property: steering +d and -d from 80 km/h (no brakes) gives mirror-image yaw rate, heading and lateral
    offset (to rounding), and a positive steer a positive (left, CCW) yaw rate (ISO 8855)."""
    out = []
    for sign in (1.0, -1.0):
        tr = run("run.initial_speed_kph=80", "run.duration_s=2", 'driver.brake_pedal={time_s=[0.0], frac=[0.0]}',
                 f"driver.steering={{time_s=[0.0, 0.2, 0.4], angle_deg=[0.0, 0.0, {sign * angle_deg}]}}").trace
        out.append(tr)
    for ch in ("yaw_rate_radps", "heading_rad", "y_m", "lateral_accel_mps2"):
        np.testing.assert_allclose(out[0][ch], -out[1][ch], atol=1e-9)
    np.testing.assert_allclose(out[0]["speed_mps"], out[1]["speed_mps"], atol=1e-9)
    assert out[0]["yaw_rate_radps"][-1] > 0.01
    # steady state: the load moves to the outer (right) wheels in a left turn
    assert out[0]["wheel_load_fr_n"][-1] > out[0]["wheel_load_fl_n"][-1]
