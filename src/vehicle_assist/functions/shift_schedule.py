"""Normal (best-power style) shift schedule of an automated transmission: up and down lines over throttle
(curve_shift.md 6, paper 003 Fig. 4).

The lines are vehicle speeds [m/s] at throttle breakpoints ``theta`` (linear interpolation, clamped):

    up[g]   g -> g+1 when u >= u_up(g, theta)          (g = 1 .. n-1)
    down[g] g -> g-1 when u <= u_dn(g, theta)          (g = 2 .. n; stored in row g-2)

The normal schedule shifts one gear at a time (no skip shifts, paper P1) and only after a dwell time since
the last shift ended (assumed; keeps the lines' hysteresis from hunting while the torque is interrupted).
Gear indices follow the gearbox: 0 neutral, 1 .. n forward. Packed parameters (vehicles/amt_car.py derived):
``shift_schedule_throttle_frac`` (n_theta), ``shift_schedule_up_flat_mps`` ((n-1)*n_theta, row-major),
``shift_schedule_down_flat_mps`` ((n-1)*n_theta, row g-2 = line g -> g-1).
"""
from __future__ import annotations

import numba as nb


@nb.njit(cache=True, nogil=True, error_model="numpy")
def _line(thetas, n_theta, flat, row, theta):
    base = row * n_theta
    if theta <= thetas[0]:
        return flat[base]
    for j in range(1, n_theta):
        if theta <= thetas[j]:
            w = (theta - thetas[j - 1]) / (thetas[j] - thetas[j - 1])
            return flat[base + j - 1] + w * (flat[base + j] - flat[base + j - 1])
    return flat[base + n_theta - 1]


@nb.njit(cache=True, nogil=True, error_model="numpy")
def upshift_speed_mps(p, gear, theta):
    """u_up(g -> g+1, theta); +inf in the top gear."""
    n_theta = int(p.shift_schedule_theta_count)
    if gear < 1 or gear >= int(p.gearbox_gear_count):
        return 1e9
    return _line(p.shift_schedule_throttle_frac, n_theta, p.shift_schedule_up_flat_mps, gear - 1, theta)


@nb.njit(cache=True, nogil=True, error_model="numpy")
def downshift_speed_mps(p, gear, theta):
    """u_dn(g -> g-1, theta) (u_a of paper 003 eq. 14); -inf in first gear."""
    n_theta = int(p.shift_schedule_theta_count)
    if gear <= 1 or gear > int(p.gearbox_gear_count):
        return -1e9
    return _line(p.shift_schedule_throttle_frac, n_theta, p.shift_schedule_down_flat_mps, gear - 2, theta)


@nb.njit(cache=True, nogil=True, error_model="numpy")
def normal_target_gear(p, gear, speed_mps, theta):
    """Gear the normal schedule asks for: one step up or down from ``gear`` (no skip shifts)."""
    if gear <= 0:
        return gear
    if speed_mps >= upshift_speed_mps(p, gear, theta):
        return gear + 1
    if speed_mps <= downshift_speed_mps(p, gear, theta):
        return gear - 1
    return gear
