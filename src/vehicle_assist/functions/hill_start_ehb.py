"""Hill-start assist of a battery-electric car with an electro-hydraulic brake (paper 001: Tan, Huang,
Yu, Shu; specification hill_start_ehb.md sections 2-5).

On a slope the EHB holds the car with a pressure computed from the measured grade, and releases it as
the motor torque rises, so that the car neither rolls back nor jerks. The paper's Stateflow chart:

* **Step1 IDLE** - EHB not working (the driver's pedal alone sets the pressure).
* **Step2 SLOPE_CHECK** (``next_1``: car standing in D, driver's brake pedal released) - on a slope?
* **Step3 HOLD** (``next_2``: |grade| >= gamma_min, uphill) - hold pressure from the grade,
  p_hold = k_s*G*sin(gamma)*r/K_b; the command moves from the driver's pressure to p_hold without
  passing through zero.
* **Step4 FOLLOW** (``next_3``: accelerator pressed) - brake force F_b = F_ang - F_tq (+ F_margin),
  F_ang = G*sin(gamma_meas), F_tq = min(T_request(pedal), T_motor)*i_0*eta/r; Stage-3 guard of the paper
  (standing and F_tq + F_b < F_ang: never release further); while moving the release rate is limited so
  that the jerk stays within j_max. Back to IDLE when F_tq > F_ang and v > v_start and the brake is off.

Added safety (ours, each with a test): a car that rolls back while the assist holds it raises the held
force at once (a biased slope sensor under-estimates the grade); the driver's brake pedal always wins
(the EHB applies the larger of the driver's and the assist's pressure, and pressing the pedal hands
control back); a lost pressure sensor, a pressure the EHB cannot build, or ``max_hold_time_s`` put the
assist in DEGRADED with the reason as the event: it keeps holding and releasing with the torque (without
the Stage-3 check when the pressure sensor is lost), raises the driver warning, and after the maximum
hold time also the parking-brake request.
Measurements only; the controller's mass, brake gain and rolling resistance are its own calibration.
"""
from __future__ import annotations

import math

import numba as nb
import numpy as np

from vehicle_assist.core.fsm import StateMachine, Transition, log_event, next_mode
from vehicle_assist.core.tables import interp

MACHINE = StateMachine(
    "hill_start_ehb",
    modes=("IDLE", "SLOPE_CHECK", "HOLD", "FOLLOW", "DEGRADED"),
    transitions=(
        Transition("IDLE", "SLOPE_CHECK", "next_1_brake_released_at_standstill"),
        Transition("SLOPE_CHECK", "HOLD", "next_2_on_uphill_slope"),
        Transition("SLOPE_CHECK", "IDLE", "level_road"),
        Transition("HOLD", "IDLE", "driver_brakes"),
        Transition("FOLLOW", "IDLE", "driver_brakes"),
        Transition("HOLD", "DEGRADED", "pressure_sensor_lost"),
        Transition("FOLLOW", "DEGRADED", "pressure_sensor_lost"),
        Transition("HOLD", "DEGRADED", "pressure_not_reached"),
        Transition("HOLD", "DEGRADED", "max_hold_time_reached"),
        Transition("FOLLOW", "DEGRADED", "max_hold_time_reached"),
        Transition("HOLD", "FOLLOW", "next_3_accelerator_pressed"),
        Transition("FOLLOW", "IDLE", "motor_carries_the_grade"),
        Transition("DEGRADED", "IDLE", "driver_brakes"),
        Transition("DEGRADED", "IDLE", "motor_carries_the_grade"),
    ),
    doc=__doc__ or "",
)
TABLE = MACHINE.table()
IDLE, SLOPE_CHECK, HOLD, FOLLOW, DEGRADED = range(5)
(G_NEXT1, G_NEXT2, G_LEVEL, G_DRIVER_BRAKES, G_SENSOR_LOST, G_NOT_REACHED, G_MAX_HOLD, G_NEXT3,
 G_CARRIES) = range(9)
assert MACHINE.guards == (
    "next_1_brake_released_at_standstill", "next_2_on_uphill_slope", "level_road", "driver_brakes",
    "pressure_sensor_lost", "pressure_not_reached", "max_hold_time_reached", "next_3_accelerator_pressed",
    "motor_carries_the_grade",
)
RELEASE_FOLLOW, RELEASE_IMMEDIATE = 0, 1
PEDAL_STEP = 1e-4  # brake-pedal change per period that counts as moving it (pedal sensor resolution, assumed)
RELEASE_MODES = {"follow_torque": RELEASE_FOLLOW, "immediate": RELEASE_IMMEDIATE}

STATE_DTYPE = np.dtype([
    ("mode", "f8"),
    ("pressure_command_pa", "f8"),
    ("brake_pedal_prev_frac", "f8"),
    ("grade_estimate_rad", "f8"),
    ("grade_force_n", "f8"),           # F_ang (incl. the rollback correction)
    ("rollback_correction_n", "f8"),
    ("torque_force_n", "f8"),          # F_tq
    ("torque_force_prev_n", "f8"),
    ("hold_pressure_pa", "f8"),
    ("hold_time_s", "f8"),
    ("mode_time_s", "f8"),
    ("parking_brake_request_flag", "f8"),
    ("slope_checked_flag", "f8"),          # next_1 fires once per brake application (no IDLE/SLOPE_CHECK flapping)
    ("torque_floor_nm", "f8"),             # motor-torque request floor while holding (torque coordination)
    ("warning_flag", "f8"),
])


def initial_state() -> np.recarray:
    return np.zeros(1, dtype=STATE_DTYPE).view(np.recarray)


@nb.njit(cache=True, nogil=True, error_model="numpy")
def step(c, m, p, dt, t, machine_id, events, n_events):
    """One controller period; ``c`` state, ``m`` measurements, ``p`` vehicle record. Returns the event count."""
    g_acc = 9.81
    mass = p.hill_start_assist_assumed_mass_kg
    r = p.hill_start_assist_wheel_radius_m
    k_b = p.hill_start_assist_brake_gain_nm_per_pa
    i0_eta = p.motor_reduction_ratio * p.motor_efficiency_frac
    standing = abs(m.vehicle_speed_mps) < p.hill_start_assist_standstill_speed_mps
    brake_applied = m.brake_pedal_frac >= p.hill_start_assist_brake_applied_frac
    # next_1 fires while the pedal is being released (P6 / spec 2.3), so the EHB takes over the pressure
    # before it falls below what holds the car; 'driver brakes' is the opposite action (pedal pressed more)
    pedal_rate = m.brake_pedal_frac - c.brake_pedal_prev_frac
    being_released = pedal_rate < -PEDAL_STEP and c.brake_pedal_prev_frac > 0.0
    pressing = brake_applied and pedal_rate > PEDAL_STEP
    mode = int(c.mode)

    # slope from the longitudinal accelerometer while the car stands (reads g*sin(gamma) at rest)
    if standing and m.longitudinal_accel_ok > 0.5 and (mode == IDLE or mode == SLOPE_CHECK):
        c.grade_estimate_rad = math.asin(min(max(m.longitudinal_accel_mps2 / g_acc, -1.0), 1.0))
    gamma = c.grade_estimate_rad
    # a car rolling back while held: the grade force was under-estimated -> raise it at once; only while
    # the EHB delivers what is asked (a pressure it cannot build is not cured by asking more), and never
    # beyond the car's weight
    delivering = m.brake_pressure_ok > 0.5 and m.brake_pressure_pa >= 0.9 * c.pressure_command_pa
    if ((mode == HOLD or mode == FOLLOW or mode == DEGRADED) and delivering
            and m.vehicle_speed_mps < -p.hill_start_assist_rollback_speed_mps):
        c.rollback_correction_n += p.hill_start_assist_rollback_gain_n_per_s * dt
    c.grade_force_n = min(mass * g_acc * math.sin(gamma) + c.rollback_correction_n, mass * g_acc)
    t_request = interp(p.motor_pedal_map_x, p.motor_pedal_map_y, p.motor_pedal_map_n, p.motor_pedal_map_extrap,
                       p.motor_pedal_map_interp, m.accelerator_frac)
    t_motor = m.motor_torque_nm if m.motor_torque_ok > 0.5 else 0.0
    # torque coordination: while the car stands on the assist's brake, the motor keeps the torque that the
    # measured brake force does not yet carry (F_t >= F_ang + F_margin - F_b): a driver backing off the pedal
    # lowers the torque only as fast as the EHB re-builds; the composition applies max(driver, floor)
    if (mode == HOLD or mode == FOLLOW or mode == DEGRADED) and standing and m.brake_pressure_ok > 0.5:
        f_brake = k_b * m.brake_pressure_pa / r
        f_margin = p.hill_start_assist_margin_rolling_frac * mass * g_acc * p.hill_start_assist_rolling_resistance_coeff
        needed_nm = max(c.grade_force_n + f_margin - f_brake, 0.0) * r / i0_eta
        c.torque_floor_nm = min(needed_nm, max(t_motor, 0.0))  # keep what the motor has, never ask for more
    else:
        c.torque_floor_nm = 0.0
    # F_tq credits the driver's request, not the floor: the brake re-builds for what the driver wants, and
    # the floor falls as it does
    c.torque_force_prev_n = c.torque_force_n
    c.torque_force_n = max(min(t_request, t_motor), 0.0) * i0_eta / r
    margin = p.hill_start_assist_margin_rolling_frac * mass * g_acc * p.hill_start_assist_rolling_resistance_coeff * math.cos(gamma)
    c.hold_pressure_pa = p.hill_start_assist_hold_safety_frac * max(c.grade_force_n, 0.0) * r / k_b
    pressure_ok = m.brake_pressure_ok > 0.5

    g = np.zeros(9, dtype=np.bool_)
    g[G_NEXT1] = being_released and standing and m.gear_lever_index >= 1.0 and c.slope_checked_flag < 0.5
    g[G_NEXT2] = gamma >= p.hill_start_assist_slope_min_rad
    g[G_LEVEL] = gamma < p.hill_start_assist_slope_min_rad
    # the driver takes over once their own request carries what the assist holds (a light touch that would
    # not hold the car does not end the hold: the EHB applies the larger of the two requests anyway)
    driver_request_pa = m.brake_pedal_frac * p.ehb_pedal_full_pressure_pa
    g[G_DRIVER_BRAKES] = pressing and driver_request_pa >= c.pressure_command_pa
    g[G_SENSOR_LOST] = not pressure_ok
    g[G_NOT_REACHED] = (pressure_ok and c.mode_time_s > p.hill_start_assist_settle_time_s
                        and m.brake_pressure_pa < 0.9 * c.pressure_command_pa)
    g[G_MAX_HOLD] = c.hold_time_s > p.hill_start_assist_max_hold_time_s
    g[G_NEXT3] = m.accelerator_frac > p.hill_start_assist_accelerator_on_frac
    g[G_CARRIES] = (c.torque_force_n > c.grade_force_n and m.vehicle_speed_mps > p.hill_start_assist_start_speed_mps
                    and c.pressure_command_pa <= 1.0)

    new_mode, guard = next_mode(TABLE, mode, g)
    if new_mode != mode:
        n_events = log_event(events, n_events, t, machine_id, mode, new_mode, guard)
        c.mode = new_mode
        c.mode_time_s = 0.0
        if new_mode == HOLD:
            c.pressure_command_pa = max(m.brake_pressure_pa, 0.0) if pressure_ok else c.hold_pressure_pa
            c.hold_time_s = 0.0
        elif new_mode == DEGRADED:
            c.warning_flag = 1.0
            c.parking_brake_request_flag = 1.0 if guard == G_MAX_HOLD else 0.0
        elif new_mode == IDLE:
            if mode == SLOPE_CHECK:
                c.slope_checked_flag = 1.0
            c.pressure_command_pa = 0.0
            c.rollback_correction_n = 0.0
            c.warning_flag = 0.0
            c.parking_brake_request_flag = 0.0
    else:
        c.mode_time_s += dt
    if new_mode == HOLD or new_mode == FOLLOW or new_mode == DEGRADED:
        c.hold_time_s += dt
    if new_mode == DEGRADED and c.hold_time_s > p.hill_start_assist_max_hold_time_s:
        c.parking_brake_request_flag = 1.0  # also when degraded for another reason first
    if pressing:
        c.slope_checked_flag = 0.0  # a new brake application re-arms next_1
    c.brake_pedal_prev_frac = m.brake_pedal_frac

    # pressure command
    p_cmd = c.pressure_command_pa
    if new_mode == HOLD:
        # from the driver's pressure to p_hold with the EHB dynamics, never through zero
        p_cmd = min(c.hold_pressure_pa, p.ehb_max_pressure_pa)
    elif new_mode == FOLLOW or new_mode == DEGRADED:
        if int(p.hill_start_assist_release_mode) == RELEASE_IMMEDIATE:
            target = 0.0  # negative control of the spec (S5): release as soon as the pedal moves
        else:
            target = max(c.grade_force_n - c.torque_force_n + margin, 0.0) * r / k_b
        p_meas = m.brake_pressure_pa if pressure_ok else c.pressure_command_pa
        if standing and c.torque_force_n + k_b * p_meas / r < c.grade_force_n:
            target = max(target, c.pressure_command_pa)  # Stage 3: released too fast -> no further release
        if target < c.pressure_command_pa and not standing:
            # jerk-aware release while moving: -dF_b/dt <= j_max*delta*m - dF_t/dt
            d_ft = (c.torque_force_n - c.torque_force_prev_n) / dt
            max_drop = r / k_b * max(0.0, p.hill_start_assist_jerk_max_mps3 * p.hill_start_assist_rotating_mass_factor
                                     * mass - d_ft) * dt
            target = max(target, c.pressure_command_pa - max_drop)
        p_cmd = min(target, p.ehb_max_pressure_pa)
    else:
        p_cmd = 0.0
    c.pressure_command_pa = p_cmd
    return n_events


@nb.njit(cache=True, nogil=True, error_model="numpy")
def is_active(c):
    mode = int(c.mode)
    return mode == HOLD or mode == FOLLOW or mode == DEGRADED
