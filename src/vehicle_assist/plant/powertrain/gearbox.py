"""Stepped gearbox with final drive; AMT gear change takes time and interrupts the torque.

    i_total = i_g(gear) * i_0          w_in = v*i_total/r_w (rigid driveline, no wheel slip)
    F_t = T*i_total*eta/r_w  when power flows to the wheels, T*i_total/(eta*r_w) when it flows back

Gear index 0 is neutral; 1..n index the forward ratios in the vehicle file's order (for the truck,
1 = crawler "C", 2 = 1st, ...). A gear change runs through neutral for ``shift_time_s`` (the shift
actuator, synchroniser and torque interruption lumped), then the requested gear is engaged.
"""
from __future__ import annotations

import numba as nb


@nb.njit(cache=True, nogil=True, error_model="numpy")
def gear_ratio(ratios, n_gears, gear):
    """Gearbox ratio of ``gear`` (0 = neutral -> 0)."""
    g = int(gear)
    if g <= 0 or g > n_gears:
        return 0.0
    return ratios[g - 1]


@nb.njit(cache=True, nogil=True, error_model="numpy")
def shift_step(engaged, target, timer_s, requested, shift_time_s, dt):
    """AMT shift actuator. Returns (engaged, target, timer_s); ``engaged`` is 0 while shifting."""
    req = int(requested)
    if req != target:
        # new request: go to neutral now; the shift takes shift_time_s from this instant
        return 0, req, (shift_time_s if req != 0 else 0.0)
    if engaged != target:
        timer_s -= dt
        if timer_s <= 0.0:
            timer_s = 0.0
            engaged = target
    return engaged, target, timer_s


@nb.njit(cache=True, nogil=True, error_model="numpy")
def efficiency_factor(torque_to_wheels, efficiency):
    """eta when the torque drives the wheels, 1/eta when the wheels drive the engine."""
    return efficiency if torque_to_wheels >= 0.0 else 1.0 / efficiency
