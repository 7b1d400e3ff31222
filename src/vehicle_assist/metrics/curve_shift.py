"""Metrics of curve-aware shifting (paper 003, curve_shift.md 8; issue #11): pure functions of an amt_car trace.

Shift events are read from ``gear_command_index`` (the TCU's command: the instant and speed at which the
strategy decided; the engaged gear follows after the torque interruption). The curve signal is the first
sample of driver phase 1 (APPROACH), curve entry the first of phase 2, curve exit the first of phase 3.
Values are NaN when the event does not occur (a check on a NaN fails).

* ``upshifts_signal_to_exit_count``: upshift commands from the curve signal to curve exit (criterion 1).
* ``upshifts_in_curve_mode_count``: upshift commands while curve mode is active (criterion 1 exactly: the gear
  index never rises between the curve command and the end of curve mode), the engine-protection releases
  included; those are also counted on their own (``protection_upshifts_count``). With the strategy off the
  command window is still tracked, so the normal schedule's lift-off upshift counts (the negative control).
* ``preview_fallback_count``: times the TCU found the preview implausible and fell back (FALLBACK mode).
* ``upshifts_after_lift_off_count``: upshift commands within 3 s after the signal (criterion 2, P13).
* ``shift_count``: gear commands that change the gear.
* ``downshift_5_4_speed_mps`` / ``_4_3_`` / ``_3_2_``: speed at the first command that crosses the line
  (a skip 5 -> 3 crosses 5->4 and 4->3 at once).
* ``downshift_margin_min_mps``: over the downshift commands in curve mode, the smallest
  speed - u_a(line below the engaged gear, theta) (criterion 3: >= 0, never later than normal).
* ``engine_speed_after_downshift_max_radps``: highest engine speed in the 0.2 s after a downshift engages
  (criterion 4: <= n_guard).
* ``kj_used_max_ratio``, ``kj_advance_max_frac`` (criterion 5; kj <= kj_max holds by construction, kj = frac*kj_max
  with frac in [0, 1], and is unit-tested in tests/functions/test_curve_shift.py).
* ``gear_at_curve_entry_index``: commanded gear at curve entry (criterion 6); ``gear_drop_max_count``: largest
  drop in one command (criterion 7: >= 2 is a skip shift).
* ``lateral_accel_max_mps2`` (|a_y|) and ``curve_accel_margin_min_mps2`` = min over the curve phase of
  a_ypot(R) - a_y (criterion 8: >= 0).
* ``time_straight_s``, ``time_approach_s``, ``time_curve_s``, ``time_exit_s``: time per driver phase.
* ``engine_work_per_distance_n``: fuelled (indicated) engine work over distance, the integral of
  max(T_e + T_fric, 0)*w_e (brake work plus the friction and pumping work the fuel also pays; zero on overrun
  fuel cut): a fuel proxy in which holding a low gear at high engine speed shows its friction cost (J/m = N =
  kJ/km; fuel mass = work/(eta_ind*H_u) for a constant indicated efficiency). ``engine_brake_work_per_distance_n``:
  the positive brake (flywheel) work alone, for comparison.
"""
from __future__ import annotations

import numpy as np

from vehicle_assist.core.trace import Trace
from vehicle_assist.metrics.common import Metric, register

LIFT_OFF_WINDOW_S = 3.0  # curve_shift.md 8 criterion 2: an upshift within 3 s after lift-off
AFTER_SHIFT_WINDOW_S = 0.2  # assumed: "right after a downshift" (criterion 4)
STRAIGHT, APPROACH, CURVE, EXIT = 0.0, 1.0, 2.0, 3.0


def _rows(trace: Trace, names: tuple[str, ...]):
    t = np.asarray(trace["time_s"], dtype=float)
    arrays = {n: np.atleast_2d(np.asarray(trace[n], dtype=float)) for n in names}
    n_rows = max(a.shape[0] for a in arrays.values())
    t2 = np.atleast_2d(t)
    for i in range(n_rows):
        row = {n: (a[i] if a.shape[0] > 1 else a[0]) for n, a in arrays.items()}
        row["time_s"] = t2[i] if t2.shape[0] > 1 else t2[0]
        yield row


def _per_row(trace: Trace, names: tuple[str, ...], fn):
    values = np.array([fn(r) for r in _rows(trace, names)], dtype=float)
    return values if trace.batch_size is not None else float(values[0])


def _first(mask: np.ndarray) -> int:
    idx = np.nonzero(mask)[0]
    return int(idx[0]) if len(idx) else -1


def _commands(r) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(sample index of each gear change, from gear, to gear)."""
    g = r["gear_command_index"]
    i = np.nonzero(np.diff(g) != 0)[0] + 1
    return i, g[i - 1], g[i]


def _window(r, start_phase: float, end_phase: float | None) -> tuple[int, int]:
    ph = r["driver_phase_index"]
    a = _first(ph == start_phase)
    if a < 0:
        return -1, -1
    b = _first((ph == end_phase) & (np.arange(len(ph)) > a)) if end_phase is not None else len(ph)
    return a, (b if b >= 0 else len(ph))


def upshifts_signal_to_exit_count(trace):
    def f(r):
        a, b = _window(r, APPROACH, EXIT)
        if a < 0:
            return np.nan
        i, g0, g1 = _commands(r)
        return float(np.sum((i >= a) & (i < b) & (g1 > g0)))
    return _per_row(trace, ("gear_command_index", "driver_phase_index"), f)


def upshifts_in_curve_mode_count(trace):
    def f(r):
        i, g0, g1 = _commands(r)
        # a command issued at the sample where curve mode ends belongs to the normal schedule
        n = np.sum((g1 > g0) & (r["curve_mode_flag"][i - 1] > 0.5) & (r["curve_mode_flag"][i] > 0.5))
        return float(n)
    return _per_row(trace, ("gear_command_index", "curve_mode_flag"), f)


def preview_fallback_count(trace):
    def f(r):
        x = r["preview_fallback_flag"] > 0.5
        return float(np.sum(x[1:] & ~x[:-1]) + (1 if x[0] else 0))
    return _per_row(trace, ("preview_fallback_flag",), f)


def curve_mode_in_curve_phase_frac(trace):
    def f(r):
        inside = r["driver_phase_index"] == CURVE
        if not np.any(inside):
            return np.nan
        return float(np.mean(r["curve_mode_flag"][inside] > 0.5))
    return _per_row(trace, ("driver_phase_index", "curve_mode_flag"), f)


def protection_upshifts(r) -> float:
    return float(np.max(r["protection_upshift_count"]))


def protection_upshifts_count(trace):
    return _per_row(trace, ("protection_upshift_count",), protection_upshifts)


def upshifts_after_lift_off_count(trace):
    def f(r):
        a, _ = _window(r, APPROACH, None)
        if a < 0:
            return np.nan
        t = r["time_s"]
        i, g0, g1 = _commands(r)
        return float(np.sum((i >= a) & (t[i] <= t[a] + LIFT_OFF_WINDOW_S) & (g1 > g0)))
    return _per_row(trace, ("gear_command_index", "driver_phase_index"), f)


def shift_count(trace):
    return _per_row(trace, ("gear_command_index",), lambda r: float(len(_commands(r)[0])))


def _downshift_speed(line_from: int):
    def metric(trace):
        def f(r):
            i, g0, g1 = _commands(r)
            hit = np.nonzero((g0 >= line_from) & (g1 <= line_from - 1))[0]
            return float(r["speed_mps"][i[hit[0]]]) if len(hit) else np.nan
        return _per_row(trace, ("gear_command_index", "speed_mps"), f)
    metric.__name__ = f"downshift_{line_from}_{line_from - 1}_speed_mps"
    return metric


def downshift_margin_min_mps(trace):
    def f(r):
        i, g0, g1 = _commands(r)
        sel = i[(g1 < g0) & (r["curve_mode_flag"][i] > 0.5)]
        if len(sel) == 0:
            return np.nan
        return float(np.min(r["speed_mps"][sel] - r["normal_downshift_speed_mps"][sel - 1]))
    return _per_row(trace, ("gear_command_index", "curve_mode_flag", "speed_mps", "normal_downshift_speed_mps"), f)


def engine_speed_after_downshift_max_radps(trace):
    def f(r):
        g = r["gear_index"]
        t = r["time_s"]
        last = 0.0
        best = np.nan
        engaged_before = g[0]
        for k in range(1, len(g)):
            if g[k] > 0 and g[k - 1] == 0:
                if g[k] < engaged_before:
                    w = r["engine_speed_radps"][k:][t[k:] <= t[k] + AFTER_SHIFT_WINDOW_S]
                    best = max(last, float(np.max(w))) if len(w) else best
                    last = best
                engaged_before = g[k]
            elif g[k] > 0:
                engaged_before = g[k]
        return best if np.isfinite(best) else 0.0
    return _per_row(trace, ("gear_index", "engine_speed_radps"), f)


def kj_used_max_ratio(trace):
    return _per_row(trace, ("kj_ratio",), lambda r: float(np.max(r["kj_ratio"])))


def kj_advance_max_frac(trace):
    return _per_row(trace, ("kj_frac",), lambda r: float(np.max(r["kj_frac"])))


def gear_at_curve_entry_index(trace):
    def f(r):
        a = _first(r["driver_phase_index"] == CURVE)
        return float(r["gear_command_index"][a]) if a >= 0 else np.nan
    return _per_row(trace, ("gear_command_index", "driver_phase_index"), f)


def gear_drop_max_count(trace):
    def f(r):
        i, g0, g1 = _commands(r)
        return float(np.max(g0 - g1)) if len(i) else 0.0
    return _per_row(trace, ("gear_command_index",), f)


def lateral_accel_max_mps2(trace):
    return _per_row(trace, ("lateral_accel_mps2",), lambda r: float(np.max(np.abs(r["lateral_accel_mps2"]))))


def curve_accel_margin_min_mps2(trace):
    def f(r):
        m = r["driver_phase_index"] == CURVE
        if not np.any(m):
            return np.nan
        return float(np.nanmin(r["tolerable_accel_true_mps2"][m] - np.abs(r["lateral_accel_mps2"][m])))
    return _per_row(trace, ("driver_phase_index", "tolerable_accel_true_mps2", "lateral_accel_mps2"), f)


def _phase_time(phase: float):
    def metric(trace):
        def f(r):
            t = r["time_s"]
            dt = np.diff(t, append=t[-1])
            return float(np.sum(dt[r["driver_phase_index"] == phase]))
        return _per_row(trace, ("driver_phase_index",), f)
    return metric


def _work_per_distance(channel: str):
    def metric(trace):
        def f(r):
            work = np.trapezoid(np.maximum(r[channel], 0.0), r["time_s"])
            dist = r["position_m"][-1] - r["position_m"][0]
            return float(work / dist) if dist > 1.0 else np.nan
        return _per_row(trace, (channel, "position_m"), f)
    return metric


engine_work_per_distance_n = _work_per_distance("engine_indicated_power_w")
engine_brake_work_per_distance_n = _work_per_distance("engine_power_w")


_GEAR = ("gear_command_index",)
for _m in (
    Metric("upshifts_signal_to_exit_count", upshifts_signal_to_exit_count, _GEAR + ("driver_phase_index",),
           "upshift commands from the curve signal to curve exit"),
    Metric("upshifts_in_curve_mode_count", upshifts_in_curve_mode_count, _GEAR + ("curve_mode_flag",),
           "upshift commands while curve mode is active (engine-protection releases included)"),
    Metric("preview_fallback_count", preview_fallback_count, ("preview_fallback_flag",),
           "times the TCU found the preview implausible and fell back to the normal schedule"),
    Metric("curve_mode_in_curve_phase_frac", curve_mode_in_curve_phase_frac, ("driver_phase_index", "curve_mode_flag"),
           "fraction of the curve phase samples with the strategy in curve mode"),
    Metric("protection_upshifts_count", protection_upshifts_count, ("protection_upshift_count",),
           "upshifts the engine protection released in curve mode"),
    Metric("upshifts_after_lift_off_count", upshifts_after_lift_off_count, _GEAR + ("driver_phase_index",),
           "upshift commands within 3 s after the curve signal (lift-off)"),
    Metric("shift_count", shift_count, _GEAR, "gear commands that change the gear"),
    Metric("downshift_5_4_speed_mps", _downshift_speed(5), _GEAR + ("speed_mps",), "speed at the first command crossing 5->4"),
    Metric("downshift_4_3_speed_mps", _downshift_speed(4), _GEAR + ("speed_mps",), "speed at the first command crossing 4->3"),
    Metric("downshift_3_2_speed_mps", _downshift_speed(3), _GEAR + ("speed_mps",), "speed at the first command crossing 3->2"),
    Metric("downshift_margin_min_mps", downshift_margin_min_mps, _GEAR + ("curve_mode_flag", "speed_mps", "normal_downshift_speed_mps"),
           "smallest speed above the normal downshift line over the downshifts in curve mode"),
    Metric("engine_speed_after_downshift_max_radps", engine_speed_after_downshift_max_radps, ("gear_index", "engine_speed_radps"),
           "highest engine speed within 0.2 s after a downshift engages"),
    Metric("kj_used_max_ratio", kj_used_max_ratio, ("kj_ratio",), "largest downshift advance kj used"),
    Metric("kj_advance_max_frac", kj_advance_max_frac, ("kj_frac",), "largest kj/kj_max fraction of a curve command"),
    Metric("gear_at_curve_entry_index", gear_at_curve_entry_index, _GEAR + ("driver_phase_index",), "commanded gear at curve entry"),
    Metric("gear_drop_max_count", gear_drop_max_count, _GEAR, "largest gear drop in one shift command"),
    Metric("lateral_accel_max_mps2", lateral_accel_max_mps2, ("lateral_accel_mps2",), "largest |a_y|"),
    Metric("curve_accel_margin_min_mps2", curve_accel_margin_min_mps2,
           ("driver_phase_index", "tolerable_accel_true_mps2", "lateral_accel_mps2"),
           "smallest a_ypot(R) - |a_y| in the curve phase"),
    Metric("time_straight_s", _phase_time(STRAIGHT), ("driver_phase_index",), "time in the straight phase"),
    Metric("time_approach_s", _phase_time(APPROACH), ("driver_phase_index",), "time in the approach phase"),
    Metric("time_curve_s", _phase_time(CURVE), ("driver_phase_index",), "time in the curve phase"),
    Metric("time_exit_s", _phase_time(EXIT), ("driver_phase_index",), "time in the exit phase"),
    Metric("engine_work_per_distance_n", engine_work_per_distance_n, ("engine_indicated_power_w", "position_m"),
           "fuelled (indicated) engine work per distance, friction and pumping included (fuel proxy)"),
    Metric("engine_brake_work_per_distance_n", engine_brake_work_per_distance_n, ("engine_power_w", "position_m"),
           "positive brake (flywheel) engine work per distance"),
):
    register(_m)
