"""Metrics of the tire-blowout compensation (paper 004; tire_blowout.md 9; issue #10).

``t_b`` = the blowout time: the first sample with ``blowout_frac > 0`` (one record period early at most); in a
run without a blowout (false-detection fault) the first sample with the compensation active, else 1 s (the
blowout time of every shipped scenario). Windows follow spec 9.5: yaw rate over [t_b, t_b + 2 s], path at
t_b + 3 s. Offsets are changes of the lane offset/heading error since t_b (a curve run starts off-centre).

Lane departure: the car leaves its lane when its offset exceeds (lane width - car width)/2 with a lane of
3.75 m (std: JTG B01-2014, China highway standard, lane width 3.75 m on expressways and class-1 highways)
and the BJ2500's width 1.794 m (cite:J2500, tire_blowout.md 7): 0.978 m.
"""
from __future__ import annotations

import numpy as np

from vehicle_assist.metrics.common import Metric, register, row_metric

LANE_WIDTH_M = 3.75  # std: JTG B01-2014
CAR_WIDTH_M = 1.794  # cite:J2500 (tire_blowout.md 7)
LANE_MARGIN_M = 0.5 * (LANE_WIDTH_M - CAR_WIDTH_M)
# Road edge (session n): the car's edge reaches the edge of the paved road when its offset exceeds the lane margin plus a
# hard shoulder. SHOULDER_M is assumed 3.0 m: the general value of an expressway's right hard shoulder at 100-120 km/h in
# JTG B01-2014 as recalled (the standard's table could not be re-read here; its minimum value is smaller, so 3.0 m is
# the generous end: a car is judged off the road later, not earlier). The same on the left, where the adjacent lane
# (3.75 m) or the median's shoulder lies: the deviation metric is unsigned (tire_blowout.md 9.5).
# Review R0 (session n): the 3.0 m is NOT verified - the JTG B01-2014 table could not be retrieved either; a secondary
# source (JTG B01's rule that an expressway whose hard shoulder is < 2.5 m needs emergency bays) shows narrower
# shoulders exist. Sensitivity on the 52 points whose verdict changed from the unclipped standstill judgement:
# 3 violations at 2.5-3.0 m, 5 at 0.5-1.5 m, 6 at 4.0 m (tire_blowout_findings.md R0).
SHOULDER_M = 3.0
ROAD_EDGE_M = LANE_MARGIN_M + SHOULDER_M
# the earliness of a road departure is counted back from this horizon: the braking points' run cap of the blowout
# envelopes (data/envelopes/tire_blowout.toml, choices.braking); any constant beyond every run's length gives the same
# verdicts, it only sets the margin when one of the two cars stays on the road
ROAD_HORIZON_S = 30.0
YAW_WINDOW_S = 2.0  # tire_blowout.md 9.5
PATH_TIME_S = 3.0  # tire_blowout.md 9.5
DEFAULT_BLOWOUT_S = 1.0
RELEASE_S = 0.25  # derived: detection ~0.08 s (0.05 s delay + signature) + dump of 150 bar to within 0.5 bar of the LPA, tau_dump*ln(300) = 0.17 s
TRACK_M = 1.473  # BJ2500 track B_f = B_r (tire_blowout.md 7, assumed there); the diagnostic M_x uses it
W = ("fl", "fr", "rl", "rr")


def blowout_time_s(t, phi, mode):
    idx = np.flatnonzero(phi > 0.0)
    if idx.size:
        return float(t[max(idx[0] - 1, 0)])
    idx = np.flatnonzero(mode > 0.0)
    return float(t[idx[0]]) if idx.size else DEFAULT_BLOWOUT_S


def _window(t, t0, t1):
    return (t >= t0 - 1e-9) & (t <= t1 + 1e-9)


def _yaw_peak(t, phi, mode, r):
    tb = blowout_time_s(t, phi, mode)
    w = _window(t, tb, tb + YAW_WINDOW_S)
    return float(np.max(np.abs(r[w] - _at(t, r, tb)))) if np.any(w) else 0.0


def _yaw_rms(t, phi, mode, r):
    """RMS of the yaw-rate change since t_b (0 before a blowout on a straight; the curve's steady yaw rate
    is not counted)."""
    tb = blowout_time_s(t, phi, mode)
    w = _window(t, tb, tb + YAW_WINDOW_S)
    return float(np.sqrt(np.mean((r[w] - _at(t, r, tb)) ** 2))) if np.any(w) else 0.0


def _at(t, x, tq):
    return float(np.interp(min(tq, t[-1]), t, x))


def _dev_3s(t, phi, mode, e):
    tb = blowout_time_s(t, phi, mode)
    return abs(_at(t, e, tb + PATH_TIME_S) - _at(t, e, tb))


def _dev_max(t, phi, mode, e):
    tb = blowout_time_s(t, phi, mode)
    w = _window(t, tb, tb + PATH_TIME_S)
    return float(np.max(np.abs(e[w] - _at(t, e, tb)))) if np.any(w) else 0.0


def _dev_run(t, phi, mode, e):
    """Largest |lane offset change since t_b| over the rest of the run (never worse anywhere, not only in 3 s)."""
    tb = blowout_time_s(t, phi, mode)
    w = t >= tb - 1e-9
    return float(np.max(np.abs(e[w] - _at(t, e, tb)))) if np.any(w) else 0.0


def _road_departure_index(t, phi, mode, e):
    """(t_b, index of the first sample from t_b on with |lane offset| beyond ROAD_EDGE_M, or -1)."""
    tb = blowout_time_s(t, phi, mode)
    k = np.flatnonzero((t >= tb - 1e-9) & (np.abs(e) > ROAD_EDGE_M))
    return tb, (int(k[0]) if k.size else -1)


def _dev_road(t, phi, mode, e):
    """The lateral deviation while the car is on the road (session n): max |lane offset change since t_b| over the run,
    at most ROAD_EDGE_M, and exactly ROAD_EDGE_M once the car has left the road (|offset| beyond the lane margin + the
    hard shoulder). How far a car travels beyond the road's edge depends on what lies there, not on the function: at the
    full stop of a braking point a twin that spun 7 m off the road ranked better than a function car that left the road
    2 s later and rolled on 40 m (status m item 1). Which of two cars leaves the road first is judged by
    ``_road_departure_earliness``."""
    _, k = _road_departure_index(t, phi, mode, e)
    if k >= 0:
        return float(ROAD_EDGE_M)
    return min(_dev_run(t, phi, mode, e), float(ROAD_EDGE_M))


def _road_departure_earliness(t, phi, mode, e):
    """How early the car leaves the road [s]: ROAD_HORIZON_S - (t_departure - t_b), 0 if it stays on the road (smaller
    is better: the later, the smaller; a comparative requirement compares it with the twin's)."""
    tb, k = _road_departure_index(t, phi, mode, e)
    if k < 0:
        return 0.0
    return float(max(0.0, ROAD_HORIZON_S - (t[k] - tb)))


def _departure(t, phi, mode, e):
    return float(_dev_max(t, phi, mode, e) > LANE_MARGIN_M)


def _lane_exceedance_left(t, e):
    """How far the car gets beyond its LEFT lane marking over the whole run [m] (lane_offset_m: left +):
    max(0, max(lane offset) - LANE_MARGIN_M). With ``_lane_exceedance_right`` the per-side reading of
    ``_lane_exceedance``: a departure on one side is not offset by the twin's on the other (review RI1, session i)."""
    return float(max(0.0, np.max(e) - LANE_MARGIN_M)) if e.size else 0.0


def _lane_exceedance_right(t, e):
    """How far the car gets beyond its RIGHT lane marking over the whole run [m]: max(0, -min(lane offset) -
    LANE_MARGIN_M)."""
    return float(max(0.0, -np.min(e) - LANE_MARGIN_M)) if e.size else 0.0


def _lane_overshoot_left(t, e):
    """The SIGNED distance of the car's edge beyond its LEFT lane marking at its furthest left over the whole run [m]:
    max(lane offset) - LANE_MARGIN_M (positive: beyond the marking by that much, as ``_lane_exceedance_left``; negative:
    still that far inside). The continuous per-side margin a comparative requirement needs (review RI3, session i: the
    clipped exceedance reads 0 anywhere inside the lane, so a side clean in both runs carried no margin and the
    requirement reported the other side's)."""
    return float(np.max(e) - LANE_MARGIN_M) if e.size else float("nan")


def _lane_overshoot_right(t, e):
    """The signed distance beyond the RIGHT marking at the car's furthest right [m]: -min(lane offset) - LANE_MARGIN_M."""
    return float(-np.min(e) - LANE_MARGIN_M) if e.size else float("nan")


def _lane_exceedance(t, e):
    """How far the car's edge gets beyond its lane marking over the whole run [m], either side: the larger of the two
    per-side readings (max(0, max |lane offset| - LANE_MARGIN_M); 0 inside the lane, stay_in_lane's boundary)."""
    return max(_lane_exceedance_left(t, e), _lane_exceedance_right(t, e))


def _decel(t, phi, mode, a):
    tb = blowout_time_s(t, phi, mode)
    w = _window(t, tb, tb + YAW_WINDOW_S)
    return float(-np.mean(a[w])) if np.any(w) else 0.0


def _detect_time(t, phi, mode, det):
    tb = blowout_time_s(t, phi, mode)
    idx = np.flatnonzero(det >= 0.0)
    return float(t[idx[0]] - tb) if idx.size else float("inf")


def _true_blown(blown):
    """(wheel index, first sample index) of the plant's blown wheel (metrics may read plant truth), or (-1, -1)."""
    idx = np.flatnonzero(blown >= 0.0)
    if not idx.size:
        return -1, -1
    return int(blown[idx[0]]), int(idx[0])


def _blown_pressure(t, blown, p0, p1, p2, p3):
    """Largest pressure of the wheel that actually blew (plant truth), over the whole run after the blowout;
    NaN without a blowout (nothing to judge)."""
    b, k = _true_blown(blown)
    if b < 0:
        return float("nan")
    return float(np.max((p0, p1, p2, p3)[b][k:]))


def _blown_pressure_late(t, blown, p0, p1, p2, p3):
    """As _blown_pressure from t_b + RELEASE_S on: a driver's pressure already in the wheel at the blowout has
    to be found and dumped first."""
    b, k = _true_blown(blown)
    if b < 0:
        return float("nan")
    w = t >= t[k] + RELEASE_S - 1e-9
    return float(np.max((p0, p1, p2, p3)[b][w])) if np.any(w) else float("nan")


def _opposite_pressure(t, blown, p0, p1, p2, p3):
    """Largest pressure of the intact wheel on the same axle as the actually blown one, after the blowout."""
    b, k = _true_blown(blown)
    if b < 0:
        return float("nan")
    return float(np.max((p0, p1, p2, p3)[(1, 0, 3, 2)[b]][k:]))


def _balance_window(t, phi, mode, det, tv):
    idx = np.flatnonzero(det >= 0.0)
    if not idx.size:
        return None
    tb = blowout_time_s(t, phi, mode)
    w = _window(t, t[idx[0]] + tv[idx[0]], tb + YAW_WINDOW_S)
    return w if np.any(w) else None


def _balance(t, phi, mode, det, tv, m_est, m_z):
    """Criterion 9.6 as the spec defines it: max |net yaw moment M_x + M_y + M_c| / |M_z_blow estimate| after
    t_det + t_valve, up to t_b + 2 s (the net moment is I_z dr/dt)."""
    w = _balance_window(t, phi, mode, det, tv)
    if w is None or abs(m_est[-1]) < 1.0:
        return float("nan")
    return float(np.max(np.abs(m_z[w])) / abs(m_est[-1]))


def _longitudinal_moment(fx, drag, blown, b_f, b_r):
    """Eq. (9) from the recorded longitudinal tire forces (forward +) and the blown tire's rim drag:
    M_x = b_f*(X_fr - X_fl) + b_r*(X_rr - X_rl) (straight-ahead steer)."""
    x = [np.array(f, dtype=float) for f in fx]
    b, _ = _true_blown(blown)
    if b >= 0:
        x[b] = x[b] - drag
    return b_f * (x[1] - x[0]) + b_r * (x[3] - x[2])


def _brake_balance(t, phi, mode, det, tv, m_est, blown, drag, f0, f1, f2, f3):
    """Diagnostic for 9.6: max |M_x| (longitudinal forces only: blown-wheel drag + brakes, eq. 9 with M_c) /
    |M_z_blow estimate| in the 9.6 window; the rest of the net moment is the lateral forces' M_y."""
    w = _balance_window(t, phi, mode, det, tv)
    if w is None or abs(m_est[-1]) < 1.0:
        return float("nan")
    half = 0.5 * TRACK_M
    m_x = _longitudinal_moment((f0, f1, f2, f3), drag, blown, half, half)
    return float(np.max(np.abs(m_x[w])) / abs(m_est[-1]))


_BASE = ("blowout_frac", "blowout_mode_index")
PRESSURES = tuple(f"wheel_pressure_{w}_pa" for w in W)
_DEFS = [
    ("blowout_yaw_rate_peak_radps", _yaw_peak, _BASE + ("yaw_rate_radps",), "peak |yaw rate - r(t_b)| in [t_b, t_b + 2 s]"),
    ("blowout_yaw_rate_rms_radps", _yaw_rms, _BASE + ("yaw_rate_radps",), "RMS of yaw rate - r(t_b) in [t_b, t_b + 2 s]"),
    ("blowout_lateral_deviation_3s_m", _dev_3s, _BASE + ("lane_offset_m",), "|lane offset change| at t_b + 3 s"),
    ("blowout_lateral_deviation_max_m", _dev_max, _BASE + ("lane_offset_m",), "max |lane offset change| in [t_b, t_b + 3 s]"),
    ("blowout_lateral_deviation_run_max_m", _dev_run, _BASE + ("lane_offset_m",),
     "max |lane offset change| from t_b to the end of the run"),
    ("blowout_lateral_deviation_road_max_m", _dev_road, _BASE + ("lane_offset_m",),
     "max |lane offset change| from t_b to the end of the run while on the road: at most, and once the car is beyond "
     "the road edge (lane margin + 3.0 m hard shoulder) exactly, lane margin + shoulder"),
    ("blowout_road_departure_earliness_s", _road_departure_earliness, _BASE + ("lane_offset_m",),
     "30 s - (time the car first leaves the road - t_b), 0 if it stays on the road (road edge: lane margin + 3.0 m "
     "hard shoulder)"),
    ("blowout_heading_error_3s_rad", _dev_3s, _BASE + ("lane_heading_error_rad",), "|heading error change| at t_b + 3 s"),
    ("blowout_lane_departure_flag", _departure, _BASE + ("lane_offset_m",),
     "1 if the offset exceeds (3.75 m lane - 1.794 m car)/2 within 3 s"),
    ("blowout_lane_exceedance_m", _lane_exceedance, ("lane_offset_m",),
     "max(0, max |lane offset| - (3.75 m lane - 1.794 m car)/2) over the whole run: how far out of the lane"),
    ("blowout_lane_exceedance_left_m", _lane_exceedance_left, ("lane_offset_m",),
     "max(0, max lane offset - (3.75 m lane - 1.794 m car)/2) over the whole run: how far beyond the LEFT marking"),
    ("blowout_lane_exceedance_right_m", _lane_exceedance_right, ("lane_offset_m",),
     "max(0, -min lane offset - (3.75 m lane - 1.794 m car)/2) over the whole run: how far beyond the RIGHT marking"),
    ("blowout_lane_overshoot_left_m", _lane_overshoot_left, ("lane_offset_m",),
     "max lane offset - (3.75 m lane - 1.794 m car)/2 over the whole run: signed distance beyond the LEFT marking (< 0 inside)"),
    ("blowout_lane_overshoot_right_m", _lane_overshoot_right, ("lane_offset_m",),
     "-min lane offset - (3.75 m lane - 1.794 m car)/2 over the whole run: signed distance beyond the RIGHT marking (< 0 inside)"),
    ("blowout_decel_mean_mps2", _decel, _BASE + ("accel_mps2",), "mean deceleration in [t_b, t_b + 2 s]"),
    ("blowout_detection_time_s", _detect_time, _BASE + ("blowout_detected_wheel_index",), "detection time after t_b"),
    ("blowout_detected_wheel_index", lambda t, d: float(np.max(d)), ("blowout_detected_wheel_index",),
     "wheel found blown (-1 none)"),
    ("blowout_moment_est_nm", lambda t, m: float(m[-1]), ("blowout_moment_est_nm",), "ECU estimate of M_z_blow"),
    ("blowout_pressure_req_pa", lambda t, p: float(np.max(p)), ("blowout_pressure_req_pa",), "required pressure (eq. 28)"),
    ("blowout_valve_time_s", lambda t, v: float(np.max(v)), ("blowout_valve_time_s",), "valve-opening time (eq. 30)"),
    ("blowout_saturated_flag", lambda t, v: float(np.max(v)), ("blowout_saturated_flag",), "accumulator too low"),
    ("blowout_limit_code", lambda t, v: float(np.max(v)), ("blowout_limit_code",), "authority limit reason code"),
    ("blowout_blown_wheel_pressure_max_pa", _blown_pressure, ("blowout_wheel_index",) + PRESSURES,
     "largest pressure of the actually blown wheel (plant truth) over the run after the blowout (criterion 9.3)"),
    ("blowout_blown_wheel_pressure_late_max_pa", _blown_pressure_late, ("blowout_wheel_index",) + PRESSURES,
     "as blowout_blown_wheel_pressure_max_pa from t_b + 0.25 s (a driver's pressure at the blowout dumped)"),
    ("blowout_opposite_pressure_max_pa", _opposite_pressure, ("blowout_wheel_index",) + PRESSURES,
     "largest pressure of the intact wheel on the blown wheel's axle after the blowout"),
    ("blowout_balance_ratio_frac", _balance,
     _BASE + ("blowout_detected_wheel_index", "blowout_valve_time_s", "blowout_moment_est_nm", "yaw_moment_nm"),
     "criterion 9.6: max |net yaw moment| / |M_z_blow| after t_det + t_valve to t_b + 2 s"),
    ("blowout_brake_balance_ratio_frac", _brake_balance,
     _BASE + ("blowout_detected_wheel_index", "blowout_valve_time_s", "blowout_moment_est_nm", "blowout_wheel_index",
              "blowout_drag_n") + tuple(f"tire_force_x_{w}_n" for w in W),
     "9.6 diagnostic: max |M_x of the longitudinal forces| / |M_z_blow| in the 9.6 window"),
]
for _name, _fn, _names, _doc in _DEFS:
    register(Metric(_name, row_metric(_fn, _names), _names, _doc))
