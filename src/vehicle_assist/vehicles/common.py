"""Pieces every vehicle composition shares: the road, scenario events and sensor buffers.

Scenario events are data in the scenario record: each fires once, at a time or when a signal crosses a
threshold, and then sets a driver input, injects a sensor fault, or ends the run.
"""
from __future__ import annotations

import types

import numba as nb
import numpy as np

from vehicle_assist.core.fsm import log_event
from vehicle_assist.core.tables import interp

from vehicle_assist.drivers.scripted import (  # noqa: F401  (re-exported for the compositions)
    IN_ACCELERATOR,
    IN_BRAKE_PEDAL,
    IN_GEAR_LEVER,
    IN_HAND_VALVE,
    IN_STEERING,
    INPUTS,
    driver_inputs,
)
# event actions
ACT_SET_INPUT, ACT_SENSOR_FAULT, ACT_STOP, ACT_ACTUATOR_FAULT = range(4)
ACTIONS = ("set_input", "sensor_fault", "stop", "actuator_fault")
OP_ABOVE, OP_BELOW = range(2)
EVENT_CAPACITY = 16
EVENT_BUFFER = 512


# road_at and road_friction_at run every plant step: inlined into the kernels, and a constant table (one
# breakpoint, what interp returns as ys[0]) is read without the call (issue 13: -x % of the truck step)
@nb.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def road_at(s, position_m):
    """(slope_rad, rolling_resistance_coeff) at a distance along the road."""
    if s.road_slope_n == 1:
        slope = s.road_slope_y[0]
    else:
        slope = interp(s.road_slope_x, s.road_slope_y, s.road_slope_n, s.road_slope_extrap, s.road_slope_interp,
                       position_m)
    if s.road_rolling_resistance_n == 1:
        coeff = s.road_rolling_resistance_y[0]
    else:
        coeff = interp(s.road_rolling_resistance_x, s.road_rolling_resistance_y, s.road_rolling_resistance_n,
                       s.road_rolling_resistance_extrap, s.road_rolling_resistance_interp, position_m)
    return slope, coeff


@nb.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def road_friction_at(s, position_m):
    """Tyre-road adhesion coefficient mu at a distance along the road (1.0 unless the scenario gives
    ``road.friction``); the compositions limit the force each axle can transmit to mu*F_z."""
    if s.road_friction_n == 1:
        return s.road_friction_y[0]
    return interp(s.road_friction_x, s.road_friction_y, s.road_friction_n, s.road_friction_extrap,
                  s.road_friction_interp, position_m)


# the sampling tick and the trace row of every kernel step: a countdown, not k % n per step (a division)
@nb.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def countdown(left, every):
    """One step of a countdown that fires at step 0 and then every ``every`` steps: (fires now, steps left).
    Start with ``left = np.int64(0)``."""
    now = left == 0
    if now:
        left = every
    return now, left - 1


@nb.njit(cache=True, nogil=True, error_model="numpy")
def due_events(s, fired, t, signals, due):
    """Mark in ``due`` the events that fire now (each fires once)."""
    any_due = False
    for i in range(int(s.event_count)):
        due[i] = False
        if fired[i]:
            continue
        sig = int(s.event_signal[i])
        if sig < 0:
            ok = t >= s.event_time_s[i] - 1e-12
        else:
            value = signals[sig]
            ok = value > s.event_threshold[i] if int(s.event_op[i]) == OP_ABOVE else value < s.event_threshold[i]
            ok = ok and t >= s.event_time_s[i] - 1e-12
        if ok:
            due[i] = True
            fired[i] = True
            any_due = True
    return any_due


@nb.njit(cache=True, nogil=True, error_model="numpy")
def sensor_delay_buffers(s, n_sensors):
    """Ring buffer for the sensor delays of the scenario (whole sampling ticks) and each sensor's delay."""
    delay_ticks = np.zeros(n_sensors)
    depth = 1
    for i in range(n_sensors):
        delay_ticks[i] = round(s.sensor_delay_s[i] / s.controller_period_s)
        depth = max(depth, int(delay_ticks[i]) + 1)
    return np.zeros((n_sensors, depth)), delay_ticks


# the per-run buffers of the kernels, inlined so that the kernel allocates them itself (as a call, the truck's
# plant step measured 2-5 % slower against the buffers written out in the kernel)
@nb.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def event_buffers(n_signals):
    """Driver and scenario-event state of a run: ``(inputs, override_on, override_value, fired, due, signals)`` -
    the driver inputs (``INPUTS`` order) and each one's event override, the fired/due flag of each event, and the
    values of the layout's ``n_signals`` event signals."""
    n_in = len(INPUTS)
    return (np.zeros(n_in), np.zeros(n_in, dtype=np.bool_), np.zeros(n_in), np.zeros(EVENT_CAPACITY, dtype=np.bool_),
            np.zeros(EVENT_CAPACITY, dtype=np.bool_), np.zeros(n_signals))


@nb.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def sensor_buffers(s, n_sensors, n_actuators):
    """Sensor-model state of a run (plant/sensors.py ``sample_sensors``): ``(history, delay_ticks, actuator_fault,
    fault, fault_value, last, truth, values, ok)`` - the delay ring buffer and each sensor's delay, ``(fault code,
    value)`` per actuator (at least one row), each sensor's injected fault and its value, last good value, true
    value, measured value and validity."""
    history, delay_ticks = sensor_delay_buffers(s, n_sensors)
    return (history, delay_ticks, np.zeros((max(1, n_actuators), 2)), np.zeros(n_sensors), np.zeros(n_sensors),
            np.zeros(n_sensors), np.zeros(n_sensors), np.zeros(n_sensors), np.zeros(n_sensors))


@nb.njit(cache=True, nogil=True, error_model="numpy")
def apply_events(s, fired, due, t, signals, events, n_events, machine_id, override_on, override_value,
                 sensor_fault, sensor_fault_value, actuator_fault):
    """Fire the scenario events due at ``t``: driver-input overrides, sensor faults, actuator faults
    (``actuator_fault[target] = (code, value)``, read by the vehicle composition) and stop.

    Returns (n_events, any event fired, stop requested)."""
    if s.event_count <= 0 or not due_events(s, fired, t, signals, due):
        return n_events, False, False
    stop = False
    for e in range(int(s.event_count)):
        if due[e]:
            n_events = log_event(events, n_events, t, machine_id, 0, 1, e)
            act = int(s.event_action[e])
            tgt = int(s.event_target[e])
            if act == ACT_SET_INPUT:
                override_on[tgt] = True
                override_value[tgt] = s.event_value[e]
            elif act == ACT_SENSOR_FAULT:
                sensor_fault[tgt] = s.event_value[e]
                sensor_fault_value[tgt] = s.event_value2[e]
            elif act == ACT_ACTUATOR_FAULT:
                actuator_fault[tgt, 0] = s.event_value[e]
                actuator_fault[tgt, 1] = s.event_value2[e]
            elif act == ACT_STOP:
                stop = True
    return n_events, True, stop


# --------------------------------------------------------------------------- batch path (the chunk call)
def _simulate_many(p_all, s_all, idx, slot, noise, meas_all, ctl_a_all, ctl_b_all, rows, events, written,
                   flat_rows, cols, gathered):
    """Run variants ``p_all[idx[j]]``, ``s_all[idx[j]]`` into ``rows[slot[j]]`` in one compiled call (no record
    unboxing per run); ``written[slot[j]]`` gets each run's record count. The state records are fresh per variant.
    ``flat_rows`` (a float64 view of ``rows``: runs, records, fields), ``cols`` and ``gathered``: right after each
    run, the fields ``cols`` of its records are copied to ``gathered[c, slot[j], :n_rec]`` while the run's trace is
    still in the core's cache (the metrics read them contiguous; no copy if ``cols`` is empty). ``rows`` of one row:
    a scratch trace that every run of the chunk overwrites (its copy in ``gathered`` is what is kept).
    Template of :func:`chunk_runner`: ``simulate`` is the layout's kernel, bound per layout."""
    for j in range(idx.shape[0]):
        i = idx[j]
        r = slot[j]
        tr = r if rows.shape[0] > 1 else 0
        n_rec, _ = simulate(p_all[i], s_all[i], noise, meas_all[j], ctl_a_all[j], ctl_b_all[j],  # noqa: F821
                            rows[tr], events)
        written[r] = n_rec
        for k in range(n_rec):
            for c in range(cols.shape[0]):
                gathered[c, r, k] = flat_rows[tr, k, cols[c]]


_NO_COLS = np.zeros(0, dtype=np.int64)
_NO_ROWS = np.zeros((1, 1, 1))


def chunk_runner(simulate, layout, meas_dtype, initial_state_a, initial_state_b):
    """``(simulate_many, run_chunk)`` of a layout whose kernel is ``simulate(p, s, noise, meas, ctl_a, ctl_b, tr,
    events)``: the compiled chunk loop and its batch interface ``run_chunk(p_all, s_all, idx, slot, noise, rows,
    events, written, flat_rows=None, cols=None, gathered=None)`` (fresh measurement and controller state records
    per variant, from ``meas_dtype`` and the two controllers' ``initial_state``; the last three: the per-run copy of
    some trace fields, see simulate_many).

    One loop for every layout, compiled per layout with its kernel bound as a global: a jitted function passed as
    an argument, or a closure over it, is keyed in numba's cache on the dispatcher object and so recompiles in
    every process; this copy of the template is cached as ``simulate_many_<layout>`` like any other function (numba
    keys it on this file only: an edit of the kernel gets a new cache directory, vehicle_assist/_cache.py)."""
    fn = types.FunctionType(_simulate_many.__code__, {"simulate": simulate, "__name__": __name__},
                            "simulate_many")
    fn.__qualname__ = f"simulate_many_{layout}"
    fn.__doc__ = _simulate_many.__doc__
    simulate_many = nb.njit(cache=True, nogil=True, error_model="numpy")(fn)

    def run_chunk(p_all, s_all, idx, slot, noise, rows, events, written, flat_rows=None, cols=None, gathered=None):
        """Batch interface: the variants ``idx`` of the packed records into trace rows ``slot`` (see
        simulate_many)."""
        n = len(idx)
        if cols is None:
            flat_rows, cols, gathered = _NO_ROWS, _NO_COLS, _NO_ROWS
        return simulate_many(p_all, s_all, idx, slot, noise, np.zeros(n, dtype=meas_dtype),
                             np.repeat(initial_state_a(), n), np.repeat(initial_state_b(), n), rows, events, written,
                             flat_rows, cols, gathered)

    return simulate_many, run_chunk
