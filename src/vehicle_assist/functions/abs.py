"""Anti-lock braking: rule-based hold / dump / build per wheel on wheel slip and wheel deceleration
(brake_assist.md 4.3; paper 002 P7; std: Bosch Automotive Handbook, ABS control cycle).

Per wheel, from the measurements only: wheel speed v_w = omega_meas*r, the ESP reference speed v_ref
(functions/esp.py), slip lambda = (v_ref - v_w)/max(v_ref, 1 m/s) and wheel-centre deceleration a_w. a_w is
filtered (``esp.abs_signal_filter_flag``, functions/esp.py ``abs_wheel_decel_mps2``): outside DUMP the least-squares
slope of the last 3 samples, -(v_w,k - v_w,k-2)/(2*dt_c), half the noise of the one-period difference; in DUMP (the
exit test) the one-period difference -(v_w - v_w_prev)/dt_c. Flag 0 (seeded defect): the one-period difference always.

    lock_threatened : lambda > L_DUMP or a_w > A_DUMP           -> DUMP
    slip_high       : lambda > L_HOLD                            -> HOLD
    slip_recovering : not lock_threatened (leave DUMP)           -> HOLD
    slip_recovered  : lambda <= L_HOLD and a_w <= A_REBUILD (wheel turning with the car again) -> BUILD (pulsed)
    build_idle      : BUILD for abs_idle_time_s with no hold/dump -> OFF (wheel back to the driver / HBA)
    abs_off         : v_ref below the ABS minimum speed, the driver released, or ABS failed -> OFF

The ESP controller (functions/esp.py) turns the ABS mode into a valve mode through its arbitration table
and applies select-low on the rear axle and the yaw-moment build-up delay on split-mu.
"""
from __future__ import annotations

import numba as nb
import numpy as np

from vehicle_assist.core.fsm import StateMachine, Transition, next_mode

OFF, HOLD, DUMP, BUILD = range(4)
MODES = ("OFF", "HOLD", "DUMP", "BUILD")
MACHINE_ROWS = (
    Transition("OFF", "DUMP", "lock_threatened", "slip or wheel deceleration beyond the dump threshold"),
    Transition("OFF", "HOLD", "slip_high", "slip beyond the hold threshold"),
    Transition("HOLD", "OFF", "abs_off", "below the ABS speed, pedal released, or ABS failed"),
    Transition("HOLD", "DUMP", "lock_threatened"),
    Transition("HOLD", "BUILD", "slip_recovered", "slip back below the hold threshold, wheel not decelerating"),
    Transition("DUMP", "OFF", "abs_off"),
    Transition("DUMP", "HOLD", "slip_recovering", "slip and deceleration back inside the dump thresholds"),
    Transition("BUILD", "OFF", "abs_off"),
    Transition("BUILD", "DUMP", "lock_threatened"),
    Transition("BUILD", "HOLD", "slip_high"),
    Transition("BUILD", "OFF", "build_idle", "no hold or dump for abs_idle_time_s: the wheel goes back to the driver"),
)
G_LOCK, G_SLIP_HIGH, G_ABS_OFF, G_RECOVERED, G_RECOVERING, G_IDLE = range(6)


def machine(wheel: str) -> StateMachine:
    return StateMachine(f"abs_{wheel}", MODES, MACHINE_ROWS, "ABS of one wheel (functions/abs.py)")


TABLE = machine("fl").table()
assert machine("fl").guards == ("lock_threatened", "slip_high", "abs_off", "slip_recovered", "slip_recovering",
                                "build_idle")


@nb.njit(cache=True, nogil=True, error_model="numpy")
def abs_step(mode, time_in_build_s, slip, wheel_decel_mps2, abs_allowed, dump_slip, hold_slip, dump_decel,
             rebuild_decel, idle_time_s, table, guards):
    """One ABS decision of one wheel: returns (new mode, guard id or -1)."""
    lock = slip > dump_slip or wheel_decel_mps2 > dump_decel
    guards[G_LOCK] = lock and abs_allowed
    guards[G_SLIP_HIGH] = slip > hold_slip and abs_allowed
    guards[G_ABS_OFF] = not abs_allowed
    guards[G_RECOVERED] = slip <= hold_slip and wheel_decel_mps2 <= rebuild_decel
    guards[G_RECOVERING] = not lock
    guards[G_IDLE] = time_in_build_s >= idle_time_s
    return next_mode(table, mode, guards)


def guard_buffer() -> np.ndarray:
    return np.zeros(6, dtype=np.bool_)
