"""Pneumatic spring (park) brake of a heavy truck: reservoir, relay valve, spring chambers
(hill_start_amt.md sections 3 and 5.3; common.md 7.2).

Circuit: reservoir (p_s) -> hand park valve -> control line -> relay valve -> spring chambers (p_sp).
The 3/2 solenoid valve of the hill-start assist sits in the control line; it is not part of this module.

    hand valve released: control line = p_s; park position: control line exhausted (0)
    relay valve + chambers, lumped, first order (exact discretisation):
        filling   (p_ctrl > p_sp):  dp_sp/dt = (p_ctrl - p_sp)/tau_fill    (air from the reservoir)
        exhausting (otherwise):     dp_sp/dt = (p_ctrl - p_sp)/tau_exh
    F_g_cap = F_g_max * clip((p_full - p_sp)/(p_full - p_start), 0, 1)     holding capacity at the ground
    lamp (park-brake pressure switch) on while p_sp < p_lamp

With p_ctrl = p_s the lamp goes out after t = tau_fill*ln(p_s/(p_s - p_lamp)): the fit of the paper's
Table 1 (tau_fill = 2.55 s, p_lamp = 4.09 bar) gives 2.53/2.24/2.01/1.83 s at 6.5/7.0/7.5/8.0 bar.
The reservoir is taken as large (its pressure does not drop while the chambers fill).

Service brake (air, lumped): chamber pressure follows pedal*p_s with a first-order lag; ground force
capacity F_sb_cap = F_sb_max * p_sb/p_ref.
"""
from __future__ import annotations

import math

import numba as nb


@nb.njit(cache=True, nogil=True, error_model="numpy")
def hand_valve_control_pressure_pa(released, reservoir_pressure_pa):
    return reservoir_pressure_pa if released > 0.5 else 0.0


@nb.njit(cache=True, nogil=True, error_model="numpy")
def spring_chamber_step(chamber_pa, control_pa, fill_decay, exhaust_decay):
    """Relay valve delivers the control pressure into the chambers (first order, exact step).

    ``fill_decay`` = exp(-dt/tau_fill) and ``exhaust_decay`` = exp(-dt/tau_exh), computed once per run
    by :func:`decay`."""
    d = fill_decay if control_pa > chamber_pa else exhaust_decay
    return control_pa + (chamber_pa - control_pa) * d


@nb.njit(cache=True, nogil=True, error_model="numpy")
def park_brake_capacity_n(chamber_pa, max_force_n, release_start_pa, release_full_pa):
    u = (release_full_pa - chamber_pa) / (release_full_pa - release_start_pa)
    return max_force_n * min(max(u, 0.0), 1.0)


def lamp_time_s(reservoir_pa: float, lamp_pa: float, fill_tau_s: float) -> float:
    """Closed form: time from an exhausted chamber to the lamp going out (Table-1 'release time')."""
    return fill_tau_s * math.log(reservoir_pa / (reservoir_pa - lamp_pa))


@nb.njit(cache=True, nogil=True, error_model="numpy")
def decay(tau_s, dt):
    """exp(-dt/tau): the exact one-step factor of a first-order lag."""
    return math.exp(-dt / tau_s)


@nb.njit(cache=True, nogil=True, error_model="numpy")
def first_order_step(value, target, decay_factor):
    """Exact step of dx/dt = (target - x)/tau with ``decay_factor`` = exp(-dt/tau)."""
    return target + (value - target) * decay_factor


# 3/2 solenoid valve in the control line (paper 000, P3; hill_start_amt.md 3) -------------------------
VALVE_OK = 0
VALVE_STUCK_DEENERGIZED = 1  # also: unpowered (wire broken, fuse): passes the driver's command
VALVE_STUCK_ENERGIZED = 2
VALVE_FAULTS = {"none": VALVE_OK, "unpowered": VALVE_STUCK_DEENERGIZED,
                "stuck_deenergized": VALVE_STUCK_DEENERGIZED, "stuck_energized": VALVE_STUCK_ENERGIZED}


@nb.njit(nb.float64(nb.float64, nb.int64), cache=True, nogil=True, error_model="numpy")
def valve_32_position(command_energized, fault):
    """Actual spool position (1 = energised) from the command and the valve's fault state."""
    if fault == VALVE_STUCK_DEENERGIZED:
        return 0.0
    if fault == VALVE_STUCK_ENERGIZED:
        return 1.0
    return 1.0 if command_energized > 0.5 else 0.0


@nb.njit(cache=True, nogil=True, error_model="numpy")
def valve_32_control_pressure_pa(hand_valve_pa, energized):
    """Relay-valve control pressure behind the 3/2 valve.

    De-energised: line A (hand valve) passes straight through to line B (fail-safe, the truck behaves as
    without the assist). Energised: line A is blocked and line B vents through port 3, so the chambers
    exhaust / stay exhausted and the spring brake stays applied whatever the driver does.
    """
    return 0.0 if energized > 0.5 else hand_valve_pa
