"""Paper 000 (Wang, Zhao, Liu 2009, electro-pneumatic hill-start assist for a heavy AMT truck):
the reproduction of its test results, hill_start_amt.md section 9.

The paper reports no numbers beyond Table 1 and the two engine-speed peaks; its results are
qualitative: no rollback and no stall on 11 deg paved and 14 deg gravel slopes, empty (13 t) and full
(30 t), and a park-brake release that starts after the drive force passed the grade resistance (phase 3
of its Fig. 5). Each shipped scenario carries those criteria as checks; these tests run them all and
compare the assisted starts with the same starts without the assist.
"""
from __future__ import annotations

import math

import pytest

import vehicle_assist as va
from tests.support import reproduction, simulate_all, unexpected_checks
from vehicle_assist.procedures.reproduce import HSA_MATRIX

RPM = math.pi / 30.0
PAPER_000 = reproduction("000")


@pytest.fixture(scope="module")
def results():
    return simulate_all(PAPER_000.scenarios)


@pytest.mark.parametrize("name", PAPER_000.scenarios)
def test_every_check_of_every_paper_000_scenario_holds(results, name):
    """hill_start_amt.md 9.1-9.3, 9.5, 9.6, 9.8, 9.10 and P12: every check comes out as the scenario expects
    (assisted starts pass; the negative controls fail their bounds)."""
    bad = unexpected_checks(results[name])
    assert not bad, bad


@pytest.mark.parametrize("name", HSA_MATRIX)
def test_matrix_no_rollback_no_stall_release_in_phase_3(results, name):
    """The issue's matrix: 11/14 deg x empty/full x 6.5/7.0/7.5/8.0 bar: rollback < 0.01 m, no stall,
    release in phase 3 (paper P6, P14). Asserted directly, independent of the files' checks."""
    m = results[name].metrics
    assert m["rollback_distance_m"] < 0.01
    assert m["engine_stalled_flag"] == 0.0
    assert m["park_release_phase_index"] == 3.0
    assert m["release_margin_s"] > 0.0  # P12: load taken before the park brake is fully released


def test_engine_speed_peaks_of_the_paper_test_points(results):
    """Calibration target, not evidence (hill_start_amt.md 9.8 says so): P13's peaks 1800 rpm full (crawler,
    pedal 0.70) and about 1100 rpm empty (1st, 0.27) are the governed speeds at the pedals chosen to give them;
    the test only guards the calibration (+/- 150 rpm)."""
    full = results["hsa_truck_full_14deg_8p0bar"].metrics["engine_speed_peak_radps"] / RPM
    empty = results["hsa_truck_empty_11deg_8p0bar"].metrics["engine_speed_peak_radps"] / RPM
    assert abs(full - 1800.0) <= 150.0
    assert abs(empty - 1100.0) <= 150.0


def test_assist_removes_the_rollback_of_an_early_release():
    """P6 / 9.10: the same driver (hand valve opened with the service-brake release) rolls back without the
    assist (negative control) and does not with it: the 3/2 valve keeps the park brake applied."""
    sets = ['driver.hand_valve={time_s=[0.0, 1.0], released=[0, 1]}']
    with_assist = va.simulate(va.load_scenario("hsa_truck_full_14deg_8p0bar", sets)).metrics
    without = results_without = va.simulate(va.load_scenario("hsa_truck_full_14deg_no_assist_early_release")).metrics
    assert without["rollback_distance_m"] > 0.05
    assert results_without["park_release_phase_index"] == 1.0
    assert with_assist["rollback_distance_m"] < 0.01
    assert with_assist["park_release_phase_index"] == 3.0


def test_study_reports_9_7_9_10_and_table_1_with_sources():
    """Issue 7: the comparisons of hill_start_amt.md 9.7 (8 empty/full pairs), 9.10 (5 assisted/baseline pairs, the
    spec's S6 among them, and the S6 negative control) and 9.12 (Table 1 through the truck kernel) are in reproduce, each with its clause.
    Table 1 must hold (+/- 0.1 s of the paper's 2.5/2.3/2.0/1.8 s); 9.7 and 9.10 are reported as they come out
    (the note in docs/functions/hill_start_amt.md says why they fail): a FAIL must carry the measured numbers."""
    from vehicle_assist.procedures.hill_start_amt_study import run_study

    _, entries = run_study(None)
    assert len([e for e in entries if "9.7" in e["why"]]) == 8
    assert len([e for e in entries if "9.10" in e["why"]]) == 6  # 5 assisted/baseline pairs and the S6 control
    table = [e for e in entries if "Table 1" in e["why"]]
    assert len(table) == 4 and all(e["pass"] for e in table)
    for e in entries:
        assert "hill_start_amt.md 9." in e["why"] and e["bound"]
        if not e["pass"]:
            assert any(ch.isdigit() for ch in e["why"].split(":")[-1])  # the measured numbers are in the reason


def test_normal_start_never_energises_the_valve(results):
    """P11 / 9.6: with the park brake released at the service-brake release the normal start program runs."""
    r = results["hsa_truck_empty_flat_normal_start"]
    assert r.metrics["valve_32_energized_flag"] == 0.0
    modes = [(e.from_mode, e.to_mode) for e in r.events if e.machine == "hill_start_amt"]
    assert modes == [("STANDBY", "NORMAL_START")]


def test_park_brake_held_until_the_release_command(results):
    """9.4: while the valve is energised the chambers stay below p_start even though the driver released the
    hand valve at 2 s (the assist holds the park brake)."""
    for name in ("hsa_truck_full_14deg_8p0bar", "hsa_truck_empty_11deg_8p0bar"):
        tr = results[name].trace
        held = tr["valve_32_energized_flag"] > 0.5
        assert held.any() and (tr["hand_valve_released_flag"][held] > 0.5).any()
        assert (tr["park_chamber_pressure_pa"][held] < 1.5e5).all()


def test_lockup_rule(results):
    """9.9: once the assist enters LOCKUP (slip <= 100 rpm, moving) the clutch command reaches 1 within
    (1 - x_c)/v_C + 0.05 s (v_C = 1 /s)."""
    for name in ("hsa_truck_full_14deg_8p0bar", "hsa_truck_empty_11deg_8p0bar"):
        r = results[name]
        lock = next(e for e in r.events if e.machine == "hill_start_amt" and e.to_mode == "LOCKUP")
        done = next(e for e in r.events if e.machine == "hill_start_amt" and e.to_mode == "DONE")
        tr = r.trace
        k = int(round(lock.time_s / 0.01))
        assert done.time_s - lock.time_s <= (1.0 - tr["clutch_command_frac"][k]) / 1.0 + 0.05


def test_paper_000_in_reproduce_summary(tmp_path):
    """Issue 3: `vehicle-assist reproduce` includes this paper; summary entries name it by its seed number '000'.

    Runs paper 000's scenarios and its own study (9.7/9.10/Table 1); the envelope study and the falsification
    campaign are verification studies with their own tests (tests/verification) and run in full reproduce."""
    from rich.console import Console

    from vehicle_assist.procedures.run import run_reproductions

    entries = run_reproductions(tmp_path, Console(file=open(tmp_path / "log.txt", "w")), papers=("000",),
                                extras=("hill_start_amt_study",))
    ours = [e for e in entries if e["paper"] == "000"]
    assert len(ours) >= 16 * 6
    scenario_checks = [e for e in ours if e["scenario"] in PAPER_000.scenarios]
    assert all(e["pass"] for e in scenario_checks)
    assert any("9.7" in e["why"] for e in ours) and any("Table 1" in e["why"] for e in ours)
    assert {"paper", "scenario", "criterion", "value", "unit", "bound", "pass"} <= set(ours[0])


def test_assist_refuses_a_grade_beyond_the_engine():
    """30 t on 14 deg in 1st gear needs ~1080 N*m at the clutch, more than 90 % of the engine's 1013 N*m
    (hill_start_amt.md 7.1: 'near the engine limit, which is why the crawler gear is used'): the assist
    stands down with that reason and keeps the park brake applied: no rollback, no stall, v == 0 exactly."""
    r = va.simulate(va.load_scenario("hsa_truck_full_14deg_8p0bar", ['driver.gear_lever={time_s=[0.0], gear=["1"]}']))
    reasons = [e.reason for e in r.events if e.machine == "hill_start_amt" and e.to_mode == "STOOD_DOWN"]
    assert reasons == ["grade_beyond_engine_torque"]
    assert (r.trace["speed_mps"] == 0.0).all()
    assert r.metrics["engine_stalled_flag"] == 0.0
    assert (r.trace["valve_32_energized_flag"][r.trace["time_s"] > 1.1] == 1.0).all()


@pytest.mark.slow
def test_full_reproduce_runs_every_paper_and_study(tmp_path):
    """`make demo` path: every registered paper and study runs and lands in summary.json (slow: minutes)."""
    from rich.console import Console

    from vehicle_assist.procedures.reproduce import REPRODUCTIONS
    from vehicle_assist.procedures.run import run_reproductions

    entries = run_reproductions(tmp_path, Console(file=open(tmp_path / "log.txt", "w")))
    assert {rep.paper for rep in REPRODUCTIONS} <= {e["paper"] for e in entries}
    assert (tmp_path / "summary.json").is_file() and (tmp_path / "index.html").is_file()
