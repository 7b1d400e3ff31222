"""Metrics shared by all assistance functions: pure functions ``f(trace) -> float`` and their registry.

Every metric reads only a :class:`~vehicle_assist.core.trace.Trace` and returns one float in SI units;
the metric's name carries the unit suffix (``rollback_distance_m``, ``clutch_slip_energy_j``). Each is
registered as a :class:`Metric` together with the channels it needs, so :func:`compute_metrics` can
evaluate whatever a trace supports (a truck trace has no motor channels, an EV trace no clutch).

Later modules add their own metrics with :func:`register`::

    register(Metric("hold_time_s", hold_time_s, ("time_s", "vehicle_held_flag"), "time held at rest"))

Definitions (SI; ``t`` = ``time_s``):

* rollback: ``max(0, x[0] - min x)`` and ``max(0, -min v)`` (rollback is motion against +x, conventions).
* energies: trapezoidal integral of the dissipated power over ``t``.
* jerk (common.md section 10): acceleration low-pass filtered by a causal 2nd-order Butterworth at
  5 Hz (assumed cut-off, spec), started in steady state on the first sample, then differentiated with
  :func:`numpy.gradient`; samples held at rest (``vehicle_held_flag == 1``) contribute zero jerk.
* launch time: from brake release (or accelerator press) to the first sample at or above a speed.
"""
from __future__ import annotations

import functools

import difflib
from collections.abc import Callable, Iterable
from dataclasses import dataclass

import numba as nb
import numpy as np

from vehicle_assist.core.trace import Trace

__all__ = [
    "Metric",
    "METRICS",
    "register",
    "compute_metrics",
    "rollback_distance_m",
    "rollback_speed_mps",
    "engine_speed_min_radps",
    "engine_speed_peak_radps",
    "engine_stalled_flag",
    "clutch_slip_energy_j",
    "brake_drag_energy_j",
    "filtered_jerk",
    "jerk_filtered_max_mps3",
    "jerk_filtered_min_mps3",
    "jerk_filtered_peak_mps3",
    "launch_time_s",
    "peak_speed_mps",
    "final_speed_mps",
    "JERK_FILTER_CUTOFF_HZ",
    "JERK_FILTER_ORDER",
    "PEDAL_APPLIED_FRAC",
    "LAUNCH_SPEED_MPS",
]

JERK_FILTER_CUTOFF_HZ = 5.0  # assumed (common.md section 10)
JERK_FILTER_ORDER = 2  # common.md section 10
PEDAL_APPLIED_FRAC = 0.01  # a pedal counts as applied at or above this travel (assumed)
LAUNCH_SPEED_MPS = 0.5  # default "vehicle has launched" speed (assumed)


def _ch(trace: Trace, name: str) -> np.ndarray:
    return np.asarray(trace[name], dtype=np.float64)


def _out(value):
    """A float for one run, an array (one value per run) for a batch trace (-0.0 shown as 0.0)."""
    return float(value) + 0.0 if np.ndim(value) == 0 else np.asarray(value, dtype=np.float64) + 0.0


# row helpers of the metrics that work on (runs, samples) arrays (metrics/hill_start.py, hill_start_ehb.py,
# blowout.py, brake_assist.py)
def channel_rows(trace: Trace, name: str) -> np.ndarray:
    """A channel as (runs, samples) float64: one row for a single run."""
    return np.atleast_2d(np.asarray(trace[name], dtype=np.float64))


def per_run(values: np.ndarray, trace: Trace):
    """One value per run: the array for a batch trace, a float for a single run (-0.0 shown as 0.0)."""
    return values if trace.batch_size is not None else float(values[0]) + 0.0


def first_true(mask: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Index of the first True along the last axis, and whether there is one (per row)."""
    return np.argmax(mask, axis=-1), mask.any(axis=-1)


def take_rows(values: np.ndarray, index: np.ndarray) -> np.ndarray:
    """``values[r, index[r]]`` of each row r (a single row serves every index)."""
    if values.shape[0] == 1 and len(index) > 1:
        values = np.broadcast_to(values, (len(index), values.shape[1]))
    return values[np.arange(len(index)), index]


def time_row(trace: Trace) -> np.ndarray:
    """``time_s`` of one run: the first row of a batch trace (its runs share the sample times)."""
    t = np.asarray(trace["time_s"], dtype=np.float64)
    return t[0] if t.ndim == 2 else t


def row_metric(fn: Callable[..., float], names: Iterable[str]) -> Callable[[Trace], float | np.ndarray]:
    """A metric ``f(trace)`` that computes ``fn(t, *channels)`` run by run: ``t`` from :func:`time_row`, the
    channels ``names`` as that run's rows; one value per run (:func:`per_run`)."""
    names = tuple(names)

    def metric(trace: Trace):
        t = time_row(trace)
        cols = [channel_rows(trace, n) for n in names]
        out = np.array([fn(t, *[c[i] for c in cols]) for i in range(cols[0].shape[0])], dtype=float)
        return per_run(out, trace)
    return metric


def _integral(trace: Trace, power_name: str) -> float:
    return _out(np.trapezoid(_ch(trace, power_name), _ch(trace, "time_s"), axis=-1))


# -- rollback, speed -------------------------------------------------------------------------------
def rollback_distance_m(trace: Trace) -> float:
    """Largest travel backwards from the start position: ``max(0, x[0] - min x)``."""
    position_m = _ch(trace, "position_m")
    return _out(np.maximum(0.0, position_m[..., 0] - np.min(position_m, axis=-1)))


def rollback_speed_mps(trace: Trace) -> float:
    """Largest backward speed: ``max(0, -min v)``."""
    return _out(np.maximum(0.0, -np.min(_ch(trace, "speed_mps"), axis=-1)))


def peak_speed_mps(trace: Trace) -> float:
    """Largest forward speed reached."""
    return _out(np.max(_ch(trace, "speed_mps"), axis=-1))


def final_speed_mps(trace: Trace) -> float:
    """Speed at the last sample."""
    return _out(_ch(trace, "speed_mps")[..., -1])


# -- engine, clutch, brakes ------------------------------------------------------------------------
def engine_speed_min_radps(trace: Trace) -> float:
    """Lowest engine speed (a dip toward stall shows here)."""
    return _out(np.min(_ch(trace, "engine_speed_radps"), axis=-1))


def engine_speed_peak_radps(trace: Trace) -> float:
    """Highest engine speed (flare during clutch slip shows here)."""
    return _out(np.max(_ch(trace, "engine_speed_radps"), axis=-1))


def engine_stalled_flag(trace: Trace) -> float:
    """1.0 if the engine stalled at any sample, else 0.0."""
    return _out((np.max(_ch(trace, "engine_stalled_flag"), axis=-1) >= 0.5).astype(float))


def clutch_slip_energy_j(trace: Trace) -> float:
    """Energy dissipated in the slipping clutch: trapezoidal integral of ``clutch_slip_power_w``."""
    return _integral(trace, "clutch_slip_power_w")


def brake_drag_energy_j(trace: Trace) -> float:
    """Energy dissipated in all brakes: trapezoidal integral of ``brake_power_w``."""
    return _integral(trace, "brake_power_w")


# -- jerk ------------------------------------------------------------------------------------------
def filtered_jerk(
    trace: Trace, cutoff_hz: float = JERK_FILTER_CUTOFF_HZ, order: int = JERK_FILTER_ORDER
) -> np.ndarray:
    """Jerk in m/s^3 of the low-pass filtered ``accel_mps2`` (common.md section 10), one value per sample.

    Filter: causal 2nd-order Butterworth (:func:`butter2_lowpass`, equal to ``scipy.signal.butter``) whose
    state starts in steady state on the first sample (as ``lfilter_zi * a[0]``), so a trace that starts at
    constant acceleration shows no start-up transient. ``dt`` is the median step; the filter assumes
    uniform sampling. If the cut-off is not below the Nyquist frequency the samples cannot carry content
    above it, and the acceleration is used unfiltered. Differentiation: :func:`numpy.gradient` over
    ``time_s``. Where ``vehicle_held_flag == 1`` the jerk is set to 0 (held at rest: v = 0, a = 0).
    """
    key = ("filtered_jerk", cutoff_hz, order)
    cache = trace.__dict__.setdefault("_metric_cache", {})
    if key in cache:
        return cache[key]
    time_s = _ch(trace, "time_s")
    accel_mps2 = _ch(trace, "accel_mps2")
    if len(time_s) < 2:
        return np.zeros_like(accel_mps2)
    dt_s = float(np.median(np.diff(time_s)))
    if not dt_s > 0.0:
        raise ValueError("filtered_jerk needs strictly increasing time_s")
    fs_hz = 1.0 / dt_s
    if cutoff_hz < 0.5 * fs_hz:
        if order != 2:
            raise ValueError("only the 2nd-order Butterworth of common.md section 10 is implemented")
        b, a = butter2_lowpass(cutoff_hz, fs_hz)
        filtered = _biquad(b, a, accel_mps2)
    else:
        filtered = accel_mps2
    jerk_mps3 = np.gradient(filtered, time_s, axis=-1)
    if "vehicle_held_flag" in trace:
        jerk_mps3 = np.where(_ch(trace, "vehicle_held_flag") >= 0.5, 0.0, jerk_mps3)
    cache[key] = jerk_mps3
    return jerk_mps3


@functools.lru_cache(maxsize=16)
def butter2_lowpass(cutoff_hz: float, fs_hz: float) -> tuple[np.ndarray, np.ndarray]:
    """2nd-order Butterworth low-pass, bilinear transform with pre-warping (closed form).

    K = tan(pi*fc/fs), n = 1/(1 + sqrt(2)*K + K^2):
    b = (K^2*n, 2*K^2*n, K^2*n),  a = (1, 2*(K^2 - 1)*n, (1 - sqrt(2)*K + K^2)*n).
    Identical to ``scipy.signal.butter(2, fc, fs=fs)`` (checked in the tests); written out because
    importing scipy.signal costs 0.5 s on every command-line run.
    """
    k = np.tan(np.pi * cutoff_hz / fs_hz)
    norm = 1.0 / (1.0 + np.sqrt(2.0) * k + k * k)
    b = np.array([k * k * norm, 2.0 * k * k * norm, k * k * norm])
    a = np.array([1.0, 2.0 * (k * k - 1.0) * norm, (1.0 - np.sqrt(2.0) * k + k * k) * norm])
    return b, a


def _biquad(b: np.ndarray, a: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Filter along the last axis (direct form II transposed), starting in steady state on x[..., 0]."""
    x2 = np.atleast_2d(np.asarray(x, dtype=np.float64))
    y = _biquad_rows(b, a, x2)
    return y.reshape(np.shape(x))


@nb.njit(cache=True, nogil=True)
def _biquad_rows(b, a, x):
    y = np.empty_like(x)
    for r in range(x.shape[0]):
        x0 = x[r, 0]
        z2 = (b[2] - a[2]) * x0  # steady state for a constant input x0 (DC gain 1)
        z1 = (b[1] - a[1]) * x0 + z2
        for i in range(x.shape[1]):
            xi = x[r, i]
            yi = b[0] * xi + z1
            z1 = b[1] * xi - a[1] * yi + z2
            z2 = b[2] * xi - a[2] * yi
            y[r, i] = yi
    return y


def jerk_filtered_max_mps3(trace: Trace) -> float:
    """Largest (most positive) filtered jerk."""
    return _out(np.max(filtered_jerk(trace), axis=-1))


def jerk_filtered_min_mps3(trace: Trace) -> float:
    """Smallest (most negative) filtered jerk."""
    return _out(np.min(filtered_jerk(trace), axis=-1))


def jerk_filtered_peak_mps3(trace: Trace) -> float:
    """Largest magnitude of the filtered jerk."""
    return _out(np.max(np.abs(filtered_jerk(trace)), axis=-1))


# -- launch ----------------------------------------------------------------------------------------
def _launch_start_s(trace: Trace) -> float:
    """Brake release after an applied brake; else first accelerator press; else ``time_s[0]``."""
    time_s = _ch(trace, "time_s")
    if "brake_pedal_frac" in trace:
        applied = _ch(trace, "brake_pedal_frac") >= PEDAL_APPLIED_FRAC
        if applied.any():
            first_applied = int(np.argmax(applied))
            released = ~applied[first_applied:]
            if released.any():
                return float(time_s[first_applied + int(np.argmax(released))])
            return float("nan")  # applied and never released: no launch
    if "accelerator_frac" in trace:
        pressed = _ch(trace, "accelerator_frac") > PEDAL_APPLIED_FRAC
        if pressed.any():
            return float(time_s[int(np.argmax(pressed))])
    return float(time_s[0])


def launch_time_s(trace: Trace, speed_threshold_mps: float = LAUNCH_SPEED_MPS) -> float:
    """Time from launch start to the first sample with ``speed_mps >= speed_threshold_mps``; NaN if none.

    Launch start is the first sample with ``brake_pedal_frac < 0.01`` after it has been ``>= 0.01``;
    if the brake is never applied, the first sample with ``accelerator_frac > 0.01``; if neither,
    ``time_s[0]``. A brake that is applied and never released gives NaN. Sample times, no interpolation.
    """
    if trace.batch_size is not None:
        return np.array([_launch_time_one(trace.row(i), speed_threshold_mps) for i in range(trace.batch_size)])
    return _launch_time_one(trace, speed_threshold_mps)


def _launch_time_one(trace: Trace, speed_threshold_mps: float) -> float:
    start_s = _launch_start_s(trace)
    if np.isnan(start_s):
        return float("nan")
    time_s = _ch(trace, "time_s")
    launched = (_ch(trace, "speed_mps") >= speed_threshold_mps) & (time_s >= start_s)
    if not launched.any():
        return float("nan")
    return float(time_s[int(np.argmax(launched))] - start_s)


# -- registry --------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Metric:
    """A named metric: ``function(trace) -> float`` in the unit of the name's suffix."""

    name: str
    function: Callable[[Trace], float]
    requires: tuple[str, ...]
    description: str

    def available(self, trace: Trace) -> bool:
        """True if every required channel is in ``trace``."""
        return all(name in trace for name in self.requires)

    def __call__(self, trace: Trace):
        """A float; for a batch trace (channels of shape (runs, samples)) one value per run."""
        return _out(self.function(trace))


METRICS: dict[str, Metric] = {}


def register(metric: Metric, *, replace: bool = False) -> Metric:
    """Add ``metric`` to :data:`METRICS`; a second metric of the same name is an error unless ``replace``."""
    if metric.name in METRICS and not replace:
        raise ValueError(f"a metric named {metric.name!r} is already registered")
    METRICS[metric.name] = metric
    return metric


def _unknown(name: str) -> ValueError:
    close = difflib.get_close_matches(name, METRICS, n=1)
    hint = f" (did you mean {close[0]!r}?)" if close else ""
    known = ", ".join(sorted(METRICS))
    return ValueError(f"unknown metric {name!r}{hint}; known metrics: {known}")


def compute_metrics(trace: Trace, names: Iterable[str] | None = None) -> dict[str, float]:
    """Evaluate metrics on ``trace``, in registration (or ``names``) order.

    Without ``names``: every registered metric whose required channels are present. With ``names``:
    exactly those; an unknown name or a missing required channel raises ``ValueError``.
    """
    if names is None:
        return {name: m(trace) for name, m in METRICS.items() if m.available(trace)}
    selected = list(names)
    for name in selected:
        if name not in METRICS:
            raise _unknown(name)
    results: dict[str, float] = {}
    for name in selected:
        metric = METRICS[name]
        missing = [c for c in metric.requires if c not in trace]
        if missing:
            raise ValueError(f"metric {name!r} needs channel(s) {missing} that the trace does not have")
        results[name] = metric(trace)
    return results


for _metric in (
    Metric("rollback_distance_m", rollback_distance_m, ("position_m",),
           "largest travel backwards from the start position"),
    Metric("rollback_speed_mps", rollback_speed_mps, ("speed_mps",), "largest backward speed"),
    Metric("engine_speed_min_radps", engine_speed_min_radps, ("engine_speed_radps",), "lowest engine speed"),
    Metric("engine_speed_peak_radps", engine_speed_peak_radps, ("engine_speed_radps",), "highest engine speed"),
    Metric("engine_stalled_flag", engine_stalled_flag, ("engine_stalled_flag",), "1 if the engine stalled"),
    Metric("clutch_slip_energy_j", clutch_slip_energy_j, ("time_s", "clutch_slip_power_w"),
           "energy dissipated in the slipping clutch"),
    Metric("brake_drag_energy_j", brake_drag_energy_j, ("time_s", "brake_power_w"),
           "energy dissipated in all brakes"),
    Metric("jerk_filtered_max_mps3", jerk_filtered_max_mps3, ("time_s", "accel_mps2"),
           "largest jerk of the 5 Hz Butterworth-filtered acceleration"),
    Metric("jerk_filtered_min_mps3", jerk_filtered_min_mps3, ("time_s", "accel_mps2"),
           "smallest jerk of the 5 Hz Butterworth-filtered acceleration"),
    Metric("jerk_filtered_peak_mps3", jerk_filtered_peak_mps3, ("time_s", "accel_mps2"),
           "largest jerk magnitude of the 5 Hz Butterworth-filtered acceleration"),
    Metric("launch_time_s", launch_time_s, ("time_s", "speed_mps"),
           "brake release (or accelerator press) to 0.5 m/s"),
    Metric("peak_speed_mps", peak_speed_mps, ("speed_mps",), "largest forward speed"),
    Metric("final_speed_mps", final_speed_mps, ("speed_mps",), "speed at the last sample"),
):
    register(_metric)
del _metric
