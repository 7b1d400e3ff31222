"""Hydraulic disc wheel brakes: pressure -> torque per wheel (common.md section 7.1).

    T_b = K_b * p_wc,   K_b = n_f * mu_b * A_wc * r_eff * eta_b          [N*m per Pa]
    F_b = T_b / r_w                                                       (force at the contact)

``n_f`` = 2 friction faces for a disc brake (set 1 to reproduce paper 004 literally). The brake is a
capacity: on a stationary wheel it is a static reaction |F| <= F_b, on a moving one a sliding force
(common.md 7.3, handled by the stick/slip rule of plant/longitudinal.py).
"""
from __future__ import annotations

import math

import numba as nb


def piston_area_m2(piston_diameter_m: float, pistons: int = 1) -> float:
    return pistons * math.pi * piston_diameter_m**2 / 4.0


def brake_gain_nm_per_pa(friction_faces: float, pad_friction: float, piston_area: float, effective_radius_m: float, efficiency: float) -> float:
    """K_b = n_f*mu_b*A_wc*r_eff*eta_b."""
    return friction_faces * pad_friction * piston_area * effective_radius_m * efficiency


@nb.njit(cache=True, nogil=True, error_model="numpy")
def wheel_brake_torque_nm(pressure_pa, gain_nm_per_pa):
    return gain_nm_per_pa * max(pressure_pa, 0.0)
