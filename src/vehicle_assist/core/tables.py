"""Lookup tables with validated, monotonic breakpoints and an explicit extrapolation policy.

A :class:`Table` is the one way maps enter the project (engine full-load curve, grade over
distance, driver pedal over time, ...). Breakpoints must be finite and strictly increasing;
``extrapolation`` says what happens outside them:

* ``"clamp"``  hold the first / last value (default for physical maps),
* ``"linear"`` extend the first / last segment.

``interpolation`` is ``"linear"`` or ``"previous"`` (zero-order hold, for gear levers and switches).
The compiled kernels read packed tables through :func:`interp`.
"""
from __future__ import annotations

from dataclasses import dataclass

import numba as nb
import numpy as np

EXTRAPOLATION = {"clamp": 0, "linear": 1}
INTERPOLATION = {"linear": 0, "previous": 1}


class TableError(ValueError):
    """A table that cannot be used; the message names what is wrong and how to fix it."""


@dataclass(frozen=True)
class Table:
    """y(x) given at breakpoints ``x`` (strictly increasing) with values ``y``."""

    x_name: str
    y_name: str
    x: tuple[float, ...]
    y: tuple[float, ...]
    extrapolation: str = "clamp"
    interpolation: str = "linear"

    def __post_init__(self) -> None:
        x = np.asarray(self.x, dtype=float)
        y = np.asarray(self.y, dtype=float)
        if x.ndim != 1 or len(x) == 0:
            raise TableError(f"{self.x_name}: needs at least one breakpoint")
        if len(x) != len(y):
            raise TableError(
                f"{self.x_name} has {len(x)} breakpoints but {self.y_name} has {len(y)} values; give one value per breakpoint"
            )
        if not np.all(np.isfinite(x)):
            raise TableError(f"{self.x_name}: breakpoints must be finite numbers (found NaN or inf)")
        if not np.all(np.isfinite(y)):
            raise TableError(f"{self.y_name}: values must be finite numbers (found NaN or inf)")
        if len(x) > 1 and not np.all(np.diff(x) > 0):
            k = int(np.argmin(np.diff(x) > 0))
            raise TableError(
                f"{self.x_name}: breakpoints must be strictly increasing, but {x[k + 1]:g} follows {x[k]:g} (position {k + 1})"
            )
        if self.extrapolation not in EXTRAPOLATION:
            raise TableError(f"extrapolation {self.extrapolation!r} unknown; use one of {sorted(EXTRAPOLATION)}")
        if self.interpolation not in INTERPOLATION:
            raise TableError(f"interpolation {self.interpolation!r} unknown; use one of {sorted(INTERPOLATION)}")

    @classmethod
    def constant(cls, x_name: str, y_name: str, value: float) -> "Table":
        return cls(x_name, y_name, (0.0,), (float(value),))

    def __call__(self, x: float | np.ndarray) -> float | np.ndarray:
        xs, ys = np.asarray(self.x, float), np.asarray(self.y, float)
        xv = np.atleast_1d(np.asarray(x, dtype=float))
        out = np.array([interp(xs, ys, len(xs), EXTRAPOLATION[self.extrapolation], INTERPOLATION[self.interpolation], v) for v in xv])
        return out if np.ndim(x) else float(out[0])

    def scaled(self, x_factor: float = 1.0, y_factor: float = 1.0, x_name: str | None = None, y_name: str | None = None) -> "Table":
        return Table(
            x_name or self.x_name,
            y_name or self.y_name,
            tuple(v * x_factor for v in self.x),
            tuple(v * y_factor for v in self.y),
            self.extrapolation,
            self.interpolation,
        )

    def is_monotonic_increasing(self) -> bool:
        return bool(np.all(np.diff(np.asarray(self.y, float)) >= 0))


@nb.njit(cache=True, nogil=True, error_model="numpy")
def interp(xs, ys, n, extrapolation, interpolation, x):
    """Evaluate a packed table (first ``n`` entries of ``xs``/``ys``) at ``x``."""
    if n == 1:
        return ys[0]
    if x <= xs[0]:
        if extrapolation == 1 and interpolation == 0:
            return ys[0] + (ys[1] - ys[0]) * (x - xs[0]) / (xs[1] - xs[0])
        return ys[0]
    if x >= xs[n - 1]:
        if extrapolation == 1 and interpolation == 0:
            return ys[n - 1] + (ys[n - 1] - ys[n - 2]) * (x - xs[n - 1]) / (xs[n - 1] - xs[n - 2])
        return ys[n - 1]
    # binary search: xs[lo] <= x < xs[hi]
    lo = 0
    hi = n - 1
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if xs[mid] <= x:
            lo = mid
        else:
            hi = mid
    if interpolation == 1:
        return ys[lo]
    return ys[lo] + (ys[hi] - ys[lo]) * (x - xs[lo]) / (xs[hi] - xs[lo])

