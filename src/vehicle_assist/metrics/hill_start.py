"""Metrics of the truck hill start (paper 000, hill_start_amt.md sections 4, 6.2 and 9): pure functions
of a trace, vectorised so that a batch trace (channels of shape (runs, samples)) gives one value per run.
The common ones (rollback, stall, engine speeds, clutch slip and brake drag energy, launch time) are in
:mod:`vehicle_assist.metrics.common`.

* ``park_release_phase_index``: the park-force phase (paper Fig. 5) in which the release began, i.e.
  at the first sample where the park-brake capacity falls below its initial value: 1 = drive force below
  the grade resistance (the park brake still carries part of the grade: releasing now rolls back),
  2 = drive force equal to the grade resistance (within 0.5 %), 3 = drive force above it (the target).
* ``release_to_load_s``: from the release command (control-line pressure to the relay valve rises) to
  the first sample where the drive force carries grade and rolling resistance (F_t >= F_i + F_f).
* ``release_margin_s``: full release time (release command to park lamp off) minus
  ``release_to_load_s``; P12 of the paper asks for a positive margin.
* ``engage_rate_mean_per_s``: mean commanded clutch rate over the assist's slip engagement (ENGAGE
  modes = phase B of hill_start_amt.md 6.3, the window of criterion 9.7); the paper expects it larger empty than
  full (P9). ``engage_rate_law_mean_per_s``: the same clutch travel over only the time the law moved the clutch
  (diagnostic: leaves out the waits at our phase-3 and engine-torque ceilings).
* ``valve_32_energized_flag``, ``park_brake_drag_energy_j``.
* ``assist_refusal_code``: largest refusal code of the run (0 = none; k = ``REFUSAL_REASONS[k - 1]`` of the
  vehicle module); ``tyre_slip_energy_j``: work dissipated at the driven tyres at the adhesion limit.
"""
from __future__ import annotations

import numpy as np

from vehicle_assist.core.trace import Trace
from vehicle_assist.functions import hill_start_amt
from vehicle_assist.metrics.common import Metric, register
from vehicle_assist.metrics.common import channel_rows as _ch
from vehicle_assist.metrics.common import first_true as _first
from vehicle_assist.metrics.common import per_run as _out
from vehicle_assist.metrics.common import take_rows as _take

PHASE_TOLERANCE_FRAC = 0.005  # |F_t - F_i| within 0.5 % of F_i counts as phase 2 (assumed)


def _time(trace: Trace) -> np.ndarray:
    return np.asarray(trace["time_s"], dtype=np.float64)


def park_release_phase_index(trace: Trace):
    """Park-force phase (1-4 of paper 000 Fig. 5) at the instant the park force starts to fall."""
    cap = _ch(trace, "park_brake_capacity_n")
    i, found = _first(cap < cap[:, :1] * (1.0 - 1e-9))
    f_t = _take(_ch(trace, "drive_force_n"), i)
    f_i = _take(_ch(trace, "grade_resistance_n"), i)
    phase = np.where(np.abs(f_t - f_i) <= PHASE_TOLERANCE_FRAC * np.abs(f_i), 2.0, np.where(f_t > f_i, 3.0, 1.0))
    phase = np.where(found & (cap[:, 0] > 0.0), phase, np.nan)  # NaN: never applied, or never released
    return _out(phase, trace)


def _release_and_load(trace: Trace) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    ctrl = _ch(trace, "relay_control_pressure_pa")
    rising = np.zeros_like(ctrl, dtype=bool)
    rising[:, 1:] = (ctrl[:, 1:] > 0.0) & (ctrl[:, :-1] <= 0.0)
    i_rel, has_rel = _first(rising)
    carry = _ch(trace, "drive_force_n") >= _ch(trace, "grade_resistance_n") + _ch(trace, "rolling_resistance_capacity_n")
    i_load, has_load = _first(carry)
    return i_rel, has_rel, i_load, has_load


def release_to_load_s(trace: Trace):
    """Release command to the first F_t >= F_i + F_f (negative: the engine carried the load before)."""
    t = _time(trace)
    i_rel, has_rel, i_load, has_load = _release_and_load(trace)
    return _out(np.where(has_rel & has_load, t[i_load] - t[i_rel], np.nan), trace)


def release_margin_s(trace: Trace):
    """Full park-brake release time minus release-to-load time (paper 000 P12: must be > 0)."""
    t = _time(trace)
    i_rel, has_rel, i_load, has_load = _release_and_load(trace)
    lamp = _ch(trace, "park_lamp_flag")
    after = np.arange(lamp.shape[1])[None, :] >= i_rel[:, None]
    i_off, has_off = _first((lamp < 0.5) & after)
    full_release_s = t[i_off] - t[i_rel]
    to_load_s = t[i_load] - t[i_rel]
    return _out(np.where(has_rel & has_load & has_off, full_release_s - to_load_s, np.nan), trace)


def engage_rate_mean_per_s(trace: Trace):
    """Mean commanded clutch rate over the assist's slip engagement (both ENGAGE modes)."""
    t = _time(trace)
    mode = _ch(trace, "hsa_mode_index")
    engage = (mode == hill_start_amt.ENGAGE_HELD) | (mode == hill_start_amt.ENGAGE_RELEASING)
    first, found = _first(engage)
    last = engage.shape[1] - 1 - np.argmax(engage[:, ::-1], axis=-1)
    x = _ch(trace, "clutch_command_frac")
    with np.errstate(invalid="ignore", divide="ignore"):
        rate = (_take(x, last) - _take(x, first)) / (t[last] - t[first])
    return _out(np.where(found & (last > first), rate, np.nan), trace)


def engage_rate_law_mean_per_s(trace: Trace):
    """Mean clutch rate over the time the engagement law moves the clutch in the slip engagement: the same
    clutch travel as ``engage_rate_mean_per_s`` divided by the phase-B time in which the command changed (the
    waits at the phase-3 ceiling, the engine-torque ceiling and the release point, which are our additions and
    not in hill_start_amt.md 6.3, are left out). A diagnostic next to 9.7, not the criterion."""
    t = _time(trace)
    mode = _ch(trace, "hsa_mode_index")
    engage = (mode == hill_start_amt.ENGAGE_HELD) | (mode == hill_start_amt.ENGAGE_RELEASING)
    x = _ch(trace, "clutch_command_frac")
    first, found = _first(engage)
    last = engage.shape[1] - 1 - np.argmax(engage[:, ::-1], axis=-1)
    moving = engage[:, 1:] & (np.abs(np.diff(x, axis=-1)) > 1e-12)
    active_s = np.sum(moving * np.diff(t)[None, :], axis=-1)
    with np.errstate(invalid="ignore", divide="ignore"):
        rate = (_take(x, last) - _take(x, first)) / active_s
    return _out(np.where(found & (active_s > 0.0), rate, np.nan), trace)


def valve_32_energized_flag(trace: Trace):
    """1 if the 3/2 valve was energised at any sample (the assist held the park brake), else 0."""
    return _out((np.max(_ch(trace, "valve_32_energized_flag"), axis=-1) > 0.5).astype(float), trace)


def park_brake_drag_energy_j(trace: Trace):
    """Energy dissipated in the park brake: integral of |F_park * v| (the truck driven, or rolling, through
    a brake that is not fully released: paper 000 P6). Zero while the truck stands (static reaction)."""
    power = np.abs(_ch(trace, "park_brake_force_n") * _ch(trace, "speed_mps"))
    return _out(np.trapezoid(power, _time(trace), axis=-1), trace)


def assist_refusal_code(trace: Trace):
    """Largest refusal code over the run (0: the assist did not refuse)."""
    return _out(np.max(_ch(trace, "assist_refusal_code"), axis=-1), trace)


def tyre_slip_energy_j(trace: Trace):
    """Energy dissipated at the driven tyres while the drive force is at the adhesion limit."""
    return _out(np.trapezoid(_ch(trace, "tyre_slip_power_w"), _time(trace), axis=-1), trace)


register(Metric("assist_refusal_code", assist_refusal_code, ("assist_refusal_code",),
                "largest refusal code of the hill-start assist (0 none; k: REFUSAL_REASONS[k - 1])"), replace=True)
register(Metric("tyre_slip_energy_j", tyre_slip_energy_j, ("time_s", "tyre_slip_power_w"),
                "energy dissipated at the driven tyres at the adhesion limit (wheel spin)"))

for _m in (
    Metric("park_release_phase_index", park_release_phase_index,
           ("park_brake_capacity_n", "drive_force_n", "grade_resistance_n"),
           "park-force phase (paper 000 Fig. 5) in which the park brake began to release (3 = target)"),
    Metric("release_to_load_s", release_to_load_s,
           ("time_s", "relay_control_pressure_pa", "drive_force_n", "grade_resistance_n", "rolling_resistance_capacity_n"),
           "release command to drive force >= grade + rolling resistance"),
    Metric("release_margin_s", release_margin_s,
           ("time_s", "relay_control_pressure_pa", "park_lamp_flag", "drive_force_n", "grade_resistance_n",
            "rolling_resistance_capacity_n"),
           "full release time minus release-to-load time (paper 000 P12: > 0)"),
    Metric("engage_rate_mean_per_s", engage_rate_mean_per_s, ("time_s", "hsa_mode_index", "clutch_command_frac"),
           "mean clutch rate during the hill-start assist's slip engagement"),
    Metric("engage_rate_law_mean_per_s", engage_rate_law_mean_per_s, ("time_s", "hsa_mode_index", "clutch_command_frac"),
           "mean clutch rate while the engagement law moves the clutch (waits at ceilings left out; diagnostic of 9.7)"),
    Metric("valve_32_energized_flag", valve_32_energized_flag, ("valve_32_energized_flag",),
           "1 if the hill-start assist energised the 3/2 valve"),
    Metric("park_brake_drag_energy_j", park_brake_drag_energy_j, ("time_s", "park_brake_force_n", "speed_mps"),
           "energy dissipated in the park brake (driving or rolling through a brake not fully released)"),
):
    register(_m)
