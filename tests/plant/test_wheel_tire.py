"""Wheel lock and the Burckhardt tire curve: closed-form checks (common.md 7.3, 8; brake_assist.md 4.4)."""
import math

import numpy as np
import pytest

from vehicle_assist.plant.tires.burckhardt import DRY_ASPHALT, braking_slip, friction_coeff
from vehicle_assist.plant.wheel import wheel_step

G = 9.81


def test_burckhardt_dry_asphalt_peak_and_locked_values():
    """Peak at s* = ln(c1*c2/c3)/c2 = 0.170 with mu = 1.170 and mu(1) = 0.760 (values quoted by brake_assist.md 4.4)."""
    c1, c2, c3 = DRY_ASPHALT
    s_star = math.log(c1 * c2 / c3) / c2
    assert s_star == pytest.approx(0.170, abs=5e-4)
    assert friction_coeff(s_star, c1, c2, c3) == pytest.approx(1.170, abs=5e-4)
    assert friction_coeff(1.0, c1, c2, c3) == pytest.approx(0.760, abs=5e-4)
    s = np.linspace(0, 1, 1001)
    mu = np.array([friction_coeff(x, c1, c2, c3) for x in s])
    assert abs(s[np.argmax(mu)] - s_star) <= 1e-3  # the sampled curve peaks where the closed form says


def test_slip_definition():
    """s = (v - omega*R)/v: free rolling 0, locked 1 (common.md 2)."""
    assert braking_slip(20.0, 20.0 / 0.3, 0.3, 1e-3) == pytest.approx(0.0, abs=1e-12)
    assert braking_slip(20.0, 0.0, 0.3, 1e-3) == 1.0


def quarter_car_stop(brake_torque_nm, v0=20.0, m=400.0, j=1.0, r=0.3, dt=1e-4):
    """Quarter car braking on dry asphalt; returns (time to stop, mean deceleration, wheel locked at the end)."""
    c1, c2, c3 = DRY_ASPHALT
    v, omega, t, locked = v0, v0 / r, 0.0, False
    while v > 0.05 and t < 10.0:
        s = braking_slip(v, omega, r, 1e-3)
        fx = friction_coeff(s, c1, c2, c3) * m * G
        omega, locked, _ = wheel_step(omega, 0.0, brake_torque_nm, -fx, r, j, dt)  # tire force turns the wheel forward
        v -= fx / m * dt
        t += dt
    return t, (v0 - v) / t, locked


def test_locked_wheel_decelerates_at_sliding_friction():
    """A brake far above the tire's torque locks the wheel at once: deceleration -> mu(1)*g = 7.46 m/s^2
    (closed form for a sliding block; 2 % covers the brief spin-down before lock)."""
    t, decel, locked = quarter_car_stop(brake_torque_nm=5000.0)
    assert locked
    assert decel == pytest.approx(0.760 * G, rel=0.02)


def test_locked_wheel_stays_at_exactly_zero_and_unlocks_when_released():
    """Held at omega = 0 exactly while the tire torque is within the brake capacity; spins up once released."""
    omega = 0.0
    for _ in range(1000):
        omega, locked, reaction = wheel_step(omega, 0.0, 1000.0, -2000.0, 0.3, 1.0, 1e-3)  # tire torque 600 N*m
        assert omega == 0.0 and locked
    assert reaction == pytest.approx(600.0)  # static reaction = exactly what holds the wheel
    omega, locked, _ = wheel_step(0.0, 0.0, 100.0, -2000.0, 0.3, 1.0, 1e-3)
    assert omega > 0.0 and not locked


def test_no_reverse_spin_when_braking_through_zero():
    """A wheel decelerating through zero within a step stops at exactly zero (no negative omega)."""
    omega, locked, _ = wheel_step(0.05, 0.0, 3000.0, 0.0, 0.3, 1.0, 1e-3)
    assert omega == 0.0 and locked
