"""Electric traction motor: torque-speed envelope and first-order torque lag.

    T_lim(w) = min(T_max, P_max/|w|)                   constant torque, then constant power
    dT_m/dt = (clip(T_req, -T_lim, T_lim) - T_m)/tau_m
State: T_m [N*m]. Input: torque request, rotor speed. Validity: the envelope of the data sheet.
"""
from __future__ import annotations

import math

import numba as nb


@nb.njit(cache=True, nogil=True, error_model="numpy")
def torque_limit_nm(speed_radps, max_torque_nm, max_power_w):
    w = abs(speed_radps)
    if w * max_torque_nm <= max_power_w:
        return max_torque_nm
    return max_power_w / w


@nb.njit(cache=True, nogil=True, error_model="numpy")
def motor_torque_step(torque_nm, request_nm, speed_radps, max_torque_nm, max_power_w, time_constant_s, dt):
    """Exact discretisation of the first-order lag toward the limited request."""
    lim = torque_limit_nm(speed_radps, max_torque_nm, max_power_w)
    target = min(max(request_nm, -lim), lim)
    return target + (torque_nm - target) * math.exp(-dt / time_constant_s)
