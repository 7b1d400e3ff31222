"""Burckhardt longitudinal tire friction curve (brake_assist.md 4.4, common.md 8).

    mu(s) = c1*(1 - exp(-c2*s)) - c3*s,     s = braking slip in [0, 1]
    F_x = mu(s)*F_z   (retarding magnitude while braking)

Dry asphalt (Burckhardt 1993 as quoted by brake_assist.md): c1 = 1.2801, c2 = 23.99, c3 = 0.52;
peak mu about 1.17 at s about 0.17, locked mu(1) about 0.76. Other surfaces use other coefficients.
This is one fidelity level of the tire interface: f(slip, F_z, params) -> force; Dugoff (paper 004)
will sit beside it with the same call shape.
"""
from __future__ import annotations

import math

import numba as nb

DRY_ASPHALT = (1.2801, 23.99, 0.52)  # c1, c2, c3 (brake_assist.md 4.4, cite:BURCK)


@nb.njit(cache=True, nogil=True, error_model="numpy")
def friction_coeff(slip, c1, c2, c3):
    s = min(max(slip, 0.0), 1.0)
    return c1 * (1.0 - math.exp(-c2 * s)) - c3 * s


@nb.njit(cache=True, nogil=True, error_model="numpy")
def braking_slip(vehicle_speed_mps, wheel_speed_radps, radius_m, v_eps):
    """s = (v - omega*R)/max(v, v_eps) (common.md 2), clipped to [0, 1]."""
    s = (vehicle_speed_mps - wheel_speed_radps * radius_m) / max(vehicle_speed_mps, v_eps)
    return min(max(s, 0.0), 1.0)
