"""Metrics of the passenger-car brake tests (paper 002, brake_assist.md 8; UN R139 windows): pure f(trace).

Times are counted from ``t0``, the first sample with the pedal force at or above 20 N (UN R139 / paper
P12). Each metric works on one run or on a batch (rows), computed row by row; NaN where undefined.

* ``hba_activated_flag`` / ``hba_activation_count``: the HBA was ACTIVE / how often it entered ACTIVE
  (false activations in the no-activation scenarios, criterion 2).
* ``hba_activation_time_s``: first ACTIVE sample - t0; ``hba_detection_delay_s``: first ACTIVE sample - the
  first sample with the sensed p_mc >= 30 bar, its rate >= 3500 bar/s and v >= 15 km/h (criterion 1).
* ``driver_pressure_deficit_pa``: largest p_src - p_w of a wheel whose valves have let the driver's
  pressure through (modes N, B; T has the inlet closed) for at least 0.1 s (5 line time constants), from t0 + 0.1 s on.
* ``stopping_distance_m`` / ``stopping_time_s``: from t0 to standstill (NaN if the car did not stop).
* ``mfdd_mps2``: mean fully developed deceleration (v_b^2 - v_e^2)/(2*(s_e - s_b)) between 0.8 v0 and
  0.1 v0, v0 the speed at t0 (UN R13-H Annex 3 definition, std).
* ``mean_decel_r139_mps2``: mean deceleration from t0 + 0.8 s until 15 km/h (UN R139 evaluation window).
* ``peak_wheel_pressure_pa``, ``peak_master_pressure_pa``; ``front_pressure_master_below_60bar_pa``:
  highest front wheel pressure at a sample with p_mc < 60 bar while HBA is ACTIVE (paper P13);
  ``front_over_master_ratio``: highest front wheel pressure / p_mc while ACTIVE (criterion 3, >= 1.5).
* ``abs_intervened_flag``: an ABS hold or dump on some wheel.
* ``wheel_lock_time_max_s``: longest spell with a wheel slip above 0.5 while v > 15 km/h (criterion 5);
  ``wheel_stopped_moving_flag``: a wheel at omega = 0 while v > 5 km/h (criterion 5).
* ``hba_exit_delay_s``: first ACTIVE -> TERMINATING sample minus the first ACTIVE sample at which a sensed exit
  condition of paper P4 holds (reference speed <= 5 km/h, sensed p_mc <= 6 bar, pedal below the 5 N switch
  force, p_mc < 0.4*peak and > 10 bar below it) (criterion 6: within one controller period); negative when a
  fault (sensor, ABS, pump) ended the assist before any of these;
* ``hba_exit_flag``: ACTIVE -> TERMINATING happened; ``rampout_settle_margin_s``: criterion 7's bound
  (p_w0 - p_src)/G_exit + 0.1 s (p_w0 the wheel pressure at the exit, p_src the driver's pressure where the
  ramp ends - the driver may still be releasing at the exit -, G_exit = 200 bar/s of
  brake_assist.md 6) minus the time from the exit until no wheel is more than 1 bar above its driver's
  pressure or every wheel is back in the normal valve mode (>= 0 meets criterion 7);
  ``rampout_undershoot_pa``: max (p_src - p_w) during TERMINATING (criterion 7: <= 2 bar).
* ``hba_build_time_s``, ``hba_abs_time_s``, ``hba_rampout_time_s``: time per HBA phase (active build with
  no ABS hold/dump, ABS intervention, ramp-out).
* ``heading_max_deg``, ``yaw_rate_max_radps``, ``lateral_deviation_max_m``: split-mu stability;
  ``steering_correction_2s_deg`` / ``steering_correction_max_deg``: largest steering-wheel angle change from
  its value at t0 within the first 2 s / over the stop (UN R13-H split-surface ABS test: 120 deg / 240 deg).
* ``wheel_lock_speed_max_mps``: highest car speed at which a wheel reads stopped (< 0.1 rad/s): criterion 5
  and the ABS cut-off of spec 4.3 (5 km/h) say it must not exceed 5 km/h.
"""
from __future__ import annotations

import math

import numpy as np

from vehicle_assist.metrics.common import Metric, register, row_metric

T0_FORCE_N = 20.0  # UN R139 / paper 002 P12
R139_END_SPEED_MPS = 15.0 / 3.6  # UN R139 / paper 002 P12
W = ("fl", "fr", "rl", "rr")
ACTIVE, TERMINATING = 1.0, 2.0


def _t0_index(force):
    idx = np.flatnonzero(force >= T0_FORCE_N)
    return int(idx[0]) if idx.size else -1


def _spells_max(t, mask):
    best = 0.0
    start = None
    for k in range(len(mask)):
        if mask[k] and start is None:
            start = t[k]
        if (not mask[k] or k == len(mask) - 1) and start is not None:
            best = max(best, t[k] - start)
            start = None
    return best


def _activation_time(t, force, mode):
    k0 = _t0_index(force)
    idx = np.flatnonzero(mode == ACTIVE)
    return t[idx[0]] - t[k0] if idx.size and k0 >= 0 else math.nan


def _detection_delay(t, mode, pmeas, rate, speed):
    seen = np.flatnonzero((pmeas >= 30e5) & (rate >= 3500e5) & (speed >= 15.0 / 3.6))
    on = np.flatnonzero(mode == ACTIVE)
    if not seen.size or not on.size:
        return math.nan
    return t[on[0]] - t[seen[0]]


def _deficit(t, force, *rest):
    k0 = _t0_index(force)
    if k0 < 0:
        return math.nan
    worst = -math.inf
    dt = t[1] - t[0] if len(t) > 1 else 1.0
    settle = int(round(0.1 / dt))
    for i in range(4):
        pw, ps, wm = rest[3 * i], rest[3 * i + 1], rest[3 * i + 2]
        through = (wm == 0.0) | (wm == 1.0)  # N, B (T has the inlet closed: valve table row T)
        run = np.zeros(len(t), dtype=int)
        count = 0
        for k in range(len(t)):
            count = count + 1 if through[k] else 0
            run[k] = count
        mask = (run > settle) & (t >= t[k0] + 0.1)
        if mask.any():
            worst = max(worst, float(np.max((ps - pw)[mask])))
    return worst


def _exit_delay(t, mode, vref, pmeas, force):
    on = np.flatnonzero(mode == ACTIVE)
    ex = np.flatnonzero((mode[1:] == TERMINATING) & (mode[:-1] == ACTIVE))
    if not on.size or not ex.size:
        return math.nan
    k_on, k_ex = on[0], ex[0] + 1
    peak = np.maximum.accumulate(np.where(np.arange(len(t)) >= k_on, pmeas, 0.0))
    cond = (vref <= 5.0 / 3.6) | (pmeas <= 6e5) | (force <= 5.0) | ((pmeas < 0.4 * peak) & (peak - pmeas > 10e5))
    cond &= np.arange(len(t)) > k_on
    first = np.flatnonzero(cond)
    return t[k_ex] - t[first[0]] if first.size else math.nan


def _activation_count(t, mode):
    on = mode == ACTIVE
    return float(np.sum(on[1:] & ~on[:-1]) + (1 if on.size and on[0] else 0))


def _stop(t, force, speed, pos):
    k0 = _t0_index(force)
    idx = np.flatnonzero(speed <= 0.05)
    if k0 < 0 or not idx.size or idx[-1] < k0:
        return math.nan, math.nan
    ks = idx[idx >= k0][0]
    return pos[ks] - pos[k0], t[ks] - t[k0]


def _mfdd(t, force, speed, pos):
    k0 = _t0_index(force)
    if k0 < 0:
        return math.nan
    v0 = speed[k0]
    after = np.arange(len(speed)) >= k0
    kb = np.flatnonzero(after & (speed <= 0.8 * v0))
    ke = np.flatnonzero(after & (speed <= 0.1 * v0))
    if not kb.size or not ke.size or pos[ke[0]] <= pos[kb[0]]:
        return math.nan
    vb, ve = speed[kb[0]], speed[ke[0]]
    return (vb**2 - ve**2) / (2.0 * (pos[ke[0]] - pos[kb[0]]))


def _mean_decel_r139(t, force, speed):
    k0 = _t0_index(force)
    if k0 < 0:
        return math.nan
    ks = np.flatnonzero((t >= t[k0] + 0.8 - 1e-9))
    ke = np.flatnonzero((t >= t[k0] + 0.8 - 1e-9) & (speed <= R139_END_SPEED_MPS))
    if not ks.size or not ke.size or t[ke[0]] <= t[ks[0]]:
        return math.nan
    return (speed[ks[0]] - speed[ke[0]]) / (t[ke[0]] - t[ks[0]])


def _lock_time(t, speed, *slips):
    mask = np.zeros(len(speed), dtype=bool)
    for s in slips:
        mask |= s > 0.5
    return _spells_max(t, mask & (speed > R139_END_SPEED_MPS))


def _stopped_moving(t, speed, *omegas):
    mask = np.zeros(len(speed), dtype=bool)
    for w in omegas:
        mask |= w <= 0.0
    return float(np.any(mask & (speed > 5.0 / 3.6)))


def _front_below_60(t, mode, pmc, pfl, pfr):
    mask = (mode == ACTIVE) & (pmc < 60e5)
    return float(np.max(np.maximum(pfl, pfr)[mask])) if mask.any() else math.nan


def _front_ratio(t, mode, pmc, pfl, pfr):
    mask = (mode == ACTIVE) & (pmc > 1e5)
    return float(np.max(np.maximum(pfl, pfr)[mask] / pmc[mask])) if mask.any() else math.nan


def _abs_intervened(t, *modes):
    return float(any(np.any((m == 1.0) | (m == 2.0)) for m in modes))


def _steer_correction(window_s):
    """Largest |steering-wheel angle - its value at t0| from t0 over ``window_s`` (all of the run if None), deg."""
    def fn(t, force, sw):
        k0 = _t0_index(force)
        if k0 < 0:
            return math.nan
        mask = t >= t[k0]
        if window_s is not None:
            mask &= t <= t[k0] + window_s + 1e-9
        return float(np.degrees(np.max(np.abs(sw[mask] - sw[k0]))))
    return fn


def _lock_speed(t, speed, *omegas):
    """Highest car speed at a sample where a wheel reads stopped (< 0.1 rad/s, as the STL requirement), 0 if none."""
    mask = np.zeros(len(speed), dtype=bool)
    for w in omegas:
        mask |= w < 0.1
    mask &= speed > 0.05
    return float(np.max(speed[mask])) if mask.any() else 0.0


G_EXIT_PA_PER_S = 200e5  # G_exit (brake_assist.md 6), the bound of criterion 7


def _settle_margin(t, mode, *rest):
    pairs, wmodes = rest[:8], rest[8:]
    idx = np.flatnonzero((mode[1:] == TERMINATING) & (mode[:-1] == ACTIVE))
    if not idx.size:
        return math.nan
    k0 = idx[0] + 1
    ok = np.ones(len(t), dtype=bool)
    normal = np.ones(len(t), dtype=bool)
    for i in range(4):
        # a wheel's ramp-out is over once it is within 1 bar of its driver's pressure or below it (a wheel that
        # ABS holds below the driver is plain ABS's business, the ramp-out only lowers wheels above the driver)
        ok &= pairs[2 * i] - pairs[2 * i + 1] < 1e5
        normal &= wmodes[i] == 0.0
    done = np.flatnonzero((ok | normal) & (np.arange(len(t)) >= k0))
    if not done.size:
        return -math.inf
    k1 = done[0]
    # the driver may still be releasing at the exit: the ramp has to reach the driver's pressure where it ends
    excess = max(pairs[2 * i][k0] - pairs[2 * i + 1][k1] for i in range(4))
    return max(excess, 0.0) / G_EXIT_PA_PER_S + 0.1 - (t[k1] - t[k0])


def _undershoot(t, mode, *pairs):
    mask = mode == TERMINATING
    if not mask.any():
        return 0.0
    return float(max(np.max((pairs[2 * i + 1] - pairs[2 * i])[mask]) for i in range(4)))


def _phase_time(which):
    def fn(t, mode, *abs_modes):
        dt = np.diff(t, append=t[-1])
        hd = np.zeros(len(t), dtype=bool)
        for m in abs_modes:
            hd |= (m == 1.0) | (m == 2.0)
        if which == "build":
            mask = (mode == ACTIVE) & ~hd
        elif which == "abs":
            mask = (mode == ACTIVE) & hd
        else:
            mask = mode == TERMINATING
        return float(np.sum(dt[mask]))
    return fn


PRESSURE_PAIRS = tuple(n for w in W for n in (f"wheel_pressure_{w}_pa", f"source_pressure_{w}_pa"))
ABS_MODES = tuple(f"abs_mode_{w}_index" for w in W)
_DEFS = [
    ("hba_activated_flag", lambda t, m: float(np.any(m == ACTIVE)), ("hba_mode_index",), "1 if the HBA was ACTIVE"),
    ("hba_activation_count", _activation_count, ("hba_mode_index",), "entries into ACTIVE"),
    ("hba_activation_time_s", _activation_time, ("pedal_force_n", "hba_mode_index"), "first ACTIVE - t0 (20 N)"),
    ("hba_detection_delay_s", _detection_delay,
     ("hba_mode_index", "master_pressure_meas_pa", "master_pressure_rate_pa_per_s", "reference_speed_mps"),
     "first ACTIVE - first sample meeting the pressure, rate and speed thresholds (criterion 1)"),
    ("driver_pressure_deficit_pa", _deficit,
     ("pedal_force_n",) + tuple(n for w in W for n in (f"wheel_pressure_{w}_pa", f"source_pressure_{w}_pa", f"wheel_mode_{w}_index"))
     , "largest shortfall of a wheel pressure below the driver's where the valves let it through"),
    ("stopping_distance_m", lambda t, f, v, x: _stop(t, f, v, x)[0], ("pedal_force_n", "speed_mps", "position_m"),
     "distance from t0 (20 N) to standstill"),
    ("stopping_time_s", lambda t, f, v, x: _stop(t, f, v, x)[1], ("pedal_force_n", "speed_mps", "position_m"),
     "time from t0 to standstill"),
    ("mfdd_mps2", _mfdd, ("pedal_force_n", "speed_mps", "position_m"), "mean fully developed deceleration"),
    ("mean_decel_r139_mps2", _mean_decel_r139, ("pedal_force_n", "speed_mps"),
     "mean deceleration from t0 + 0.8 s to 15 km/h (UN R139 window)"),
    ("peak_wheel_pressure_pa", lambda t, *p: float(max(np.max(x) for x in p)),
     tuple(f"wheel_pressure_{w}_pa" for w in W), "highest wheel pressure"),
    ("peak_master_pressure_pa", lambda t, p: float(np.max(p)), ("master_pressure_pa",), "highest master pressure"),
    ("front_pressure_master_below_60bar_pa", _front_below_60,
     ("hba_mode_index", "master_pressure_pa", "wheel_pressure_fl_pa", "wheel_pressure_fr_pa"),
     "highest front wheel pressure while HBA ACTIVE and p_mc < 60 bar"),
    ("front_over_master_ratio", _front_ratio,
     ("hba_mode_index", "master_pressure_pa", "wheel_pressure_fl_pa", "wheel_pressure_fr_pa"),
     "highest front wheel pressure / p_mc while HBA ACTIVE"),
    ("abs_intervened_flag", _abs_intervened, ABS_MODES, "an ABS hold or dump happened"),
    ("wheel_lock_time_max_s", _lock_time, ("speed_mps",) + tuple(f"wheel_slip_{w}_frac" for w in W),
     "longest spell with a wheel slip > 0.5 above 15 km/h"),
    ("wheel_stopped_moving_flag", _stopped_moving, ("speed_mps",) + tuple(f"wheel_speed_{w}_radps" for w in W),
     "a wheel stood still while the car moved faster than 5 km/h"),
    ("hba_exit_delay_s", _exit_delay,
     ("hba_mode_index", "reference_speed_mps", "master_pressure_meas_pa", "pedal_force_n"),
     "ACTIVE -> TERMINATING after the first sensed exit condition (criterion 6)"),
    ("hba_exit_flag", lambda t, m: float(np.any((m[1:] == TERMINATING) & (m[:-1] == ACTIVE))), ("hba_mode_index",),
     "ACTIVE -> TERMINATING happened"),
    ("rampout_settle_margin_s", _settle_margin,
     ("hba_mode_index",) + PRESSURE_PAIRS + tuple(f"wheel_mode_{w}_index" for w in W),
     "criterion 7 bound minus the time to settle within 1 bar of the driver's pressure"),
    ("rampout_undershoot_pa", _undershoot, ("hba_mode_index",) + PRESSURE_PAIRS,
     "max (p_src - p_w) during the ramp-out"),
    ("hba_build_time_s", _phase_time("build"), ("hba_mode_index",) + ABS_MODES, "time in active build"),
    ("hba_abs_time_s", _phase_time("abs"), ("hba_mode_index",) + ABS_MODES, "time ACTIVE with ABS intervening"),
    ("hba_rampout_time_s", _phase_time("rampout"), ("hba_mode_index",) + ABS_MODES, "time in ramp-out"),
    ("heading_max_deg", lambda t, h: float(np.degrees(np.max(np.abs(h)))), ("heading_rad",), "largest |heading|"),
    ("yaw_rate_max_radps", lambda t, r: float(np.max(np.abs(r))), ("yaw_rate_radps",), "largest |yaw rate|"),
    ("lateral_deviation_max_m", lambda t, y: float(np.max(np.abs(y))), ("y_m",), "largest |lateral offset|"),
    ("steering_correction_2s_deg", _steer_correction(2.0), ("pedal_force_n", "steering_wheel_angle_rad"),
     "largest steering-wheel correction in the first 2 s from t0 (R13-H split-surface ABS test)"),
    ("steering_correction_max_deg", _steer_correction(None), ("pedal_force_n", "steering_wheel_angle_rad"),
     "largest steering-wheel correction from t0 on (R13-H split-surface ABS test)"),
    ("wheel_lock_speed_max_mps", _lock_speed, ("speed_mps",) + tuple(f"wheel_speed_{w}_radps" for w in W),
     "highest car speed with a wheel stopped (< 0.1 rad/s); criterion 5 / ABS cut-off: <= 5 km/h"),
]
for _name, _fn, _names, _doc in _DEFS:
    register(Metric(_name, row_metric(_fn, _names), _names, _doc))
