"""AMT passenger car of paper 003 (curve-aware shifting with map preview; curve_shift.md 5.3 and 6; issue #11).

Composition: longitudinal body on the road's grade (common.md 3) + torque-demand engine + 5-speed AMT gearbox
with final drive (plant/powertrain/gearbox.py: the shift runs through neutral for ``shift_time_s``, the torque
interruption) + lumped service brake with a lag + the platform's single-track mode (plant/chassis/single_track.py)
driven along the road's curvature; the five-phase curve driver (drivers/curve_driver.py) or the scripted driver;
sensors incl. the map preview (plant/map_preview.py); the TCU runs the curve-aware strategy over the normal
schedule (functions/curve_shift.py, shift_schedule.py).

Why these pieces: the spec's vehicle model (5.3) is a point mass with a rigid driveline in gear; the truck's
governed diesel (plant/powertrain/engine.py) models an all-speed governor, so the car keeps its friction torque
(``friction_torque_nm``) and full-load table but has a torque-demand map:

    T_e = theta*T_full(w) + (1 - theta)*T_mot(w),   T_mot(w) = -(c0 + c1*w)     (curve_shift.md 5.3)
    below idle the idle governor adds min(K_idle*(w_idle - w), T_full(w))
    in gear:   (delta*m) dv/dt = T_e*i*eta/r - F_f - F_w - F_i - F_b,   w_e = v*i/r (rigid, no clutch slip)
    shifting:  (delta*m) dv/dt = -F_f - F_w - F_i - F_b, engine synchronised to the target gear's speed
               linearly over the shift time (the AMT's engine-speed control; no clutch slip modelled)

The truck's clutch plant is not used: a moving AMT car shifts with the clutch opened and re-closed at
synchronous speed, which the torque interruption represents. Lateral: beta, r from the single-track step with
u = v and the driver's steer; the lateral dynamics do not load the longitudinal model (cornering drag neglected).
Per plant step (1 ms): events; at the sampling tick the driver, the sensors and every ``curve_shift.period_s``
the TCU; forces; record; advance (semi-implicit Euler).
"""
from __future__ import annotations

import math
from pathlib import Path

import numba as nb
import numpy as np

from vehicle_assist.conventions import G_MPS2, STANDSTILL_SPEED_MPS
from vehicle_assist.core.fsm import StateMachine, Transition, log_event
from vehicle_assist.core.tables import Table, interp
from vehicle_assist.drivers import curve_driver
from vehicle_assist.functions import curve_shift
from vehicle_assist.plant.chassis import single_track
from vehicle_assist.plant.longitudinal import (
    aero_drag_n,
    equivalent_mass_kg,
    grade_resistance_n,
    rolling_resistance_capacity_n,
    stick_slip_step,
)
from vehicle_assist.plant.map_preview import CURVE_MAX_RADIUS_M, CURVE_MIN_LENGTH_M, next_curve, preview
from vehicle_assist.plant.powertrain.engine import friction_torque_nm
from vehicle_assist.plant.powertrain.gearbox import efficiency_factor, gear_ratio, shift_step
from vehicle_assist.plant.sensors import sample_sensors
from vehicle_assist.vehicles.common import (
    IN_ACCELERATOR,
    IN_BRAKE_PEDAL,
    IN_GEAR_LEVER,
    apply_events,
    countdown,
    driver_inputs,
    event_buffers,
    road_at,
    sensor_buffers,
)

LAYOUT = "amt_car"
G = G_MPS2
V_EPS = STANDSTILL_SPEED_MPS

SENSORS = (
    "vehicle_speed_mps",
    "engine_speed_radps",
    "accelerator_frac",
    "brake_pedal_frac",
    "gear_engaged_index",
    "lateral_accel_mps2",
    "yaw_rate_radps",
    "curve_distance_m",
    "curve_radius_m",
    "curve_length_m",
    "curve_valid_flag",
)
SENSOR_DOC = {
    "curve_distance_m": "map preview: distance to the start of the next curve (negative inside it)",
    "curve_radius_m": "map preview: smallest radius of the next curve",
    "curve_length_m": "map preview: length of the next curve",
    "curve_valid_flag": "map preview: 1 while a curve is known within the preview range",
}
MEAS_DTYPE = np.dtype([(n, "f8") for n in SENSORS] + [(n.rsplit("_", 1)[0] + "_ok", "f8") for n in SENSORS])
EVENT_SIGNALS = ("speed_mps", "position_m", "engine_speed_radps")
INPUTS = ("accelerator", "brake_pedal", "gear_lever")
ACTUATORS: tuple[str, ...] = ()
DEFAULT_GEAR_INDEX = 1

CHANNELS: dict[str, str] = {
    "time_s": "time since the start of the run",
    "position_m": "distance travelled along the road's reference line",
    "speed_mps": "vehicle speed (forward +)",
    "accel_mps2": "longitudinal acceleration dv/dt",
    "slope_rad": "road grade angle (uphill +)",
    "curvature_per_m": "road curvature at the car (left +)",
    "gear_index": "engaged gear (0 = neutral while shifting)",
    "gear_command_index": "gear commanded by the TCU",
    "gear_command_prev_index": "gear command of the previous recorded sample (recorder delay line: lets an STL "
                               "requirement compare consecutive commands without rtamt's prev on numbers, which "
                               "returns 0 for prev(x) - x)",
    "engine_speed_radps": "engine speed",
    "engine_torque_nm": "engine net torque at the flywheel",
    "engine_power_w": "engine power T_e*w_e (negative: motoring)",
    "engine_indicated_power_w": "fuelled (indicated) engine power max(T_e + T_fric, 0)*w_e: brake power plus the friction "
                                "and pumping the fuel must also cover; 0 on overrun (fuel cut)",
    "drive_force_n": "tractive force at the wheels",
    "brake_force_n": "service brake force (magnitude of the retarding force)",
    "accelerator_frac": "accelerator (driver)",
    "brake_pedal_frac": "brake pedal (driver)",
    "steering_angle_rad": "front steer angle (driver)",
    "yaw_rate_radps": "yaw rate (single-track mode)",
    "sideslip_rad": "sideslip angle at the CG",
    "lateral_accel_mps2": "lateral acceleration (single-track mode, left +)",
    "driver_phase_index": "curve driver phase (0 straight, 1 approach, 2 curve, 3 exit; -1 scripted)",
    "curve_mode_flag": "1 while the curve command window is open (curve mode; the strategy acts on it only when enabled)",
    "curve_mode_held_index": "1 while curve mode is active at this and at the previous recorded sample (recorder "
                             "delay line; a number, not a flag, so that an STL robustness over it stays finite)",
    "preview_fallback_flag": "1 while the TCU has found the preview implausible and runs the normal schedule (FALLBACK)",
    "protection_upshift_count": "upshifts the engine protection released in curve mode so far (functions/curve_shift.py)",
    "advance_hold_count": "TCU periods so far in which the advance horizon kept a higher gear than the advanced/skip "
                          "downshift rule alone (predicted curve-entry engine speed above n_guard; functions/curve_shift.py)",
    "kj_ratio": "downshift advance kj of the line below the engaged gear (0 outside curve mode)",
    "kj_max_ratio": "kj_max of that line at the current throttle (eq. 14)",
    "kj_frac": "kj/kj_max held for the curve mode (from a_y_pred, a_ypot, a_ys)",
    "lateral_accel_pred_mps2": "a_y_pred = u_cmd^2/R at the curve command",
    "tolerable_accel_mps2": "a_ypot(R) at the curve command",
    "safety_accel_mps2": "a_ys(u_cmd) at the curve command",
    "normal_downshift_speed_mps": "u_a: normal-schedule downshift speed of the line below the engaged gear",
    "advanced_downshift_speed_mps": "u' = u_a*(1 + kj), capped at u_max",
    "preview_distance_m": "map preview distance to the next curve, as measured",
    "preview_radius_m": "map preview radius, as measured",
    "preview_valid_flag": "map preview validity, as measured",
    "curve_distance_true_m": "true distance to the start of the next curve",
    "curve_radius_true_m": "true radius of the next curve",
    "tolerable_accel_true_mps2": "a_ypot of the next curve's true radius (eq. 9/10 with the file's k)",
}
TRACE_DTYPE = np.dtype([(name, "f8") for name in CHANNELS])
MACHINES = (
    StateMachine("gearbox", ("IN_GEAR", "SHIFTING"), (
        Transition("IN_GEAR", "SHIFTING", "gear_change_started"),
        Transition("SHIFTING", "IN_GEAR", "gear_engaged"),
    )),
    curve_shift.MACHINE,
    curve_driver.MACHINE,
)
M_GEARBOX, M_SHIFT, M_DRIVER = range(3)
M_SCENARIO = len(MACHINES)


@nb.njit(cache=True, nogil=True, error_model="numpy")
def engine_torque_nm(p, w_e, theta):
    """T_e = theta*T_full + (1 - theta)*T_mot, plus the idle governor below idle (curve_shift.md 5.3)."""
    t_full = interp(p.engine_full_load_torque_x, p.engine_full_load_torque_y, p.engine_full_load_torque_n,
                    p.engine_full_load_torque_extrap, p.engine_full_load_torque_interp, w_e)
    t_mot = friction_torque_nm(w_e, p.engine_friction_offset_nm, p.engine_friction_slope_nm_per_radps)
    th = min(max(theta, 0.0), 1.0)
    t = th * t_full + (1.0 - th) * t_mot
    if w_e < p.engine_idle_speed_radps:
        t = max(t, min(p.engine_idle_governor_gain_nm_per_radps * (p.engine_idle_speed_radps - w_e), t_full))
    return t


@nb.njit(cache=True, nogil=True, error_model="numpy")
def simulate(p, s, noise, meas, ctl, drv, tr, events):
    """Run one scenario (arguments as in vehicles/truck_amt.py); returns (rows written, events logged)."""
    dt = s.plant_step_s
    n_steps = int(round(s.duration_s / dt))
    ctrl_every = max(1, int(round(s.controller_period_s / dt)))
    tcu_every = max(1, int(round(p.curve_shift_period_s / s.controller_period_s)))
    rec_every = max(1, int(round(s.record_period_s / dt)))
    n_sens = noise.shape[1]
    m = p.body_mass_kg
    r_w = p.body_wheel_radius_m
    i0 = p.gearbox_final_drive_ratio
    eta = p.gearbox_efficiency_frac
    n_gears = len(p.gearbox_ratios)
    l_f = p.chassis_cg_to_front_axle_m
    l_r = p.chassis_wheelbase_m - l_f
    brake_decay = math.exp(-dt / p.brakes_time_constant_s)
    steer_decay = math.exp(-dt / p.curve_driver_steer_time_constant_s)
    use_driver = p.curve_driver_enabled_flag > 0.5

    inputs, override_on, override_value, fired, due, signals = event_buffers(len(EVENT_SIGNALS))
    history, delay_ticks, actuator_fault, fault, fault_value, last, truth, values, ok = \
        sensor_buffers(s, n_sens, len(ACTUATORS))

    x = s.initial_position_m
    v = s.initial_speed_mps
    a = 0.0
    driver_inputs(s, 0.0, override_on, override_value, inputs)
    gear = min(max(int(round(inputs[IN_GEAR_LEVER])), 1), n_gears)  # the AMT starts in the lever's gear
    gear_target = gear
    shift_timer = 0.0
    ctl.gear_command_index = gear
    ctl.engaged_prev = gear
    w_e = max(v * gear_ratio(p.gearbox_ratios, n_gears, gear) * i0 / r_w, 0.0)
    if use_driver:
        curve_driver.start(drv, p, v)
        inputs[IN_ACCELERATOR] = drv.throttle_frac
        inputs[IN_BRAKE_PEDAL] = 0.0
    beta = 0.0
    yaw = 0.0
    a_y = 0.0
    steer = 0.0
    steer_target = 0.0
    f_b = 0.0
    n_events = np.int64(0)
    n_rec = np.int64(0)
    tick = np.int64(0)
    p_d = 0.0
    p_r = 0.0
    p_l = 0.0
    p_v = 0.0
    ctrl_left = np.int64(0)  # steps to the next sampling tick / trace row (countdowns)
    rec_left = np.int64(0)
    for k in range(n_steps + 1):
        t = k * dt
        ctrl_now, ctrl_left = countdown(ctrl_left, ctrl_every)
        rec_now, rec_left = countdown(rec_left, rec_every)
        signals[0] = v
        signals[1] = x
        signals[2] = w_e
        event_now = False
        stop = False
        if s.event_count > 0:
            n_events, event_now, stop = apply_events(s, fired, due, t, signals, events, n_events, M_SCENARIO,
                                                     override_on, override_value, fault, fault_value, actuator_fault)
        kappa = interp(s.road_curvature_x, s.road_curvature_y, s.road_curvature_n, s.road_curvature_extrap,
                       s.road_curvature_interp, x)
        if ctrl_now or event_now:
            if use_driver:
                if ctrl_now:
                    n_events = curve_driver.step(drv, p, s, t, x, v, s.controller_period_s, M_DRIVER, events, n_events)
                inputs[IN_ACCELERATOR] = drv.throttle_frac
                inputs[IN_BRAKE_PEDAL] = drv.brake_frac
                for i in range(2):
                    if override_on[i]:
                        inputs[i] = override_value[i]
            else:
                driver_inputs(s, t, override_on, override_value, inputs)
            steer_target = single_track.steer_for_curvature_rad(kappa, v, p.chassis_wheelbase_m,
                                                                p.chassis_understeer_rad_per_mps2)
        if ctrl_now:
            p_d, p_r, p_l, p_v = preview(p, s, x)
            truth[0] = v
            truth[1] = w_e
            truth[2] = inputs[IN_ACCELERATOR]
            truth[3] = inputs[IN_BRAKE_PEDAL]
            truth[4] = gear
            truth[5] = a_y
            truth[6] = yaw
            truth[7] = p_d
            truth[8] = p_r
            truth[9] = p_l
            truth[10] = p_v
            sample_sensors(truth, history, tick, noise[min(tick, noise.shape[0] - 1)], s.sensor_noise_std, s.sensor_bias,
                           delay_ticks, fault, fault_value, last, values, ok)
            meas.vehicle_speed_mps = values[0]
            meas.engine_speed_radps = values[1]
            meas.accelerator_frac = values[2]
            meas.brake_pedal_frac = values[3]
            meas.gear_engaged_index = values[4]
            meas.lateral_accel_mps2 = values[5]
            meas.yaw_rate_radps = values[6]
            meas.curve_distance_m = values[7]
            meas.curve_radius_m = values[8]
            meas.curve_length_m = values[9]
            meas.curve_valid_flag = values[10]
            meas.vehicle_speed_ok = ok[0]
            meas.engine_speed_ok = ok[1]
            meas.accelerator_ok = ok[2]
            meas.brake_pedal_ok = ok[3]
            meas.gear_engaged_ok = ok[4]
            meas.lateral_accel_ok = ok[5]
            meas.yaw_rate_ok = ok[6]
            meas.curve_distance_ok = ok[7]
            meas.curve_radius_ok = ok[8]
            meas.curve_length_ok = ok[9]
            meas.curve_valid_ok = ok[10]
            if tick % tcu_every == 0:
                n_events = curve_shift.step(ctl, meas, p, p.curve_shift_period_s, t, M_SHIFT, events, n_events)
            tick += 1

        # forces at t
        slope, f_coeff = road_at(s, x)
        f_i = grade_resistance_n(m, slope)
        f_roll_cap = rolling_resistance_capacity_n(m, slope, f_coeff)
        f_w = aero_drag_n(p.body_drag_area_m2, v)
        ratio = gear_ratio(p.gearbox_ratios, n_gears, gear) * i0
        theta = inputs[IN_ACCELERATOR]
        if ratio > 0.0:
            w_e = max(v, 0.0) * ratio / r_w
        t_e = engine_torque_nm(p, w_e, theta)
        if ratio > 0.0:
            f_t = t_e * ratio * efficiency_factor(t_e, eta) / r_w
            m_eq = equivalent_mass_kg(m, p.body_wheel_inertia_total_kgm2, r_w, p.engine_inertia_kgm2, ratio, eta)
        else:
            f_t = 0.0
            m_eq = equivalent_mass_kg(m, p.body_wheel_inertia_total_kgm2, r_w, 0.0, 0.0, eta)
        v_new, a, held, reaction = stick_slip_step(v, f_t - f_i - f_w, f_roll_cap + f_b, m_eq, dt, V_EPS)
        beta, yaw, a_y = single_track.step(beta, yaw, max(v, 0.0), steer, m, p.chassis_yaw_inertia_kgm2, l_f, l_r,
                                           p.chassis_cornering_stiffness_front_n_per_rad,
                                           p.chassis_cornering_stiffness_rear_n_per_rad, dt)

        if rec_now and n_rec < tr.shape[0]:
            row = tr[n_rec]
            row.time_s = t
            row.position_m = x
            row.speed_mps = v
            row.accel_mps2 = a
            row.slope_rad = slope
            row.curvature_per_m = kappa
            row.gear_index = gear
            row.gear_command_index = ctl.gear_command_index
            row.gear_command_prev_index = tr[n_rec - 1].gear_command_index if n_rec > 0 else ctl.gear_command_index
            row.engine_speed_radps = w_e
            row.engine_torque_nm = t_e
            row.engine_power_w = t_e * w_e
            row.engine_indicated_power_w = max(t_e - friction_torque_nm(w_e, p.engine_friction_offset_nm,
                                                                        p.engine_friction_slope_nm_per_radps), 0.0) * w_e
            row.drive_force_n = f_t
            row.brake_force_n = f_b
            row.accelerator_frac = inputs[IN_ACCELERATOR]
            row.brake_pedal_frac = inputs[IN_BRAKE_PEDAL]
            row.steering_angle_rad = steer
            row.yaw_rate_radps = yaw
            row.sideslip_rad = beta
            row.lateral_accel_mps2 = a_y
            row.driver_phase_index = drv.phase if use_driver else -1.0
            row.curve_mode_flag = 1.0 if int(ctl.mode) == curve_shift.CURVE else 0.0
            row.curve_mode_held_index = row.curve_mode_flag * tr[n_rec - 1].curve_mode_flag if n_rec > 0 else 0.0
            row.preview_fallback_flag = 1.0 if int(ctl.mode) == curve_shift.FALLBACK else 0.0
            row.kj_ratio = ctl.kj_ratio
            row.protection_upshift_count = ctl.protection_upshift_count
            row.advance_hold_count = ctl.advance_hold_count
            row.kj_max_ratio = ctl.kj_max_ratio
            row.kj_frac = ctl.kj_frac
            row.lateral_accel_pred_mps2 = ctl.lateral_accel_pred_mps2
            row.tolerable_accel_mps2 = ctl.tolerable_accel_mps2
            row.safety_accel_mps2 = ctl.safety_accel_mps2
            row.normal_downshift_speed_mps = ctl.normal_downshift_speed_mps
            row.advanced_downshift_speed_mps = ctl.advanced_downshift_speed_mps
            row.preview_distance_m = meas.curve_distance_m
            row.preview_radius_m = meas.curve_radius_m
            row.preview_valid_flag = meas.curve_valid_flag
            c_d, c_r, _c_l, c_i = next_curve(s, x)
            row.curve_distance_true_m = c_d if c_i >= 0 else np.nan
            row.curve_radius_true_m = c_r if c_i >= 0 else np.nan
            row.tolerable_accel_true_mps2 = curve_shift.tolerable_lateral_accel_mps2(
                c_r, p.curve_shift_driver_style_k, p.curve_shift_fit_radius_min_m,
                p.curve_shift_fit_radius_max_m) if c_i >= 0 else np.nan
            n_rec += 1
        if k == n_steps or stop:
            break

        # advance to t + dt
        v = v_new
        x += v * dt
        f_b = inputs[IN_BRAKE_PEDAL] * p.brakes_max_force_n + (f_b - inputs[IN_BRAKE_PEDAL] * p.brakes_max_force_n) * brake_decay
        steer = steer_target + (steer - steer_target) * steer_decay
        old_gear = gear
        gear, gear_target, shift_timer = shift_step(gear, gear_target, shift_timer, ctl.gear_command_index,
                                                    p.gearbox_shift_time_s, dt)
        if gear == 0:
            # the AMT synchronises the engine to the target gear over the remaining shift time
            w_sync = max(v, 0.0) * gear_ratio(p.gearbox_ratios, n_gears, gear_target) * i0 / r_w
            w_e += (w_sync - w_e) * min(dt / max(shift_timer, dt), 1.0)
        if gear != old_gear:
            if gear == 0:
                n_events = log_event(events, n_events, t + dt, M_GEARBOX, 0, 1, 0)
            else:
                n_events = log_event(events, n_events, t + dt, M_GEARBOX, 1, 0, 1)
    return n_rec, n_events


# --------------------------------------------------------------------------- layout interface (Python side)
def gear_names(model) -> list[str]:
    return ["N"] + list(model.gearbox.gear_names)


def derived(flat: dict) -> dict:
    """Packed shift lines, gear count, understeer gradient and the a_ys table of the handling diagram."""
    out = dict(flat)
    if "shift_schedule_up_mps" in out:  # (a re-derivation after a dotted override finds the packed lines)
        up = np.asarray(out.pop("shift_schedule_up_mps"), dtype=float)
        down = np.asarray(out.pop("shift_schedule_down_mps"), dtype=float)
        out["shift_schedule_up_flat_mps"] = up.ravel()
        out["shift_schedule_down_flat_mps"] = down.ravel()
        out["shift_schedule_theta_count"] = float(up.shape[1])
    out["gearbox_gear_count"] = float(len(out["gearbox_ratios"]))
    m = flat["body_mass_kg"]
    l_f = flat["chassis_cg_to_front_axle_m"]
    l_r = flat["chassis_wheelbase_m"] - l_f
    k_f = flat["chassis_cornering_stiffness_front_n_per_rad"]
    k_r = flat["chassis_cornering_stiffness_rear_n_per_rad"]
    out["chassis_understeer_rad_per_mps2"] = single_track.understeer_gradient(m, l_f, l_r, k_f, k_r)
    speeds = tuple(float(u) for u in np.arange(2.0, 52.0, 2.0))
    a_ys = tuple(single_track.safety_threshold(u, m, l_f, l_r, k_f, k_r, flat["chassis_peak_friction_front"],
                                               flat["chassis_peak_friction_rear"], flat["chassis_magic_formula_shape"])[0]
                 for u in speeds)
    out["curve_shift_safety_accel"] = Table("speed_mps", "accel_mps2", speeds, a_ys)
    return out


def controller_states() -> tuple:
    meas = np.zeros(1, dtype=MEAS_DTYPE).view(np.recarray)
    return meas[0], curve_shift.initial_state()[0], curve_driver.initial_state()[0]


def run_kernel(p, s, noise, trace, events):
    meas, ctl, drv = controller_states()
    return simulate(p, s, noise, meas, ctl, drv, trace, events)


# --------------------------------------------------------------------------- the road (scenario record)
ROAD_SAMPLE_STEP_M = 1.0  # curvature sampled every metre from the .xodr (exact values at element ends)


def resolve_road_file(name: str, anchor: Path | None) -> Path:
    """A .xodr path: absolute; or relative to the scenario's folder; or to the working directory (a ``--set
    road.opendrive=my_road.xodr`` on the command line); or a shipped road by file name - the first that exists."""
    from importlib import resources

    path = Path(name)
    if path.is_absolute():
        return path
    if anchor is not None and (anchor / path).exists():
        return anchor / path
    if (Path.cwd() / path).exists():
        return Path.cwd() / path
    shipped = Path(str(resources.files("vehicle_assist") / "data" / "roads")) / path.name
    if shipped.exists() and path.parent == Path("."):
        return shipped
    return (anchor / path) if anchor is not None else path


def road_geometry(sc) -> dict:
    """s, curvature, grade (and x, y for drawing) of the scenario's road; curves as the map lists them."""
    from vehicle_assist.io.opendrive import find_curves, read_opendrive

    road = sc.model.road
    if road.opendrive is not None:
        anchor = sc.path.parent if sc.path is not None else None
        odr = read_opendrive(resolve_road_file(road.opendrive, anchor), road.opendrive_road_id)
        sm = odr.sample(ROAD_SAMPLE_STEP_M)
        geo = {k: sm[k] for k in ("s_m", "curvature_per_m", "x_m", "y_m", "grade_rad")}
        geo["has_grade"] = bool(odr.elevations)
        geo["source"] = str(odr.path)
    elif road.curve_radius is not None:
        s = np.asarray(road.curve_radius.distance_m, dtype=float)
        radius = np.asarray(road.curve_radius.radius_m, dtype=float)
        kappa = np.where(radius >= 1e5, 0.0, 1.0 / radius)
        geo = {"s_m": s, "curvature_per_m": kappa, "has_grade": False, "source": "road.curve_radius"}
    else:
        geo = {"s_m": np.array([0.0]), "curvature_per_m": np.array([0.0]), "has_grade": False, "source": "straight"}
    geo["curves"] = find_curves(geo["s_m"], geo["curvature_per_m"], CURVE_MAX_RADIUS_M, CURVE_MIN_LENGTH_M) \
        if len(geo["s_m"]) > 1 else []
    return geo


def scenario_record(sc, where: str) -> dict:
    """Road fields the kernel reads (loader hook): curvature table, curve list, grade from the .xodr."""
    from vehicle_assist.io.opendrive import OpenDriveError
    from vehicle_assist.scenarios.errors import InputError

    from vehicle_assist.scenarios.guards import check_path_text

    if sc.model.road.opendrive is not None:
        check_path_text(sc.model.road.opendrive, f"{where}: road.opendrive")
    try:
        geo = road_geometry(sc)
    except OpenDriveError as exc:
        raise InputError(f"{where}: road.opendrive: {exc}") from None
    out: dict = {"road_curvature": Table("distance_m", "curvature_per_m", tuple(float(v) for v in geo["s_m"]),
                                         tuple(float(v) for v in geo["curvature_per_m"]))}
    curves = geo["curves"]
    n = max(1, len(curves))
    out["road_curve_count"] = float(len(curves))
    out["road_curve_start_m"] = np.array([c.start_m for c in curves] or [0.0])[:n]
    out["road_curve_length_m"] = np.array([c.length_m for c in curves] or [0.0])[:n]
    out["road_curve_radius_m"] = np.array([c.radius_m for c in curves] or [0.0])[:n]
    if geo["has_grade"]:
        road = sc.model.road
        if road.slope_deg is not None or road.slope is not None:
            raise InputError(f"{where}: road: the .xodr has an elevation profile; give either it or slope_deg/slope, not both")
        out["road_slope"] = Table("distance_m", "slope_rad", tuple(float(v) for v in geo["s_m"]),
                                  tuple(float(v) for v in geo["grade_rad"]))
    return out
