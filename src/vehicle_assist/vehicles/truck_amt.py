"""Heavy AMT truck: longitudinal body on a grade + governed diesel + dry clutch + AMT gearbox +
air service brake + spring park brake, driven by the scenario's driver and the AMT start program.

This module is the one place that knows plants, sensors, controllers and the driver of this vehicle.
Each plant step (1 ms default):

1. scenario events and driver inputs (pedals, gear lever, hand park valve);
2. every controller period: sample all sensors (bias, noise, delay, faults), then run the controllers
   on that one sample (sample, then advance);
3. actuators (clutch actuator lag, AMT shift), pneumatics (service brake, relay valve + spring chambers);
4. driveline and vehicle (clutch slip/lock, engine, stick/slip at standstill), semi-implicit Euler;
5. every record period: write the trace row.

Hybrid elements are state machines whose mode changes are logged as events:
vehicle HELD/MOVING, clutch SLIPPING/LOCKED, engine RUNNING/STALLED, gearbox IN_GEAR/SHIFTING.
Driveline equations (hill_start_amt.md 5.2):

    slipping:  J_e*dw_e/dt = T_e - T_c,   T_c = T_cap*sign(w_e - w_in)
               delta_v*m*dv/dt = T_c*i*eta/r - F_f - F_w - F_i - F_brakes     (stick/slip at rest)
    locked:    (delta_v*m + J_e*(i/r)^2*eta)*dv/dt = T_e*i*eta/r - F_f - F_w - F_i - F_brakes
               T_c = T_e - J_e*(i/r)*dv/dt, lock kept while |T_c| <= T_cap

Tyre adhesion (issue 7): the drive force and the park-brake force act on the driven, spring-braked rear
tandem and are limited to mu*F_z,rear; the service brake (all axles) and the park brake together to
mu*m*g*cos(alpha). mu from ``road.friction`` (``road_friction_at``, default 1.0). The rear axle load is the
static split of the empty truck plus the payload at its own split, with the grade load transfer
(common.md 9, acceleration transfer neglected at launch):

    F_z,rear = g*[(m0*phi0 + m_p*phi_p)*cos(alpha) + (m0*h0 + m_p*h_p)/l*sin(alpha)],   m_p = max(m - m0, 0)

Wheel spin is quasi-static: beyond the limit the driven wheels slip, the ground force stays at mu*F_z,rear
and the driveline speed stays tied to the vehicle speed (no separate wheel-spin state; the surplus clutch
work goes into the tyre contact). A spinning start therefore shows as a truck that does not climb (or rolls
back) while the clutch delivers more than the grade needs.
"""
from __future__ import annotations

import math

import numba as nb
import numpy as np

from vehicle_assist.conventions import G_MPS2, STANDSTILL_SPEED_MPS
from vehicle_assist.core.fsm import StateMachine, Transition, log_event
from vehicle_assist.functions import amt_launch, hill_start_amt
from vehicle_assist.plant.brakes.pneumatic import (
    decay,
    first_order_step,
    hand_valve_control_pressure_pa,
    park_brake_capacity_n,
    spring_chamber_step,
    valve_32_control_pressure_pa,
    valve_32_position,
)
from vehicle_assist.plant.longitudinal import (
    aero_drag_n,
    equivalent_mass_kg,
    grade_resistance_n,
    rolling_resistance_capacity_n,
    stick_slip_step,
)
from vehicle_assist.plant.powertrain.clutch import actuator_step, clutch_capacity_nm, sign, slip_power_w
from vehicle_assist.plant.powertrain.engine import engine_torque_nm
from vehicle_assist.plant.powertrain.gearbox import efficiency_factor, gear_ratio, shift_step
from vehicle_assist.plant.sensors import sample_sensors
from vehicle_assist.vehicles.common import (
    IN_ACCELERATOR,
    IN_BRAKE_PEDAL,
    IN_GEAR_LEVER,
    IN_HAND_VALVE,
    apply_events,
    chunk_runner,
    countdown,
    driver_inputs,
    event_buffers,
    road_at,
    road_friction_at,
    sensor_buffers,
)

LAYOUT = "truck_amt"
G = G_MPS2
V_EPS = STANDSTILL_SPEED_MPS
W_EPS = 1e-6  # rad/s: slip speeds below this count as zero

SENSORS = (
    "vehicle_speed_mps",
    "engine_speed_radps",
    "input_shaft_speed_radps",
    "clutch_position_frac",
    "longitudinal_accel_mps2",
    "park_lamp_flag",
    "reservoir_pressure_pa",
    "brake_pedal_frac",
    "accelerator_frac",
    "hand_valve_released_flag",
    "gear_lever_index",
    "gear_engaged_index",
    "vehicle_mass_kg",
)
SENSOR_DOC = {
    "longitudinal_accel_mps2": "specific force along x: dv/dt + g*sin(slope); reads g*sin(slope) at rest",
    "park_lamp_flag": "park-brake pressure switch: 1 while the spring chambers are below the lamp pressure",
    "vehicle_mass_kg": "load estimate (air-suspension / axle-load sensing); used by the load-adaptive release",
}
ACTUATORS = ("valve_32",)  # actuator faults: valve_32 unpowered | stuck_deenergized | stuck_energized
MEAS_DTYPE = np.dtype([(n, "f8") for n in SENSORS] + [(n.rsplit("_", 1)[0] + "_ok", "f8") for n in SENSORS])
EVENT_SIGNALS = ("speed_mps", "position_m", "engine_speed_radps", "clutch_position_frac", "park_chamber_pressure_pa")

CHANNELS: dict[str, str] = {
    "time_s": "time since the start of the run",
    "position_m": "distance travelled along the road (uphill +)",
    "speed_mps": "vehicle speed (forward +)",
    "accel_mps2": "vehicle acceleration dv/dt",
    "slope_rad": "road grade angle at the vehicle (uphill +)",
    "drive_force_n": "clutch torque at the wheels, T_c*i*eta/r (force on the vehicle, +x)",
    "grade_resistance_n": "F_i = m*g*sin(alpha) (resistance, + opposes forward motion)",
    "aero_drag_n": "F_w (resistance, + opposes forward motion)",
    "rolling_resistance_force_n": "rolling resistance acting on the vehicle (+x); a reaction at rest",
    "rolling_resistance_capacity_n": "F_f = m*g*f*cos(alpha): rolling resistance while moving, its bound at rest",
    "service_brake_force_n": "service brake force on the vehicle (+x); a reaction at rest",
    "service_brake_capacity_n": "service brake holding capacity at the ground",
    "park_brake_force_n": "park brake force on the vehicle (+x = uphill, the F_g of paper 000); a reaction at rest",
    "park_brake_capacity_n": "park brake holding capacity at the ground, F_g_cap(p_sp) (the brake's own; the tyres may pass less: adhesion_limit_n)",
    "brake_power_w": "power dissipated by service and park brakes while the vehicle moves",
    "vehicle_held_flag": "1 while held at exactly zero speed by static friction",
    "engine_speed_radps": "engine (flywheel) speed",
    "engine_torque_nm": "engine net torque at the flywheel",
    "engine_stalled_flag": "1 once the engine has stalled",
    "clutch_position_frac": "clutch actuator position (0 open, 1 fully engaged)",
    "clutch_command_frac": "clutch position commanded by the AMT controller",
    "clutch_capacity_nm": "clutch torque capacity at the actual position",
    "clutch_torque_nm": "torque transmitted by the clutch",
    "input_shaft_speed_radps": "gearbox input (clutch driven plate) speed",
    "clutch_locked_flag": "1 while the clutch is locked (no slip)",
    "clutch_slip_power_w": "power dissipated in the clutch |T_c*(w_e - w_in)|",
    "gear_index": "engaged gear (0 = neutral or shifting; 1.. = the vehicle file's gear order)",
    "park_chamber_pressure_pa": "spring-chamber pressure (gauge)",
    "relay_control_pressure_pa": "relay-valve control-line pressure (gauge)",
    "reservoir_pressure_pa": "air reservoir pressure (gauge)",
    "park_lamp_flag": "park warning lamp (pressure switch): 1 = park brake applied",
    "accelerator_frac": "driver accelerator pedal",
    "brake_pedal_frac": "driver service brake pedal",
    "hand_valve_released_flag": "driver hand park valve: 1 = released (supplies the control line)",
    "amt_mode_index": "mode of the AMT start program (see the amt_launch state machine)",
    "hsa_mode_index": "mode of the hill-start assist (see the hill_start_amt state machine)",
    "valve_32_energized_flag": "3/2 solenoid valve spool position: 1 = energised (park brake held)",
    "engine_speed_rate_radps2": "engine-speed rate dn_e/dt as filtered by the hill-start assist",
    "assist_refusal_code": "0, or k >= 1: the hill-start assist refused / stood down for REFUSAL_REASONS[k - 1]",
    "rear_axle_load_n": "normal load on the driven rear tandem, static split + grade transfer",
    "adhesion_limit_n": "mu*F_z,rear: the largest force the driven tandem passes to the road",
    "tyre_slip_power_w": "power dissipated at the driven tyres while the drive force is at the adhesion limit",
}
REFUSAL_REASONS: tuple[str, ...] = hill_start_amt.REFUSAL_REASONS
TRACE_DTYPE = np.dtype([(name, "f8") for name in CHANNELS])

MACHINES = (
    StateMachine("vehicle", ("HELD", "MOVING"), (
        Transition("HELD", "MOVING", "drive_exceeds_hold_capacity"),
        Transition("MOVING", "HELD", "static_friction_holds"),
    )),
    StateMachine("clutch", ("SLIPPING", "LOCKED"), (
        Transition("SLIPPING", "LOCKED", "slip_crossed_zero_within_capacity"),
        Transition("LOCKED", "SLIPPING", "torque_exceeds_capacity"),
    )),
    StateMachine("engine", ("RUNNING", "STALLED"), (Transition("RUNNING", "STALLED", "speed_below_stall_speed"),)),
    StateMachine("gearbox", ("IN_GEAR", "SHIFTING"), (
        Transition("IN_GEAR", "SHIFTING", "gear_change_started"),
        Transition("SHIFTING", "IN_GEAR", "gear_engaged"),
    )),
    amt_launch.MACHINE,
    hill_start_amt.MACHINE,
)
M_VEHICLE, M_CLUTCH, M_ENGINE, M_GEARBOX, M_AMT, M_HSA = range(6)
M_SCENARIO = len(MACHINES)  # scenario events are logged under this id


@nb.njit(cache=True, nogil=True, error_model="numpy")
def rear_axle_load_n(p, mass_kg, slope_rad):
    """F_z of the driven rear tandem: static split of the empty truck plus the payload, and the grade
    load transfer m*g*sin(alpha)*h/l (common.md 9 with a_x = 0)."""
    m0 = min(p.axles_empty_mass_kg, mass_kg)
    mp = mass_kg - m0
    static = m0 * p.axles_empty_rear_load_frac + mp * p.axles_payload_rear_load_frac
    moment = (m0 * p.axles_empty_cg_height_m + mp * p.axles_payload_cg_height_m) / p.axles_wheelbase_m
    return G * (static * math.cos(slope_rad) + moment * math.sin(slope_rad))


@nb.njit(cache=True, nogil=True, error_model="numpy")
def simulate(p, s, noise, meas, tcu, hsa, tr, events):
    """Run one scenario. ``p`` vehicle record, ``s`` scenario record, ``noise`` (ticks x sensors) standard
    normal draws, ``meas``/``tcu`` measurement and controller-state records, ``tr`` trace rows, ``events``
    event buffer. Returns (rows written, events logged)."""
    dt = s.plant_step_s
    n_steps = int(round(s.duration_s / dt))
    ctrl_every = max(1, int(round(s.controller_period_s / dt)))  # sensor sampling tick
    # each controller runs at its own ECU period, a whole number of sampling ticks
    amt_launch_every = max(1, int(round(p.amt_launch_period_s / s.controller_period_s)))
    hsa_every = max(1, int(round(p.hill_start_assist_period_s / s.controller_period_s)))
    hsa_enabled = p.hill_start_assist_enabled_flag > 0.5
    valve_fault = np.int64(0)
    valve_pos = 0.0
    hsa_active = False
    clutch_cmd = 0.0
    rec_every = max(1, int(round(s.record_period_s / dt)))
    n_sens = noise.shape[1]
    m_kg = p.body_mass_kg
    r = p.body_wheel_radius_m
    i0 = p.gearbox_final_drive_ratio
    eta = p.gearbox_efficiency_frac
    j_e = p.engine_inertia_kgm2
    p_s = p.park_brake_reservoir_pressure_pa
    fill_decay = decay(p.park_brake_fill_time_constant_s, dt)
    exhaust_decay = decay(p.park_brake_exhaust_time_constant_s, dt)
    service_decay = decay(p.service_brake_time_constant_s, dt)

    # --- driver inputs, event state -----------------------------------------------------------
    inputs, override_on, override_value, fired, due, signals = event_buffers(len(EVENT_SIGNALS))
    driver_inputs(s, 0.0, override_on, override_value, inputs)

    # --- sensors -----------------------------------------------------------------------------
    history, delay_ticks, actuator_fault, fault, fault_value, last, truth, values, ok = \
        sensor_buffers(s, n_sens, len(ACTUATORS))

    # --- plant state -------------------------------------------------------------------------
    x = s.initial_position_m
    v = s.initial_speed_mps
    a = 0.0
    w_e = p.engine_idle_speed_radps
    stalled = np.bool_(False)
    locked = np.bool_(False)
    x_c = 0.0
    gear = int(round(inputs[IN_GEAR_LEVER]))  # start in the lever gear (driver selected it before)
    gear_target = gear
    shift_timer = 0.0
    tcu.gear_command_index = gear
    w_in = v * gear_ratio(p.gearbox_ratios, len(p.gearbox_ratios), gear) * i0 / r
    held = abs(v) < V_EPS
    p_ctrl = hand_valve_control_pressure_pa(inputs[IN_HAND_VALVE], p_s)
    p_sp = p_ctrl
    p_sb = inputs[IN_BRAKE_PEDAL]  # service brake chamber level, 0..1 of full
    n_events = np.int64(0)  # np.int64, not 0: a literal 0 makes numba compile callees twice
    n_rec = np.int64(0)
    tick = np.int64(0)
    t_c = 0.0
    f_t = 0.0
    f_roll = 0.0
    f_sb = 0.0
    f_pb = 0.0
    f_sb_cap = 0.0
    f_pb_cap = 0.0
    f_pb_cap_brake = 0.0
    p_brake = 0.0
    t_e = 0.0
    cap = 0.0
    slope = 0.0
    f_i = 0.0
    f_w = 0.0
    f_roll_cap = 0.0
    last_slope = np.nan
    last_coeff = np.nan
    last_x_c = np.nan
    last_mu = np.nan
    mu = 1.0
    f_z_rear = 0.0
    f_adh = np.inf
    f_adh_all = np.inf
    f_spin = 0.0

    # the road at the start position, so that the first sensor sample reads the real grade
    slope, f_coeff = road_at(s, x)
    ctrl_left = np.int64(0)  # steps to the next sampling tick / trace row (countdowns)
    rec_left = np.int64(0)
    for k in range(n_steps + 1):
        t = k * dt
        ctrl_now, ctrl_left = countdown(ctrl_left, ctrl_every)
        rec_now, rec_left = countdown(rec_left, rec_every)
        # 1. scenario events, driver
        signals[0] = v
        signals[1] = x
        signals[2] = w_e
        signals[3] = x_c
        signals[4] = p_sp
        event_now = False
        stop = False
        if s.event_count > 0:  # (a call per 1 ms step with 13 array arguments costs 40 % of the run time)
            n_events, event_now, stop = apply_events(s, fired, due, t, signals, events, n_events, M_SCENARIO,
                                                     override_on, override_value, fault, fault_value, actuator_fault)
        if event_now:
            valve_fault = int(actuator_fault[0, 0])
        if ctrl_now or event_now:
            # the scripted driver acts at the sampling tick (100 Hz by default: far above human bandwidth;
            # at every 1 ms step it cost a quarter of the run time), and at once when an event overrides it
            driver_inputs(s, t, override_on, override_value, inputs)

        # 2. sample, then run the controllers on that sample
        if ctrl_now:
            truth[0] = v
            truth[1] = w_e
            truth[2] = w_in
            truth[3] = x_c
            truth[4] = a + G * math.sin(slope)
            truth[5] = 1.0 if p_sp < p.park_brake_lamp_pressure_pa else 0.0
            truth[6] = p_s
            truth[7] = inputs[IN_BRAKE_PEDAL]
            truth[8] = inputs[IN_ACCELERATOR]
            truth[9] = inputs[IN_HAND_VALVE]
            truth[10] = round(inputs[IN_GEAR_LEVER])
            truth[11] = gear
            truth[12] = m_kg
            sample_sensors(truth, history, tick, noise[min(tick, noise.shape[0] - 1)], s.sensor_noise_std, s.sensor_bias,
                           delay_ticks, fault, fault_value, last, values, ok)
            meas.vehicle_speed_mps = values[0]
            meas.engine_speed_radps = values[1]
            meas.input_shaft_speed_radps = values[2]
            meas.clutch_position_frac = values[3]
            meas.longitudinal_accel_mps2 = values[4]
            meas.park_lamp_flag = values[5]
            meas.reservoir_pressure_pa = values[6]
            meas.brake_pedal_frac = values[7]
            meas.accelerator_frac = values[8]
            meas.hand_valve_released_flag = values[9]
            meas.gear_lever_index = values[10]
            meas.gear_engaged_index = values[11]
            meas.vehicle_speed_ok = ok[0]
            meas.engine_speed_ok = ok[1]
            meas.input_shaft_speed_ok = ok[2]
            meas.clutch_position_ok = ok[3]
            meas.longitudinal_accel_ok = ok[4]
            meas.park_lamp_ok = ok[5]
            meas.reservoir_pressure_ok = ok[6]
            meas.brake_pedal_ok = ok[7]
            meas.accelerator_ok = ok[8]
            meas.hand_valve_released_ok = ok[9]
            meas.gear_lever_ok = ok[10]
            meas.gear_engaged_ok = ok[11]
            meas.vehicle_mass_kg = values[12]
            meas.vehicle_mass_ok = ok[12]
            if hsa_enabled and tick % hsa_every == 0:
                was_done = int(hsa.mode) == hill_start_amt.DONE
                n_events = hill_start_amt.step(hsa, meas, p, p.hill_start_assist_period_s, t, M_HSA, events, n_events)
                if int(hsa.mode) == hill_start_amt.DONE and not was_done:
                    # the assist hands a closed clutch to the AMT start program
                    n_events = log_event(events, n_events, t, M_AMT, int(tcu.mode), amt_launch.CLOSED,
                                         amt_launch.G_HANDED_OVER)
                    tcu.mode = amt_launch.CLOSED
                    tcu.clutch_command_frac = 1.0
                    tcu.gear_command_index = meas.gear_engaged_index
            if hsa_enabled:
                hsa_active = hill_start_amt.is_active(hsa)
                tcu_mode = int(tcu.mode)
                if hsa_active and (tcu_mode == amt_launch.APPROACH or tcu_mode == amt_launch.ENGAGE
                                   or tcu_mode == amt_launch.CLOSED):
                    # the assist takes the clutch from a launch the start program had begun
                    n_events = log_event(events, n_events, t, M_AMT, int(tcu.mode), amt_launch.OPEN,
                                         amt_launch.G_TOOK_OVER)
                    tcu.mode = amt_launch.OPEN
                    tcu.clutch_command_frac = 0.0
            if tick % amt_launch_every == 0 and not hsa_active:
                n_events = amt_launch.step(tcu, meas, p, p.amt_launch_period_s, t, M_AMT, events, n_events)
            clutch_cmd = hsa.clutch_command_frac if hsa_active else tcu.clutch_command_frac
            tick += 1

        # 3. forces at t, from the state at t; the driveline and vehicle give the state at t + dt
        ratio = gear_ratio(p.gearbox_ratios, len(p.gearbox_ratios), gear) * i0
        slope, f_coeff = road_at(s, x)
        mu = road_friction_at(s, x)
        if slope != last_slope or f_coeff != last_coeff or mu != last_mu:  # trig only when the road changes
            f_i = grade_resistance_n(m_kg, slope)
            f_roll_cap = rolling_resistance_capacity_n(m_kg, slope, f_coeff)
            f_z_rear = rear_axle_load_n(p, m_kg, slope)
            f_adh = mu * f_z_rear
            f_adh_all = mu * m_kg * G * math.cos(slope)
            last_slope = slope
            last_coeff = f_coeff
            last_mu = mu
        f_w = aero_drag_n(p.body_drag_area_m2, v)
        f_sb_cap = p.service_brake_max_force_n * p_sb
        f_pb_cap = park_brake_capacity_n(p_sp, p.park_brake_max_force_n, p.park_brake_release_start_pressure_pa,
                                         p.park_brake_release_full_pressure_pa)
        # the spring brake acts on the rear tandem, the service brake on all axles: both adhesion-limited; the
        # rear tyres pass drive and park-brake force together (drive force of the previous step)
        f_pb_cap_brake = f_pb_cap  # the brake's own capacity F_g_cap(p_sp), recorded (paper 000 Fig. 5 phases)
        # holding against a rollback the tyres pass F_t + F_pb <= mu F_z; against the drive (phase 3, F_pb downhill)
        # they pass F_t - |F_pb|, so the adhesion limits the brake only in the first case
        if f_t < f_i:
            f_pb_cap = min(f_pb_cap, max(f_adh - max(f_t, 0.0), 0.0))
        else:
            f_pb_cap = min(f_pb_cap, f_adh + f_t)
        f_sb_cap = min(f_sb_cap, max(f_adh_all - f_pb_cap, 0.0))
        hold_cap = f_roll_cap + f_sb_cap + f_pb_cap
        if x_c != last_x_c:  # the capacity map only when the clutch moves
            cap = clutch_capacity_nm(x_c, p.clutch_max_torque_nm, p.clutch_kiss_point_frac, p.clutch_capacity_exponent)
            last_x_c = x_c
        t_e = engine_torque_nm(p, w_e, inputs[IN_ACCELERATOR], stalled)
        was_held = held
        locked_new = locked
        v_new = v
        w_e_new = w_e
        w_in_new = w_in
        reaction = 0.0
        t_break = 0.0
        f_spin = 0.0
        if ratio > 0.0 and locked:
            # one rigid body: engine + driveline + vehicle
            m_eq = equivalent_mass_kg(m_kg, p.body_wheel_inertia_total_kgm2, r,
                                      p.clutch_input_inertia_kgm2 + j_e, ratio, eta)
            f_drive = t_e * ratio * efficiency_factor(t_e * v if v != 0.0 else t_e, eta) / r
            f_drive = min(max(f_drive, -f_adh), f_adh)  # driven tandem at its adhesion limit: wheel spin
            v_new, a, held, reaction = stick_slip_step(v, f_drive - f_i - f_w, hold_cap, m_eq, dt, V_EPS)
            t_c = t_e - j_e * (ratio / r) * a  # torque the clutch must carry to keep engine and vehicle together
            if abs(t_c) > cap:
                locked_new = False
                t_break = t_c
                n_events = log_event(events, n_events, t, M_CLUTCH, 1, 0, 1)
            else:
                f_t = t_c * ratio * efficiency_factor(t_c * v if v != 0.0 else t_c, eta) / r
                f_spin = f_t
                f_t = min(max(f_t, -f_adh), f_adh)
                w_in_new = v_new * ratio / r
                w_e_new = w_in_new
        if not (ratio > 0.0 and locked_new):
            slip = w_e - w_in
            # at the break-away step the slip is still zero: the clutch carries its capacity in the
            # direction of the torque that broke the lock
            t_c = cap * (sign(slip) if slip != 0.0 else sign(t_break))
            if ratio > 0.0:
                f_t = t_c * ratio * efficiency_factor(t_c * v if v != 0.0 else t_c, eta) / r
                f_spin = f_t
                f_t = min(max(f_t, -f_adh), f_adh)  # driven tandem at its adhesion limit: wheel spin
                m_eq = equivalent_mass_kg(m_kg, p.body_wheel_inertia_total_kgm2, r, p.clutch_input_inertia_kgm2, ratio, eta)
            else:
                f_t = 0.0
                t_c = 0.0
                m_eq = equivalent_mass_kg(m_kg, p.body_wheel_inertia_total_kgm2, r, 0.0, 0.0, eta)
            v_new, a, held, reaction = stick_slip_step(v, f_t - f_i - f_w, hold_cap, m_eq, dt, V_EPS)
            w_e_new = max(w_e + dt * (t_e - t_c) / j_e, 0.0)
            if ratio > 0.0:
                w_in_new = v_new * ratio / r
                if cap > 0.0 and (w_e_new - w_in_new) * slip <= 0.0 and slip != 0.0 and not stalled and not held:
                    # slip speed crossed zero: lock if the coupled system needs less than the capacity
                    m_lock = equivalent_mass_kg(m_kg, p.body_wheel_inertia_total_kgm2, r,
                                                p.clutch_input_inertia_kgm2 + j_e, ratio, eta)
                    f_lock = min(max(t_e * ratio * efficiency_factor(t_e * v_new, eta) / r, -f_adh), f_adh)
                    a_lock = (f_lock - f_i - f_w + reaction) / m_lock
                    t_req = t_e - j_e * (ratio / r) * a_lock
                    if abs(t_req) <= cap:
                        # perfectly plastic coupling: the common speed conserves angular momentum
                        # (engine J_e and the vehicle's inertia seen at the input shaft)
                        j_vehicle = m_eq * (r / ratio) ** 2
                        w_common = (j_e * w_e_new + j_vehicle * w_in_new) / (j_e + j_vehicle)
                        w_e_new = w_common
                        w_in_new = w_common
                        v_new = w_common * r / ratio
                        locked_new = True
                        n_events = log_event(events, n_events, t, M_CLUTCH, 0, 1, 0)
            else:
                # neutral: the driven plate follows the engine when the clutch grips, else spins down
                w_in_new = w_e_new if cap > 0.0 else w_in * math.exp(-dt / 2.0)

        # brakes and rolling resistance share the hold reaction: park brake first, then service, then rolling
        if held:
            need = reaction
            f_pb = min(max(need, -f_pb_cap), f_pb_cap)
            need -= f_pb
            f_sb = min(max(need, -f_sb_cap), f_sb_cap)
            need -= f_sb
            f_roll = need
            p_brake = 0.0
        else:
            d = sign(reaction)
            f_pb = d * f_pb_cap
            f_sb = d * f_sb_cap
            f_roll = d * f_roll_cap
            p_brake = (f_pb_cap + f_sb_cap) * abs(v)

        # 4. record the state at t with the forces acting at t
        if rec_now and n_rec < tr.shape[0]:
            row = tr[n_rec]
            row.time_s = t
            row.position_m = x
            row.speed_mps = v
            row.accel_mps2 = a
            row.slope_rad = slope
            row.drive_force_n = f_t
            row.grade_resistance_n = f_i
            row.aero_drag_n = f_w
            row.rolling_resistance_force_n = f_roll
            row.rolling_resistance_capacity_n = f_roll_cap
            row.service_brake_force_n = f_sb
            row.service_brake_capacity_n = f_sb_cap
            row.park_brake_force_n = f_pb
            row.park_brake_capacity_n = f_pb_cap_brake
            row.brake_power_w = p_brake
            row.vehicle_held_flag = 1.0 if held else 0.0
            row.engine_speed_radps = w_e
            row.engine_torque_nm = t_e
            row.engine_stalled_flag = 1.0 if stalled else 0.0
            row.clutch_position_frac = x_c
            row.clutch_command_frac = clutch_cmd
            row.clutch_capacity_nm = cap
            row.clutch_torque_nm = t_c if ratio > 0.0 or cap > 0.0 else 0.0
            row.input_shaft_speed_radps = w_in
            row.clutch_locked_flag = 1.0 if locked else 0.0
            row.clutch_slip_power_w = slip_power_w(t_c, w_e, w_in) if not locked else 0.0
            row.gear_index = gear
            row.park_chamber_pressure_pa = p_sp
            row.relay_control_pressure_pa = p_ctrl
            row.reservoir_pressure_pa = p_s
            row.park_lamp_flag = 1.0 if p_sp < p.park_brake_lamp_pressure_pa else 0.0
            row.accelerator_frac = inputs[IN_ACCELERATOR]
            row.brake_pedal_frac = inputs[IN_BRAKE_PEDAL]
            row.hand_valve_released_flag = inputs[IN_HAND_VALVE]
            row.amt_mode_index = tcu.mode
            row.hsa_mode_index = hsa.mode if hsa_enabled else -1.0
            row.valve_32_energized_flag = valve_pos
            row.engine_speed_rate_radps2 = hsa.engine_speed_rate_radps2
            row.assist_refusal_code = hsa.refusal_code if hsa_enabled else 0.0
            row.rear_axle_load_n = f_z_rear
            row.adhesion_limit_n = f_adh
            row.tyre_slip_power_w = abs(f_spin - f_t) * abs(v) if ratio > 0.0 else 0.0
            n_rec += 1
        if k == n_steps or stop:
            break

        # 5. advance every state to t + dt
        if held != was_held:
            n_events = log_event(events, n_events, t, M_VEHICLE, 0 if was_held else 1, 0 if held else 1, 1 if held else 0)
        v = v_new
        x += v * dt
        w_e = w_e_new
        w_in = w_in_new
        locked = locked_new
        if not stalled and w_e < p.engine_stall_speed_radps:
            stalled = True
            locked = np.bool_(False)
            n_events = log_event(events, n_events, t + dt, M_ENGINE, 0, 1, 0)
        x_c = actuator_step(x_c, clutch_cmd, p.clutch_actuator_time_constant_s,
                            p.clutch_actuator_max_rate_per_s, dt)
        old_gear = gear
        gear, gear_target, shift_timer = shift_step(gear, gear_target, shift_timer, tcu.gear_command_index,
                                                    p.gearbox_shift_time_s, dt)
        if gear != old_gear:
            if gear == 0:
                n_events = log_event(events, n_events, t + dt, M_GEARBOX, 0, 1, 0)
                locked = np.bool_(False)
            else:
                n_events = log_event(events, n_events, t + dt, M_GEARBOX, 1, 0, 1)
                w_in = v * gear_ratio(p.gearbox_ratios, len(p.gearbox_ratios), gear) * i0 / r  # synchroniser
        p_sb = first_order_step(p_sb, inputs[IN_BRAKE_PEDAL], service_decay)
        valve_pos = valve_32_position(hsa.valve_command_flag if hsa_enabled else 0.0, valve_fault)
        p_ctrl = valve_32_control_pressure_pa(hand_valve_control_pressure_pa(inputs[IN_HAND_VALVE], p_s), valve_pos)
        p_sp = spring_chamber_step(p_sp, p_ctrl, fill_decay, exhaust_decay)
    return n_rec, n_events


# --------------------------------------------------------------------------- layout interface (Python side)
INPUTS = ("accelerator", "brake_pedal", "gear_lever", "hand_valve")
DEFAULT_GEAR_INDEX = 2  # "1" (first gear) in the shipped truck's order C, 1, 2, ...


def gear_names(model) -> list[str]:
    return ["N"] + list(model.gearbox.gear_names)


def derived(flat: dict) -> dict:
    """Peak of the full-load curve, the torque at which the governor's speed droop is defined."""
    out = dict(flat)
    out["engine_governor_peak_torque_nm"] = float(max(flat["engine_full_load_torque"].y))
    return out


def controller_states() -> tuple:
    """Fresh measurement record and controller state records (the kernel's mutable arguments)."""
    meas = np.zeros(1, dtype=MEAS_DTYPE).view(np.recarray)
    return meas[0], amt_launch.initial_state()[0], hill_start_amt.initial_state()[0]


def run_kernel(p, s, noise, trace, events):
    meas, tcu, hsa = controller_states()
    return simulate(p, s, noise, meas, tcu, hsa, trace, events)


# the batch path: one compiled call per chunk of variants (vehicles/common.py chunk_runner)
simulate_many, run_chunk = chunk_runner(simulate, LAYOUT, MEAS_DTYPE, amt_launch.initial_state, hill_start_amt.initial_state)
