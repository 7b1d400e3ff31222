"""The five-phase curve driver of paper 003 (P8; curve_shift.md 5.1): straight, approach with braking, curve,
exit, straight. A human model: it sees the road (true curve positions and radii), the speedometer and its own
pedals; it does not see the map preview or the TCU.

    STRAIGHT -> APPROACH  curve_in_sight        the next curve starts within sight_distance_m (the curve signal)
    APPROACH -> CURVE     curve_entered         position past the curve start
    CURVE    -> EXIT      curve_left            position past the curve end
    EXIT     -> STRAIGHT  cruise_speed_reached  speed back at u1
    EXIT     -> APPROACH  curve_in_sight        the next curve comes into sight before u1 is reached

Phase actions (u1 = the straight speed: the run's initial speed, eq. 11 with the scenario's f_act):
* STRAIGHT: speed keeping, theta = clip(theta_i + k_p*(u1 - u), 0, 1), theta_i integrates k_i*(u1 - u).
* APPROACH: throttle ramps from its value at the signal to 0 over t_lift (P13: pedal at 0 about 2 s after
  lift-off); if u > u3, brake from t_brake after the signal with a_req = (u^2 - u3^2)/(2*d) recomputed every
  step from the remaining distance d (eq. 12), pedal = m*a_req/F_b,max.
* CURVE: u_t = min(u3, u_entry), theta = clip(c0 + c1*(u_t - u), 0, theta_max) (curve_shift.md 5.1), and a
  light brake if the car runs more than 0.5 m/s above u_t.
* EXIT: theta = theta_exit until u1.
u3 = sqrt(a_y_fit(R)*R) (eq. 13, a_y_drv = k*a_ypot = a_y_fit(R)). Steering: the steady-state steer for the
road curvature at the current speed (delta = (l + K*u^2)/R; a driver who knows the car), turned in through a
first-order lag ``steer_time_constant_s`` (vehicles/amt_car.py); the lateral model then gives a_y and yaw rate.
"""
from __future__ import annotations

import numba as nb
import numpy as np

from vehicle_assist.core.fsm import StateMachine, Transition, log_event, next_mode
from vehicle_assist.functions.curve_shift import curve_speed_mps
from vehicle_assist.plant.map_preview import next_curve

MACHINE = StateMachine(
    "curve_driver",
    modes=("STRAIGHT", "APPROACH", "CURVE", "EXIT"),
    transitions=(
        Transition("STRAIGHT", "APPROACH", "curve_in_sight"),
        Transition("APPROACH", "CURVE", "curve_entered"),
        Transition("CURVE", "EXIT", "curve_left"),
        Transition("EXIT", "APPROACH", "curve_in_sight"),
        Transition("EXIT", "STRAIGHT", "cruise_speed_reached"),
    ),
    doc=__doc__ or "",
)
TABLE = MACHINE.table()
STRAIGHT, APPROACH, CURVE, EXIT = range(4)
G_SIGHT, G_ENTERED, G_LEFT, G_CRUISE = range(4)
assert MACHINE.guards == ("curve_in_sight", "curve_entered", "curve_left", "cruise_speed_reached")

STATE_DTYPE = np.dtype([(n, "f8") for n in (
    "phase", "curve_index", "signal_time_s", "signal_throttle_frac", "throttle_integral_frac", "straight_speed_mps",
    "entry_speed_mps", "target_speed_mps", "curve_start_m", "curve_end_m", "curve_radius_m", "throttle_frac",
    "brake_frac")])


def initial_state() -> np.recarray:
    s = np.zeros(1, dtype=STATE_DTYPE).view(np.recarray)
    s.curve_index[0] = -1
    return s


@nb.njit(cache=True, nogil=True, error_model="numpy")
def start(st, p, speed_mps):
    st.phase = STRAIGHT
    st.straight_speed_mps = speed_mps
    st.throttle_integral_frac = p.curve_driver_straight_throttle_frac
    st.throttle_frac = p.curve_driver_straight_throttle_frac
    st.curve_index = -1


@nb.njit(cache=True, nogil=True, error_model="numpy")
def step(st, p, s, t, position_m, speed_mps, dt, machine_id, events, n_events):
    """One driver decision (at the sampling tick); writes st.throttle_frac and st.brake_frac."""
    u = speed_mps
    d, radius, length, idx = next_curve(s, position_m)
    phase = int(st.phase)
    guards = np.zeros(4, dtype=np.bool_)
    guards[G_SIGHT] = idx >= 0 and 0.0 <= d <= p.curve_driver_sight_distance_m and idx != int(st.curve_index)
    guards[G_ENTERED] = position_m >= st.curve_start_m
    guards[G_LEFT] = position_m >= st.curve_end_m
    guards[G_CRUISE] = u >= st.straight_speed_mps
    new_phase, reason = next_mode(TABLE, phase, guards)
    if new_phase != phase:
        n_events = log_event(events, n_events, t, machine_id, phase, new_phase, reason)
        if new_phase == APPROACH:
            st.curve_index = idx
            st.signal_time_s = t
            st.signal_throttle_frac = st.throttle_frac
            st.curve_start_m = position_m + d
            st.curve_end_m = position_m + d + length
            st.curve_radius_m = radius
            st.target_speed_mps = curve_speed_mps(radius, p.curve_shift_fit_radius_min_m, p.curve_shift_fit_radius_max_m)
        elif new_phase == CURVE:
            st.entry_speed_mps = u
            st.target_speed_mps = min(st.target_speed_mps, u)
        elif new_phase == STRAIGHT:
            st.throttle_integral_frac = st.throttle_frac
        st.phase = new_phase
        phase = new_phase
    m = p.body_mass_kg
    f_max = p.brakes_max_force_n
    theta = 0.0
    brake = 0.0
    if phase == STRAIGHT:
        err = st.straight_speed_mps - u
        st.throttle_integral_frac = min(max(st.throttle_integral_frac + p.curve_driver_speed_integral_gain * err * dt, 0.0), 1.0)
        theta = min(max(st.throttle_integral_frac + p.curve_driver_speed_gain_per_mps * err, 0.0), 1.0)
    elif phase == APPROACH:
        since = t - st.signal_time_s
        theta = st.signal_throttle_frac * max(1.0 - since / p.curve_driver_lift_time_s, 0.0)
        u3 = st.target_speed_mps
        remaining = st.curve_start_m - position_m
        if u > u3 and since >= p.curve_driver_brake_delay_s:
            a_req = (u * u - u3 * u3) / (2.0 * max(remaining, 1.0))
            brake = min(max(m * a_req / f_max, 0.0), 1.0)
    elif phase == CURVE:
        u_t = st.target_speed_mps
        theta = min(max(p.curve_driver_curve_throttle_base_frac + p.curve_driver_curve_throttle_gain * (u_t - u), 0.0),
                    p.curve_driver_curve_throttle_max_frac)
        if u > u_t + 0.5:
            brake = min(max(m * 0.5 * (u - u_t) / f_max, 0.0), 1.0)
    else:
        theta = p.curve_driver_exit_throttle_frac
    st.throttle_frac = theta
    st.brake_frac = brake
    return n_events
