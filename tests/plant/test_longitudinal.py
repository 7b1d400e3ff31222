"""Unit tests of plant/longitudinal.py: the Karnopp stick/slip rule, delta, drag and grade forces.

References: common.md 3 (driving equation), 3.1 (the 21.15 drag form), 3.3 (stick/slip at standstill),
4 (physical rotating-mass factor). The kernels are called compiled; one test also runs ``.py_func``
(uncompiled) to show both give the same numbers.
"""
from __future__ import annotations

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from vehicle_assist.conventions import G_MPS2, RHO_AIR_KGPM3, STANDSTILL_SPEED_MPS
from vehicle_assist.plant.longitudinal import (
    aero_drag_n,
    equivalent_mass_kg,
    grade_resistance_n,
    rolling_resistance_capacity_n,
    stick_slip_step,
)

V_EPS = STANDSTILL_SPEED_MPS
DT_S = 1.0e-3

capacities = st.floats(min_value=0.0, max_value=1.0e6, allow_nan=False)
fractions = st.floats(min_value=-1.0, max_value=1.0, allow_nan=False)
masses = st.floats(min_value=100.0, max_value=1.0e5, allow_nan=False)
# speeds inside the standstill band |v| < v_eps (both signs, and exact zero)
band_speeds = st.one_of(st.just(0.0), st.floats(min_value=-0.999 * V_EPS, max_value=0.999 * V_EPS, allow_nan=False))


# ------------------------------------------------------------------------------------------ stick / slip
@settings(max_examples=300, deadline=None)
@given(v=band_speeds, cap=capacities, frac=fractions, m_eq=masses)
def test_held_at_exactly_zero_when_net_force_within_capacity(v, cap, frac, m_eq) -> None:
    """common.md 3.3: |v| < v_eps and |F_net| <= F_hold_cap -> v = 0 exactly, a = 0, reaction = -F_net.

    Exact equality (no tolerance): the rule assigns 0.0, it does not integrate towards it, so any
    creep (e.g. 1e-17 m/s) would be a bug that accumulates into position drift.
    """
    net = frac * cap  # |frac| <= 1, so |net| <= cap holds in floating point too
    v_new, accel, held, reaction = stick_slip_step(v, net, cap, m_eq, DT_S, V_EPS)
    assert held
    assert v_new == 0.0 and accel == 0.0
    assert reaction == -net


@settings(max_examples=300, deadline=None)
@given(cap=capacities, excess=st.floats(min_value=1e-3, max_value=1e6, allow_nan=False),
       sign=st.sampled_from([1.0, -1.0]), m_eq=masses)
def test_breakaway_acceleration_is_net_minus_capacity_over_mass(cap, excess, sign, m_eq) -> None:
    """common.md 3.3 breakaway from rest: dv/dt = (F - sign(F)*cap)/(delta*m), moving in the sense of F.

    Tolerance: rounding only. The kernel forms (cap + excess) - cap, which loses up to a few ulps of
    (cap + excess) when excess << cap, hence abs 1e-12*(cap + excess)/m, else 1e-9 relative.
    """
    net = sign * (cap + excess)
    v_new, accel, held, reaction = stick_slip_step(0.0, net, cap, m_eq, DT_S, V_EPS)
    assert not held
    expected = sign * excess / m_eq
    assert accel == pytest.approx(expected, rel=1e-9, abs=1e-12 * (cap + excess) / m_eq)
    assert v_new == pytest.approx(expected * DT_S, rel=1e-9, abs=1e-12 * (cap + excess) / m_eq * DT_S)
    assert reaction == -sign * cap


def test_breakaway_numbers_by_hand() -> None:
    """Hand-checkable case: F = 1500 N, cap = 1000 N, delta*m = 1000 kg -> a = 0.5 m/s^2, v(dt) = 5e-4 m/s."""
    v_new, accel, held, reaction = stick_slip_step(0.0, 1500.0, 1000.0, 1000.0, DT_S, V_EPS)
    assert (held, accel, reaction) == (False, 0.5, -1000.0)
    assert v_new == pytest.approx(5.0e-4, rel=1e-15)


@pytest.mark.parametrize("v0", [0.01, -0.01, 0.09, -0.099])
def test_stops_at_exactly_zero_when_braking_through_zero(v0) -> None:
    """common.md 3.3 / plant docstring: a speed that would cross zero within a step stops at exactly zero.

    Brake capacity 1e5 N on 1000 kg gives a = 100 m/s^2 (dv = 0.1 m/s per 1 ms step), so every v0 here
    (|v0| < 0.1 m/s) would overshoot zero in one step;
    the rule must return 0.0 (not a small negative number) and report a = -v0/dt.
    """
    v_new, accel, held, reaction = stick_slip_step(v0, 0.0, 1.0e5, 1000.0, DT_S, V_EPS)
    assert v_new == 0.0
    assert accel == pytest.approx(-v0 / DT_S, rel=1e-15)
    assert not held
    assert reaction == -math.copysign(1.0e5, v0)
    # next step: at rest with nothing pushing -> held, stays exactly zero
    v2, a2, held2, _ = stick_slip_step(v_new, 0.0, 1.0e5, 1000.0, DT_S, V_EPS)
    assert (v2, a2, held2) == (0.0, 0.0, True)


def test_repeated_braking_steps_reach_zero_without_chatter() -> None:
    """Integrating a braked vehicle from 1 m/s: speed decreases monotonically, stops at 0.0, stays 0.0.

    Closed form: constant deceleration cap/m = 2 m/s^2 -> stop after 0.5 s = 500 steps (+-1 step).
    """
    v, steps_to_stop, history = 1.0, None, []
    for k in range(1000):
        v, _, held, _ = stick_slip_step(v, 0.0, 2000.0, 1000.0, DT_S, V_EPS)
        history.append(v)
        if v == 0.0 and steps_to_stop is None:
            steps_to_stop = k + 1
    assert all(b <= a for a, b in zip(history, history[1:]))
    assert min(history) == 0.0
    assert abs(steps_to_stop - 500) <= 1
    assert all(x == 0.0 for x in history[steps_to_stop:])


@settings(max_examples=200, deadline=None)
@given(v=st.floats(min_value=V_EPS, max_value=60.0), sign=st.sampled_from([1.0, -1.0]),
       cap=st.floats(min_value=0.0, max_value=1e6), m_eq=masses)
def test_holds_never_add_kinetic_energy(v, sign, cap, m_eq) -> None:
    """conventions.md property: a brake / rolling resistance never creates energy.

    With no driving force, one step may only reduce |v| (to exactly 0 at worst), never reverse it.
    """
    v0 = sign * v
    v_new, _, _, reaction = stick_slip_step(v0, 0.0, cap, m_eq, DT_S, V_EPS)
    assert abs(v_new) <= abs(v0)
    assert v_new * v0 >= 0.0
    assert reaction * v0 <= 0.0


def test_py_func_matches_compiled() -> None:
    """The numba kernel and its uncompiled ``.py_func`` implement the same rule (bit-identical here)."""
    for args in [(0.0, 10.0, 20.0, 1000.0), (0.0, 30.0, 20.0, 1000.0), (2.0, -50.0, 20.0, 1500.0), (0.005, 0.0, 1e5, 800.0)]:
        a = stick_slip_step(args[0], args[1], args[2], args[3], DT_S, V_EPS)
        b = stick_slip_step.py_func(args[0], args[1], args[2], args[3], DT_S, V_EPS)
        assert tuple(a) == tuple(b)


# ------------------------------------------------------------------------------------------ delta, forces
def test_rotating_mass_factor_ev_matches_physical_formula() -> None:
    """common.md 4: delta = 1 + sum(J_w)/(m r^2) + J_m i^2 eta/(m r^2).

    Compact EV values (compact_ev.toml): m 1500 kg, r 0.30 m, sum J_w 3.6, J_m 0.05 kg m^2, i 8, eta 0.92:
    delta = 1 + (3.6 + 0.05*64*0.92)/(1500*0.09) = 1.04847. Tolerance: rounding only (1e-14).
    """
    delta = equivalent_mass_kg(1500.0, 3.6, 0.30, 0.05, 8.0, 0.92) / 1500.0
    expected = 1.0 + (3.6 + 0.05 * 8.0**2 * 0.92) / (1500.0 * 0.3**2)
    assert delta == pytest.approx(expected, rel=1e-14)
    assert delta == pytest.approx(1.048474, abs=1e-6)


def test_rotating_mass_factor_truck_crawler_locked() -> None:
    """common.md 4 with the engine included after lock-up (hill_start_amt.md 5.2), 30 t truck in crawler:
    J_line = J_in + J_e = 3.3 kg m^2, i = 12.99*5.73, eta 0.88, sum J_w 220, r 0.53.
    delta = 1 + (220 + 3.3*74.43^2*0.88)/(30000*0.53^2); the crawler makes delta large (common.md 4 note).
    """
    i = 12.99 * 5.73
    delta = equivalent_mass_kg(30000.0, 220.0, 0.53, 3.3, i, 0.88) / 30000.0
    expected = 1.0 + (220.0 + 3.3 * i**2 * 0.88) / (30000.0 * 0.53**2)
    assert delta == pytest.approx(expected, rel=1e-14)
    assert 2.9 < delta < 3.0  # 2.935; the empirical 1 + 0.04 + 0.04 i_g^2 form would give 7.8


@pytest.mark.parametrize("u_kph", [10.0, 50.0, 100.0, 130.0])
@pytest.mark.parametrize("drag_area_m2", [0.66, 6.0])
def test_aero_drag_matches_21_15_form(u_kph, drag_area_m2) -> None:
    """common.md 3.1 / hill_start_ehb criterion 10: C_D*A*u^2/21.15 (u in km/h) equals 0.5*rho*C_D*A*v^2.

    With rho = 1.2258 the constant is 21.1454, so the two agree to 0.02 %; the criterion's 0.1 % bound
    leaves room for the rounding of 21.15 only. Negative control: plugging m/s into the 21.15 form is off
    by 3.6^2 = 12.96.
    """
    v = u_kph / 3.6
    si = aero_drag_n(drag_area_m2, v)
    assert si == pytest.approx(drag_area_m2 * u_kph**2 / 21.15, rel=1e-3)
    assert si == pytest.approx(0.5 * 1.2258 * drag_area_m2 * v**2, rel=1e-14)
    wrong = drag_area_m2 * v**2 / 21.15
    assert si / wrong == pytest.approx(12.96, rel=1e-3)


def test_aero_drag_is_odd_in_speed() -> None:
    """F_w = 0.5 rho CdA v|v| opposes the motion in both directions (still air)."""
    assert aero_drag_n(0.66, -20.0) == -aero_drag_n(0.66, 20.0) < 0.0
    assert aero_drag_n(0.66, 0.0) == 0.0
    assert RHO_AIR_KGPM3 == 1.2258


def test_grade_and_rolling_forces() -> None:
    """common.md 3.2/3.3: F_i = m g sin(alpha) (exact sine, not tan), F_f = m g f cos(alpha).

    Hand numbers for the empty truck on 11 deg: 13000*9.81*sin(11 deg) = 24333.9 N; with f = 0.015
    F_f = 1877.8 N. Tolerance 0.1 N on hand-rounded values; the sine/tangent difference is 455 N.
    """
    a = math.radians(11.0)
    assert grade_resistance_n(13000.0, a) == pytest.approx(24333.9, abs=0.1)
    assert abs(grade_resistance_n(13000.0, a) - 13000.0 * G_MPS2 * math.tan(a)) > 400.0
    assert rolling_resistance_capacity_n(13000.0, a, 0.015) == pytest.approx(1877.8, abs=0.1)
    assert grade_resistance_n(13000.0, -a) == -grade_resistance_n(13000.0, a)
