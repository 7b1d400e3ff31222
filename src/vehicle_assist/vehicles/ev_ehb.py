"""Compact battery-electric car with EHB: longitudinal body on a grade + single-speed motor drive +
four hydraulic disc brakes fed by an electro-hydraulic brake actuator (hill_start_ehb.md 2, 3).

Per plant step (1 ms): events and driver; every controller period sample the sensors and run the VCU;
then the motor torque lag, the EHB pressure, and the vehicle with stick/slip at standstill:

    F_t = T_m*i_0*eta/r        F_b_cap = K_b_tot*p/r,  K_b_tot = 2*K_b_front + 2*K_b_rear
    delta*m*dv/dt = F_t - F_f - F_w - F_i - F_b       (brake and rolling resistance are reactions at rest)
    delta*m = m + sum(J_w)/r^2 + J_m*i_0^2*eta/r^2

Tyre adhesion (issue #7, common.md 9): axle loads with the static split and the grade (and previous-step
acceleration) load transfer, F_zf = m*(g*cos*l_r - (a + g*sin)*h)/l, F_zr = m*g*cos - F_zf; the drive
force is limited to mu*F_z of the driven axle, each axle's brake reaction to what its tyres can still
transmit (driven axle: mu*F_z -/+ the drive force), mu = road.friction_mu at the car (road_friction_at).
Lumped: no wheel-spin or lock-up dynamics (the tyre force saturates Coulomb-like at mu*F_z).
"""
from __future__ import annotations

import math

import numba as nb
import numpy as np

from vehicle_assist.conventions import G_MPS2, STANDSTILL_SPEED_MPS
from vehicle_assist.core.fsm import StateMachine, Transition, log_event
from vehicle_assist.functions import ev_vcu, hill_start_ehb
from vehicle_assist.plant.brakes.ehb import ehb_pressure_step
from vehicle_assist.plant.brakes.hydraulic import brake_gain_nm_per_pa, piston_area_m2
from vehicle_assist.plant.longitudinal import (
    aero_drag_n,
    equivalent_mass_kg,
    grade_resistance_n,
    rolling_resistance_capacity_n,
    stick_slip_step,
)
from vehicle_assist.plant.powertrain.clutch import sign
from vehicle_assist.plant.powertrain.gearbox import efficiency_factor
from vehicle_assist.plant.powertrain.motor import motor_torque_step
from vehicle_assist.plant.sensors import sample_sensors
from vehicle_assist.vehicles.common import (
    IN_ACCELERATOR,
    IN_BRAKE_PEDAL,
    IN_GEAR_LEVER,
    apply_events,
    chunk_runner,
    countdown,
    driver_inputs,
    event_buffers,
    road_at,
    road_friction_at,
    sensor_buffers,
)

LAYOUT = "ev_ehb"
G = G_MPS2
V_EPS = STANDSTILL_SPEED_MPS

SENSORS = (
    "vehicle_speed_mps",
    "motor_speed_radps",
    "motor_torque_nm",
    "brake_pressure_pa",
    "longitudinal_accel_mps2",
    "brake_pedal_frac",
    "accelerator_frac",
    "gear_lever_index",
)
MEAS_DTYPE = np.dtype([(n, "f8") for n in SENSORS] + [(n.rsplit("_", 1)[0] + "_ok", "f8") for n in SENSORS])
EVENT_SIGNALS = ("speed_mps", "position_m", "motor_torque_nm", "brake_pressure_pa")
INPUTS = ("accelerator", "brake_pedal", "gear_lever")
ACTUATORS: tuple[str, ...] = ("ehb",)  # actuator fault: ehb limited (limit_bar = ...)
DEFAULT_GEAR_INDEX = 1  # D
# reasons for which the assist refuses a hold or a start (code k >= 1 in assist_refusal_code is
# REFUSAL_REASONS[k-1]); they are the guard names of the refusal rows of the hill_start_ehb machine
REFUSAL_REASONS: tuple[str, ...] = hill_start_ehb.REFUSAL_GUARDS

CHANNELS: dict[str, str] = {
    "time_s": "time since the start of the run",
    "position_m": "distance travelled along the road (uphill +)",
    "speed_mps": "vehicle speed (forward +)",
    "accel_mps2": "vehicle acceleration dv/dt",
    "slope_rad": "road grade angle at the vehicle (uphill +)",
    "drive_force_n": "motor torque at the wheels, T_m*i_0*eta/r (force on the vehicle, +x)",
    "grade_resistance_n": "F_i = m*g*sin(gamma) (resistance, + opposes forward motion)",
    "aero_drag_n": "F_w (resistance, + opposes forward motion)",
    "rolling_resistance_force_n": "rolling resistance on the vehicle (+x); a reaction at rest",
    "service_brake_force_n": "hydraulic brake force on the vehicle (+x); a reaction at rest",
    "service_brake_capacity_n": "brake holding capacity at the ground, K_b_tot*p/r",
    "brake_power_w": "power dissipated by the brakes while the vehicle moves",
    "vehicle_held_flag": "1 while held at exactly zero speed by static friction",
    "motor_speed_radps": "motor (rotor) speed",
    "motor_torque_nm": "motor torque (after the torque lag)",
    "motor_torque_request_nm": "motor torque command (the driver's request, lowered by the assist's ceiling)",
    "driver_torque_request_nm": "motor torque the driver's accelerator asks for (VCU pedal map)",
    "brake_pressure_pa": "EHB (wheel-cylinder) pressure",
    "brake_pressure_command_pa": "EHB pressure command",
    "accelerator_frac": "driver accelerator pedal",
    "brake_pedal_frac": "driver brake pedal",
    "gear_index": "drive position (0 = N, 1 = D)",
    "hsa_mode_index": "mode of the hill-start assist (see the hill_start_ehb state machine)",
    "hsa_pressure_command_pa": "pressure requested by the hill-start assist",
    "grade_force_estimate_n": "F_ang: grade force the assist estimates from the slope sensor",
    "torque_force_estimate_n": "F_tq: drive force the assist credits to the motor",
    "parking_brake_request_flag": "1 when the assist asks for the parking brake (maximum hold time reached, refusal)",
    "warning_flag": "1 while the assist warns the driver (degraded, refused)",
    "assist_refusal_code": "0, or 1 + index in REFUSAL_REASONS while the assist refuses a hold or a start",
    "motor_force_n": "motor torque at the wheels before the tyre limit, T_m*i_0*eta/r",
    "torque_ceiling_nm": "the assist's motor-torque ceiling (below the driver's request; 1e9 = none)",
    "front_axle_load_n": "F_zf with the grade (and acceleration) load transfer",
    "rear_axle_load_n": "F_zr",
    "friction_mu": "tyre-road adhesion coefficient at the car",
}
TRACE_DTYPE = np.dtype([(name, "f8") for name in CHANNELS])
MACHINES = (
    StateMachine("vehicle", ("HELD", "MOVING"), (
        Transition("HELD", "MOVING", "drive_exceeds_hold_capacity"),
        Transition("MOVING", "HELD", "static_friction_holds"),
    )),
    ev_vcu.MACHINE,
    hill_start_ehb.MACHINE,
)
M_VEHICLE, M_VCU, M_HSA = range(3)
M_SCENARIO = len(MACHINES)


@nb.njit(cache=True, nogil=True, error_model="numpy")
def simulate(p, s, noise, meas, vcu, hsa, tr, events):
    """Run one scenario; arguments as in :func:`vehicle_assist.vehicles.truck_amt.simulate`."""
    dt = s.plant_step_s
    n_steps = int(round(s.duration_s / dt))
    ctrl_every = max(1, int(round(s.controller_period_s / dt)))  # sensor sampling tick
    # each controller runs at its own ECU period, a whole number of sampling ticks
    vcu_every = max(1, int(round(p.vcu_period_s / s.controller_period_s)))
    hsa_every = max(1, int(round(p.hill_start_assist_period_s / s.controller_period_s)))
    hsa_enabled = p.hill_start_assist_enabled_flag > 0.5
    hsa_active = False
    pressure_command = 0.0
    ehb_limit_pa = p.ehb_max_pressure_pa
    rec_every = max(1, int(round(s.record_period_s / dt)))
    n_sens = noise.shape[1]
    m_kg = p.body_mass_kg
    r = p.body_wheel_radius_m
    i0 = p.motor_reduction_ratio
    eta = p.motor_efficiency_frac
    k_b = p.brakes_total_gain_nm_per_pa

    inputs, override_on, override_value, fired, due, signals = event_buffers(len(EVENT_SIGNALS))
    driver_inputs(s, 0.0, override_on, override_value, inputs)

    history, delay_ticks, actuator_fault, fault, fault_value, last, truth, values, ok = \
        sensor_buffers(s, n_sens, len(ACTUATORS))

    x = s.initial_position_m
    v = s.initial_speed_mps
    a = 0.0
    t_m = 0.0
    held = abs(v) < V_EPS
    # the driver's initial pedal has built its pressure before the run starts
    pressure = min(max(inputs[IN_BRAKE_PEDAL], 0.0), 1.0) * p.ehb_pedal_full_pressure_pa
    vcu.brake_pressure_command_pa = pressure
    pressure_command = pressure
    torque_command = 0.0
    slope = 0.0
    f_t = 0.0
    f_i = 0.0
    f_w = 0.0
    f_roll = 0.0
    f_b = 0.0
    f_b_cap = 0.0
    p_brake = 0.0
    n_events = np.int64(0)  # np.int64, not 0: a literal 0 makes numba compile callees twice
    n_rec = np.int64(0)
    tick = np.int64(0)
    m_eq = equivalent_mass_kg(m_kg, p.body_wheel_inertia_total_kgm2, r, p.motor_rotor_inertia_kgm2, i0, eta)
    k_front = p.brakes_front_gain_nm_per_pa
    k_rear = p.brakes_rear_gain_nm_per_pa
    wheelbase = p.chassis_wheelbase_m
    l_f = p.chassis_cg_to_front_axle_m
    l_r = wheelbase - l_f
    h_cg = p.chassis_cg_height_m
    rear_driven = p.chassis_driven_axle > 0.5
    f_motor = 0.0
    f_zf = 0.0
    f_zr = 0.0
    mu = 1.0

    # the road at the start position, so that the first sensor sample reads the real grade
    slope, f_coeff = road_at(s, x)
    ctrl_left = np.int64(0)  # steps to the next sampling tick / trace row (countdowns)
    rec_left = np.int64(0)
    for k in range(n_steps + 1):
        t = k * dt
        ctrl_now, ctrl_left = countdown(ctrl_left, ctrl_every)
        rec_now, rec_left = countdown(rec_left, rec_every)
        signals[0] = v
        signals[1] = x
        signals[2] = t_m
        signals[3] = pressure
        event_now = False
        stop = False
        if s.event_count > 0:  # (a call per 1 ms step with 13 array arguments costs 40 % of the run time)
            n_events, event_now, stop = apply_events(s, fired, due, t, signals, events, n_events, M_SCENARIO,
                                                     override_on, override_value, fault, fault_value, actuator_fault)
        if event_now:
            if actuator_fault[0, 0] > 0.0:
                ehb_limit_pa = min(p.ehb_max_pressure_pa, actuator_fault[0, 1])
        if ctrl_now or event_now:
            # the scripted driver acts at the sampling tick (100 Hz by default: far above human bandwidth;
            # at every 1 ms step it cost a quarter of the run time), and at once when an event overrides it
            driver_inputs(s, t, override_on, override_value, inputs)

        if ctrl_now:
            truth[0] = v
            truth[1] = v * i0 / r
            truth[2] = t_m
            truth[3] = pressure
            truth[4] = a + G * math.sin(slope)
            truth[5] = inputs[IN_BRAKE_PEDAL]
            truth[6] = inputs[IN_ACCELERATOR]
            truth[7] = round(inputs[IN_GEAR_LEVER])
            sample_sensors(truth, history, tick, noise[min(tick, noise.shape[0] - 1)], s.sensor_noise_std, s.sensor_bias,
                           delay_ticks, fault, fault_value, last, values, ok)
            meas.vehicle_speed_mps = values[0]
            meas.motor_speed_radps = values[1]
            meas.motor_torque_nm = values[2]
            meas.brake_pressure_pa = values[3]
            meas.longitudinal_accel_mps2 = values[4]
            meas.brake_pedal_frac = values[5]
            meas.accelerator_frac = values[6]
            meas.gear_lever_index = values[7]
            meas.vehicle_speed_ok = ok[0]
            meas.motor_speed_ok = ok[1]
            meas.motor_torque_ok = ok[2]
            meas.brake_pressure_ok = ok[3]
            meas.longitudinal_accel_ok = ok[4]
            meas.brake_pedal_ok = ok[5]
            meas.accelerator_ok = ok[6]
            meas.gear_lever_ok = ok[7]
            if tick % vcu_every == 0:
                n_events = ev_vcu.step(vcu, meas, p, p.vcu_period_s, t, M_VCU, events, n_events)
            if hsa_enabled and tick % hsa_every == 0:
                n_events = hill_start_ehb.step(hsa, meas, p, p.hill_start_assist_period_s, t, M_HSA, events, n_events)
                hsa_active = hill_start_ehb.is_active(hsa)
            # brake by wire: the larger of the driver's and the assist's pressure request
            pressure_command = max(vcu.brake_pressure_command_pa, hsa.pressure_command_pa) if hsa_active \
                else vcu.brake_pressure_command_pa
            # torque coordination: the assist may only lower the driver's request (a rate ceiling), never raise it
            torque_command = min(vcu.torque_request_nm, hsa.torque_ceiling_nm) if hsa_active else vcu.torque_request_nm
            tick += 1

        # forces at t from the state at t
        slope, f_coeff = road_at(s, x)
        f_i = grade_resistance_n(m_kg, slope)
        f_w = aero_drag_n(p.body_drag_area_m2, v)
        f_roll_cap = rolling_resistance_capacity_n(m_kg, slope, f_coeff)
        f_b_cap = k_b * pressure / r
        # power-flow direction of the driveline efficiency; below the stick/slip threshold the motor drives (a
        # switch at creep speeds made the car chatter between held and moving)
        f_motor = t_m * i0 * efficiency_factor(t_m * v if abs(v) >= V_EPS else t_m, eta) / r
        # axle loads (static split + grade and acceleration transfer) and the tyre adhesion limit
        mu = road_friction_at(s, x)
        cos_s = math.cos(slope)
        f_zf = m_kg * (G * cos_s * l_r - (min(max(a, -G), G) + G * math.sin(slope)) * h_cg) / wheelbase
        f_zf = min(max(f_zf, 0.0), m_kg * G * cos_s)
        f_zr = m_kg * G * cos_s - f_zf
        f_z_driven = f_zr if rear_driven else f_zf
        f_z_free = f_zf if rear_driven else f_zr
        b_driven = (k_rear if rear_driven else k_front) * pressure / r
        b_free = (k_front if rear_driven else k_rear) * pressure / r
        f_t = min(max(f_motor, -mu * f_z_driven), mu * f_z_driven)
        net = f_t - f_i - f_w
        d = (1.0 if v > 0.0 else -1.0) if abs(v) >= V_EPS else (1.0 if net > 0.0 else -1.0)
        # brake reaction against the motion d that the tyres can still transmit
        f_b_eff = min(b_driven, max(mu * f_z_driven + d * f_t, 0.0)) + min(b_free, mu * f_z_free)
        was_held = held
        v_new, a, held, reaction = stick_slip_step(v, net, f_roll_cap + f_b_eff, m_eq, dt, V_EPS)
        if held:
            f_b = min(max(reaction, -f_b_eff), f_b_eff)
            f_roll = reaction - f_b
            p_brake = 0.0
        else:
            d = sign(reaction)
            f_b = d * f_b_eff
            f_roll = d * f_roll_cap
            p_brake = f_b_eff * abs(v)

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
            row.service_brake_force_n = f_b
            row.service_brake_capacity_n = f_b_cap
            row.brake_power_w = p_brake
            row.vehicle_held_flag = 1.0 if held else 0.0
            row.motor_speed_radps = v * i0 / r
            row.motor_torque_nm = t_m
            row.motor_torque_request_nm = torque_command
            row.driver_torque_request_nm = vcu.torque_request_nm
            row.brake_pressure_pa = pressure
            row.brake_pressure_command_pa = pressure_command
            row.hsa_mode_index = hsa.mode if hsa_enabled else -1.0
            row.hsa_pressure_command_pa = hsa.pressure_command_pa
            row.grade_force_estimate_n = hsa.grade_force_n
            row.torque_force_estimate_n = hsa.torque_force_n
            row.parking_brake_request_flag = hsa.parking_brake_request_flag
            row.warning_flag = hsa.warning_flag
            row.assist_refusal_code = hsa.refusal_code
            row.motor_force_n = f_motor
            row.torque_ceiling_nm = hsa.torque_ceiling_nm if hsa_active else 1e9
            row.front_axle_load_n = f_zf
            row.rear_axle_load_n = f_zr
            row.friction_mu = mu
            row.accelerator_frac = inputs[IN_ACCELERATOR]
            row.brake_pedal_frac = inputs[IN_BRAKE_PEDAL]
            row.gear_index = round(inputs[IN_GEAR_LEVER])
            n_rec += 1
        if k == n_steps or stop:
            break

        # advance to t + dt
        if held != was_held:
            n_events = log_event(events, n_events, t, M_VEHICLE, 0 if was_held else 1, 0 if held else 1, 1 if held else 0)
        v = v_new
        x += v * dt
        t_m = motor_torque_step(t_m, torque_command, v * i0 / r, p.motor_max_torque_nm, p.motor_max_power_w,
                                p.motor_time_constant_s, dt)
        pressure = ehb_pressure_step(pressure, pressure_command, p.ehb_time_constant_s,
                                     p.ehb_build_rate_pa_per_s, p.ehb_release_rate_pa_per_s, ehb_limit_pa, dt)
    return n_rec, n_events


def gear_names(model) -> list[str]:
    return ["N", "D"]


def derived(flat: dict) -> dict:
    """Brake gain of the four wheels from caliper data (common.md 7.1): K_b_tot = 2*K_b_f + 2*K_b_r."""
    out = dict(flat)
    faces = flat["brakes_friction_faces_count"]
    mu = flat["brakes_pad_friction_coeff"]
    eff = flat["brakes_efficiency_frac"]
    k_f = brake_gain_nm_per_pa(faces, mu, piston_area_m2(flat["brakes_front_piston_diameter_m"]), flat["brakes_front_effective_radius_m"], eff)
    k_r = brake_gain_nm_per_pa(faces, mu, piston_area_m2(flat["brakes_rear_piston_diameter_m"]), flat["brakes_rear_effective_radius_m"], eff)
    out["brakes_total_gain_nm_per_pa"] = 2.0 * k_f + 2.0 * k_r
    out["brakes_front_gain_nm_per_pa"] = 2.0 * k_f
    out["brakes_rear_gain_nm_per_pa"] = 2.0 * k_r
    return out


def controller_states() -> tuple:
    meas = np.zeros(1, dtype=MEAS_DTYPE).view(np.recarray)
    return meas[0], ev_vcu.initial_state()[0], hill_start_ehb.initial_state()[0]


def run_kernel(p, s, noise, trace, events):
    meas, vcu, hsa = controller_states()
    return simulate(p, s, noise, meas, vcu, hsa, trace, events)


# the batch path: one compiled call per chunk of variants (vehicles/common.py chunk_runner)
simulate_many, run_chunk = chunk_runner(simulate, LAYOUT, MEAS_DTYPE, ev_vcu.initial_state, hill_start_ehb.initial_state)
