"""Hill-start assist of a battery-electric car with an electro-hydraulic brake (paper 001: Tan, Huang,
Yu, Shu; specification hill_start_ehb.md sections 2-5).

On a slope the EHB holds the car with a pressure computed from the measured grade, and releases it as
the motor torque rises, so that the car neither rolls back nor jerks. The paper's Stateflow chart:

* **Step1 IDLE** - EHB not working (the driver's pedal alone sets the pressure).
* **Step2 SLOPE_CHECK** (``next_1``: car standing in D, driver's brake pedal released) - on a slope?
* **Step3 HOLD** (``next_2``: |grade| >= gamma_min, uphill) - hold force K_h = k_s*m_cal*g*sin(gamma);
  the command moves from the driver's pressure to it without passing through zero.
* **Step4 FOLLOW** (``next_3``: accelerator pressed) - brake force F_b = K - F_tq with
  K = k_s*F_ang + F_margin (the hold safety factor is kept until the motor really carries the grade:
  F_b + F_tq stays at the hold force of the heaviest car, whatever the real mass), F_ang = m_cal*g*sin(gamma)
  (+ rollback correction), F_tq = min(driver's request, torque ceiling, measured torque)*i_0*eta/r;
  Stage-3 guard of the paper (standing and F_tq + F_b < F_ang: never release further).
  Back to IDLE when the car moves forward (v > v_start), the brake is off and the torque ceiling has
  reached the driver's request.

Jerk (paper P8, +-0.1 m/s^3) is bounded by the assist itself, not by the driver's pedal: the net push on
the held car N = F_t - F_b may rise only at B = jerk_design_frac*j_max*delta*m_light once it is within
reach of the lightest car's breakaway force (m_light*g*(sin + f*cos)); after breakaway (car moving) the
brake is released first at B with the torque ceiling frozen, then the torque ceiling rises at B to the
driver's request. The ceiling is only ever *below* the driver's request: the assist never asks for
traction torque the driver did not ask for (the former "torque floor" is removed).

Refusal (explicit, with the computed reason as guard name and ``refusal_code`` = 1 + index in
REFUSAL_REASONS of vehicles/ev_ehb.py): a car rolling back (v < -rollback_speed) while the applied forces
would hold the heaviest car (F_b + F_tq >= k_s*F_ang) and the accelerometer shows they are not transmitted
(a_meas*m_max < adhesion_ratio*(F_b + F_tq)) is adhesion-limited: ``brake_adhesion_limit`` if the brake
alone should hold, else ``traction_limit``; rolling back with the motor at its maximum torque:
``grade_beyond_motor_torque``. REFUSED keeps the brake applied (at least the hold force and the pressure
at refusal), warns and requests the parking brake; the driver's pedal ends it. A driver's brake that
cannot hold the car in IDLE (rolling back in D, same adhesion test) also refuses, keeping the pressure
when the driver lifts the pedal.

Added safety (ours, each with a test): the slope decision of Step2 needs a grade read from a valid
accelerometer at this standstill; without one (sensor lost) SLOPE_CHECK -> IDLE ``slope_sensor_lost`` with the
driver warning (the assist is not available; before, it decided "level road" from the default grade 0);
a car that rolls back while the assist holds it raises the held force at once (a biased slope sensor under-estimates the grade); the driver's brake pedal always wins
(the EHB applies the larger of the driver's and the assist's pressure, and pressing the pedal hands
control back); a lost pressure sensor, a pressure the EHB cannot build, or ``max_hold_time_s`` put the
assist in DEGRADED with the reason as the event: it keeps holding and releasing with the torque (without
the Stage-3 check when the pressure sensor is lost), raises the driver warning, and after the maximum
hold time also the parking-brake request.
Measurements only; the controller's masses, brake gain and rolling resistance are its own calibration.
"""
from __future__ import annotations

import math

import numba as nb
import numpy as np

from vehicle_assist.core.fsm import StateMachine, Transition, log_event, next_mode
from vehicle_assist.core.tables import interp

MACHINE = StateMachine(
    "hill_start_ehb",
    modes=("IDLE", "SLOPE_CHECK", "HOLD", "FOLLOW", "DEGRADED", "REFUSED"),
    transitions=(
        Transition("IDLE", "SLOPE_CHECK", "next_1_brake_released_at_standstill"),
        Transition("IDLE", "REFUSED", "brake_adhesion_limit"),
        Transition("IDLE", "HOLD", "rollback_in_drive"),
        Transition("SLOPE_CHECK", "HOLD", "next_2_on_uphill_slope"),
        Transition("SLOPE_CHECK", "IDLE", "level_road"),
        Transition("HOLD", "IDLE", "driver_brakes"),
        Transition("FOLLOW", "IDLE", "driver_brakes"),
        Transition("HOLD", "REFUSED", "brake_adhesion_limit"),
        Transition("FOLLOW", "REFUSED", "brake_adhesion_limit"),
        Transition("FOLLOW", "REFUSED", "traction_limit"),
        Transition("FOLLOW", "REFUSED", "grade_beyond_motor_torque"),
        Transition("DEGRADED", "REFUSED", "brake_adhesion_limit"),
        Transition("DEGRADED", "REFUSED", "traction_limit"),
        Transition("DEGRADED", "REFUSED", "grade_beyond_motor_torque"),
        Transition("HOLD", "DEGRADED", "pressure_sensor_lost"),
        Transition("FOLLOW", "DEGRADED", "pressure_sensor_lost"),
        Transition("HOLD", "DEGRADED", "pressure_not_reached"),
        Transition("HOLD", "DEGRADED", "max_hold_time_reached"),
        Transition("FOLLOW", "DEGRADED", "max_hold_time_reached"),
        Transition("HOLD", "FOLLOW", "next_3_accelerator_pressed"),
        Transition("FOLLOW", "IDLE", "motor_carries_the_grade"),
        Transition("DEGRADED", "IDLE", "driver_brakes"),
        Transition("DEGRADED", "IDLE", "motor_carries_the_grade"),
        Transition("REFUSED", "IDLE", "driver_brakes"),
        Transition("SLOPE_CHECK", "IDLE", "slope_sensor_lost"),
    ),
    doc=__doc__ or "",
)
TABLE = MACHINE.table()
IDLE, SLOPE_CHECK, HOLD, FOLLOW, DEGRADED, REFUSED = range(6)
(G_NEXT1, G_ADHESION, G_ROLLBACK, G_NEXT2, G_LEVEL, G_DRIVER_BRAKES, G_TRACTION, G_MOTOR_LIMIT, G_SENSOR_LOST,
 G_NOT_REACHED, G_MAX_HOLD, G_NEXT3, G_CARRIES, G_SLOPE_LOST) = range(14)
assert MACHINE.guards == (
    "next_1_brake_released_at_standstill", "brake_adhesion_limit", "rollback_in_drive", "next_2_on_uphill_slope",
    "level_road",
    "driver_brakes", "traction_limit", "grade_beyond_motor_torque", "pressure_sensor_lost", "pressure_not_reached",
    "max_hold_time_reached", "next_3_accelerator_pressed", "motor_carries_the_grade", "slope_sensor_lost",
)
# refusal reasons in the order of vehicles/ev_ehb.REFUSAL_REASONS (code k >= 1 is reason k-1)
REFUSAL_GUARDS = ("brake_adhesion_limit", "traction_limit", "grade_beyond_motor_torque")
MACHINE_GUARD_IDS = np.array([MACHINE.guard(name) for name in REFUSAL_GUARDS], dtype=np.int64)
RELEASE_FOLLOW, RELEASE_IMMEDIATE = 0, 1
PEDAL_STEP = 1e-4  # brake-pedal change per period that counts as moving it (pedal sensor resolution, assumed)
RELEASE_MODES = {"follow_torque": RELEASE_FOLLOW, "immediate": RELEASE_IMMEDIATE}
RELEASE_RAMP_S = 0.5  # brake release after breakaway: rate ramp-up time (assumed, 10 x tau_ehb)
RELEASE_TAIL_S = 0.2  # and ease-out time constant near zero (assumed, 4 x tau_ehb)
SLIDE_CONFIRM_S = 0.3  # rolling back this long (summed) while the applied forces would hold the heaviest car or are
# not transmitted: the tyres slide (assumed; a biased slope sensor is caught within ~0.1 s)
MOTOR_AT_LIMIT_FRAC = 0.99  # measured torque >= 99 % of the maximum counts as "at the motor's limit" (assumed)

STATE_DTYPE = np.dtype([
    ("mode", "f8"),
    ("pressure_command_pa", "f8"),
    ("brake_pedal_prev_frac", "f8"),
    ("grade_estimate_rad", "f8"),
    ("grade_force_n", "f8"),           # F_ang (incl. the rollback correction)
    ("rollback_correction_n", "f8"),
    ("torque_force_n", "f8"),          # F_tq
    ("hold_pressure_pa", "f8"),
    ("hold_time_s", "f8"),
    ("mode_time_s", "f8"),
    ("parking_brake_request_flag", "f8"),
    ("slope_checked_flag", "f8"),          # next_1 fires once per brake application (no IDLE/SLOPE_CHECK flapping)
    ("torque_ceiling_nm", "f8"),           # motor-torque ceiling (<= the driver's request) while the assist is active
    ("ceiling_force_n", "f8"),             # the ceiling as a force at the wheels
    ("brake_force_command_n", "f8"),       # F_b the assist commands
    ("net_push_n", "f8"),                  # N = F_t - F_b commanded (rate-limited near breakaway)
    ("mass_ratio", "f8"),                  # lower bound of the car's mass / m_light, proven by holding at N
    ("release_rate_n_per_s", "f8"),        # brake release rate after breakaway (ramped, smooth for the jerk)
    ("driver_force_prev_n", "f8"),         # the driver's request (as a force) one period ago
    ("rollback_time_s", "f8"),             # time rolling back, summed over the engagement
    ("refusal_code", "f8"),                # 0 none, k = 1 + index in REFUSAL_GUARDS
    ("warning_flag", "f8"),
    ("grade_valid_flag", "f8"),            # 1 once the grade was read at this standstill from a valid accelerometer
    ("guards", "f8", (14,)),               # guard values of the tick (scratch: no allocation per tick)
])


def initial_state() -> np.recarray:
    s = np.zeros(1, dtype=STATE_DTYPE).view(np.recarray)
    s.torque_ceiling_nm[:] = 1e9
    return s


@nb.njit(cache=True, nogil=True, error_model="numpy")
def step(c, m, p, dt, t, machine_id, events, n_events):
    """One controller period; ``c`` state, ``m`` measurements, ``p`` vehicle record. Returns the event count."""
    g_acc = 9.81
    mass = p.hill_start_assist_calibration_mass_kg
    k_s = p.hill_start_assist_hold_safety_frac
    m_max = k_s * mass  # the heaviest car the hold covers
    r = p.hill_start_assist_wheel_radius_m
    k_b = p.hill_start_assist_brake_gain_nm_per_pa
    f_coef = p.hill_start_assist_rolling_resistance_coeff
    i0_eta = p.motor_reduction_ratio * p.motor_efficiency_frac
    f_motor_max = p.motor_max_torque_nm * i0_eta / r
    jerk_limit = p.hill_start_assist_jerk_limit_flag > 0.5
    # force-rise budget that keeps the lightest car within the jerk bound: dN/dt <= frac*j_max*delta*m_light
    budget = (p.hill_start_assist_jerk_design_frac * p.hill_start_assist_jerk_max_mps3
              * p.hill_start_assist_rotating_mass_factor * p.hill_start_assist_lightest_mass_kg)
    standing = abs(m.vehicle_speed_mps) < p.hill_start_assist_standstill_speed_mps
    moving_forward = m.vehicle_speed_mps >= p.hill_start_assist_standstill_speed_mps
    rolling_back = m.vehicle_speed_mps < -p.hill_start_assist_rollback_speed_mps
    brake_applied = m.brake_pedal_frac >= p.hill_start_assist_brake_applied_frac
    # next_1 fires while the pedal is being released (P6 / spec 2.3), so the EHB takes over the pressure
    # before it falls below what holds the car; 'driver brakes' is the opposite action (pedal pressed more)
    pedal_rate = m.brake_pedal_frac - c.brake_pedal_prev_frac
    being_released = pedal_rate < -PEDAL_STEP and c.brake_pedal_prev_frac > 0.0
    pressing = brake_applied and pedal_rate > PEDAL_STEP
    mode = int(c.mode)
    active = mode == HOLD or mode == FOLLOW or mode == DEGRADED
    pressure_ok = m.brake_pressure_ok > 0.5

    # slope from the longitudinal accelerometer while the car stands (reads g*sin(gamma) at rest)
    if standing and m.longitudinal_accel_ok > 0.5 and (mode == IDLE or mode == SLOPE_CHECK):
        c.grade_estimate_rad = math.asin(min(max(m.longitudinal_accel_mps2 / g_acc, -1.0), 1.0))
        c.grade_valid_flag = 1.0
    elif mode == IDLE and not standing:
        c.grade_valid_flag = 0.0  # driven since the last reading: it belongs to another place on the road
        # (not in SLOPE_CHECK: it is entered at standstill, and a car that starts to roll there keeps that reading)
    gamma = c.grade_estimate_rad
    t_request = interp(p.motor_pedal_map_x, p.motor_pedal_map_y, p.motor_pedal_map_n, p.motor_pedal_map_extrap,
                       p.motor_pedal_map_interp, m.accelerator_frac)
    t_motor = m.motor_torque_nm if m.motor_torque_ok > 0.5 else 0.0
    f_driver = max(t_request, 0.0) * i0_eta / r
    f_motor = max(t_motor, 0.0) * i0_eta / r
    f_brake_meas = k_b * max(m.brake_pressure_pa, 0.0) / r if pressure_ok else k_b * c.pressure_command_pa / r

    # refusal tests (rolling back): are the applied forces transmitted? (accelerometer reads the transmitted
    # forward force per mass while the car rolls back: a + g*sin(gamma) = (F_b + F_t + F_f)/m)
    applied = f_brake_meas + (f_motor if (mode == FOLLOW or mode == DEGRADED) else 0.0)
    a_meas = m.longitudinal_accel_mps2 if m.longitudinal_accel_ok > 0.5 else 1e9
    not_transmitted = rolling_back and a_meas * m_max < p.hill_start_assist_adhesion_ratio_frac * applied
    hold_heaviest = k_s * mass * g_acc * math.sin(gamma) if active else 0.0
    # a car rolling back while held: the grade force was under-estimated -> raise it at once; only while
    # the EHB delivers what is asked and the forces reach the ground (more pressure does not cure a
    # pressure the EHB cannot build, nor sliding tyres), and never beyond the car's weight
    delivering = pressure_ok and m.brake_pressure_pa >= 0.9 * c.pressure_command_pa
    if rolling_back:
        c.rollback_time_s += dt  # summed over the engagement (reset on entering HOLD): a car that creeps back in
        # short bursts, each caught by the correction below, is sliding too
    if (active or mode == REFUSED) and delivering and rolling_back:
        c.rollback_correction_n += p.hill_start_assist_rollback_gain_n_per_s * dt
    # sliding tyres are told from an under-estimated grade (biased slope sensor, heavier car) by persistence:
    # the correction above catches the latter within a few periods
    sliding = rolling_back and c.rollback_time_s >= SLIDE_CONFIRM_S and (
        not_transmitted or (active and delivering and applied >= hold_heaviest))
    # (never beyond the weight of the heaviest car the hold covers)
    c.grade_force_n = min(mass * g_acc * math.sin(gamma) + c.rollback_correction_n, mass * g_acc)
    margin = p.hill_start_assist_margin_rolling_frac * mass * g_acc * f_coef * math.cos(gamma)
    margin_0 = margin
    k_hold = k_s * max(c.grade_force_n, 0.0) + margin  # K: hold force kept until the motor carries the grade
    c.hold_pressure_pa = k_s * max(c.grade_force_n, 0.0) * r / k_b

    g = c.guards
    g[:] = 0.0
    g[G_NEXT1] = being_released and standing and m.gear_lever_index >= 1.0 and c.slope_checked_flag < 0.5
    # after handing back: the car stops on the slope and rolls back in D with the driver off the brake (e.g. a
    # driver who lifts the accelerator while creeping uphill): hold it again (the last grade reading at rest)
    g[G_ROLLBACK] = (m.gear_lever_index >= 1.0 and rolling_back and not brake_applied
                     and gamma >= p.hill_start_assist_slope_min_rad and c.slope_checked_flag > 0.5
                     and int(p.hill_start_assist_release_mode) != RELEASE_IMMEDIATE)
    # the slope decision needs a grade read at this standstill: with the accelerometer lost there is none, and
    # "level road" would be a decision from an invalid signal -> stand down with the warning (HSA unavailable)
    grade_valid = c.grade_valid_flag > 0.5
    g[G_NEXT2] = grade_valid and gamma >= p.hill_start_assist_slope_min_rad
    g[G_LEVEL] = grade_valid and gamma < p.hill_start_assist_slope_min_rad
    g[G_SLOPE_LOST] = not grade_valid
    # the driver takes over once their own request carries what the assist holds (a light touch that would
    # not hold the car does not end the hold: the EHB applies the larger of the two requests anyway)
    driver_request_pa = m.brake_pedal_frac * p.ehb_pedal_full_pressure_pa
    handover_pa = c.pressure_command_pa
    if mode == REFUSED:  # refused: the driver takes over with a pedal that holds the heaviest car (not p_max)
        handover_pa = min(handover_pa, (k_s * mass * g_acc * math.sin(gamma) + margin_0) * r / k_b)
    g[G_DRIVER_BRAKES] = pressing and driver_request_pa >= handover_pa
    if mode == IDLE:
        # the driver's own brake cannot hold the car in D (sliding tyres): keep it applied
        g[G_ADHESION] = (m.gear_lever_index >= 1.0 and brake_applied and not_transmitted)
    else:
        g[G_ADHESION] = sliding and applied >= hold_heaviest and f_brake_meas >= hold_heaviest
    # the motor at its limit and the car rolls back, or stands with the brake already released: if the motor
    # gives more than the heaviest car needs (K), its force does not reach the road (traction limit of the driven
    # axle), else the motor cannot carry the grade
    at_limit = t_motor >= MOTOR_AT_LIMIT_FRAC * p.motor_max_torque_nm and c.ceiling_force_n >= f_motor_max * 0.999
    stuck = at_limit and ((rolling_back and not not_transmitted)
                          or (not moving_forward and (mode == FOLLOW or mode == DEGRADED)
                              and c.brake_force_command_n <= 1.0))
    g[G_TRACTION] = (sliding and applied >= hold_heaviest and f_brake_meas < hold_heaviest) or \
        (stuck and f_motor >= k_s * mass * g_acc * math.sin(gamma) + p.hill_start_assist_margin_rolling_frac
         * mass * g_acc * f_coef * math.cos(gamma))
    g[G_MOTOR_LIMIT] = stuck
    g[G_SENSOR_LOST] = not pressure_ok
    g[G_NOT_REACHED] = (pressure_ok and c.mode_time_s > p.hill_start_assist_settle_time_s
                        and m.brake_pressure_pa < 0.9 * c.pressure_command_pa)
    g[G_MAX_HOLD] = c.hold_time_s > p.hill_start_assist_max_hold_time_s
    g[G_NEXT3] = m.accelerator_frac > p.hill_start_assist_accelerator_on_frac
    # the ceiling of the last period reached the driver's request of the last period: handing back adds only the
    # driver's own increment of one period
    caught_up = (not jerk_limit) or c.ceiling_force_n >= c.driver_force_prev_n - 1e-6
    g[G_CARRIES] = (moving_forward and m.vehicle_speed_mps > p.hill_start_assist_start_speed_mps
                    and c.pressure_command_pa <= 1.0 and caught_up)

    new_mode, guard = next_mode(TABLE, mode, g)
    if new_mode != mode:
        n_events = log_event(events, n_events, t, machine_id, mode, new_mode, guard)
        c.mode = new_mode
        c.mode_time_s = 0.0
        if new_mode == HOLD:
            c.pressure_command_pa = max(m.brake_pressure_pa, 0.0) if pressure_ok else c.hold_pressure_pa
            c.slope_checked_flag = 1.0
            c.rollback_time_s = 0.0
            c.brake_force_command_n = k_b * c.pressure_command_pa / r
            c.ceiling_force_n = 0.0
            c.hold_time_s = 0.0
        elif new_mode == FOLLOW:
            c.brake_force_command_n = k_b * c.pressure_command_pa / r
            c.ceiling_force_n = min(f_motor, f_driver)
            c.net_push_n = c.ceiling_force_n - c.brake_force_command_n
            c.mass_ratio = 1.0
        elif new_mode == DEGRADED:
            c.warning_flag = 1.0
            c.parking_brake_request_flag = 1.0 if guard == G_MAX_HOLD else 0.0
        elif new_mode == REFUSED:
            c.warning_flag = 1.0
            c.parking_brake_request_flag = 1.0
            for k in range(len(REFUSAL_GUARDS)):
                if MACHINE_GUARD_IDS[k] == guard:
                    c.refusal_code = k + 1.0
            # keep at least what is applied now (the driver's or the assist's pressure)
            c.pressure_command_pa = max(c.pressure_command_pa, max(m.brake_pressure_pa, 0.0) if pressure_ok else 0.0)
        elif new_mode == IDLE:
            if mode == SLOPE_CHECK or mode == FOLLOW or mode == DEGRADED:
                c.slope_checked_flag = 1.0  # (the rollback catch stays armed after a start)
            c.pressure_command_pa = 0.0
            c.rollback_correction_n = 0.0
            c.warning_flag = 0.0
            c.parking_brake_request_flag = 0.0
            c.refusal_code = 0.0
            if guard == G_SLOPE_LOST:
                c.warning_flag = 1.0  # the driver is told the hill-start assist is not available
    else:
        c.mode_time_s += dt
    if new_mode == HOLD or new_mode == FOLLOW or new_mode == DEGRADED:
        c.hold_time_s += dt
    if new_mode == DEGRADED and c.hold_time_s > p.hill_start_assist_max_hold_time_s:
        c.parking_brake_request_flag = 1.0  # also when degraded for another reason first
    if pressing:
        c.slope_checked_flag = 0.0  # a new brake application re-arms next_1
    c.brake_pedal_prev_frac = m.brake_pedal_frac
    c.driver_force_prev_n = f_driver

    # pressure command and torque ceiling
    p_cmd = c.pressure_command_pa
    ceiling = 1e9
    if new_mode == HOLD:
        # from the driver's pressure to the hold force, never through zero
        p_cmd = min(k_hold * r / k_b, p.ehb_max_pressure_pa)
        c.brake_force_command_n = k_b * p_cmd / r
        c.torque_force_n = 0.0
    elif new_mode == FOLLOW or new_mode == DEGRADED:
        f_cap_prev = c.ceiling_force_n
        f_b_prev = c.brake_force_command_n
        probing = False
        if int(p.hill_start_assist_release_mode) == RELEASE_IMMEDIATE:
            f_b = 0.0  # negative control of the spec (S5): release as soon as the pedal moves
            f_cap = f_driver
        elif not jerk_limit:
            # negative control of the spec (S6): torque as the driver asks, brake follows it at once
            f_cap = f_driver
            f_b = max(k_hold - min(f_driver, f_motor), 0.0)
        elif moving_forward:
            # the car moves forward with the brake on: the motor carries the grade. The net push keeps rising
            # at the budget B, but the brake goes first at 2B while the torque ceiling is lowered at B (only
            # ever below the driver's request), so the drag is gone in half the time; then the ceiling rises
            # at B to the driver's request
            # at B to the driver's request. The ceiling is set from the *measured* brake force, so the torque
            # makes up for the EHB's lag and the net push stays smooth when the brake reaches zero
            rate = max(c.mass_ratio, 1.0) * budget  # the mass proven before breakaway
            # the release rate ramps from the standing split (rate/2) to 2*rate within RELEASE_RAMP_S and eases
            # out over RELEASE_TAIL_S near zero: no step in the brake-force rate, which the EHB lag would turn
            # into a jerk
            c.release_rate_n_per_s = min(2.0 * rate, c.release_rate_n_per_s + 1.5 * rate * dt / RELEASE_RAMP_S)
            f_b = max(f_b_prev - min(c.release_rate_n_per_s, f_b_prev / RELEASE_TAIL_S) * dt, 0.0)
            if f_b < 1.0:
                f_b = 0.0
            n_prev = min(c.net_push_n, f_cap_prev - f_brake_meas)  # from the measured brake at the switch
            f_cap = max(min(n_prev + rate * dt + f_brake_meas, f_driver), 0.0)
            c.net_push_n = f_cap - f_brake_meas
        else:
            # standing: net push N = F_t - F_b, rate-limited near the lightest car's breakaway
            f_d = min(f_driver, f_motor_max)
            # (only while the motor really gives its maximum: the request alone says nothing in N or with a motor
            # fault, and releasing then let the car creep back at up to 5 mm/s on 10 deg)
            probing = (f_d >= f_motor_max * 0.999 and k_hold > f_motor_max
                       and t_motor >= MOTOR_AT_LIMIT_FRAC * p.motor_max_torque_nm)
            if probing:
                n_des = f_motor_max  # driver asks the motor's maximum: allow the brake to go (watched for rollback)
            else:
                n_des = f_d - max(k_hold - f_d, 0.0)
            n_prev = c.net_push_n
            n_light = p.hill_start_assist_lightest_mass_kg * g_acc * (math.sin(gamma) + f_coef * math.cos(gamma))
            n_window = 0.9 * n_light
            # a car still held at net push N weighs at least N/(g*(sin + f*cos)): the budget grows with it
            if n_light > 0.0:
                c.mass_ratio = max(1.0, n_prev / n_light)
            n_cmd = n_des
            if n_des > n_prev:  # a rise: free up to the window, then at the budget
                n_cmd = min(n_des, max(n_prev, n_window) + c.mass_ratio * budget * dt)
            c.net_push_n = n_cmd
            c.release_rate_n_per_s = 0.5 * c.mass_ratio * budget
            f_cap = min(max(0.5 * (n_cmd + k_hold), n_cmd), f_d)
            f_b = max(f_cap - n_cmd, 0.0)
            # the brake never credits more motor force than the motor gives (lag, fault) or the driver asks
            # (skipped only by the probe; before, any full pedal, n_des = f_motor_max, skipped it: N + full pedal crept back)
            f_b = f_b if probing else max(f_b, k_hold - min(f_cap, f_driver, f_motor))
            f_b = max(f_b, 0.0)
        c.torque_force_n = min(f_cap, f_driver, f_motor)
        if standing and c.torque_force_n + f_brake_meas < c.grade_force_n and pressure_ok and not probing:
            f_b = max(f_b, f_b_prev)  # Stage 3: released too fast -> no further release
        if rolling_back and int(p.hill_start_assist_release_mode) != RELEASE_IMMEDIATE:
            f_b = max(f_b, k_hold)  # rolling back: re-apply the hold force at once
        c.ceiling_force_n = f_cap
        c.brake_force_command_n = f_b
        p_cmd = min(f_b * r / k_b, p.ehb_max_pressure_pa)
        ceiling = f_cap * r / i0_eta
    elif new_mode == REFUSED:
        p_cmd = min(max(c.pressure_command_pa, k_hold * r / k_b), p.ehb_max_pressure_pa)
        c.brake_force_command_n = k_b * p_cmd / r
    else:
        p_cmd = 0.0
        c.brake_force_command_n = 0.0
        c.torque_force_n = 0.0
    c.pressure_command_pa = p_cmd
    c.torque_ceiling_nm = ceiling
    return n_events



@nb.njit(cache=True, nogil=True, error_model="numpy")
def is_active(c):
    mode = int(c.mode)
    return mode == HOLD or mode == FOLLOW or mode == DEGRADED or mode == REFUSED
