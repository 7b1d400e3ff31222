"""Paper 001 (Tan, Huang, Yu, Shu: hill-start assist of an electric car with EHB): reproduction of its
simulation result (5 deg, Fig. 8: no rollback, jerk within +-0.1 m/s^3) and of the criteria of
hill_start_ehb.md section 5. Vehicle data of the paper (its Table 1) are lost: the numbers compared here
are the spec's derived values (hold pressure 8.6 bar at 5 deg) and the paper's bounds.
"""
from __future__ import annotations

import math

import pytest

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


def test_hold_pressure_equals_the_closed_form(results):
    """hill_start_ehb.md 3 (derived): p_hold = k_s*m*g*sin(5 deg)*r/K_b_tot = 1.2*1282.5 N/(179.3 N/bar) = 8.58 bar;
    the EHB holds it before the accelerator is pressed (within the 0.5 % the EHB's first-order tracking leaves)."""
    r = results["hsa_ev_5deg_paper"]
    tr = r.trace
    follow = next(e.time_s for e in r.events if e.machine == "hill_start_ehb" and e.to_mode == "FOLLOW")
    k = int(round((follow - 0.05) / 0.01))
    expected_pa = 1.2 * 1500 * 9.81 * math.sin(math.radians(5)) * 0.30 / 53.8e-5
    assert tr["brake_pressure_pa"][k] == pytest.approx(expected_pa, rel=0.005)


def test_ten_degrees_needs_about_17_bar(results):
    """hill_start_ehb.md 4 S3: hold pressure about 17 bar on 10 deg (1.2*1500*9.81*sin 10 deg*0.30/53.8 = 17.1 bar)."""
    tr = results["hsa_ev_10deg"].trace
    assert max(tr["hsa_pressure_command_pa"]) / 1e5 == pytest.approx(17.1, abs=0.2)


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


def test_calibration_map_holds_everywhere(tmp_path):
    """Issue 4: the sweep of slope 0-20 deg x mass 1500-1950 kg x accelerator rate 0.01-0.1 /s (176 variants in
    one batch): the assist never lets the car roll back more than 0.01 m (its rollback correction re-applies
    the brake when the real mass exceeds its calibration), and the heat-map figure is written."""
    from vehicle_assist.procedures.ehb_sweep import run_ehb_sweep

    figure, table, summary = run_ehb_sweep(tmp_path)
    assert summary["variants"] == 176
    assert summary["max_rollback_m"] <= 0.01
    assert figure.stat().st_size > 10_000 and table.exists()
