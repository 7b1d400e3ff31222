"""Spring-chamber (park brake) model of plant/brakes/pneumatic.py against paper 000 Table 1.

References: hill_start_amt.md 3 (circuit), 5.3 (first-order fill fitted to Table 1: tau_fill = 2.55 s,
p_lamp = 4.09 bar), 9 criterion 12 (Table 1 within +-0.1 s), common.md 7.2 (capacity law).
"""
from __future__ import annotations

import math

import pytest

import vehicle_assist as va
from vehicle_assist.plant.brakes.pneumatic import (
    decay,
    hand_valve_control_pressure_pa,
    lamp_time_s,
    park_brake_capacity_n,
    spring_chamber_step,
)

DT_S = 1.0e-3
BAR = 1.0e5
TABLE_1 = {6.5: 2.5, 7.0: 2.3, 7.5: 2.0, 8.0: 1.8}  # paper 000 Table 1: reservoir bar -> release time s


@pytest.fixture(scope="module")
def truck_params() -> dict:
    return va.load_vehicle("heavy_amt_truck_empty").flat()


def simulated_lamp_time_s(reservoir_pa: float, lamp_pa: float, tau_fill_s: float, tau_exh_s: float) -> float:
    """Step spring_chamber_step from an exhausted chamber until p_sp >= p_lamp (lamp goes out)."""
    p, n = 0.0, 0
    fill, exhaust = decay(tau_fill_s, DT_S), decay(tau_exh_s, DT_S)
    while p < lamp_pa:
        p = spring_chamber_step(p, reservoir_pa, fill, exhaust)
        n += 1
        assert n < 100_000
    return n * DT_S


@pytest.mark.parametrize("reservoir_bar", sorted(TABLE_1))
def test_lamp_time_closed_form_equals_stepped_crossing(truck_params, reservoir_bar) -> None:
    """The closed form tau ln(p_s/(p_s - p_lamp)) equals the step-by-step crossing within one step.

    spring_chamber_step is the exact discretisation of the first-order fill, so the first sample above
    p_lamp is the closed-form time rounded up to the 1 ms grid: 0 <= t_sim - t_closed < dt.
    """
    p = truck_params
    p_s = reservoir_bar * BAR
    closed = lamp_time_s(p_s, p["park_brake_lamp_pressure_pa"], p["park_brake_fill_time_constant_s"])
    stepped = simulated_lamp_time_s(p_s, p["park_brake_lamp_pressure_pa"], p["park_brake_fill_time_constant_s"],
                                    p["park_brake_exhaust_time_constant_s"])
    assert 0.0 <= stepped - closed < DT_S + 1e-12


@pytest.mark.parametrize("reservoir_bar", sorted(TABLE_1))
def test_reproduces_paper_table_1(truck_params, reservoir_bar) -> None:
    """hill_start_amt.md criterion 12: with the shipped truck's tau_fill and p_lamp the model reproduces
    paper 000 Table 1 (2.5/2.3/2.0/1.8 s at 6.5/7.0/7.5/8.0 bar) within +-0.1 s (the paper prints one
    decimal, and the 2-parameter fit leaves residuals up to 0.06 s: 2.53/2.24/2.01/1.83 s).
    """
    p = truck_params
    assert p["park_brake_fill_time_constant_s"] == 2.55
    assert p["park_brake_lamp_pressure_pa"] == pytest.approx(4.09 * BAR)
    t = lamp_time_s(reservoir_bar * BAR, p["park_brake_lamp_pressure_pa"], p["park_brake_fill_time_constant_s"])
    assert t == pytest.approx(TABLE_1[reservoir_bar], abs=0.1)


def test_table_1_trend_and_spec_values(truck_params) -> None:
    """hill_start_amt.md 5.3 model column: 2.53/2.24/2.01/1.83 s (to the printed 0.01 s), falling with p_s."""
    p = truck_params
    times = [lamp_time_s(b * BAR, p["park_brake_lamp_pressure_pa"], p["park_brake_fill_time_constant_s"]) for b in sorted(TABLE_1)]
    assert [round(t, 2) for t in times] == [2.53, 2.24, 2.01, 1.83]
    assert all(b < a for a, b in zip(times, times[1:]))


def test_chamber_exhausts_with_exhaust_time_constant() -> None:
    """hill_start_amt.md 3: exhausting d p/dt = -p/tau_exh; one exact step from 8 bar with tau 0.5 s
    gives 8 e^{-dt/0.5} bar (rounding tolerance); filling uses tau_fill, not tau_exh."""
    fill, exhaust = decay(2.55, DT_S), decay(0.5, DT_S)
    assert spring_chamber_step(8 * BAR, 0.0, fill, exhaust) == pytest.approx(8 * BAR * math.exp(-DT_S / 0.5), rel=1e-14)
    assert spring_chamber_step(0.0, 8 * BAR, fill, exhaust) == pytest.approx(8 * BAR * (1 - math.exp(-DT_S / 2.55)), rel=1e-12)


def test_hand_valve_and_capacity_law() -> None:
    """Valve table of hill_start_amt.md 3 (released -> p_s, park -> 0) and common.md 7.2 capacity:
    F_g_max below p_start, 0 above p_full, linear in between (midpoint -> half)."""
    assert hand_valve_control_pressure_pa(1.0, 8 * BAR) == 8 * BAR
    assert hand_valve_control_pressure_pa(0.0, 8 * BAR) == 0.0
    f_max, p0, p1 = 1.0e5, 1.5 * BAR, 4.09 * BAR
    assert park_brake_capacity_n(0.0, f_max, p0, p1) == f_max
    assert park_brake_capacity_n(p0, f_max, p0, p1) == f_max
    assert park_brake_capacity_n(0.5 * (p0 + p1), f_max, p0, p1) == pytest.approx(0.5 * f_max, rel=1e-12)
    assert park_brake_capacity_n(p1, f_max, p0, p1) == 0.0
    assert park_brake_capacity_n(8 * BAR, f_max, p0, p1) == 0.0
