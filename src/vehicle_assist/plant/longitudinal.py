"""Longitudinal vehicle on a grade with stick/slip at standstill (common.md sections 3, 4).

Model (driving equation, Yu Zhisheng ch. 1):

    delta*m * dv/dt = F_t - F_f - F_w - F_i - F_brake
    F_i = m*g*sin(alpha)                       grade resistance (alpha uphill +)
    F_f = m*g*f*cos(alpha)*sign(v)             rolling resistance
    F_w = 0.5*rho_air*C_D*A*v*|v|              aerodynamic drag (still air)
    delta*m = m + sum(J_w)/r_w^2 + J_line*i^2*eta/r_w^2    rotating-mass factor (physical form, section 4)

Standstill (Karnopp stick/slip, section 3.3): rolling resistance and brakes are reactions bounded by a
capacity. While |v| < v_eps and |F_t - F_i - F_w| <= F_hold_cap the vehicle is held at exactly v = 0
and the holds supply the reaction; otherwise it slides with the capacity opposing the motion. A speed
that would cross zero within a step stops at zero, so a braked vehicle comes to rest without chatter.

States: position x [m], speed v [m/s]. Inputs: net driving force, hold capacity, equivalent mass.
Validity: |alpha| < 45 deg, no wheel slip (wheel-slip models live in plant/tires), still air.
"""
from __future__ import annotations

import math

import numba as nb

from vehicle_assist.conventions import G_MPS2, RHO_AIR_KGPM3

G = G_MPS2
RHO_AIR = RHO_AIR_KGPM3


@nb.njit(cache=True, nogil=True, error_model="numpy")
def grade_resistance_n(mass_kg, slope_rad):
    """F_i = m*g*sin(alpha): positive uphill (opposes forward motion)."""
    return mass_kg * G * math.sin(slope_rad)


@nb.njit(cache=True, nogil=True, error_model="numpy")
def rolling_resistance_capacity_n(mass_kg, slope_rad, coeff):
    """Magnitude m*g*f*cos(alpha): sliding force while moving, reaction bound at rest."""
    return mass_kg * G * coeff * math.cos(slope_rad)


@nb.njit(cache=True, nogil=True, error_model="numpy")
def aero_drag_n(drag_area_m2, speed_mps):
    """F_w = 0.5*rho*C_D*A*v*|v| (common.md 3.1: identical to C_D*A*u_a^2/21.15 with u_a in km/h)."""
    return 0.5 * RHO_AIR * drag_area_m2 * speed_mps * abs(speed_mps)


@nb.njit(cache=True, nogil=True, error_model="numpy")
def equivalent_mass_kg(mass_kg, wheel_inertia_total_kgm2, wheel_radius_m, line_inertia_kgm2, ratio, efficiency):
    """delta*m: mass plus wheel inertia and driveline inertia reflected to the wheel (common.md 4)."""
    r2 = wheel_radius_m * wheel_radius_m
    return mass_kg + wheel_inertia_total_kgm2 / r2 + line_inertia_kgm2 * ratio * ratio * efficiency / r2


@nb.njit(cache=True, nogil=True, error_model="numpy")
def stick_slip_step(v, net_force_n, hold_capacity_n, equivalent_mass, dt, v_eps):
    """One step of the Karnopp rule.

    Returns (v_new, accel, held, hold_reaction_n): ``hold_reaction_n`` is the force the holds
    (brakes + rolling resistance) exert on the vehicle along +x; at rest it balances ``net_force_n``.
    """
    if abs(v) < v_eps and abs(net_force_n) <= hold_capacity_n:
        return 0.0, 0.0, True, -net_force_n
    if abs(v) >= v_eps:
        direction = 1.0 if v > 0.0 else -1.0
    else:
        direction = 1.0 if net_force_n > 0.0 else -1.0
    reaction = -direction * hold_capacity_n
    accel = (net_force_n + reaction) / equivalent_mass
    v_new = v + accel * dt
    if abs(v) >= v_eps and v_new * v < 0.0:
        # the holds stop the vehicle within this step: come to rest at exactly zero
        v_new = 0.0
        accel = -v / dt
    return v_new, accel, False, reaction
