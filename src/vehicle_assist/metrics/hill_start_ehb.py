"""Metrics of the EV hill start with EHB (paper 001, hill_start_ehb.md section 5), vectorised over runs.

* ``hold_force_ratio``: lowest brake holding capacity K_b_tot*p/r over the car's *true* grade resistance
  m*g*sin(gamma) (plant channels, not the controller's estimate) while the assist holds (HOLD), counted
  from the EHB settling time (0.25 s = 5 tau_ehb) after entering HOLD; criterion 3 (p >= 0.95*p_hold,
  p_hold = k_s*G*sin(gamma)*r/K_b) asks >= 0.95*k_s = 1.14 with k_s = 1.2.
* ``residual_pressure_at_p2_pa``: brake pressure at the first sample where the drive force reaches the
  grade resistance (point P2 of the paper's Fig. 3); the paper asks it to be non-zero (P4).
* ``release_after_start_s``: from the first sample with v > 0.05 m/s to the brake pressure below
  0.1 bar (criterion 5 asks <= 2 s).
* ``assist_idle_after_start_s``: from the first sample with v > 0.05 m/s to the assist back in IDLE
  (Step1); the second half of criterion 5 ("and EHB state = Step1", within the same 2 s). Separate from
  ``release_after_start_s`` because the assist can stay in FOLLOW with the brake at zero while its torque
  ceiling catches up with the driver's request (NaN if never back in IDLE after the start).
* ``hold_entered_flag``: 1 if the assist entered HOLD (criterion 7: never on a level road).
* ``pressure_reapply_pa``: largest rise of the brake pressure over its running minimum while the
  assist follows the torque (criterion 8: a hesitating driver makes it re-apply).
* ``assist_refusal_code``: largest refusal code of the run (0 none; k = 1 + index in
  vehicles/ev_ehb.REFUSAL_REASONS).
* ``torque_above_driver_nm``: largest motor-torque command above the driver's own request (issue #7:
  the assist must never ask for traction torque the driver did not ask for; 0 when it does not).
"""
from __future__ import annotations

import numpy as np

from vehicle_assist.core.trace import Trace
from vehicle_assist.functions import hill_start_ehb as H
from vehicle_assist.metrics.common import METRICS, Metric, register
from vehicle_assist.metrics.common import channel_rows as _ch
from vehicle_assist.metrics.common import first_true as _first
from vehicle_assist.metrics.common import per_run as _out
from vehicle_assist.metrics.common import take_rows as _take

SETTLE_S = 0.25  # 5 x tau_ehb (hill_start_ehb.md 5, criterion 3)
START_SPEED_MPS = 0.05  # v_start (hill_start_ehb.md 3)
RELEASED_PA = 0.1e5  # "p < 0.1 bar" (criterion 5)


def hold_force_ratio(trace: Trace):
    """min(brake capacity / true grade resistance) over HOLD samples at least SETTLE_S after entering HOLD
    (NaN if never held)."""
    t = np.asarray(trace["time_s"], dtype=np.float64)
    mode = _ch(trace, "hsa_mode_index")
    hold = mode == H.HOLD
    i0, found = _first(hold)
    settled = hold & (t[None, :] >= t[i0][:, None] + SETTLE_S)
    with np.errstate(invalid="ignore", divide="ignore"):
        ratio = _ch(trace, "service_brake_capacity_n") / _ch(trace, "grade_resistance_n")
    ratio = np.where(settled, ratio, np.inf)
    best = np.min(ratio, axis=-1)
    return _out(np.where(found & settled.any(axis=-1), best, np.nan), trace)


def residual_pressure_at_p2_pa(trace: Trace):
    """Brake pressure when the drive force first reaches the grade resistance (P2)."""
    f_t, f_i = _ch(trace, "drive_force_n"), _ch(trace, "grade_resistance_n")
    f_t, f_i = np.broadcast_arrays(f_t, f_i)
    i, found = _first((f_t >= f_i) & (f_i > 0.0))
    p = np.broadcast_to(_ch(trace, "brake_pressure_pa"), f_t.shape)
    return _out(np.where(found, _take(p, i), np.nan), trace)


def _time_after_start(trace: Trace, hit: np.ndarray):
    """Time from v > v_start to the first sample at or after it where ``hit`` holds (NaN if never, or no start)."""
    t = np.asarray(trace["time_s"], dtype=np.float64)
    v, hit = np.broadcast_arrays(_ch(trace, "speed_mps"), hit)
    i_start, started = _first(v > START_SPEED_MPS)
    after = np.arange(v.shape[1])[None, :] >= i_start[:, None]
    i_hit, found = _first(hit & after)
    return _out(np.where(started & found, t[i_hit] - t[i_start], np.nan), trace)


def release_after_start_s(trace: Trace):
    """Time from v > v_start to brake pressure < 0.1 bar (0 if already released; NaN if never)."""
    return _time_after_start(trace, _ch(trace, "brake_pressure_pa") < RELEASED_PA)


def assist_idle_after_start_s(trace: Trace):
    """Time from v > v_start to the first sample at or after it with the assist in IDLE (NaN if never)."""
    return _time_after_start(trace, _ch(trace, "hsa_mode_index") == H.IDLE)


def hold_entered_flag(trace: Trace):
    """1 if the assist held the car at any sample, else 0."""
    return _out((_ch(trace, "hsa_mode_index") == H.HOLD).any(axis=-1).astype(float), trace)


def pressure_reapply_pa(trace: Trace):
    """Largest rise of the pressure above its running minimum while the assist follows the torque."""
    mode, p = _ch(trace, "hsa_mode_index"), _ch(trace, "brake_pressure_pa")
    follow = mode == H.FOLLOW
    masked = np.where(follow, p, np.inf)
    running_min = np.minimum.accumulate(masked, axis=-1)
    rise = np.where(follow & np.isfinite(running_min), p - running_min, 0.0)
    return _out(np.max(rise, axis=-1), trace)


ASSIST_JERK_TAIL_S = 1.0  # the ease-in after the assist hands back still belongs to its start (assumed)
START_PHASE_MAX_SPEED_MPS = 5.0  # a hill start ends by 18 km/h (assumed; the motor's power corner is at 12 m/s)


def assist_jerk_peak_mps3(trace: Trace):
    """Largest |filtered jerk| (common.md 10) while the assist is engaged (HOLD, FOLLOW, DEGRADED, REFUSED) and
    up to ASSIST_JERK_TAIL_S after it hands back, below START_PHASE_MAX_SPEED_MPS: the part of the start the
    assist shapes (0 if never). Later the driver's pedal and the motor's power limit shape the acceleration."""
    from vehicle_assist.metrics.common import filtered_jerk

    t = np.asarray(trace["time_s"], dtype=np.float64)
    mode = _ch(trace, "hsa_mode_index")
    engaged = mode >= H.HOLD
    idx = np.arange(mode.shape[1])[None, :]
    last = np.maximum.accumulate(np.where(engaged, idx, -1), axis=-1)
    window = ((last >= 0) & (t[None, :] - t[np.maximum(last, 0)] <= ASSIST_JERK_TAIL_S)
              & (_ch(trace, "speed_mps") <= START_PHASE_MAX_SPEED_MPS))
    jerk = np.abs(np.atleast_2d(filtered_jerk(trace)))
    return _out(np.max(np.where(window, jerk, 0.0), axis=-1), trace)


def assist_refusal_code(trace: Trace):
    """Largest refusal code of the run (0 = the assist never refused)."""
    return _out(np.max(_ch(trace, "assist_refusal_code"), axis=-1), trace)


def torque_above_driver_nm(trace: Trace):
    """max(motor torque command - driver's request, 0) over the run."""
    excess = _ch(trace, "motor_torque_request_nm") - _ch(trace, "driver_torque_request_nm")
    return _out(np.maximum(np.max(excess, axis=-1), 0.0), trace)


for _m in (
    Metric("hold_force_ratio", hold_force_ratio, ("time_s", "hsa_mode_index", "service_brake_capacity_n", "grade_resistance_n"),
           "lowest brake capacity / true grade resistance while the EV assist holds (after settling)"),
    Metric("assist_jerk_peak_mps3", assist_jerk_peak_mps3, ("time_s", "accel_mps2", "hsa_mode_index", "speed_mps"),
           "largest filtered jerk while the EV assist is engaged and 1 s after"),
    Metric("torque_above_driver_nm", torque_above_driver_nm, ("motor_torque_request_nm", "driver_torque_request_nm"),
           "largest motor-torque command above the driver's request"),
    Metric("residual_pressure_at_p2_pa", residual_pressure_at_p2_pa, ("drive_force_n", "grade_resistance_n", "brake_pressure_pa"),
           "brake pressure when the drive force first reaches the grade resistance (P2 of paper 001)"),
    Metric("release_after_start_s", release_after_start_s, ("time_s", "speed_mps", "brake_pressure_pa"),
           "from v > 0.05 m/s to brake pressure < 0.1 bar"),
    Metric("assist_idle_after_start_s", assist_idle_after_start_s, ("time_s", "speed_mps", "hsa_mode_index"),
           "from v > 0.05 m/s to the EV assist back in IDLE (Step1)"),
    Metric("hold_entered_flag", hold_entered_flag, ("hsa_mode_index", "brake_pressure_command_pa"),
           "1 if the EV hill-start assist held the car"),
    Metric("pressure_reapply_pa", pressure_reapply_pa, ("hsa_mode_index", "brake_pressure_pa", "brake_pressure_command_pa"),
           "largest re-application of brake pressure while following the torque"),
):
    register(_m)
# the same metric serves the truck (metrics/hill_start.py): register it once, whichever module comes first
if "assist_refusal_code" not in METRICS:
    register(Metric("assist_refusal_code", assist_refusal_code, ("assist_refusal_code",),
                    "largest refusal code (0 none, k = 1 + index in the vehicle's REFUSAL_REASONS)"))
