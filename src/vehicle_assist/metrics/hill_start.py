"""Metrics of the truck hill start (paper 000, hill_start_amt.md sections 4, 6.2 and 9): pure functions
of a trace. The common ones (rollback, stall, engine speeds, clutch slip and brake drag energy, launch
time) are in :mod:`vehicle_assist.metrics.common`.

* ``park_release_phase_index``: the park-force phase (paper Fig. 5) in which the release began, i.e.
  at the first sample where the park-brake capacity falls below its maximum: 1 = drive force below the
  grade resistance (the park brake still carries part of the grade: releasing now rolls back),
  2 = drive force equal to the grade resistance (within 0.5 %), 3 = drive force above it (the target).
* ``release_to_load_s``: from the release command (control-line pressure to the relay valve rises) to
  the first sample where the drive force carries grade and rolling resistance (F_t >= F_i + F_f).
* ``release_margin_s``: full release time (release command to park lamp off) minus
  ``release_to_load_s``; P12 of the paper asks for a positive margin.
* ``engage_rate_mean_per_s``: mean clutch rate over the assist's slip engagement (ENGAGE modes);
  the paper asks it to be larger empty than full (P9).
"""
from __future__ import annotations

import numpy as np

from vehicle_assist.core.trace import Trace
from vehicle_assist.functions import hill_start_amt
from vehicle_assist.metrics.common import Metric, register

PHASE_TOLERANCE_FRAC = 0.005  # |F_t - F_i| within 0.5 % of F_i counts as phase 2 (assumed)


def _per_run(trace: Trace, fn):
    if trace.batch_size is not None:
        return np.array([fn(trace.row(i)) for i in range(trace.batch_size)])
    return fn(trace)


def _first(mask: np.ndarray) -> int | None:
    return int(np.argmax(mask)) if mask.any() else None


def _release_index(trace: Trace) -> int | None:
    ctrl = np.asarray(trace["relay_control_pressure_pa"])
    rising = (ctrl[1:] > 0.0) & (ctrl[:-1] <= 0.0)
    i = _first(rising)
    return None if i is None else i + 1


def _phase(trace: Trace) -> float:
    cap = np.asarray(trace["park_brake_capacity_n"])
    if cap[0] <= 0.0:
        return float("nan")  # the park brake was not applied at the start
    i = _first(cap < cap[0] * (1.0 - 1e-9))
    if i is None:
        return float("nan")  # never released
    f_t = trace["drive_force_n"][i]
    f_i = trace["grade_resistance_n"][i]
    if abs(f_t - f_i) <= PHASE_TOLERANCE_FRAC * abs(f_i):
        return 2.0
    return 3.0 if f_t > f_i else 1.0


def park_release_phase_index(trace: Trace):
    """Park-force phase (1-4 of paper 000 Fig. 5) at the instant the park force starts to fall."""
    return _per_run(trace, _phase)


def _release_to_load(trace: Trace) -> float:
    i = _release_index(trace)
    if i is None:
        return float("nan")
    carry = np.asarray(trace["drive_force_n"]) >= (np.asarray(trace["grade_resistance_n"])
                                                    + np.asarray(trace["rolling_resistance_capacity_n"]))
    j = _first(carry)
    if j is None:
        return float("nan")
    return float(trace["time_s"][j] - trace["time_s"][i])


def release_to_load_s(trace: Trace):
    """Release command to the first F_t >= F_i + F_f (negative: the engine carried the load before)."""
    return _per_run(trace, _release_to_load)


def _margin(trace: Trace) -> float:
    i = _release_index(trace)
    if i is None:
        return float("nan")
    lamp_off = _first((np.asarray(trace["park_lamp_flag"]) < 0.5) & (np.arange(len(trace)) >= i))
    if lamp_off is None:
        return float("nan")
    full_release_s = trace["time_s"][lamp_off] - trace["time_s"][i]
    return float(full_release_s - _release_to_load(trace))


def release_margin_s(trace: Trace):
    """Full park-brake release time minus release-to-load time (paper 000 P12: must be > 0)."""
    return _per_run(trace, _margin)


def _engage_rate(trace: Trace) -> float:
    mode = np.asarray(trace["hsa_mode_index"])
    engage = (mode == hill_start_amt.ENGAGE_HELD) | (mode == hill_start_amt.ENGAGE_RELEASING)
    idx = np.flatnonzero(engage)
    if len(idx) < 2:
        return float("nan")
    x = np.asarray(trace["clutch_command_frac"])
    t = np.asarray(trace["time_s"])
    return float((x[idx[-1]] - x[idx[0]]) / (t[idx[-1]] - t[idx[0]]))


def engage_rate_mean_per_s(trace: Trace):
    """Mean commanded clutch rate over the assist's slip engagement (both ENGAGE modes)."""
    return _per_run(trace, _engage_rate)


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
):
    register(_m)


def valve_32_energized_flag(trace: Trace):
    """1 if the 3/2 valve was energised at any sample (the assist held the park brake), else 0."""
    return _per_run(trace, lambda tr: float(np.max(np.asarray(tr["valve_32_energized_flag"])) > 0.5))


register(Metric("valve_32_energized_flag", valve_32_energized_flag, ("valve_32_energized_flag",),
                "1 if the hill-start assist energised the 3/2 valve"))


def _park_drag(trace: Trace) -> float:
    power = np.abs(np.asarray(trace["park_brake_force_n"]) * np.asarray(trace["speed_mps"]))
    return float(np.trapezoid(power, np.asarray(trace["time_s"])))


def park_brake_drag_energy_j(trace: Trace):
    """Energy dissipated in the park brake: integral of |F_park * v| (the truck driven, or rolling, through
    a brake that is not fully released: paper 000 P6). Zero while the truck stands (static reaction)."""
    return _per_run(trace, _park_drag)


register(Metric("park_brake_drag_energy_j", park_brake_drag_energy_j, ("time_s", "park_brake_force_n", "speed_mps"),
                "energy dissipated in the park brake (driving or rolling through a brake not fully released)"))
