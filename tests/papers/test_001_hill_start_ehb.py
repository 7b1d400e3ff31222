"""Paper 001 (Tan, Huang, Yu, Shu: hill-start assist of an electric car with EHB): reproduction of its
simulation result (5 deg, Fig. 8: no rollback, jerk within +-0.1 m/s^3) and of the criteria of
hill_start_ehb.md section 5. Vehicle data of the paper (its Table 1) are lost: the numbers compared here
are the spec's derived values (hold pressure 8.6 bar at 5 deg) and the paper's bounds.
"""
from __future__ import annotations

import math

import pytest

import vehicle_assist as va
from tests.support import reproduction, simulate_all, unexpected_checks

PAPER_001 = reproduction("001")


@pytest.fixture(scope="module")
def results():
    return simulate_all(PAPER_001.scenarios)


@pytest.mark.parametrize("name", PAPER_001.scenarios)
def test_every_check_of_every_paper_001_scenario_holds(results, name):
    """hill_start_ehb.md 5.1-5.9: every check comes out as the scenario expects (negative controls fail)."""
    bad = unexpected_checks(results[name])
    assert not bad, bad


def test_paper_case_no_rollback_and_jerk_within_bound(results):
    """Paper 001 P8 (Fig. 8c, 8d): on 5 deg the speed is never negative and the filtered jerk stays within
    +-0.1 m/s^3 (2nd-order Butterworth 5 Hz, common.md 10). Asserted directly, independent of the file."""
    m = results["hsa_ev_5deg_paper"].metrics
    assert m["rollback_speed_mps"] <= 1e-3
    assert m["jerk_filtered_max_mps3"] <= 0.1 and m["jerk_filtered_min_mps3"] >= -0.1


PAPER_CAR = "vehicle.hill_start_assist.calibration_mass_kg=1500"  # the spec's car (hill_start_ehb.md 3: m = 1500 kg)


def hold_pressure_bar(name: str) -> float:
    """Brake pressure 0.05 s before the accelerator is pressed (HOLD, settled), with the assist calibrated for the
    spec's 1500 kg car."""
    r = va.simulate(va.load_scenario(name, [PAPER_CAR]))
    follow = next(e.time_s for e in r.events if e.machine == "hill_start_ehb" and e.to_mode == "FOLLOW")
    k = int(round((follow - 0.05) / 0.01))
    return r.trace["brake_pressure_pa"][k] / 1e5


def test_hold_pressure_equals_the_spec_worked_number():
    """hill_start_ehb.md 3 worked numbers (reference: the spec's own arithmetic, not the controller's code):
    F_i = 1500*9.81*sin 5 deg = 1282.5 N, brake force per bar 179 N/bar (K_b_tot/r = 53.8 N*m/bar / 0.30 m),
    p_hold = 1.2*1282.5/179.3 = 8.6 bar. The hold adds the design margin F_margin = 0.5*G*f*cos(gamma) = 110 N
    (spec 2.2; 0.61 bar), so the held pressure is 8.6 bar + 0.61 bar, to the 0.05 bar the spec's rounding leaves."""
    f_i = 1500 * 9.81 * math.sin(math.radians(5))
    assert f_i == pytest.approx(1282.5, abs=0.1)
    p_hold_bar = 1.2 * f_i / 179.3
    assert p_hold_bar == pytest.approx(8.6, abs=0.05)
    margin_bar = 0.5 * 1500 * 9.81 * 0.015 * math.cos(math.radians(5)) / 179.3
    assert hold_pressure_bar("hsa_ev_5deg_paper") == pytest.approx(p_hold_bar + margin_bar, abs=0.05)


def test_ten_degrees_needs_about_17_bar():
    """hill_start_ehb.md 4 S3: hold pressure about 17 bar on 10 deg for the spec's car (1.2*1500*9.81*sin 10 deg/179.3
    = 17.1 bar, + 0.61 bar F_margin)."""
    assert hold_pressure_bar("hsa_ev_10deg") == pytest.approx(17.1 + 0.6, abs=0.3)


def test_shipped_hold_covers_the_heaviest_car(results):
    """Issue #7 envelope (1300-2100 kg): the shipped assist does not know the load, so its hold must carry the gross
    mass: brake capacity >= 2100*9.81*sin(gamma) at the settled hold, checked against the plant's true grade force
    of the 1500 kg car scaled to 2100 kg (statics reference, common.md 3.3)."""
    for name in ("hsa_ev_5deg_paper", "hsa_ev_10deg"):
        assert results[name].metrics["hold_force_ratio"] >= 2100 / 1500


def test_assist_removes_the_rollback_of_the_baseline(results):
    """The same car and slope without the assist rolls back (0.23 m in ev_5deg_hold_and_pull_away, negative
    control); with it the paper case does not roll back at all."""
    assert results["ev_5deg_hold_and_pull_away"].metrics["rollback_distance_m"] > 0.05
    assert results["hsa_ev_5deg_paper"].metrics["rollback_distance_m"] <= 1e-3


def test_flat_road_pressure_follows_the_driver(results):
    """hill_start_ehb.md 5.7: on a level road the assist never holds, and the pressure is below 0.1 bar from
    0.5 s after the driver's brake release (1.3 s) on."""
    r = results["hsa_ev_flat"]
    tr = r.trace
    assert not any(e.to_mode in ("HOLD", "FOLLOW") for e in r.events if e.machine == "hill_start_ehb")
    assert (tr["brake_pressure_pa"][tr["time_s"] >= 1.8] < 0.1e5).all()


def test_paper_jerk_criterion_at_twice_the_pedal_rate(results):
    """Paper 001 P8 (Fig. 8d, +-0.1 m/s^3) with the accelerator pressed at 0.045 /s, twice the spec's S1 ramp
    (issue #7: the bound must come from the assist, not from a slow driver), on 5 and 10 deg."""
    for name in ("hsa_ev_5deg_paper_2x_ramp", "hsa_ev_10deg_2x_ramp", "hsa_ev_10deg"):
        m = results[name].metrics
        assert m["jerk_filtered_max_mps3"] <= 0.1 and m["jerk_filtered_min_mps3"] >= -0.1, name
        assert m["rollback_speed_mps"] <= 1e-3


def test_calibration_map_speed_never_below_minus_1_mm_per_s(tmp_path):
    """Paper 001 P8 (Fig. 8c) / hill_start_ehb.md 5.1 over the map of slope 0-20 deg x mass 1300-2100 kg x accelerator
    rate 0.01-0.1 /s (220 variants, one batch): v >= -1 mm/s at every variant the motor can start (motor force >
    grade + rolling resistance, computed from the vehicle data in the procedure), rollback <= 1 cm where it cannot,
    and the assist's jerk within 0.1 m/s^3 (P8) everywhere; the heat-map figure is written."""
    from vehicle_assist.procedures.ehb_sweep import run_ehb_sweep

    figure, table, summary = run_ehb_sweep(tmp_path)
    assert summary["variants"] == 220
    assert summary["speed_violations_startable"] == 0, summary
    assert summary["unstartable_max_rollback_m"] <= 0.01
    assert summary["max_jerk_mps3"] <= 0.1
    assert figure.stat().st_size > 10_000 and table.exists()
