"""Dry clutch: actuator position -> torque capacity, slip/lock (hill_start_amt.md section 5.2).

    T_cap(x_c) = 0                                            x_c <= x_kiss
    T_cap(x_c) = T_max*((x_c - x_kiss)/(1 - x_kiss))^k_c      x_c >  x_kiss
    slipping:  T_c = T_cap*sign(w_e - w_in)
    locked:    w_e = w_in and T_c is whatever keeps them together, while |T_c| <= T_cap

Lock-up happens when the slip speed crosses zero within a step and the torque needed to stay locked is
within capacity; break-away when it is not. Energy dissipated: P_slip = |T_c*(w_e - w_in)|.
The actuator is a first-order lag with a rate limit (position 0 = open, 1 = fully engaged).
"""
from __future__ import annotations

import math

import numba as nb


@nb.njit(cache=True, nogil=True, error_model="numpy")
def clutch_capacity_nm(position_frac, max_torque_nm, kiss_point_frac, exponent):
    if position_frac <= kiss_point_frac:
        return 0.0
    u = min((position_frac - kiss_point_frac) / (1.0 - kiss_point_frac), 1.0)
    return max_torque_nm * u ** exponent


@nb.njit(cache=True, nogil=True, error_model="numpy")
def clutch_position_for_capacity(capacity_nm, max_torque_nm, kiss_point_frac, exponent):
    """Inverse of :func:`clutch_capacity_nm` (position at which the capacity is reached)."""
    u = min(max(capacity_nm / max_torque_nm, 0.0), 1.0) ** (1.0 / exponent)
    return kiss_point_frac + u * (1.0 - kiss_point_frac)


@nb.njit(cache=True, nogil=True, error_model="numpy")
def actuator_step(position, command, time_constant_s, max_rate_per_s, dt):
    """First-order lag toward ``command`` with a rate limit; result clipped to [0, 1]."""
    rate = (command - position) / time_constant_s
    rate = min(max(rate, -max_rate_per_s), max_rate_per_s)
    new = position + rate * dt
    if (command - position) * (command - new) < 0.0:
        new = command
    return min(max(new, 0.0), 1.0)


@nb.njit(cache=True, nogil=True, error_model="numpy")
def slip_power_w(torque_nm, engine_speed_radps, input_speed_radps):
    return abs(torque_nm * (engine_speed_radps - input_speed_radps))


@nb.njit(cache=True, nogil=True, error_model="numpy")
def sign(x):
    return math.copysign(1.0, x) if x != 0.0 else 0.0
