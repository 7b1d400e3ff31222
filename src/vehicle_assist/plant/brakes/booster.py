"""Vacuum brake booster with run-out (brake_assist.md 4.1; std: Breuer & Bill, *Brake Technology Handbook*).

Input force at the booster rod F_in = F_pedal * i_pedal (pedal lever ratio). Below run-out the booster
multiplies it by k_boost; at run-out the vacuum's assist is exhausted (output F_runout) and any further
force passes through unassisted (gain 1):

    F_target = k_boost*F_in                          for k_boost*F_in <= F_runout
    F_target = F_runout + (F_in - F_runout/k_boost)  above (the run-out point F_in = F_runout/k_boost)
    d(F_out)/dt = (F_target - F_out)/tau_boost
"""
from __future__ import annotations

import math

import numba as nb


@nb.njit(cache=True, nogil=True, error_model="numpy")
def booster_target_n(pedal_force_n, pedal_ratio, boost_gain, runout_force_n):
    f_in = max(pedal_force_n, 0.0) * pedal_ratio
    if boost_gain * f_in <= runout_force_n:
        return boost_gain * f_in
    return runout_force_n + (f_in - runout_force_n / boost_gain)


def runout_pedal_force_n(pedal_ratio: float, boost_gain: float, runout_force_n: float) -> float:
    """Pedal force at the run-out point: F_runout/(k_boost*i_pedal)."""
    return runout_force_n / (boost_gain * pedal_ratio)


@nb.njit(cache=True, nogil=True, error_model="numpy")
def booster_step(f_out_n, target_n, time_constant_s, dt):
    """First-order lag, exact discretisation (stable for any dt)."""
    return target_n + (f_out_n - target_n) * math.exp(-dt / time_constant_s)
