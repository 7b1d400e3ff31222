"""Sensors: sampled at the controller rate, with optional bias, noise (seeded) and delay, and faults.

    y_k = x(t_k - d) + bias + sigma*n_k,     n_k ~ N(0, 1) drawn before the run from the scenario seed
    delay d is a whole number of controller periods (rounded); a ring buffer keeps past samples.
Faults (set by scenario events): 1 = lost (value 0, validity flag 0, like a CAN timeout),
2 = stuck (holds the last value - the first sample if stuck from the start - flag still 1: undetectable
by plausibility alone),
3 = biased (adds the event's value to the bias).
Controllers only ever see these measurements, never the plant state.
"""
from __future__ import annotations

import numba as nb

FAULT_NONE = 0
FAULT_LOST = 1
FAULT_STUCK = 2
FAULT_BIAS = 3
FAULTS = {"none": FAULT_NONE, "lost": FAULT_LOST, "stuck": FAULT_STUCK, "bias": FAULT_BIAS}


@nb.njit(cache=True, nogil=True, error_model="numpy")
def sample_sensors(truth, history, tick, noise_row, noise_std, bias, delay_ticks, fault, fault_value, last, out_value, out_ok):
    """Sample every sensor: fills ``out_value``/``out_ok`` and updates the ring buffer and ``last``."""
    depth = history.shape[1]
    slot = tick % depth
    for i in range(truth.shape[0]):
        history[i, slot] = truth[i]
        d = int(delay_ticks[i])
        if d > tick:
            d = tick
        if d > depth - 1:
            d = depth - 1
        x = history[i, (tick - d) % depth]
        y = x + bias[i] + noise_std[i] * noise_row[i]
        f = int(fault[i])
        if f == FAULT_LOST:
            out_value[i] = 0.0
            out_ok[i] = 0.0
        elif f == FAULT_STUCK and tick > 0:
            out_value[i] = last[i]
            out_ok[i] = 1.0
        else:
            if f == FAULT_BIAS:
                y += fault_value[i]
            out_value[i] = y
            out_ok[i] = 1.0
            last[i] = y
