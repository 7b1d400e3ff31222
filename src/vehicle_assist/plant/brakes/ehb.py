"""Electro-hydraulic brake (EHB) pressure actuator (hill_start_ehb.md section 2.5).

A motor-driven master cylinder tracks the pressure command:

    dp/dt = clip((p_cmd - p)/tau_ehb, -R_release, +R_build),   0 <= p <= p_max

State: p [Pa]. Input: p_cmd [Pa]. The command is saturated to [0, p_max] (actuator limit).
"""
from __future__ import annotations

import numba as nb


@nb.njit(cache=True, nogil=True, error_model="numpy")
def ehb_pressure_step(pressure_pa, command_pa, time_constant_s, build_rate_pa_per_s, release_rate_pa_per_s, max_pressure_pa, dt):
    target = min(max(command_pa, 0.0), max_pressure_pa)
    rate = (target - pressure_pa) / time_constant_s
    rate = min(max(rate, -release_rate_pa_per_s), build_rate_pa_per_s)
    new = pressure_pa + rate * dt
    if (target - pressure_pa) * (target - new) < 0.0:
        new = target
    return min(max(new, 0.0), max_pressure_pa)
