"""AMT normal start program: the automated clutch of a plain AMT launch, and gear pre-selection.

This is the start program that an AMT without hill-start assist runs (the paper 000 "normal start
program"); the hill-start assist builds on it. It sees measurements only.

Modes and transitions (first matching row wins; every change is logged with its guard):

    OPEN      -> SHIFTING  gear_change_requested   lever gear differs from the engaged gear, clutch open
    SHIFTING  -> OPEN      gear_engaged            the gearbox reports the lever gear
    OPEN      -> APPROACH  launch_requested        gear engaged and accelerator >= launch threshold
    APPROACH  -> ENGAGE    kiss_point_reached      clutch command at the kiss point
    APPROACH  -> OPEN      launch_abandoned        accelerator released while (nearly) stopped
    ENGAGE    -> LOCKUP    slip_small              |n_e - n_in| <= lock-up slip, vehicle moving, and (lock-up engine
                                                   check) the engine runs at or above the lock-up speed and its
                                                   full-load torque there covers the torque the clutch carries
    ENGAGE    -> OPEN      launch_abandoned
    LOCKUP    -> CLOSED    clutch_closed           clutch command reached 1
    CLOSED    -> OPEN      engine_pulled_down      engine speed below the anti-stall speed (stopping)
    APPROACH, ENGAGE, CLOSED -> OPEN  assist_took_over   set by the vehicle composition (never by this
                                                   step) when the hill-start assist takes the clutch (CLOSED: its
                                                   rollback catch after it handed the closed clutch over)
    OPEN      -> CLOSED    assist_handed_over      set by the vehicle composition when the hill-start assist
                                                   finishes with the clutch closed (never by this step)

Clutch command rates: APPROACH +v_A; ENGAGE +v_engage (fixed), or -v_back while the engine is below
the anti-stall speed; LOCKUP +v_C; OPEN/SHIFTING: clutch open (command 0).

Lock-up engine check (issue 7): locking the clutch ties the engine to the vehicle. If the engine has been
dragged down to the input-shaft speed (slip small because the engine fell, not because the truck caught
up) it cannot carry the load there and stalls. The clutch torque is estimated from the engine side,
``T_c = T_e(n_e, theta) - J_e dw_e/dt`` (governor model of the engine file, as an AMT gets engine torque
over the vehicle bus), and lock-up waits until ``n_e >= n_lock`` and ``T_full(n_e) >= T_c``. With
``hill_start_assist.lockup_engine_check_flag = 0`` the check is off (the defect, for the verification engine).

The engine torque model shared with the hill-start assist (:func:`engine_available_torque_nm`)::

    T_av(w, theta) = min(K_gov*(w_set(theta) - w), T_full(w))       all-speed governor, hill_start_amt.md 5.1
"""
from __future__ import annotations

import numba as nb
import numpy as np

from vehicle_assist.core.fsm import StateMachine, Transition, log_event, next_mode
from vehicle_assist.core.tables import interp

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
        Transition("CLOSED", "OPEN", "assist_took_over"),
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

STATE_DTYPE = np.dtype([("mode", "f8"), ("clutch_command_frac", "f8"), ("gear_command_index", "f8"),
                        ("engine_speed_prev_radps", "f8"), ("engine_speed_rate_radps2", "f8"),
                        ("guards", "f8", (10,))])  # guard values of the tick (scratch: no allocation per tick)
SPEED_RATE_FILTER_S = 0.05  # low-pass of dn_e/dt for the clutch-torque estimate (assumed, as the assist's)


def initial_state() -> np.recarray:
    s = np.zeros(1, dtype=STATE_DTYPE).view(np.recarray)
    s.mode[0] = OPEN
    return s


@nb.njit(cache=True, nogil=True, error_model="numpy")
def full_load_torque_nm(p, speed_radps):
    """T_full(w) of the engine file (the engine's full-load curve)."""
    return interp(p.engine_full_load_torque_x, p.engine_full_load_torque_y, p.engine_full_load_torque_n,
                  p.engine_full_load_torque_extrap, p.engine_full_load_torque_interp, speed_radps)


@nb.njit(cache=True, nogil=True, error_model="numpy")
def governed_speed_radps(p, accelerator_frac):
    a = min(max(accelerator_frac, 0.0), 1.0)
    return p.engine_idle_speed_radps + a * (p.engine_high_idle_speed_radps - p.engine_idle_speed_radps)


@nb.njit(cache=True, nogil=True, error_model="numpy")
def governor_gain_nm_per_radps(p, set_speed_radps):
    """The governor's gain K_gov = T_peak/(droop*w_set) (constant gain if the file gives no droop)."""
    if p.engine_governor_droop_frac > 0.0:
        return p.engine_governor_peak_torque_nm / (p.engine_governor_droop_frac * max(set_speed_radps, 1.0))
    return p.engine_governor_gain_nm_per_radps


@nb.njit(cache=True, nogil=True, error_model="numpy")
def engine_available_torque_nm(p, speed_radps, accelerator_frac):
    """Torque the governed engine delivers at speed w and pedal theta: min(K (w_set - w), T_full(w)), >= 0."""
    w_set = governed_speed_radps(p, accelerator_frac)
    t_gov = governor_gain_nm_per_radps(p, w_set) * (w_set - speed_radps)
    return max(min(t_gov, full_load_torque_nm(p, speed_radps)), 0.0)


@nb.njit(cache=True, nogil=True, error_model="numpy")
def engine_best_torque_nm(p, accelerator_frac, lowest_speed_radps):
    """Largest torque the engine holds at pedal theta on a speed at or above ``lowest_speed_radps``:
    max over w in [w_low, w_set] of T_av(w, theta) (0 if w_set <= w_low). Evaluated on 48 speeds."""
    w_set = governed_speed_radps(p, accelerator_frac)
    if w_set <= lowest_speed_radps:
        return 0.0
    best = 0.0
    n = 48
    for i in range(n + 1):
        w = lowest_speed_radps + (w_set - lowest_speed_radps) * i / n
        best = max(best, engine_available_torque_nm(p, w, accelerator_frac))
    return best


@nb.njit(cache=True, nogil=True, error_model="numpy")
def step(c, m, p, dt, t, machine_id, events, n_events):
    """One controller period. ``c`` controller state (mutated), ``m`` measurements, ``p`` parameters.

    Returns the updated event count.
    """
    slip = abs(m.engine_speed_radps - m.input_shaft_speed_radps)
    if m.engine_speed_ok > 0.5:
        raw = (m.engine_speed_radps - c.engine_speed_prev_radps) / dt if c.engine_speed_prev_radps > 0.0 else 0.0
        c.engine_speed_rate_radps2 += dt / (SPEED_RATE_FILTER_S + dt) * (raw - c.engine_speed_rate_radps2)
        c.engine_speed_prev_radps = m.engine_speed_radps
    engine_can_lock = True
    if p.hill_start_assist_lockup_engine_check_flag > 0.5:
        # clutch torque from the engine side, and the engine's full-load torque at the lock-up speed
        t_clutch = (engine_available_torque_nm(p, m.engine_speed_radps, m.accelerator_frac)
                    - p.engine_inertia_kgm2 * c.engine_speed_rate_radps2)
        engine_can_lock = (m.engine_speed_ok > 0.5 and m.engine_speed_radps >= p.amt_launch_lockup_min_speed_radps
                           and full_load_torque_nm(p, m.engine_speed_radps) >= t_clutch)
    g = c.guards  # g[G_TOOK_OVER], g[G_HANDED_OVER] stay False here: see the table
    g[:] = 0.0
    g[G_GEAR_CHANGE] = m.gear_lever_index != m.gear_engaged_index or m.gear_lever_index != c.gear_command_index
    g[G_GEAR_ENGAGED] = m.gear_engaged_index == c.gear_command_index
    g[G_LAUNCH] = m.gear_engaged_index > 0 and m.accelerator_frac >= p.amt_launch_launch_accelerator_frac
    g[G_KISS] = c.clutch_command_frac >= p.clutch_kiss_point_frac
    g[G_ABANDON] = m.accelerator_frac < 0.5 * p.amt_launch_launch_accelerator_frac and m.vehicle_speed_mps < p.amt_launch_moving_speed_mps
    g[G_SLIP_SMALL] = (slip <= p.amt_launch_lockup_slip_radps and m.vehicle_speed_mps > p.amt_launch_moving_speed_mps
                       and engine_can_lock)
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
