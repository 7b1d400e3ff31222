"""Passenger car (1.8 T class sedan) with an ESP unit: two-track body, four spinning wheels, Burckhardt or
Dugoff tires, pedal -> vacuum booster -> tandem master cylinder -> X-split circuits with rear proportioning
-> ESP hydraulic unit -> four disc brakes; the ESP controller hosts ABS and the hydraulic brake assist of
paper 002 (brake_assist.md; issue #9). Platform for paper 004 (tire blowout): same body, tires, unit.

Per plant step (default 1 ms; the scenarios of paper 002 use 0.5 ms):
1. scenario events; scripted driver (pedal fraction x ``pedal.full_scale_force_n`` = pedal force, steering);
2. at each sampling tick the sensors (4 wheel speeds, master pressure, a_x, a_y, yaw rate, steering angle,
   brake-light switch) and, every ``esp.period_s``, the ESP controller on that sample;
3. booster and master cylinder; per wheel the ESP unit mode -> wheel pressure -> brake torque capacity;
4. loads (quasi-static transfer with the previous step's accelerations), tire forces at the present state,
   record, then advance the body (semi-implicit Euler) and the wheels (linearly implicit tire term).
The car is held at rest once the planar speed and the yaw rate are both small (two_track.at_rest); the run ends
``STOP_AFTER_S`` after that.
"""
from __future__ import annotations

import math

import numba as nb
import numpy as np

from vehicle_assist.conventions import G_MPS2, RHO_AIR_KGPM3
from vehicle_assist.core.fsm import StateMachine, Transition, log_event
from vehicle_assist.drivers import lane_keeper as lk
from vehicle_assist.functions import abs as abs_fn
from vehicle_assist.functions import blowout_compensation as bc
from vehicle_assist.functions import brake_assist as hba
from vehicle_assist.functions import esp
from vehicle_assist.plant.brakes.booster import booster_step, booster_target_n
from vehicle_assist.plant.brakes.esp_unit import VALVE_TABLE, source_rate_pa_per_s, wheel_pressure_step
from vehicle_assist.plant.brakes.hydraulic import brake_gain_nm_per_pa, piston_area_m2
from vehicle_assist.plant.brakes.master_cylinder import master_pressure_pa, proportioned_pa
from vehicle_assist.plant.chassis.load_transfer import wheel_loads
from vehicle_assist.plant.chassis.two_track import (
    STOP_SPEED_MPS,
    at_rest,
    body_forces,
    braking_slip,
    wheel_kinematics,
    wheel_spin_step,
    yaw_moment,
)
from vehicle_assist.plant.sensors import sample_sensors
from vehicle_assist.plant.tires import blowout as bo
from vehicle_assist.plant.tires.model import BURCKHARDT_SETS, MODEL_DUGOFF, peak_mu, tire_forces
from vehicle_assist.vehicles.common import (
    IN_BRAKE_PEDAL,
    IN_STEERING,
    apply_events,
    countdown,
    driver_inputs,
    event_buffers,
    road_friction_at,
    sensor_buffers,
)

LAYOUT = "sedan_esp"
ROAD_GRADE = False  # the two-track plant has no grade force: a scenario slope is refused (loader), not ignored
G = G_MPS2
STOP_AFTER_S = 1.0  # assumed: the run ends 1 s after standstill (ramp-out and hand-back are over by then)
WHEELS = ("fl", "fr", "rl", "rr")

SENSORS = tuple(f"wheel_speed_{w}_radps" for w in WHEELS) + (
    "master_pressure_pa",
    "longitudinal_accel_mps2",
    "lateral_accel_mps2",
    "yaw_rate_radps",
    "steering_angle_rad",
    "brake_light_switch_flag",
    "tpms_alarm_wheel_index",
)
MEAS_DTYPE = np.dtype([(n, "f8") for n in SENSORS] + [(n.rsplit("_", 1)[0] + "_ok", "f8") for n in SENSORS]
                      + [("esp_valves_ok", "f8"), ("return_pump_ok", "f8")]
                      + [(f"inlet_valve_{w}_ok", "f8") for w in WHEELS])
EVENT_SIGNALS = ("speed_mps", "position_m", "master_pressure_pa", "pedal_force_n")
INPUTS = ("brake_pedal", "steering")
ACTUATORS: tuple[str, ...] = ("esp_valves", "return_pump") + tuple(f"inlet_valve_{w}" for w in WHEELS)
# actuator_fault (unpowered): ABS failed / pump failed; inlet_valve_* (any fault): that wheel's inlet stuck closed
DEFAULT_GEAR_INDEX = 0

_CH = {
    "time_s": "time since the start of the run",
    "position_m": "distance travelled along the path",
    "x_m": "global x of the CG (initial heading = +x)",
    "y_m": "global y of the CG (left +)",
    "heading_rad": "yaw angle psi (CCW +)",
    "speed_mps": "longitudinal speed u of the CG (body axes)",
    "lateral_speed_mps": "lateral speed v of the CG (body axes, left +)",
    "yaw_rate_radps": "yaw rate r (CCW +)",
    "accel_mps2": "longitudinal acceleration du/dt - v*r (forward +)",
    "lateral_accel_mps2": "lateral acceleration dv/dt + u*r (left +)",
    "vehicle_held_flag": "1 once the car is held at rest",
    "pedal_force_n": "driver's pedal force",
    "brake_pedal_frac": "scripted pedal fraction (x pedal.full_scale_force_n = force)",
    "steering_angle_rad": "front wheel steer angle",
    "steering_wheel_angle_rad": "steering-wheel angle = front wheel steer angle x lane_keeper.steering_ratio",
    "booster_force_n": "booster output force on the master-cylinder piston",
    "master_pressure_pa": "master-cylinder pressure p_mc (both chambers)",
    "master_pressure_meas_pa": "p_mc as the ESP's pressure sensor reports it",
    "reference_speed_mps": "the ESP's reference speed from the wheel speeds",
    "hba_mode_index": "HBA mode (0 INACTIVE, 1 ACTIVE, 2 TERMINATING; -1 disabled)",
    "hba_available_flag": "1 while the ESP offers HBA (enabled, ABS, pump and pressure sensor healthy)",
    "hba_entry_flags": "bit field of the HBA entry conditions (1 p, 2 rate, 4 speed, 8 pedal, 16 rising, 32 sensor, 64 ABS)",
    "master_pressure_rate_pa_per_s": "dp_mc/dt as the HBA computes it (sampled)",
    "pump_on_flag": "return-pump motor running",
    "friction_mu": "road friction scale at the car",
    "blowout_frac": "deflation phi of the blown tire (0 intact, 1 flat; tire_blowout.md 3 eq. 21)",
    "blowout_transfer_n": "load transfer f through the suspension diagonals (eqs. 13-20)",
    "blowout_drag_n": "retarding drag of the blown tire on its rim",
    "blowout_mode_index": "compensation mode (functions/blowout_compensation.py MODES)",
    "blowout_detected_wheel_index": "wheel the ECU found blown (-1 none)",
    "blowout_wheel_index": "plant truth: the wheel that blew out, from the blowout on (-1 none or before); metrics only",
    "blowout_moment_est_nm": "the ECU's estimate of the added yaw moment M_z_blow (eqs. 22-25)",
    "blowout_pressure_req_pa": "target pressure of the compensating wheel: its pressure at detection + p_w (eq. 28)",
    "blowout_valve_time_s": "inlet-valve opening time (eq. 30)",
    "blowout_saturated_flag": "1 if the required pressure exceeds 0.9 p_max (accumulator too low)",
    "blowout_limit_code": ("authority limit / refusal: 0 none, 1 opposite inlet stuck (other axle used), 2 no healthy "
                           "wheel, 3 refused: |r| > 0.85*mu*g/u, 4 refused: |beta_est| > atan(0.02*mu*g), 5 rear blowout beyond "
                           "the stable region toward the blown side: the front wheel of the compensating side braked "
                           "(spin_front_flag), 6 the blown rear's side's front inlet stuck: the blown rear left to the "
                           "driver and ABS while braking, no counter-brake (blown_side_fault_flag)"),
    "yaw_moment_nm": "net yaw moment of the tire forces M_x + M_y (eqs. 9-11)",
    "lane_offset_m": "lateral offset of the CG from the lane centre (left +)",
    "lane_heading_error_rad": "heading minus lane heading",
}
for _w in WHEELS:
    _CH[f"wheel_speed_{_w}_radps"] = f"wheel speed {_w}"
    _CH[f"wheel_slip_{_w}_frac"] = f"braking slip {_w} (0 rolling, 1 locked), plant"
    _CH[f"wheel_load_{_w}_n"] = f"vertical load {_w}"
    _CH[f"wheel_pressure_{_w}_pa"] = f"wheel-cylinder pressure {_w}"
    _CH[f"source_pressure_{_w}_pa"] = f"driver's pressure at {_w} (p_mc front, p_prop(p_mc) rear)"
    _CH[f"tire_force_x_{_w}_n"] = f"longitudinal tire force {_w} (wheel axes, forward +)"
    _CH[f"tire_force_y_{_w}_n"] = f"lateral tire force {_w} (wheel axes, left +)"
    _CH[f"abs_mode_{_w}_index"] = f"ABS mode {_w} (0 OFF, 1 HOLD, 2 DUMP, 3 BUILD)"
    _CH[f"wheel_mode_{_w}_index"] = f"ESP unit valve mode {_w} (plant/brakes/esp_unit.py MODES)"
    _CH[f"wheel_locked_{_w}_flag"] = f"1 while wheel {_w} is locked (omega = 0) with the car moving"
for _c in ("1", "2"):
    _CH[f"usv_closed_c{_c}_flag"] = f"switching valve of circuit {_c} closed"
    _CH[f"hsv_open_c{_c}_flag"] = f"high-pressure valve of circuit {_c} open"
CHANNELS: dict[str, str] = _CH
TRACE_DTYPE = np.dtype([(name, "f8") for name in CHANNELS])
MACHINES = (
    StateMachine("vehicle", ("MOVING", "HELD"), (Transition("MOVING", "HELD", "stopped"),)),
    abs_fn.machine("fl"), abs_fn.machine("fr"), abs_fn.machine("rl"), abs_fn.machine("rr"),
    hba.MACHINE,
    bc.MACHINE,
)
M_VEHICLE, M_ABS0, M_HBA, M_BLOWOUT = 0, 1, 5, 6
M_SCENARIO = len(MACHINES)


@nb.njit(cache=True, nogil=True, error_model="numpy")
def simulate(p, s, noise, meas, ctl, wheels, hst, bst, lkbuf, tr, events):
    """Run one scenario; arguments as in :func:`vehicle_assist.vehicles.ev_ehb.simulate`."""
    dt = s.plant_step_s
    n_steps = int(round(s.duration_s / dt))
    ctrl_every = max(1, int(round(s.controller_period_s / dt)))
    esp_every = max(1, int(round(p.esp_period_s / s.controller_period_s)))
    rec_every = max(1, int(round(s.record_period_s / dt)))
    n_sens = noise.shape[1]
    # parameters (short symbols as in the spec)
    m = p.body_mass_kg
    i_z = p.body_yaw_inertia_kgm2
    r_w = p.body_wheel_radius_m
    j_w = p.body_wheel_inertia_kgm2
    l_f = p.chassis_cg_to_front_axle_m
    l_r = p.chassis_wheelbase_m - l_f
    h = p.chassis_cg_height_m
    b_f = 0.5 * p.chassis_front_track_m
    b_r = 0.5 * p.chassis_rear_track_m
    pos_x = np.array([l_f, l_f, -l_r, -l_r])
    pos_y = np.array([b_f, -b_f, b_r, -b_r])
    lever = max(math.sqrt(l_f * l_f + b_f * b_f), math.sqrt(l_r * l_r + b_r * b_r))  # farthest contact point from the CG
    # plant truth: the pads' actual friction is brakes_gain_scale_frac x nominal; the ECU plans with the nominal
    # p.brakes_*_gain_nm_per_pa (functions/), so a gain error is testable (issue #10)
    gain = np.array([p.brakes_front_gain_nm_per_pa, p.brakes_front_gain_nm_per_pa,
                     p.brakes_rear_gain_nm_per_pa, p.brakes_rear_gain_nm_per_pa]) * p.brakes_gain_scale_frac
    cx_true = p.tires_longitudinal_stiffness_n * p.tires_longitudinal_stiffness_scale_frac  # plant truth likewise
    c_y = np.array([p.tires_cornering_stiffness_front_n_per_rad, p.tires_cornering_stiffness_front_n_per_rad,
                    p.tires_cornering_stiffness_rear_n_per_rad, p.tires_cornering_stiffness_rear_n_per_rad])
    side_set = np.array([int(p.surface_left), int(p.surface_right), int(p.surface_left), int(p.surface_right)])
    tire_model = int(p.tires_model)
    source_kind = int(p.esp_unit_pressure_source)
    blown = int(p.blowout_wheel_index)
    t_blow = 1e18
    k_sf = bo.series_rate_npm(p.blowout_suspension_rate_front_n_per_m, p.blowout_tire_vertical_rate_n_per_m)
    k_sr = bo.series_rate_npm(p.blowout_suspension_rate_rear_n_per_m, p.blowout_tire_vertical_rate_n_per_m)
    follow = int(p.lane_keeper_steering_mode) == lk.FOLLOW
    lk_delay = int(round(p.lane_keeper_reaction_delay_s / dt))
    k_us = lk.understeer_gradient(m, l_f, l_r, 2.0 * c_y[0], 2.0 * c_y[2])
    rw = np.full(4, r_w)
    b_open_s = np.zeros(4)
    inlet_ok = np.ones(4)
    phi = 0.0
    f_tr = 0.0
    f_bd = 0.0
    e_y = 0.0
    e_psi = 0.0
    delta = 0.0

    inputs, override_on, override_value, fired, due, signals = event_buffers(len(EVENT_SIGNALS))
    history, delay_ticks, actuator_fault, fault, fault_value, last, truth, values, ok = \
        sensor_buffers(s, n_sens, len(ACTUATORS))
    abs_guards = np.zeros(6, dtype=np.bool_)
    hba_guards = np.zeros(8, dtype=np.bool_)

    # state
    u = s.initial_speed_mps
    v = s.initial_lateral_speed_mps
    r = 0.0
    gx = 0.0
    gy = 0.0
    psi = 0.0
    dist = s.initial_position_m
    a_x = 0.0
    a_y = 0.0
    if p.lane_keeper_lane_radius_m != 0.0:  # start in steady cornering on the lane's circle (linear single track; R < 0 right)
        r = u / p.lane_keeper_lane_radius_m
        v = u * (l_r - m * l_f * u * u / ((l_f + l_r) * 2.0 * c_y[2])) / p.lane_keeper_lane_radius_m
        a_y = u * r
        psi = -math.atan2(v, u)  # the velocity, not the body axis, is tangent to the lane (side-slip)
    omega = np.full(4, u / r_w)
    pw = np.zeros(4)
    driver_inputs(s, 0.0, override_on, override_value, inputs)
    f_pedal = max(inputs[IN_BRAKE_PEDAL], 0.0) * p.pedal_full_scale_force_n
    f_boost = booster_target_n(f_pedal, p.pedal_ratio, p.booster_gain, p.booster_runout_force_n)
    p_mc = master_pressure_pa(f_boost, p.master_cylinder_area_m2)
    psrc = np.zeros(4)
    for i in range(4):
        pw[i] = p_mc if i < 2 else proportioned_pa(p_mc, p.master_cylinder_proportioning_knee_pa,
                                                   p.master_cylinder_proportioning_slope_frac)
        psrc[i] = pw[i]
    held = False
    held_since = 0.0
    n_events = np.int64(0)
    n_rec = np.int64(0)
    tick = np.int64(0)
    fz = np.zeros(4)
    fx = np.zeros(4)
    fy = np.zeros(4)
    slip = np.zeros(4)
    damp = np.zeros(4)
    vlong = np.zeros(4)
    locked = np.zeros(4, dtype=np.bool_)
    xb = np.zeros(4)
    yb = np.zeros(4)
    valve = np.zeros(4)  # per circuit: USV closed, HSV open ; pump
    pump_on = False

    ctrl_left = np.int64(0)  # steps to the next sampling tick / trace row (countdowns)
    rec_left = np.int64(0)
    for k in range(n_steps + 1):
        t = k * dt
        ctrl_now, ctrl_left = countdown(ctrl_left, ctrl_every)
        rec_now, rec_left = countdown(rec_left, rec_every)
        signals[0] = u
        signals[1] = dist
        signals[2] = p_mc
        signals[3] = f_pedal
        stop = False
        if s.event_count > 0:
            n_events, _ev, stop = apply_events(s, fired, due, t, signals, events, n_events, M_SCENARIO,
                                               override_on, override_value, fault, fault_value, actuator_fault)
        valves_ok = actuator_fault[0, 0] == 0.0
        pump_ok = actuator_fault[1, 0] == 0.0
        for i in range(4):
            inlet_ok[i] = 1.0 if actuator_fault[2 + i, 0] == 0.0 else 0.0
        driver_inputs(s, t, override_on, override_value, inputs)  # every step: panic pedals rise in ~10 ms
        f_pedal = max(inputs[IN_BRAKE_PEDAL], 0.0) * p.pedal_full_scale_force_n
        e_y, e_psi = lk.lane_errors(gx, gy, psi, p.lane_keeper_lane_radius_m)
        # curve feed-forward of the driver (drivers/lane_keeper.py): held for the entry speed, or at the present one
        d_ff = lk.curve_steer_rad(p.lane_keeper_lane_radius_m, u if follow else s.initial_speed_mps, l_f + l_r, k_us)
        if follow:
            k_lat, k_head = lk.preview_gains(p.lane_keeper_lateral_gain_rad_per_m, p.lane_keeper_heading_gain_frac, u)
            # the driver sees the course (velocity direction), not the body axis: e_psi + side-slip angle
            delta = lk.lane_keeper_step(lkbuf, k, lk_delay, e_y, e_psi + math.atan2(v, max(u, 0.1)), inputs[IN_STEERING] + d_ff, delta if k > 0 else inputs[IN_STEERING] + d_ff,
                                        k_lat, k_head,
                                        p.lane_keeper_max_steer_rate_radps / p.lane_keeper_steering_ratio, dt)
        else:
            delta = inputs[IN_STEERING] + d_ff
        # blowout event (time or position) and deflation
        if blown >= 0 and t_blow > 1e17:
            if (p.blowout_position_m >= 0.0 and dist >= p.blowout_position_m) or (p.blowout_position_m < 0.0 and t >= p.blowout_time_s):
                t_blow = t
        if blown >= 0:
            phi = bo.deflation_frac(t, t_blow, p.blowout_deflation_time_s)
            rw[blown] = bo.blown_radius_m(phi, r_w, p.blowout_inner_radius_m)
        bls = f_pedal > p.pedal_light_switch_force_n

        if ctrl_now:
            for i in range(4):
                truth[i] = omega[i]
            truth[4] = p_mc
            truth[5] = a_x
            truth[6] = a_y
            truth[7] = r
            truth[8] = delta
            truth[9] = 1.0 if bls else 0.0
            truth[10] = float(blown + 1) if (blown >= 0 and phi >= p.blowout_tpms_alarm_drop_frac) else 0.0
            sample_sensors(truth, history, tick, noise[min(tick, noise.shape[0] - 1)], s.sensor_noise_std,
                           s.sensor_bias, delay_ticks, fault, fault_value, last, values, ok)
            meas.wheel_speed_fl_radps = values[0]
            meas.wheel_speed_fr_radps = values[1]
            meas.wheel_speed_rl_radps = values[2]
            meas.wheel_speed_rr_radps = values[3]
            meas.master_pressure_pa = values[4]
            meas.longitudinal_accel_mps2 = values[5]
            meas.lateral_accel_mps2 = values[6]
            meas.yaw_rate_radps = values[7]
            meas.steering_angle_rad = values[8]
            meas.brake_light_switch_flag = values[9]
            meas.wheel_speed_fl_ok = ok[0]
            meas.wheel_speed_fr_ok = ok[1]
            meas.wheel_speed_rl_ok = ok[2]
            meas.wheel_speed_rr_ok = ok[3]
            meas.master_pressure_ok = ok[4]
            meas.longitudinal_accel_ok = ok[5]
            meas.lateral_accel_ok = ok[6]
            meas.yaw_rate_ok = ok[7]
            meas.steering_angle_ok = ok[8]
            meas.brake_light_switch_ok = ok[9]
            meas.tpms_alarm_wheel_index = values[10]
            meas.tpms_alarm_wheel_ok = ok[10]
            meas.inlet_valve_fl_ok = inlet_ok[0]  # the ECU's valve-coil diagnosis
            meas.inlet_valve_fr_ok = inlet_ok[1]
            meas.inlet_valve_rl_ok = inlet_ok[2]
            meas.inlet_valve_rr_ok = inlet_ok[3]
            meas.esp_valves_ok = 1.0 if valves_ok else 0.0  # the ECU's own actuator diagnosis
            meas.return_pump_ok = 1.0 if pump_ok else 0.0
            if tick % esp_every == 0:
                n_events = esp.esp_step(ctl, wheels, hst, meas, p, p.esp_period_s, t, M_ABS0, M_HBA, events,
                                        n_events, abs_guards, hba_guards, bst, M_BLOWOUT)
            tick += 1

        # ESP unit valves (VALVE_TABLE rows) per circuit (X-split: fl+rr circuit 1, fr+rl circuit 2)
        for c in range(4):
            valve[c] = 0.0
        pump_on = False
        for i in range(4):
            wm = int(wheels[i, esp.A_WHEEL_MODE]) if valves_ok else 0
            c = 0 if (i == 0 or i == 3) else 1
            valve[2 * c] = max(valve[2 * c], VALVE_TABLE[wm, 0])
            valve[2 * c + 1] = max(valve[2 * c + 1], VALVE_TABLE[wm, 1])
            if VALVE_TABLE[wm, 4] > 0.5:
                pump_on = True

        # forces at t from the state at t
        mu_scale = road_friction_at(s, dist)
        fz[0], fz[1], fz[2], fz[3] = wheel_loads(m, G, l_f, l_r, h, 2.0 * b_f, 2.0 * b_r,
                                                 p.chassis_roll_stiffness_front_frac, a_x, a_y)
        if blown >= 0 and phi > 0.0:
            f_tr = bo.transfer_n(blown, fz[0], fz[1], fz[2], fz[3], r_w - rw[blown], k_sf, k_sr)
            fz[0], fz[1], fz[2], fz[3] = bo.redistributed_loads(blown, fz[0], fz[1], fz[2], fz[3], f_tr)
        sum_x = 0.0
        sum_y = 0.0
        for i in range(4):
            d_i = delta if i < 2 else 0.0
            vl, tan_a = wheel_kinematics(u, v, r, d_i, pos_x[i], pos_y[i])
            vlong[i] = vl
            if not held and omega[i] * rw[i] > max(vl, 0.0):
                # no drive torque on these wheels: an over-speeding wheel rolls with the ground (it cannot roll backward)
                omega[i] = max(vl, 0.0) / rw[i]
            sl = braking_slip(vl, omega[i], rw[i]) if not held else 0.0
            c1 = BURCKHARDT_SETS[side_set[i], 0]
            c2 = BURCKHARDT_SETS[side_set[i], 1]
            c3 = BURCKHARDT_SETS[side_set[i], 2]
            kx = cx_true
            ky = c_y[i]
            if i == blown and phi > 0.0:
                kx *= bo.stiffness_factor(phi, p.blowout_longitudinal_stiffness_frac)
                ky *= bo.stiffness_factor(phi, p.blowout_cornering_stiffness_frac)
            backward = not held and vl < 0.0
            if backward:
                # rolling backward (a spun car; the wheel's backward rotation is not a state, omega >= 0): the brake
                # acts quasi-statically - the slip at which the tire force balances the brake torque capacity, or the
                # locked wheel (s = 1) when the tire cannot carry it; the force then points forward, against the
                # motion (braking_slip alone gave s = 0 for v_long < 0: a braked car rolling backward had no brake)
                sl = _backward_slip(tire_model, gain[i] * max(pw[i], 0.0) / rw[i], tan_a, fz[i], mu_scale,
                                    c1, c2, c3, kx, ky, p.blowout_friction_reduction_coeff, -vl)
            slip[i] = sl
            if held:
                fx[i] = 0.0
                fy[i] = 0.0
                damp[i] = 0.0
            elif backward:
                fxm, fy[i] = _tire(tire_model, sl, tan_a, fz[i], mu_scale, c1, c2, c3, kx, ky,
                                   p.blowout_friction_reduction_coeff, -vl)
                fx[i] = -fxm  # mirrored: the retarding force of a wheel moving backward points forward
                damp[i] = 0.0
            else:
                fx[i], fy[i] = _tire(tire_model, sl, tan_a, fz[i], mu_scale, c1, c2, c3, kx, ky,
                                     p.blowout_friction_reduction_coeff, vl)
                f2, _ = _tire(tire_model, min(sl + 1e-4, 1.0), tan_a, fz[i], mu_scale, c1, c2, c3, kx, ky,
                              p.blowout_friction_reduction_coeff, vl)
                ds = min(sl + 1e-4, 1.0) - sl
                dfds = (f2 - fx[i]) / ds if ds > 0.0 else 0.0
                damp[i] = rw[i] * rw[i] * max(-dfds, 0.0) / max(vl, 1.0)
            fxb = fx[i]
            if i == blown and phi > 0.0 and not held:
                f_bd = bo.blown_drag_n(phi, p.blowout_drag_coeff, fz[i], mu_scale * peak_mu(c1, c2, c3))
                fxb -= f_bd if vl > 0.0 else (-f_bd if vl < 0.0 else 0.0)  # the flat tire's drag opposes the motion
            xb[i], yb[i] = body_forces(fxb, fy[i], d_i)
            sum_x += xb[i]
            sum_y += yb[i]
            locked[i] = omega[i] <= 0.0 and u > STOP_SPEED_MPS
        m_z = yaw_moment(xb[0], xb[1], xb[2], xb[3], yb[0], yb[1], yb[2], yb[3], l_f, l_r, b_f, b_r)
        f_drag = 0.5 * RHO_AIR_KGPM3 * p.body_drag_area_m2 * u * abs(u)
        f_roll = m * G * p.body_rolling_resistance_coeff if u > 0.0 else 0.0
        if u < 0.0:  # rolling backward (a car spinning or sliding at low speed): the resistance opposes u
            f_roll = -m * G * p.body_rolling_resistance_coeff
        a_x_new = (sum_x - f_drag - f_roll) / m if not held else 0.0
        a_y_new = sum_y / m if not held else 0.0

        if rec_now and n_rec < tr.shape[0]:
            row = tr[n_rec]
            row.time_s = t
            row.position_m = dist
            row.x_m = gx
            row.y_m = gy
            row.heading_rad = psi
            row.speed_mps = u
            row.lateral_speed_mps = v
            row.yaw_rate_radps = r
            row.accel_mps2 = a_x_new
            row.lateral_accel_mps2 = a_y_new
            row.vehicle_held_flag = 1.0 if held else 0.0
            row.pedal_force_n = f_pedal
            row.brake_pedal_frac = inputs[IN_BRAKE_PEDAL]
            row.steering_angle_rad = delta
            row.steering_wheel_angle_rad = delta * p.lane_keeper_steering_ratio
            row.booster_force_n = f_boost
            row.master_pressure_pa = p_mc
            row.master_pressure_meas_pa = meas.master_pressure_pa
            row.reference_speed_mps = ctl[esp.C_V_REF]
            row.hba_mode_index = hst[hba.S_MODE] if p.brake_assist_enabled_flag > 0.5 else -1.0
            row.hba_available_flag = ctl[esp.C_HBA_AVAILABLE]
            row.hba_entry_flags = hst[hba.S_ENTRY_FLAGS]
            row.master_pressure_rate_pa_per_s = hst[hba.S_RATE]
            row.pump_on_flag = 1.0 if (pump_on and pump_ok) else 0.0
            row.friction_mu = mu_scale
            row.blowout_frac = phi
            row.blowout_transfer_n = f_tr
            row.blowout_drag_n = f_bd
            row.blowout_mode_index = bst[bc.S_MODE]
            row.blowout_detected_wheel_index = bst[bc.S_BLOWN]
            row.blowout_wheel_index = float(blown) if (blown >= 0 and phi > 0.0) else -1.0
            row.blowout_moment_est_nm = bst[bc.S_M_EST]
            row.blowout_pressure_req_pa = bst[bc.S_P_REQ]
            row.blowout_valve_time_s = bst[bc.S_T_VALVE]
            row.blowout_saturated_flag = bst[bc.S_SATURATED]
            row.blowout_limit_code = bst[bc.S_LIMIT_CODE]
            row.yaw_moment_nm = m_z
            row.lane_offset_m = e_y
            row.lane_heading_error_rad = e_psi
            row.usv_closed_c1_flag = valve[0]
            row.hsv_open_c1_flag = valve[1]
            row.usv_closed_c2_flag = valve[2]
            row.hsv_open_c2_flag = valve[3]
            row.wheel_speed_fl_radps = omega[0]
            row.wheel_speed_fr_radps = omega[1]
            row.wheel_speed_rl_radps = omega[2]
            row.wheel_speed_rr_radps = omega[3]
            row.wheel_slip_fl_frac = slip[0]
            row.wheel_slip_fr_frac = slip[1]
            row.wheel_slip_rl_frac = slip[2]
            row.wheel_slip_rr_frac = slip[3]
            row.wheel_load_fl_n = fz[0]
            row.wheel_load_fr_n = fz[1]
            row.wheel_load_rl_n = fz[2]
            row.wheel_load_rr_n = fz[3]
            row.wheel_pressure_fl_pa = pw[0]
            row.wheel_pressure_fr_pa = pw[1]
            row.wheel_pressure_rl_pa = pw[2]
            row.wheel_pressure_rr_pa = pw[3]
            row.source_pressure_fl_pa = psrc[0]
            row.source_pressure_fr_pa = psrc[1]
            row.source_pressure_rl_pa = psrc[2]
            row.source_pressure_rr_pa = psrc[3]
            row.tire_force_x_fl_n = fx[0]
            row.tire_force_x_fr_n = fx[1]
            row.tire_force_x_rl_n = fx[2]
            row.tire_force_x_rr_n = fx[3]
            row.tire_force_y_fl_n = fy[0]
            row.tire_force_y_fr_n = fy[1]
            row.tire_force_y_rl_n = fy[2]
            row.tire_force_y_rr_n = fy[3]
            row.abs_mode_fl_index = wheels[0, esp.A_MODE]
            row.abs_mode_fr_index = wheels[1, esp.A_MODE]
            row.abs_mode_rl_index = wheels[2, esp.A_MODE]
            row.abs_mode_rr_index = wheels[3, esp.A_MODE]
            row.wheel_mode_fl_index = wheels[0, esp.A_WHEEL_MODE] if valves_ok else 0.0
            row.wheel_mode_fr_index = wheels[1, esp.A_WHEEL_MODE] if valves_ok else 0.0
            row.wheel_mode_rl_index = wheels[2, esp.A_WHEEL_MODE] if valves_ok else 0.0
            row.wheel_mode_rr_index = wheels[3, esp.A_WHEEL_MODE] if valves_ok else 0.0
            row.wheel_locked_fl_flag = 1.0 if locked[0] else 0.0
            row.wheel_locked_fr_flag = 1.0 if locked[1] else 0.0
            row.wheel_locked_rl_flag = 1.0 if locked[2] else 0.0
            row.wheel_locked_rr_flag = 1.0 if locked[3] else 0.0
            n_rec += 1
        if k == n_steps or stop or (held and t - held_since >= STOP_AFTER_S):
            break

        # advance to t + dt: booster, master cylinder, wheel pressures
        f_boost = booster_step(f_boost, booster_target_n(f_pedal, p.pedal_ratio, p.booster_gain, p.booster_runout_force_n),
                               p.booster_time_constant_s, dt)
        p_mc = master_pressure_pa(f_boost, p.master_cylinder_area_m2)
        p_rear = proportioned_pa(p_mc, p.master_cylinder_proportioning_knee_pa, p.master_cylinder_proportioning_slope_frac)
        for i in range(4):
            psrc[i] = p_mc if i < 2 else p_rear
            wm = int(wheels[i, esp.A_WHEEL_MODE]) if valves_ok else 0
            if inlet_ok[i] < 0.5 and VALVE_TABLE[wm, 2] > 0.0 and VALVE_TABLE[wm, 3] < 0.5:
                wm = 3  # inlet stuck closed: whatever opens the inlet only holds (H)
            # accumulator source (EHB of paper 004): the inlet passes nothing for the dead time t0 (eq. 29)
            b_open_s[i] = b_open_s[i] + dt if (wm == 1 or wm == 5) else 0.0
            rate = source_rate_pa_per_s(source_kind, pw[i], p.esp_unit_pump_build_rate_pa_per_s, p.esp_unit_pump_relief_pa,
                                        p.esp_unit_accumulator_pa, p.esp_unit_accumulator_time_constant_s, pump_ok)
            if source_kind == 1 and b_open_s[i] <= p.esp_unit_inlet_dead_time_s:
                rate = 0.0
            pw[i] = wheel_pressure_step(wm, pw[i], psrc[i], dt, p.esp_unit_line_time_constant_s, rate,
                                        p.esp_unit_pump_relief_pa, p.esp_unit_pulse_duty_frac,
                                        p.esp_unit_dump_time_constant_s, p.esp_unit_lpa_pressure_pa,
                                        p.esp_unit_exit_rate_pa_per_s, p.esp_unit_pump_build_rate_pa_per_s)
        if held:
            continue
        # wheels (brake torque capacity K_b*p) and body
        for i in range(4):
            omega[i], _lk = wheel_spin_step(omega[i], gain[i] * max(pw[i], 0.0), fx[i], damp[i], rw[i], j_w, dt)
        a_x = a_x_new
        a_y = a_y_new
        du = a_x + v * r
        dv = a_y - u * r
        dr = m_z / i_z
        u += du * dt
        v += dv * dt
        r += dr * dt
        psi += r * dt
        gx += (u * math.cos(psi) - v * math.sin(psi)) * dt
        gy += (u * math.sin(psi) + v * math.cos(psi)) * dt
        dist += math.sqrt(u * u + v * v) * dt
        if at_rest(u, v, r, lever):  # every contact point slow (was: u alone, which froze a car sliding sideways)
            held = True
            held_since = t + dt
            u = 0.0
            v = 0.0
            r = 0.0
            a_x = 0.0
            a_y = 0.0
            for i in range(4):
                omega[i] = 0.0
            n_events = log_event(events, n_events, t + dt, M_VEHICLE, 0, 1, 0)
    return n_rec, n_events


@nb.njit(cache=True, nogil=True, error_model="numpy")
def _backward_slip(model, f_brake_n, tan_a, fz, scale, c1, c2, c3, cx, cy, eps_r, speed_mps):
    """Slip of a braked wheel rolling backward, quasi-static (its rotation is not integrated backward): the smallest
    s whose retarding tire force equals the brake force f_brake_n = T_b/R (the stable, rising branch), 1 (locked)
    when no slip carries it, 0 when unbraked."""
    if f_brake_n <= 0.0:
        return 0.0
    n = 32
    lo = 0.0
    hi = -1.0
    for k in range(1, n + 1):
        s_k = k / n
        if -_tire(model, s_k, tan_a, fz, scale, c1, c2, c3, cx, cy, eps_r, speed_mps)[0] >= f_brake_n:
            hi = s_k
            break
        lo = s_k
    if hi < 0.0:
        return 1.0
    for _ in range(30):
        mid = 0.5 * (lo + hi)
        if -_tire(model, mid, tan_a, fz, scale, c1, c2, c3, cx, cy, eps_r, speed_mps)[0] >= f_brake_n:
            hi = mid
        else:
            lo = mid
    return hi


@nb.njit(cache=True, nogil=True, error_model="numpy")
def _tire(model, slip, tan_a, fz, scale, c1, c2, c3, cx, cy, eps_r, u_w):
    """tire_forces, with the Dugoff friction reduction with slip speed (tire_blowout.md 2.3) when eps_r > 0."""
    if model == MODEL_DUGOFF and eps_r > 0.0:
        fxm, fyv = bo.dugoff_full(slip, tan_a, fz, scale * peak_mu(c1, c2, c3), cx, cy, eps_r, u_w)
        return -fxm, fyv
    return tire_forces(model, slip, tan_a, fz, scale, c1, c2, c3, cx, cy)


def gear_names(model) -> list[str]:
    return ["D"]


def derived(flat: dict) -> dict:
    """Brake gains per wheel (common.md 7.1) and the master-cylinder bore area."""
    out = dict(flat)
    faces = flat["brakes_friction_faces_count"]
    mu = flat["brakes_pad_friction_coeff"]
    eff = flat["brakes_efficiency_frac"]
    out["brakes_front_gain_nm_per_pa"] = brake_gain_nm_per_pa(
        faces, mu, piston_area_m2(flat["brakes_front_piston_diameter_m"]), flat["brakes_front_effective_radius_m"], eff)
    out["brakes_rear_gain_nm_per_pa"] = brake_gain_nm_per_pa(
        faces, mu, piston_area_m2(flat["brakes_rear_piston_diameter_m"]), flat["brakes_rear_effective_radius_m"], eff)
    out["master_cylinder_area_m2"] = piston_area_m2(flat["master_cylinder_bore_diameter_m"])
    return out


def controller_states() -> tuple:
    meas = np.zeros(1, dtype=MEAS_DTYPE).view(np.recarray)
    ctl, wheels, hst = esp.initial_state()
    return meas[0], ctl, wheels, hst, bc.initial_state(), lk.initial_buffer()


def run_kernel(p, s, noise, trace, events):
    meas, ctl, wheels, hst, bst, lkbuf = controller_states()
    return simulate(p, s, noise, meas, ctl, wheels, hst, bst, lkbuf, trace, events)
