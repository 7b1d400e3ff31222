"""core/tables.py: validated lookup tables and the compiled ``interp``.

Reference: numpy.interp (linear interpolation with end clamping) for the 'linear'/'clamp' case;
hand-written closed forms for linear extrapolation and zero-order hold ('previous'). Tolerances are
floating-point rounding: interp evaluates y0 + (y1 - y0)(x - x0)/(x1 - x0) while numpy uses a
precomputed slope, so results may differ by a few ulps of max|y| (bound 1e-12 relative to the table scale).
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from vehicle_assist.core.tables import EXTRAPOLATION, INTERPOLATION, Table, TableError, interp

LINEAR, PREVIOUS = INTERPOLATION["linear"], INTERPOLATION["previous"]
CLAMP, EXTRAP = EXTRAPOLATION["clamp"], EXTRAPOLATION["linear"]

finite = st.floats(min_value=-1e6, max_value=1e6, allow_nan=False, allow_infinity=False)


@st.composite
def tables(draw, min_size=2):
    xs = draw(st.lists(st.floats(min_value=-1e4, max_value=1e4, allow_nan=False), min_size=min_size, max_size=12, unique=True))
    xs = np.sort(np.asarray(xs, dtype=float))
    assume(np.all(np.diff(xs) > 1e-6 * max(1.0, float(np.max(np.abs(xs))))))  # well-conditioned segments
    ys = np.asarray(draw(st.lists(finite, min_size=len(xs), max_size=len(xs))), dtype=float)
    return xs, ys


def scale(ys) -> float:
    return max(1.0, float(np.max(np.abs(ys))))


@settings(max_examples=200, deadline=None)
@given(tab=tables(), u=st.lists(st.floats(min_value=-0.2, max_value=1.2), min_size=1, max_size=20))
def test_linear_clamp_matches_numpy_interp(tab, u) -> None:
    """'linear' interpolation with 'clamp' extrapolation is numpy.interp (inside and outside the range)."""
    xs, ys = tab
    q = xs[0] + np.asarray(u) * (xs[-1] - xs[0])
    got = np.array([interp(xs, ys, len(xs), CLAMP, LINEAR, x) for x in q])
    np.testing.assert_allclose(got, np.interp(q, xs, ys), rtol=0, atol=1e-12 * scale(ys) * 4)


@settings(max_examples=100, deadline=None)
@given(tab=tables())
def test_breakpoints_are_returned_exactly(tab) -> None:
    """At a breakpoint the table returns its value exactly (no rounding), for both interpolations."""
    xs, ys = tab
    for mode in (LINEAR, PREVIOUS):
        assert [interp(xs, ys, len(xs), CLAMP, mode, x) for x in xs] == list(ys)


@settings(max_examples=100, deadline=None)
@given(tab=tables(), d=st.floats(min_value=1e-3, max_value=1e3))
def test_linear_extrapolation_extends_end_segments(tab, d) -> None:
    """'linear' extrapolation: y = y_end + slope_end*(x - x_end) on both sides; 'clamp' holds the end value."""
    xs, ys = tab
    n = len(xs)
    lo_slope = (ys[1] - ys[0]) / (xs[1] - xs[0])
    hi_slope = (ys[-1] - ys[-2]) / (xs[-1] - xs[-2])
    tol = 1e-9 * (scale(ys) + abs(lo_slope * d) + abs(hi_slope * d))
    assert interp(xs, ys, n, EXTRAP, LINEAR, xs[0] - d) == pytest.approx(ys[0] - lo_slope * d, abs=tol)
    assert interp(xs, ys, n, EXTRAP, LINEAR, xs[-1] + d) == pytest.approx(ys[-1] + hi_slope * d, abs=tol)
    assert interp(xs, ys, n, CLAMP, LINEAR, xs[0] - d) == ys[0]
    assert interp(xs, ys, n, CLAMP, LINEAR, xs[-1] + d) == ys[-1]


@settings(max_examples=100, deadline=None)
@given(tab=tables(), u=st.lists(st.floats(min_value=-0.2, max_value=1.2), min_size=1, max_size=20))
def test_previous_is_zero_order_hold(tab, u) -> None:
    """'previous' (gear lever, switches): y of the last breakpoint <= x; first value before the table.
    Linear extrapolation does not apply to a zero-order hold (it holds the end value)."""
    xs, ys = tab
    for x in xs[0] + np.asarray(u) * (xs[-1] - xs[0]):
        k = max(int(np.searchsorted(xs, x, side="right")) - 1, 0)
        assert interp(xs, ys, len(xs), CLAMP, PREVIOUS, x) == ys[k]
        assert interp(xs, ys, len(xs), EXTRAP, PREVIOUS, x) == ys[k]


def test_hand_values() -> None:
    """Hand-checkable: x (0, 1, 3), y (0, 10, 30). Midpoints 5 and 20; hold gives 10 at x = 2;
    linear extrapolation 40 at x = 4 and -10 at x = -1; clamp 30 and 0."""
    xs, ys = np.array([0.0, 1.0, 3.0]), np.array([0.0, 10.0, 30.0])
    assert interp(xs, ys, 3, CLAMP, LINEAR, 0.5) == 5.0
    assert interp(xs, ys, 3, CLAMP, LINEAR, 2.0) == 20.0
    assert interp(xs, ys, 3, CLAMP, PREVIOUS, 2.0) == 10.0
    assert interp(xs, ys, 3, EXTRAP, LINEAR, 4.0) == 40.0
    assert interp(xs, ys, 3, EXTRAP, LINEAR, -1.0) == -10.0
    assert interp(xs, ys, 3, CLAMP, LINEAR, 4.0) == 30.0
    assert interp(xs, ys, 3, CLAMP, LINEAR, -1.0) == 0.0


def test_only_first_n_entries_are_read() -> None:
    """Packed records pad tables to a capacity (core/records.py); interp must ignore entries beyond n."""
    xs = np.array([0.0, 1.0, 2.0, 1e9, -5.0])
    ys = np.array([0.0, 1.0, 4.0, np.nan, 1e9])
    assert interp(xs, ys, 3, CLAMP, LINEAR, 1.5) == 2.5
    assert interp(xs, ys, 3, CLAMP, LINEAR, 50.0) == 4.0
    assert interp(xs, ys, 3, EXTRAP, LINEAR, 3.0) == 7.0


def test_single_point_table_is_constant() -> None:
    """A one-breakpoint table (Table.constant) returns its value everywhere, for any policy."""
    t = Table.constant("time_s", "frac", 0.25)
    for x in (-1e9, 0.0, 3.0, 1e9):
        assert t(x) == 0.25
        assert interp(np.array([0.0]), np.array([0.25]), 1, EXTRAP, LINEAR, x) == 0.25


def test_table_call_scalar_and_vector() -> None:
    """Table.__call__ gives a float for a scalar and an array for an array, through the compiled interp."""
    t = Table("x", "y", (0.0, 2.0), (0.0, 4.0), "linear")
    assert isinstance(t(1.0), float) and t(1.0) == 2.0
    np.testing.assert_array_equal(t(np.array([-1.0, 1.0, 3.0])), [-2.0, 2.0, 6.0])
    assert Table("x", "y", (0.0, 2.0), (0.0, 4.0))(3.0) == 4.0  # default 'clamp'


@pytest.mark.parametrize("x, y, match", [
    ((0.0, 2.0, 1.0), (0.0, 1.0, 2.0), "strictly increasing"),
    ((0.0, 1.0, 1.0), (0.0, 1.0, 2.0), "strictly increasing"),
    ((0.0, math.nan), (0.0, 1.0), "finite"),
    ((0.0, math.inf), (0.0, 1.0), "finite"),
    ((0.0, 1.0), (0.0, math.nan), "finite"),
    ((0.0, 1.0, 2.0), (0.0, 1.0), "breakpoints"),
    ((), (), "at least one"),
])
def test_bad_tables_raise_table_error(x, y, match) -> None:
    """Non-monotonic, NaN/inf and mismatched tables are rejected with a TableError naming the problem."""
    with pytest.raises(TableError, match=match):
        Table("x_m", "y_n", x, y)


def test_bad_policies_raise_table_error() -> None:
    with pytest.raises(TableError, match="extrapolation"):
        Table("x", "y", (0.0, 1.0), (0.0, 1.0), extrapolation="cubic")
    with pytest.raises(TableError, match="interpolation"):
        Table("x", "y", (0.0, 1.0), (0.0, 1.0), interpolation="spline")
    assert issubclass(TableError, ValueError)


def test_non_monotonic_message_names_position() -> None:
    """The message says which breakpoint breaks the order (so a user can fix the file)."""
    with pytest.raises(TableError, match=r"1 follows 2 \(position 2\)"):
        Table("speed_rpm", "torque_nm", (0.0, 2.0, 1.0), (0.0, 1.0, 2.0))
