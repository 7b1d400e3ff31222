"""Wheel spin dynamics with brake torque as a capacity, and wheel lock (common.md 8 and 7.3).

    J_w * d(omega)/dt = T_drive - T_b - F_x*r_w          (omega >= 0, forward rolling)

The brake is a friction element: while the wheel turns it applies its full torque against the spin;
once omega reaches zero the wheel is LOCKED and the brake holds it with a static reaction as long as
the torque trying to spin it (T_drive - F_x*r_w, the tire force turning it forward) stays within the
brake capacity. It unlocks when that torque exceeds the capacity. A wheel crossing zero within a step
stops at exactly zero (no reverse spin, no chatter). This is the wheel-level twin of the vehicle
stick/slip rule in :mod:`vehicle_assist.plant.longitudinal`.
"""
from __future__ import annotations

import numba as nb


@nb.njit(cache=True, nogil=True, error_model="numpy")
def wheel_step(omega, drive_torque_nm, brake_capacity_nm, tire_force_n, radius_m, inertia_kgm2, dt):
    """Returns (omega_new, locked, brake_torque_nm): the brake torque actually applied (<= capacity)."""
    spin_torque = drive_torque_nm - tire_force_n * radius_m  # torque accelerating the wheel, brake aside
    if omega <= 0.0 and -brake_capacity_nm <= spin_torque <= brake_capacity_nm:
        return 0.0, True, spin_torque  # locked: the brake reacts exactly what is needed
    if omega <= 0.0 and spin_torque < -brake_capacity_nm:
        return 0.0, True, brake_capacity_nm  # would spin backwards: held at zero (no reverse rotation)
    new = omega + dt * (spin_torque - brake_capacity_nm) / inertia_kgm2
    if new < 0.0:
        return 0.0, True, brake_capacity_nm
    return new, False, brake_capacity_nm
