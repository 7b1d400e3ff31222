"""Pedal -> booster -> master cylinder -> proportioning -> ESP unit, against hand calculations and the spec's table.

References: booster run-out F_runout/(k_boost*i_pedal) = 6500/(7*3.8) = 244.4 N and the unassisted slope above
it (brake_assist.md 4.1, by hand); pedal-to-master gain 0.597 bar/N (brake_assist.md 4.1, printed there);
rear proportioning 35 + 0.35*(p - 35) bar (spec 4.2, by hand); the valve/pump table of brake_assist.md 2
written out here literally; pump build at G_pump = 300 bar/s up to p_lim = 200 bar (spec 2, 6).
"""
from __future__ import annotations

import numpy as np
import pytest

import vehicle_assist as va
from vehicle_assist.plant.brakes import esp_unit as U
from vehicle_assist.plant.brakes.booster import booster_target_n, runout_pedal_force_n
from vehicle_assist.plant.brakes.master_cylinder import proportioned_pa


def test_booster_runout_point_and_slopes() -> None:
    assert runout_pedal_force_n(3.8, 7.0, 6500.0) == pytest.approx(244.36, abs=0.01)
    assert booster_target_n(100.0, 3.8, 7.0, 6500.0) == pytest.approx(2660.0)
    # above run-out only the driver's own force adds: 6500 + (300*3.8 - 6500/7) = 6711.43 N
    assert booster_target_n(300.0, 3.8, 7.0, 6500.0) == pytest.approx(6711.43, abs=0.01)
    lo = booster_target_n(240.0, 3.8, 7.0, 6500.0) - booster_target_n(230.0, 3.8, 7.0, 6500.0)
    hi = booster_target_n(260.0, 3.8, 7.0, 6500.0) - booster_target_n(250.0, 3.8, 7.0, 6500.0)
    assert lo == pytest.approx(7.0 * 3.8 * 10) and hi == pytest.approx(3.8 * 10)


def test_rear_proportioning_by_hand() -> None:
    assert proportioned_pa(30e5, 35e5, 0.35) == 30e5
    assert proportioned_pa(60e5, 35e5, 0.35) == pytest.approx(43.75e5)


def test_master_pressure_from_pedal_force_in_the_car() -> None:
    """HBA off, 100 N held: p_mc = 100 N * 0.597 bar/N = 59.7 bar (brake_assist.md 4.1), rear wheel 43.75 bar."""
    tr = va.simulate(va.load_scenario("hba_off_110kph_dry", ["run.duration_s=1.0"])).trace
    k = np.searchsorted(tr["time_s"], 0.8)
    assert tr["master_pressure_pa"][k] / 1e5 == pytest.approx(59.7, abs=0.05)
    assert tr["wheel_pressure_rl_pa"][k] / 1e5 == pytest.approx(35 + 0.35 * (59.7 - 35), abs=0.1)
    assert tr["wheel_pressure_fl_pa"][k] / 1e5 == pytest.approx(59.7, abs=0.1)


SPEC_TABLE = {  # brake_assist.md 2: mode -> (USV closed, HSV open, EV open (0.5 pulsed), AV open, pump on)
    "N": (0, 0, 1, 0, 0), "B": (1, 1, 1, 0, 1), "HI": (1, 0, 0, 0, 0), "H": (0, 0, 0, 0, 0),
    "D": (0, 0, 0, 1, 1), "BP": (1, 1, 0.5, 0, 1), "T": (1, 0, 0, 1, 1),
}


def test_valve_table_is_the_spec_table() -> None:
    for name, row in SPEC_TABLE.items():
        assert tuple(U.VALVE_TABLE[U.MODES.index(name)]) == row, name


def test_pump_build_rate_and_relief() -> None:
    """Mode B: the wheel pressure rises at G_pump = 300 bar/s and stops at the relief p_lim = 200 bar."""
    p, dt = 60e5, 1e-4
    history = []
    for _ in range(6000):
        rate = U.source_rate_pa_per_s(U.SOURCE_RETURN_PUMP, p, 300e5, 200e5, 0.0, 1.0, True)
        p = U.wheel_pressure_step(U.B, p, 60e5, dt, 0.015, rate, 200e5, 0.3, 0.03, 1e5, 200e5, 300e5)
        history.append(p)
    assert history[999] == pytest.approx(60e5 + 300e5 * 0.1, rel=1e-9)
    assert max(history) == pytest.approx(200e5)


def test_dead_pump_still_passes_the_driver_pressure() -> None:
    """Mode B with the pump failed: the USV check valve lets the driver's pressure reach the wheel (issue #9)."""
    p = 0.0
    for _ in range(2000):
        rate = U.source_rate_pa_per_s(U.SOURCE_RETURN_PUMP, p, 300e5, 200e5, 0.0, 1.0, False)
        p = U.wheel_pressure_step(U.B, p, 60e5, 1e-4, 0.015, rate, 200e5, 0.3, 0.03, 1e5, 200e5, 300e5)
    assert p == pytest.approx(60e5, rel=1e-3)


def test_accumulator_source_is_replaceable() -> None:
    """The EHB accumulator source of paper 004 behind the same call: rate (p_acc - p)/tau."""
    assert U.source_rate_pa_per_s(U.SOURCE_ACCUMULATOR, 20e5, 0.0, 0.0, 120e5, 0.05, True) == pytest.approx(100e5 / 0.05)


def test_dump_and_rampout() -> None:
    p = 100e5
    for _ in range(300):  # 30 ms = tau_dump: p - p_LPA falls to 1/e (explicit Euler at 0.1 ms: within 0.2 %)
        p = U.wheel_pressure_step(U.D, p, 60e5, 1e-4, 0.015, 0.0, 200e5, 0.3, 0.03, 1e5, 200e5, 300e5)
    assert (p - 1e5) / 99e5 == pytest.approx(np.exp(-1.0), rel=2e-3)
    p = 100e5
    for _ in range(1000):  # T: 200 bar/s down toward 60 bar, never below it
        p = U.wheel_pressure_step(U.T, p, 60e5, 1e-4, 0.015, 0.0, 200e5, 0.3, 0.03, 1e5, 200e5, 300e5)
    assert p == pytest.approx(80e5, rel=1e-6)
    for _ in range(5000):
        p = U.wheel_pressure_step(U.T, p, 60e5, 1e-4, 0.015, 0.0, 200e5, 0.3, 0.03, 1e5, 200e5, 300e5)
    assert 60e5 <= p < 61e5


def test_logged_valve_states_follow_the_table_per_circuit() -> None:
    """Criterion 4: in the paper's run every sample's switching and high-pressure valve states of a circuit are the
    table's (a circuit valve is closed/open if either wheel's mode asks it; X-split: FL+RR, FR+RL)."""
    tr = va.simulate(va.load_scenario("hba_paper_110kph_dry")).trace
    modes = {w: tr[f"wheel_mode_{w}_index"].astype(int) for w in ("fl", "fr", "rl", "rr")}
    for c, (a, b) in (("1", ("fl", "rr")), ("2", ("fr", "rl"))):
        usv = np.maximum(U.VALVE_TABLE[modes[a], 0], U.VALVE_TABLE[modes[b], 0])
        hsv = np.maximum(U.VALVE_TABLE[modes[a], 1], U.VALVE_TABLE[modes[b], 1])
        np.testing.assert_array_equal(tr[f"usv_closed_c{c}_flag"], usv)
        np.testing.assert_array_equal(tr[f"hsv_open_c{c}_flag"], hsv)
    assert {"B", "HI", "D", "BP", "T", "N"} <= {U.MODES[m] for m in np.concatenate(list(modes.values()))}
