"""AMT normal start program: the automated clutch of a plain AMT launch, and gear pre-selection.

This is the start program that an AMT without hill-start assist runs (the paper 000 "normal start
program"); the hill-start assist builds on it. It sees measurements only.

Modes and transitions (first matching row wins; every change is logged with its guard):

    OPEN      -> SHIFTING  gear_change_requested   lever gear differs from the engaged gear, clutch open
    SHIFTING  -> OPEN      gear_engaged            the gearbox reports the lever gear
    OPEN      -> APPROACH  launch_requested        gear engaged and accelerator >= launch threshold
    APPROACH  -> ENGAGE    kiss_point_reached      clutch command at the kiss point
    APPROACH  -> OPEN      launch_abandoned        accelerator released while (nearly) stopped
    ENGAGE    -> LOCKUP    slip_small              |n_e - n_in| <= lock-up slip and vehicle moving
    ENGAGE    -> OPEN      launch_abandoned
    LOCKUP    -> CLOSED    clutch_closed           clutch command reached 1
    CLOSED    -> OPEN      engine_pulled_down      engine speed below the anti-stall speed (stopping)
    APPROACH, ENGAGE -> OPEN  assist_took_over     set by the vehicle composition (never by this step) when
                                                   the hill-start assist takes the clutch
    OPEN      -> CLOSED    assist_handed_over      set by the vehicle composition when the hill-start assist
                                                   finishes with the clutch closed (never by this step)

Clutch command rates: APPROACH +v_A; ENGAGE +v_engage (fixed), or -v_back while the engine is below
the anti-stall speed; LOCKUP +v_C; OPEN/SHIFTING: clutch open (command 0).
"""
from __future__ import annotations

import numba as nb
import numpy as np

from vehicle_assist.core.fsm import StateMachine, Transition, log_event, next_mode

MACHINE = StateMachine(
    "amt_launch",
    modes=("OPEN", "SHIFTING", "APPROACH", "ENGAGE", "LOCKUP", "CLOSED"),
    transitions=(
        Transition("OPEN", "SHIFTING", "gear_change_requested"),
        Transition("SHIFTING", "OPEN", "gear_engaged"),
        Transition("OPEN", "APPROACH", "launch_requested"),
        Transition("APPROACH", "ENGAGE", "kiss_point_reached"),
        Transition("APPROACH", "OPEN", "launch_abandoned"),
        Transition("ENGAGE", "LOCKUP", "slip_small"),
        Transition("ENGAGE", "OPEN", "launch_abandoned"),
        Transition("LOCKUP", "CLOSED", "clutch_closed"),
        Transition("CLOSED", "OPEN", "engine_pulled_down"),
        # set by the vehicle composition (never by this step): an assist takes the clutch, and hands it back
        Transition("APPROACH", "OPEN", "assist_took_over"),
        Transition("ENGAGE", "OPEN", "assist_took_over"),
        Transition("OPEN", "CLOSED", "assist_handed_over"),
    ),
    doc=__doc__ or "",
)
TABLE = MACHINE.table()
OPEN, SHIFTING, APPROACH, ENGAGE, LOCKUP, CLOSED = range(6)
(G_GEAR_CHANGE, G_GEAR_ENGAGED, G_LAUNCH, G_KISS, G_ABANDON, G_SLIP_SMALL, G_CLOSED, G_PULLED_DOWN, G_TOOK_OVER,
 G_HANDED_OVER) = range(10)
assert MACHINE.guards == (
    "gear_change_requested", "gear_engaged", "launch_requested", "kiss_point_reached",
    "launch_abandoned", "slip_small", "clutch_closed", "engine_pulled_down", "assist_took_over",
    "assist_handed_over",
)

STATE_DTYPE = np.dtype([("mode", "f8"), ("clutch_command_frac", "f8"), ("gear_command_index", "f8")])


def initial_state() -> np.recarray:
    s = np.zeros(1, dtype=STATE_DTYPE).view(np.recarray)
    s.mode[0] = OPEN
    return s


@nb.njit(cache=True, nogil=True, error_model="numpy")
def step(c, m, p, dt, t, machine_id, events, n_events):
    """One controller period. ``c`` controller state (mutated), ``m`` measurements, ``p`` parameters.

    Returns the updated event count.
    """
    slip = abs(m.engine_speed_radps - m.input_shaft_speed_radps)
    g = np.zeros(10, dtype=np.bool_)  # g[G_TOOK_OVER], g[G_HANDED_OVER] stay False here: see the table
    g[G_GEAR_CHANGE] = m.gear_lever_index != m.gear_engaged_index or m.gear_lever_index != c.gear_command_index
    g[G_GEAR_ENGAGED] = m.gear_engaged_index == c.gear_command_index
    g[G_LAUNCH] = m.gear_engaged_index > 0 and m.accelerator_frac >= p.amt_launch_launch_accelerator_frac
    g[G_KISS] = c.clutch_command_frac >= p.clutch_kiss_point_frac
    g[G_ABANDON] = m.accelerator_frac < 0.5 * p.amt_launch_launch_accelerator_frac and m.vehicle_speed_mps < p.amt_launch_moving_speed_mps
    g[G_SLIP_SMALL] = slip <= p.amt_launch_lockup_slip_radps and m.vehicle_speed_mps > p.amt_launch_moving_speed_mps
    g[G_CLOSED] = c.clutch_command_frac >= 1.0
    g[G_PULLED_DOWN] = m.engine_speed_ok > 0.5 and m.engine_speed_radps < p.amt_launch_anti_stall_speed_radps

    mode = int(c.mode)
    new_mode, guard = next_mode(TABLE, mode, g)
    if new_mode != mode:
        n_events = log_event(events, n_events, t, machine_id, mode, new_mode, guard)
        c.mode = new_mode
        if new_mode == SHIFTING:
            c.gear_command_index = m.gear_lever_index

    x = c.clutch_command_frac
    if new_mode == OPEN or new_mode == SHIFTING:
        x = 0.0
    elif new_mode == APPROACH:
        x = min(x + p.amt_launch_approach_rate_per_s * dt, p.clutch_kiss_point_frac)
    elif new_mode == ENGAGE:
        if m.engine_speed_ok > 0.5 and m.engine_speed_radps < p.amt_launch_anti_stall_speed_radps:
            x = max(x - p.amt_launch_back_off_rate_per_s * dt, p.clutch_kiss_point_frac)
        else:
            x = x + p.amt_launch_engage_rate_per_s * dt
    elif new_mode == LOCKUP or new_mode == CLOSED:
        x = x + p.amt_launch_lockup_rate_per_s * dt
    c.clutch_command_frac = min(max(x, 0.0), 1.0)
    return n_events
