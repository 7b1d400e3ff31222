"""Tire-blowout compensation by differential braking (paper 004; tire_blowout.md 4-5), hosted in the ESP
controller (functions/esp.py), on the measurement record only.

Formulas (pure, also used by the tests and the study):

* ``intact_braking_force_n``: Dugoff closed forms at alpha = 0 per wheel, both H branches (spec 4):
  H = mu*F_z*(1 - s)/(2*C_x*s); H >= 1: C_x*s/(1 - s); H < 1: mu*F_z - (mu*F_z)^2*(1 - s)/(4*C_x*s).
* ``added_yaw_moment_nm`` (eqs. 22-25, any blown wheel, branch per intact wheel):
  M_z_blow = b_f*(F_b_fl - F_b_fr) + b_r*(F_b_rl - F_b_rr), blown wheel F_b = mu_blow*F'_z (s = 1).
* ``required_pressure_pa`` (eqs. 26-28): p_w = M_z_blow*R_w/(b*K_b), K_b = A_p*r_b*mu_b*eta_b*n_f [N*m/Pa].
* ``valve_pressure_pa`` / ``valve_time_s`` (eqs. 29-30): two-segment build after the inlet valve opens and
  its inverse; p1 = 0.45*p_max, p2 = 0.9*p_max; above p2 the time saturates at t2 (flag).

Controller (``blowout_step``), modes as data (``MACHINE``):
IDLE -> BUILD (blowout_detected): the blown wheel is the one whose wheel speed exceeds the median of the
others by more than ``wheel_speed_threshold`` for ``detection_delay_s`` (its rolling radius fell) and/or
the TPMS alarm names it; the ECU then computes loads (its nominal data and the measured a_x), the transfer
f (eqs. 13-20), M_z_blow with the intact wheels' measured mean slip, p_w and the valve time; the opposite
wheel of the same axle gets an accumulator build for t_valve, then HOLD. The blown wheel is kept released.
IDLE -> LIMITED (inlet_valve_stuck): the opposite wheel's inlet valve is diagnosed stuck closed; the
intact rear (front) wheel of the same side takes over, its pressure capped at the ECU's lock estimate
mu*F'_z*R/K_b (authority limited: its moment arm and load are smaller) - the reason is logged.
BUILD -> HOLD (valve_time_elapsed). HOLD/LIMITED -> IDLE (vehicle_slow: v_ref below the minimum speed) and
HOLD -> IDLE (yaw_implausible: the car yaws away from the presumed blown side by more than
``abort_yaw_rate`` - a false detection; the brake is released; only with a single detection source: with TPMS
and wheel speeds both confirming, an over-compensation at low friction is left to ABS, since releasing there
let the car drift 3.2 m instead of staying near the lane - falsification finding).
Optional closed loop (``closed_loop_flag``): in HOLD, yaw toward the blown side above the deadband adds
pulsed build on the braking wheel, yaw away from it dumps; otherwise hold.
"""
from __future__ import annotations

import math

import numba as nb
import numpy as np

from vehicle_assist.core.fsm import StateMachine, Transition, log_event
from vehicle_assist.plant.tires.blowout import OPPOSITE, redistributed_loads, transfer_n

IDLE, BUILD, HOLD, LIMITED = range(4)
MODES = ("IDLE", "BUILD", "HOLD", "LIMITED")
MACHINE = StateMachine("blowout_compensation", MODES, (
    Transition("IDLE", "BUILD", "blowout_detected", "wheel speed and/or TPMS name a blown wheel for detection_delay_s"),
    Transition("IDLE", "LIMITED", "inlet_valve_stuck", "opposite wheel's inlet diagnosed stuck closed: same-side other axle, capped"),
    Transition("BUILD", "HOLD", "valve_time_elapsed", "inlet open for t_valve (eq. 30), then hold"),
    Transition("HOLD", "IDLE", "yaw_implausible", "car yaws away from the presumed blown side: false detection, release"),
    Transition("HOLD", "IDLE", "vehicle_slow", "reference speed below the minimum speed"),
    Transition("LIMITED", "IDLE", "vehicle_slow", "reference speed below the minimum speed"),
))
G_DETECTED, G_STUCK, G_VALVE_DONE, G_YAW_IMPLAUSIBLE, G_SLOW = range(5)
REASONS = ("blowout_detected", "inlet_valve_stuck", "valve_time_elapsed", "yaw_implausible", "vehicle_slow")
# per-wheel requests to the ESP arbitration
Q_NONE, Q_BUILD, Q_HOLD, Q_RELEASE, Q_PULSE = range(5)
# state vector
S_MODE, S_BLOWN, S_SUSPECT, S_SUSPECT_S, S_T_DET, S_M_EST, S_P_REQ, S_T_VALVE, S_ELAPSED, S_TARGET, S_SATURATED, \
    S_SLIP_EST, S_LIMIT_CODE, S_MODE_ELAPSED = range(14)
STATE_SIZE = 14


def initial_state() -> np.ndarray:
    st = np.zeros(STATE_SIZE)
    st[S_BLOWN] = -1.0
    st[S_SUSPECT] = -1.0
    st[S_TARGET] = -1.0
    return st


@nb.njit(cache=True, nogil=True, error_model="numpy")
def intact_braking_force_n(slip, fz_n, mu, cx_n):
    """Retarding force of an intact wheel at braking slip s, alpha = 0 (spec 4, both H branches)."""
    if slip <= 0.0 or fz_n <= 0.0:
        return 0.0
    s = min(slip, 1.0)
    if s >= 1.0:
        return mu * fz_n
    h = mu * fz_n * (1.0 - s) / (2.0 * cx_n * s)
    if h >= 1.0:
        return cx_n * s / (1.0 - s)
    return mu * fz_n - (mu * fz_n) ** 2 * (1.0 - s) / (4.0 * cx_n * s)


@nb.njit(cache=True, nogil=True, error_model="numpy")
def added_yaw_moment_nm(blown, fz_fl, fz_fr, fz_rl, fz_rr, slip, mu, mu_blow, cx_front_n, cx_rear_n, b_f, b_r):
    """M_z_blow [N*m] (eqs. 22-25) from redistributed loads F'_z; CCW + (a left blown wheel gives > 0)."""
    if blown < 0:
        return 0.0
    fz = (fz_fl, fz_fr, fz_rl, fz_rr)
    fb = np.zeros(4)
    for i in range(4):
        if i == blown:
            fb[i] = mu_blow * fz[i]
        else:
            fb[i] = intact_braking_force_n(slip, fz[i], mu, cx_front_n if i < 2 else cx_rear_n)
    return b_f * (fb[0] - fb[1]) + b_r * (fb[2] - fb[3])


@nb.njit(cache=True, nogil=True, error_model="numpy")
def required_pressure_pa(m_z_nm, wheel_radius_m, half_track_m, gain_nm_per_pa):
    """Eq. (28): p_w = |M_z_blow|*R_w/(b*K_b), K_b = A_p*r_b*mu_b*eta_b*n_f (eq. 26)."""
    return abs(m_z_nm) * wheel_radius_m / (half_track_m * gain_nm_per_pa)


@nb.njit(cache=True, nogil=True, error_model="numpy")
def valve_pressure_pa(t, p_max_pa, t0_s, t1_s, t2_s):
    """Eq. (29): wheel pressure t seconds after the inlet valve is energised (two linear segments)."""
    p1 = 0.45 * p_max_pa
    p2 = 0.9 * p_max_pa
    if t <= t0_s:
        return 0.0
    if t <= t1_s:
        return p1 * (t - t0_s) / (t1_s - t0_s)
    if t <= t2_s:
        return p1 + (p2 - p1) * (t - t1_s) / (t2_s - t1_s)
    return p2


@nb.njit(cache=True, nogil=True, error_model="numpy")
def valve_time_s(p_pa, p_max_pa, t0_s, t1_s, t2_s):
    """Eq. (30): (valve-opening time for pressure p, saturated flag); p > 0.9*p_max saturates at t2."""
    p1 = 0.45 * p_max_pa
    p2 = 0.9 * p_max_pa
    if p_pa <= 0.0:
        return 0.0, False
    if p_pa <= p1:
        return t0_s + (t1_s - t0_s) * p_pa / p1, False
    if p_pa <= p2:
        return t1_s + (t2_s - t1_s) * (p_pa - p1) / (p2 - p1), False
    return t2_s, True


@nb.njit(cache=True, nogil=True, error_model="numpy")
def ecu_loads(p, a_x):
    """The ECU's static + longitudinal-transfer wheel loads from its nominal data (straight driving)."""
    m = p.body_mass_kg
    g = 9.81
    l = p.chassis_wheelbase_m
    l_f = p.chassis_cg_to_front_axle_m
    l_r = l - l_f
    h = p.chassis_cg_height_m
    front = 0.5 * m * (g * l_r - a_x * h) / l
    rear = 0.5 * m * (g * l_f + a_x * h) / l
    return front, front, rear, rear


@nb.njit(cache=True, nogil=True, error_model="numpy")
def blowout_step(st, vw, v_ref, slip_mean, a_x, yaw_rate, tpms_wheel, inlet_ok, p, dt, t, machine_id, events,
                 n_events, requests):
    """One ESP period of the compensation; fills ``requests[4]`` (Q_*); returns n_events."""
    for i in range(4):
        requests[i] = Q_NONE
    if p.blowout_compensation_enabled_flag < 0.5:
        return n_events
    mode = int(st[S_MODE])
    # detection: wheel-speed signature and/or TPMS alarm (index 1..4; 0 none)
    cand_ws = -1
    if v_ref > p.blowout_compensation_min_speed_mps:
        for i in range(4):
            others = np.zeros(3)
            k = 0
            for j in range(4):
                if j != i:
                    others[k] = vw[j]
                    k += 1
            med = np.median(others)
            if vw[i] > med * (1.0 + p.blowout_compensation_wheel_speed_threshold_frac):
                cand_ws = i
    cand_tp = int(tpms_wheel + 0.5) - 1
    src = int(p.blowout_compensation_detection)  # 0 wheel speeds, 1 TPMS, 2 both
    cand = cand_ws if src == 0 else cand_tp if src == 1 else (cand_ws if cand_ws == cand_tp else -1)
    if mode == IDLE and st[S_BLOWN] < 0.0:
        if cand >= 0 and cand == int(st[S_SUSPECT]):
            st[S_SUSPECT_S] += dt
        else:
            st[S_SUSPECT] = cand
            st[S_SUSPECT_S] = 0.0
        if cand >= 0 and st[S_SUSPECT_S] >= p.blowout_compensation_detection_delay_s - 1e-9:
            b = cand
            st[S_BLOWN] = b
            st[S_T_DET] = t
            # estimate (eqs. 13-25) with the ECU's nominal data
            f0, f1, f2, f3 = ecu_loads(p, a_x)
            d_r = p.body_wheel_radius_m - p.blowout_inner_radius_m
            f = transfer_n(b, f0, f1, f2, f3, d_r, p.blowout_suspension_rate_front_n_per_m,
                           p.blowout_suspension_rate_rear_n_per_m)
            g0, g1, g2, g3 = redistributed_loads(b, f0, f1, f2, f3, f)
            s_est = min(max(slip_mean, 0.0), 0.3)
            st[S_SLIP_EST] = s_est
            b_f = 0.5 * p.chassis_front_track_m
            b_r = 0.5 * p.chassis_rear_track_m
            mu = p.blowout_compensation_mu_estimate_frac
            m_z = added_yaw_moment_nm(b, g0, g1, g2, g3, s_est, mu, mu * p.blowout_compensation_blow_drag_frac,
                                      p.tires_longitudinal_stiffness_n, p.tires_longitudinal_stiffness_n, b_f, b_r)
            st[S_M_EST] = m_z
            target = OPPOSITE[b]
            new = BUILD
            reason = G_DETECTED
            if inlet_ok[target] < 0.5:
                target = OPPOSITE[b] + 2 if b < 2 else OPPOSITE[b] - 2  # same side as the opposite wheel, other axle
                new = LIMITED
                reason = G_STUCK
                st[S_LIMIT_CODE] = 1.0
            st[S_TARGET] = target
            half = b_f if target < 2 else b_r
            gain = p.brakes_front_gain_nm_per_pa if target < 2 else p.brakes_rear_gain_nm_per_pa
            p_req = required_pressure_pa(m_z, p.body_wheel_radius_m, half, gain)
            if new == LIMITED:
                gl = (g0, g1, g2, g3)
                p_lock = mu * gl[target] * p.body_wheel_radius_m / gain
                p_req = min(p_req, p_lock)
            p_max = p.esp_unit_accumulator_pa
            t_v, sat = valve_time_s(p_req, p_max, p.blowout_compensation_valve_dead_time_s,
                                    p.blowout_compensation_valve_t1_s, p.blowout_compensation_valve_t2_s)
            st[S_P_REQ] = p_req
            st[S_T_VALVE] = t_v
            st[S_SATURATED] = 1.0 if sat else 0.0
            st[S_ELAPSED] = 0.0
            n_events = log_event(events, n_events, t, machine_id, mode, new, reason)
            mode = new
            st[S_MODE] = mode
            if inlet_ok[target] < 0.5:  # no healthy wheel on that side either: no authority
                st[S_LIMIT_CODE] = 2.0
    elif mode == BUILD or mode == LIMITED:
        st[S_ELAPSED] += dt
        if mode == BUILD and st[S_ELAPSED] >= st[S_T_VALVE] - 1e-9:
            n_events = log_event(events, n_events, t, machine_id, mode, HOLD, G_VALVE_DONE)
            mode = HOLD
            st[S_MODE] = mode
        elif mode == LIMITED and v_ref < p.blowout_compensation_min_speed_mps:
            n_events = log_event(events, n_events, t, machine_id, mode, IDLE, G_SLOW)
            mode = IDLE
            st[S_MODE] = mode
    elif mode == HOLD:
        st[S_ELAPSED] += dt
        b = int(st[S_BLOWN])
        toward = yaw_rate * (1.0 if (b == 0 or b == 2) else -1.0)  # yaw toward the blown side +
        # plausibility by yaw only for a single-source detection; TPMS + wheel speeds together are trusted
        if src != 2 and toward < -p.blowout_compensation_abort_yaw_rate_radps:
            n_events = log_event(events, n_events, t, machine_id, mode, IDLE, G_YAW_IMPLAUSIBLE)
            mode = IDLE
            st[S_MODE] = mode
            st[S_TARGET] = -1.0  # released; the blown flag stays (no re-detection of the same event)
        elif v_ref < p.blowout_compensation_min_speed_mps:
            n_events = log_event(events, n_events, t, machine_id, mode, IDLE, G_SLOW)
            mode = IDLE
            st[S_MODE] = mode
            st[S_TARGET] = -1.0
    st[S_MODE_ELAPSED] = st[S_ELAPSED]
    # requests
    b = int(st[S_BLOWN])
    tg = int(st[S_TARGET])
    if b >= 0:
        requests[b] = Q_RELEASE
    if tg >= 0 and inlet_ok[tg] > 0.5:
        if mode == BUILD:
            requests[tg] = Q_BUILD
        elif mode == LIMITED:
            requests[tg] = Q_BUILD if st[S_ELAPSED] < st[S_T_VALVE] else Q_HOLD
        elif mode == HOLD:
            requests[tg] = Q_HOLD
            if p.blowout_compensation_closed_loop_flag > 0.5:
                toward = yaw_rate * (1.0 if (b == 0 or b == 2) else -1.0)
                if toward > p.blowout_compensation_yaw_deadband_radps:
                    requests[tg] = Q_PULSE
                elif toward < -p.blowout_compensation_yaw_deadband_radps:
                    requests[tg] = Q_RELEASE
    return n_events
