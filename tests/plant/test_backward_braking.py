"""A braked car rolling backward (a spun car after a blowout; issue #10 independent review d): the brake must act.

Since the stop-freeze fix (bffdbd8) a spinning car keeps sliding and its u can turn negative before the 5-s run ends
(the no-compensation twin of the review's seed-42 RL point: u = -2.1 m/s at 4.9 s). The wheels do not roll backward in
the plant (omega >= 0), and the braking slip s = (v - omega*R)/max(v, v_eps) clipped to [0, 1] is 0 for v < 0: a braked
car rolling backward had no brake at all (10 m/s backward, 60 bar: 0.14 m/s^2, rolling resistance and drag only).

Independent references: Newton's law for a car braked below the friction limit with the wheels held (no wheel
rotation, so no wheel-inertia term): m*a = sum_i K_i*p_i/R + 0.5*rho*C_dA*u^2 + m*g*f_r, with the disc-brake gains
K_b of brake_assist.md 6 (front 2.23e-4, rear 6.90e-5 N*m/Pa) and the sedan's m 1600 kg, R 0.31 m, C_dA 0.66 m^2,
f_r 0.012 (sedan_1p8t.toml); Coulomb: the deceleration cannot exceed the road's peak friction (Burckhardt dry peak
1.17 at s 0.17, brake_assist.md 4.4) times g; the kinetic energy cannot rise.
"""
from __future__ import annotations

import numpy as np
import pytest

import vehicle_assist as va

K_FRONT, K_REAR = 2.23e-4, 6.90e-5  # brake_assist.md 6
M, R, CDA, FR, RHO, G = 1600.0, 0.31, 0.66, 0.012, 1.2258, 9.81
MU_PEAK_DRY = 1.17  # Burckhardt dry peak (brake_assist.md 4.4)


def _run(u0_mps: float, pedal: float):
    sets = [f"run.initial_speed_kph={u0_mps * 3.6}", "run.duration_s=1.2",
            f"driver.brake_pedal.frac=[0.0, 0.0, {pedal}, {pedal}, 0.0]"]
    return va.simulate(va.load_scenario("hba_off_110kph_dry", sets), requirements=False).trace


def test_light_brake_backward_decelerates_as_newton() -> None:
    """Below the friction limit the brake force is K_b*p/R on each wheel, pointing forward (against the motion)."""
    tr = _run(-10.0, 0.04)
    t = np.asarray(tr["time_s"])
    w = (t >= 0.6) & (t <= 1.0)
    u = np.asarray(tr["speed_mps"])[w]
    assert np.all(u < -2.0)  # still rolling backward in the window
    brake = sum(k * np.asarray(tr[f"wheel_pressure_{n}_pa"])[w]
                for k, n in ((K_FRONT, "fl"), (K_FRONT, "fr"), (K_REAR, "rl"), (K_REAR, "rr"))) / R
    assert brake.min() > 2000.0  # the brake is applied (~20 bar)
    pred = (brake + 0.5 * RHO * CDA * u * u + M * G * FR) / M  # forward acceleration (u < 0)
    assert np.asarray(tr["accel_mps2"])[w] == pytest.approx(pred, rel=0.01)


def test_hard_brake_backward_is_friction_limited_and_dissipative() -> None:
    """60 bar backward: decelerates at more than the rear brakes alone give but not above mu*g; energy never rises."""
    tr = _run(-10.0, 0.1)
    t = np.asarray(tr["time_s"])
    u = np.asarray(tr["speed_mps"])
    w = (t >= 0.5) & (t <= 0.9) & (u < -1.0)
    a = np.asarray(tr["accel_mps2"])[w]
    assert w.sum() > 50  # rows of the 0.4-s window
    # lower bound: the rear brakes alone (K_r*p_r/R per wheel with the proportioned rear pressure, ~1 kN, below the
    # rear tires' friction limit of ~0.76*4 kN); the front axle adds a positive friction-limited force. Upper: Coulomb
    rear = K_REAR * (np.asarray(tr["wheel_pressure_rl_pa"])[w] + np.asarray(tr["wheel_pressure_rr_pa"])[w]) / R / M
    assert rear.min() > 1.0  # the rear brake is applied (proportioned pressure)
    assert np.all(a > rear) and np.all(a < MU_PEAK_DRY * G)
    e = 0.5 * M * (u ** 2 + np.asarray(tr["lateral_speed_mps"]) ** 2)
    assert np.all(np.diff(e) <= 1e-9 * e[0])


def test_forward_braking_unchanged_sign() -> None:
    """The mirror image: the same pedal forward decelerates (negative a_x) - the backward branch is not taken."""
    tr = _run(10.0, 0.04)
    t = np.asarray(tr["time_s"])
    w = (t >= 0.6) & (t <= 1.0)
    assert np.all(np.asarray(tr["accel_mps2"])[w] < -1.0)
