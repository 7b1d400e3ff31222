"""Hydraulic brake assist (HBA) of paper 002: recognise a panic application that is too soft from the
master-cylinder pressure and its rise rate, and let the ESP pump raise the wheel pressures to the ABS
control level (brake_assist.md 3; paper P2-P4, P10).

Entry (all, spec 3 / paper P3): p_mc >= P_ON; dp_mc/dt >= G_ON seen within the last T_WIN; v_ref >= V_ON;
brake-light switch on (pedal applied); p_mc rose on each of the last N_RISE samples; pressure sensor
healthy (valid and plausible); and ABS and the pump available (paper P2: "if ABS fails, HBA is not
available"). Exit (any, paper P4): v_ref <= V_OFF; pedal released; p_mc <= P_OFF; p_mc dropped clearly
(p_mc < K_DROP*p_peak and p_peak - p_mc > DP_DROP); sensor, ABS or pump failed. TERMINATING ramps the
wheels out to the driver's pressure (paper P8) and ends when the ECU's wheel-pressure estimate is within
1 bar of it; re-entry only through the full entry test.
"""
from __future__ import annotations

import numba as nb
import numpy as np

from vehicle_assist.core.fsm import StateMachine, Transition, next_mode

INACTIVE, ACTIVE, TERMINATING = range(3)
MODES = ("INACTIVE", "ACTIVE", "TERMINATING")
MACHINE = StateMachine("hba", MODES, (
    Transition("INACTIVE", "ACTIVE", "entry_conditions_met", "paper P3 (1)-(6), spec 3"),
    Transition("ACTIVE", "TERMINATING", "sensor_failed", "pressure sensor invalid or implausible (P3 (6))"),
    Transition("ACTIVE", "TERMINATING", "abs_unavailable", "ABS or return pump failed (paper P2)"),
    Transition("ACTIVE", "TERMINATING", "speed_below_exit", "v <= V_OFF (P4 (1), P10: 5 km/h)"),
    Transition("ACTIVE", "TERMINATING", "pedal_released", "brake-light switch off (P4 (2))"),
    Transition("ACTIVE", "TERMINATING", "pressure_below_exit", "p_mc <= P_OFF (P4 (3), P10: 6 bar)"),
    Transition("ACTIVE", "TERMINATING", "pressure_dropped", "p_mc dropped clearly from its peak (P4 (4), spec 3)"),
    Transition("TERMINATING", "ACTIVE", "entry_conditions_met", "re-entry only through the full entry test (spec 3)"),
    Transition("TERMINATING", "INACTIVE", "ramp_out_complete", "wheel pressures back at the driver's (P8)"),
), "Hydraulic brake assist (functions/brake_assist.py)")
TABLE = MACHINE.table()
GUARDS = MACHINE.guards
G_ENTRY, G_SENSOR, G_ABS, G_SPEED, G_PEDAL, G_PRESSURE, G_DROP, G_RAMPED = range(8)
assert GUARDS == ("entry_conditions_met", "sensor_failed", "abs_unavailable", "speed_below_exit", "pedal_released",
                  "pressure_below_exit", "pressure_dropped", "ramp_out_complete")

# state vector (named indices)
S_MODE, S_P_PREV, S_RISE_COUNT, S_RATE_LATCH_S, S_P_PEAK, S_RATE, S_ENTRY_FLAGS = range(7)
STATE_SIZE = 7


def initial_state() -> np.ndarray:
    return np.zeros(STATE_SIZE)


@nb.njit(cache=True, nogil=True, error_model="numpy")
def hba_step(st, p_mc, speed_mps, pedal_applied, sensor_ok, abs_ok, ramp_done, dt, p, guards):
    """One HBA decision: updates the state vector ``st``; returns (new mode, guard id or -1)."""
    rate = (p_mc - st[S_P_PREV]) / dt
    st[S_RATE] = rate
    st[S_RISE_COUNT] = st[S_RISE_COUNT] + 1.0 if p_mc > st[S_P_PREV] else 0.0
    if rate >= p.brake_assist_on_rate_pa_per_s:
        st[S_RATE_LATCH_S] = p.brake_assist_rate_window_s + 0.5 * dt  # latched for T_WIN (spec 3)
    else:
        st[S_RATE_LATCH_S] = max(st[S_RATE_LATCH_S] - dt, 0.0)
    st[S_P_PREV] = p_mc
    mode = int(st[S_MODE])
    if mode == ACTIVE:
        st[S_P_PEAK] = max(st[S_P_PEAK], p_mc)
    c1 = p_mc >= p.brake_assist_on_pressure_pa
    c2 = st[S_RATE_LATCH_S] > 0.0
    c3 = speed_mps >= p.brake_assist_on_speed_mps
    c4 = pedal_applied
    c5 = st[S_RISE_COUNT] >= p.brake_assist_rise_samples_count
    c6 = sensor_ok
    st[S_ENTRY_FLAGS] = (1.0 * c1 + 2.0 * c2 + 4.0 * c3 + 8.0 * c4 + 16.0 * c5 + 32.0 * c6 + 64.0 * abs_ok)
    guards[G_ENTRY] = c1 and c2 and c3 and c4 and c5 and c6 and abs_ok
    guards[G_SENSOR] = not sensor_ok
    guards[G_ABS] = not abs_ok
    guards[G_SPEED] = speed_mps <= p.brake_assist_off_speed_mps
    guards[G_PEDAL] = not pedal_applied
    guards[G_PRESSURE] = p_mc <= p.brake_assist_off_pressure_pa
    guards[G_DROP] = (p_mc < p.brake_assist_drop_ratio_frac * st[S_P_PEAK]
                      and st[S_P_PEAK] - p_mc > p.brake_assist_drop_min_pa)
    guards[G_RAMPED] = ramp_done
    new, reason = next_mode(TABLE, mode, guards)
    if new == ACTIVE and mode != ACTIVE:
        st[S_P_PEAK] = p_mc
    st[S_MODE] = new
    return new, reason


def guard_buffer() -> np.ndarray:
    return np.zeros(len(GUARDS), dtype=np.bool_)
