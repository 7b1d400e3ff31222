"""Tandem master cylinder and rear proportioning (brake_assist.md 4.1-4.2).

Both chambers of a tandem cylinder carry the same pressure (floating piston, friction and spring
neglected): p_mc = F_out/A_mc. Circuit 1 of the X-split feeds FL and RR, circuit 2 FR and RL; each
rear wheel sees the proportioned pressure p_prop(p) = p for p <= p_knee, else p_knee + s_prop*(p - p_knee).
The integrated ESP pressure sensor reads p_mc (circuit 1, as in the Bosch unit; plant/sensors.py adds
faults).
"""
from __future__ import annotations

import numba as nb

CIRCUIT_OF_WHEEL = (0, 1, 1, 0)  # X-split: fl, rr on circuit 0; fr, rl on circuit 1


@nb.njit(cache=True, nogil=True, error_model="numpy")
def master_pressure_pa(booster_force_n, bore_area_m2):
    return max(booster_force_n, 0.0) / bore_area_m2


@nb.njit(cache=True, nogil=True, error_model="numpy")
def proportioned_pa(pressure_pa, knee_pa, slope_frac):
    if pressure_pa <= knee_pa:
        return pressure_pa
    return knee_pa + slope_frac * (pressure_pa - knee_pa)
