"""Diesel engine with an all-speed (RQV-type) governor, full-load curve, friction and stall
(hill_start_amt.md section 5.1).

    n_set(theta) = n_idle + theta*(n_hi_idle - n_idle)                  pedal sets the governed speed
    T_e = clip(K_gov*(w_set - w_e), T_fric(w_e), T_full(w_e))           net torque at the flywheel
    K_gov = T_peak/(delta*w_set)   with a speed droop delta > 0 (else the file's constant gain)

Speed droop (issue 7): a mechanical all-speed governor lets the speed fall in proportion to the load; the
droop delta = (n_no_load - n_full_load)/n_no_load is a property of the governor (vehicle governors are given a
large droop for stable, smooth speed control; 10 % is the example value of an engine maker's governor
documentation). With the droop the full torque is reached delta*n_set below the set speed (180 rpm at
1805 rpm, 110 rpm at 1095 rpm) instead of a fixed 100 rpm.
    T_fric(w_e) = -(c0 + c1*w_e)                                        motoring friction (w_e > 0)
    J_e * dw_e/dt = T_e - T_c                                           (clutch slipping)

Stall: once w_e falls below the stall speed the engine stops firing (a stalled engine stays off for the
rest of the run, as in a test); only friction acts and w_e is clamped at >= 0 (no reverse rotation).
State: w_e [rad/s], stalled flag. Input: accelerator 0..1, clutch torque. Validity: 0..high idle.
"""
from __future__ import annotations

import numba as nb

from vehicle_assist.core.tables import interp


@nb.njit(cache=True, nogil=True, error_model="numpy")
def friction_torque_nm(speed_radps, offset_nm, slope_nm_per_radps):
    """Motoring (drag) torque, <= 0, zero at standstill."""
    if speed_radps <= 0.0:
        return 0.0
    return -(offset_nm + slope_nm_per_radps * speed_radps)


@nb.njit(cache=True, nogil=True, error_model="numpy")
def governed_speed_radps(accelerator_frac, idle_radps, high_idle_radps):
    a = min(max(accelerator_frac, 0.0), 1.0)
    return idle_radps + a * (high_idle_radps - idle_radps)


@nb.njit(cache=True, nogil=True, error_model="numpy")
def governor_gain_nm_per_radps(p, set_speed_radps):
    """K_gov: T_peak/(droop*w_set) with a speed droop, else the file's constant gain."""
    if p.engine_governor_droop_frac > 0.0:
        return p.engine_governor_peak_torque_nm / (p.engine_governor_droop_frac * max(set_speed_radps, 1.0))
    return p.engine_governor_gain_nm_per_radps


@nb.njit(cache=True, nogil=True, error_model="numpy")
def engine_torque_nm(p, speed_radps, accelerator_frac, stalled):
    """Net flywheel torque of the governed engine; friction only when stalled."""
    t_fric = friction_torque_nm(speed_radps, p.engine_friction_offset_nm, p.engine_friction_slope_nm_per_radps)
    if stalled:
        return t_fric
    t_full = interp(p.engine_full_load_torque_x, p.engine_full_load_torque_y, p.engine_full_load_torque_n,
                    p.engine_full_load_torque_extrap, p.engine_full_load_torque_interp, speed_radps)
    w_set = governed_speed_radps(accelerator_frac, p.engine_idle_speed_radps, p.engine_high_idle_speed_radps)
    t_gov = governor_gain_nm_per_radps(p, w_set) * (w_set - speed_radps)
    return min(max(t_gov, t_fric), max(t_full, t_fric))
