"""EV vehicle control unit (no assist): accelerator -> motor torque request, brake pedal -> EHB pressure.

Measurements only. The pedal-to-torque map is a table in the vehicle file (hill_start_ehb.md 2.4: the
paper's fitted Fig. 7 is lost, the shipped table samples the spec's assumed curve). The brake is by
wire (hill_start_ehb.md P1): pressure command = pedal travel x the pressure at full pedal.
Drive position ``D`` (gear index 1) gives torque; ``N`` (0) none.

Modes: NEUTRAL <-> DRIVE (``drive_selected`` / ``neutral_selected``).
"""
from __future__ import annotations

import numba as nb
import numpy as np

from vehicle_assist.core.fsm import StateMachine, Transition, log_event, next_mode
from vehicle_assist.core.tables import interp

MACHINE = StateMachine(
    "ev_vcu",
    modes=("NEUTRAL", "DRIVE"),
    transitions=(
        Transition("NEUTRAL", "DRIVE", "drive_selected"),
        Transition("DRIVE", "NEUTRAL", "neutral_selected"),
    ),
)
TABLE = MACHINE.table()
NEUTRAL, DRIVE = range(2)
G_DRIVE, G_NEUTRAL = range(2)
STATE_DTYPE = np.dtype([("mode", "f8"), ("torque_request_nm", "f8"), ("brake_pressure_command_pa", "f8"),
                        ("guards", "f8", (2,))])  # guard values of the tick (scratch: no allocation per tick)


def initial_state() -> np.recarray:
    return np.zeros(1, dtype=STATE_DTYPE).view(np.recarray)


@nb.njit(cache=True, nogil=True, error_model="numpy")
def step(c, m, p, dt, t, machine_id, events, n_events):
    g = c.guards
    g[:] = 0.0
    g[G_DRIVE] = m.gear_lever_index >= 1.0
    g[G_NEUTRAL] = m.gear_lever_index < 1.0
    mode = int(c.mode)
    new_mode, guard = next_mode(TABLE, mode, g)
    if new_mode != mode:
        n_events = log_event(events, n_events, t, machine_id, mode, new_mode, guard)
        c.mode = new_mode
    if new_mode == DRIVE:
        c.torque_request_nm = interp(p.motor_pedal_map_x, p.motor_pedal_map_y, p.motor_pedal_map_n,
                                     p.motor_pedal_map_extrap, p.motor_pedal_map_interp, m.accelerator_frac)
    else:
        c.torque_request_nm = 0.0
    c.brake_pressure_command_pa = min(max(m.brake_pedal_frac, 0.0), 1.0) * p.ehb_pedal_full_pressure_pa
    return n_events
