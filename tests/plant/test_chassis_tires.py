"""Two-track chassis, load transfer and the tire interface against closed forms worked by hand.

References: statics of a two-axle car (common.md 9; the numbers below are computed by hand from the sedan's
m = 1600 kg, l = 2.71 m, l_f = 1.08 m, h = 0.55 m, B = 1.55 m, phi_f = 0.6); the Dugoff closed forms of
tire_blowout.md 2.3 (H >= 1 and H < 1 branches, s = 1 limit); the Burckhardt peak quoted in brake_assist.md
4.4 (mu 1.17 at s 0.17, locked 0.76); a torque bracket for the time to lock a wheel.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from vehicle_assist.plant.chassis.load_transfer import wheel_loads
from vehicle_assist.plant.chassis.two_track import braking_slip, wheel_spin_step
from vehicle_assist.plant.tires.dugoff import dugoff_forces
from vehicle_assist.plant.tires.model import (
    BURCKHARDT_SETS,
    MODEL_BURCKHARDT,
    MODEL_DUGOFF,
    burckhardt_peak,
    tire_forces,
)

G = 9.81
M, L, LF, H, B, PHI = 1600.0, 2.71, 1.08, 0.55, 1.55, 0.6
LR = L - LF


def test_static_axle_loads_by_hand() -> None:
    """At rest: front axle m*g*l_r/l = 1600*9.81*1.63/2.71 = 9440.7 N, rear 6255.3 N (by hand), halves per wheel."""
    fl, fr, rl, rr = wheel_loads(M, G, LF, LR, H, B, B, PHI, 0.0, 0.0)
    assert fl == pytest.approx(9440.7 / 2, abs=0.5) and fr == pytest.approx(fl)
    assert rl == pytest.approx(6255.3 / 2, abs=0.5) and rr == pytest.approx(rl)


def test_dynamic_axle_loads_braking_and_cornering() -> None:
    """Braking at 1 g moves m*g*h/l = 1600*9.81*0.55/2.71 = 3185.6 N to the front axle (by hand); a left turn at
    a_y = 5 m/s^2 moves m*a_y*h*phi_f/B_f = 1600*5*0.55*0.6/1.55 = 1703.2 N from FL to FR and
    1600*5*0.55*0.4/1.55 = 1135.5 N from RL to RR. The total stays m*g (a negative control: no transfer sign flip)."""
    fl, fr, rl, rr = wheel_loads(M, G, LF, LR, H, B, B, PHI, -G, 0.0)
    assert fl + fr == pytest.approx(9440.7 + 3185.6, abs=1.0)
    assert rl + rr == pytest.approx(6255.3 - 3185.6, abs=1.0)
    fl, fr, rl, rr = wheel_loads(M, G, LF, LR, H, B, B, PHI, 0.0, 5.0)
    assert fr - fl == pytest.approx(2 * 1703.2, abs=0.5)
    assert rr - rl == pytest.approx(2 * 1135.5, abs=0.5)
    assert fl + fr + rl + rr == pytest.approx(M * G)
    assert fr > fl  # left turn loads the right (outer) wheels


@pytest.mark.parametrize("slip", [0.002, 0.005, 0.02, 0.1, 0.5, 0.9])
def test_dugoff_closed_forms_straight(slip: float) -> None:
    """tire_blowout.md 2.3 with alpha = 0: H >= 1 -> F_x = C_x s/(1-s); H < 1 -> mu F_z - (mu F_z)^2 (1-s)/(4 C_x s)."""
    fz, mu, cx, cy = 4000.0, 0.8, 60e3, 50e3
    fx, fy = dugoff_forces(slip, 0.0, fz, mu, cx, cy)
    h = mu * fz * (1 - slip) / (2 * cx * slip)
    expected = cx * slip / (1 - slip) if h >= 1 else mu * fz - (mu * fz) ** 2 * (1 - slip) / (4 * cx * slip)
    assert fx == pytest.approx(expected, rel=1e-12)
    assert fy == 0.0
    assert fx <= mu * fz + 1e-9


def test_dugoff_locked_limit_and_combined_slip() -> None:
    """s = 1: F_x = C_x mu F_z/sqrt(C_x^2 + C_y^2 tan^2) (the analytic limit); the resultant never exceeds mu*F_z."""
    fz, mu, cx, cy = 4000.0, 0.8, 60e3, 50e3
    fx, _ = dugoff_forces(1.0, 0.0, fz, mu, cx, cy)
    assert fx == pytest.approx(mu * fz)
    ta = math.tan(math.radians(5))
    fx, fy = dugoff_forces(1.0, ta, fz, mu, cx, cy)
    assert fx == pytest.approx(cx * mu * fz / math.hypot(cx, cy * ta))
    for s in np.linspace(0.0, 0.99, 25):
        for a in (0.0, 0.02, 0.1, 0.3):
            fx, fy = dugoff_forces(s, a, fz, mu, cx, cy)
            assert math.hypot(fx, fy) <= mu * fz * (1 + 1e-9)


def test_burckhardt_dry_peak_matches_spec_and_sets_order() -> None:
    """brake_assist.md 4.4: dry peak mu 1.17 at s 0.17, locked mu(1) = 0.76; wet and snow peaks lower."""
    s_pk, mu_pk = burckhardt_peak(*BURCKHARDT_SETS[0])
    assert s_pk == pytest.approx(0.170, abs=0.002) and mu_pk == pytest.approx(1.17, abs=0.005)
    fx, _ = tire_forces(MODEL_BURCKHARDT, 1.0, 0.0, 1000.0, 1.0, *BURCKHARDT_SETS[0], 1e5, 6e4)
    assert -fx == pytest.approx(760.1, abs=0.5)
    peaks = [burckhardt_peak(*BURCKHARDT_SETS[i])[1] for i in range(3)]
    assert peaks[0] > peaks[1] > peaks[2] > 0.15
    # one interface: both models brake with a negative (rearward) force and push left for a positive slip angle
    for model in (MODEL_BURCKHARDT, MODEL_DUGOFF):
        fx, fy = tire_forces(model, 0.05, 0.02, 4000.0, 1.0, *BURCKHARDT_SETS[0], 1e5, 6e4)
        assert fx < 0.0 and fy > 0.0


def test_time_to_lock_under_a_pressure_step_is_inside_the_torque_bracket() -> None:
    """Wheel at 20 m/s, car speed held, brake torque step T_b = 4000 N*m, F_z = 6000 N, J = 1, r = 0.31, dry.
    The tire torque lies between 0 and mu_peak*F_z*r = 1.17*6000*0.31 = 2176 N*m, so omega reaches 0 between
    J*omega0/T_b = 16.1 ms and J*omega0/(T_b - 2176) = 35.4 ms (omega0 = 64.5 rad/s); checked at 0.1 ms."""
    r, j, v, fz, tb, dt = 0.31, 1.0, 20.0, 6000.0, 4000.0, 1e-4
    omega = v / r
    t = 0.0
    locked = False
    while not locked and t < 0.2:
        s = braking_slip(v, omega, r)
        fx, _ = tire_forces(MODEL_BURCKHARDT, s, 0.0, fz, 1.0, *BURCKHARDT_SETS[0], 1e5, 6e4)
        f2, _ = tire_forces(MODEL_BURCKHARDT, min(s + 1e-4, 1.0), 0.0, fz, 1.0, *BURCKHARDT_SETS[0], 1e5, 6e4)
        damping = r * r * max(-(f2 - fx) / 1e-4, 0.0) / v
        omega, locked = wheel_spin_step(omega, tb, fx, damping, r, j, dt)
        t += dt
    omega0 = v / r
    assert locked
    assert j * omega0 / tb - dt <= t <= j * omega0 / (tb - 1.17 * fz * r) + dt
