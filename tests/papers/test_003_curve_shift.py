"""Paper 003 reproduction (curve-aware AMT shifting; curve_shift.md 7 and 8, issue #11).

Every shipped curve scenario's checks hold (each cites its clause); the pairwise claims of the issue are checked
here across strategy-on / strategy-off twins: gear at curve entry lower or equal with the strategy and strictly
lower at 80 km/h (criterion 6), the lift-off upshift only without the strategy (criterion 2), the proving-ground
4->3 earlier than the normal schedule's (P13: ~27 instead of ~24 km/h). Negative control: the normal schedule run
against the strategy's criterion 1 must fail it. Known failures (the paper's proving-ground numbers the model does not
reach, with the reason in each check's why) must keep failing, so that a silent change is noticed.
"""
from __future__ import annotations

import pytest

import vehicle_assist as va
from vehicle_assist.procedures.reproduce import REPRODUCTIONS

CASES = (80, 70, 65, 48)
KNOWN_FAIL = {("curve_pg", "downshift_4_3_speed_mps"), ("curve_pg", "downshift_3_2_speed_mps"),
              ("curve_pg_baseline", "downshift_3_2_speed_mps")}


@pytest.fixture(scope="module")
def results():
    names = [f"curve_{k}{v}" for v in CASES for k in ("s", "b")] + [
        "curve_pg", "curve_pg_baseline", "curve_pg_kj0125", "curve_s80_map_missing", "curve_s80_map_dropout",
        "curve_s80_map_late", "curve_s80_map_radius_wrong", "curve_s80_map_radius_small"]
    return {n: va.simulate(va.load_scenario(n)) for n in names}


def test_every_check_holds(results):
    bad = [(n, c.metric, c.value, c.bound) for n, r in results.items() for c in r.checks
           if not c.ok and (n, c.metric) not in KNOWN_FAIL]
    assert not bad
    for n, metric in KNOWN_FAIL:
        c = [c for c in results[n].checks if c.metric == metric][0]
        assert not c.ok, f"{n}: {metric} now passes; update KNOWN_FAIL and the report"
        assert c.why.startswith("KNOWN FAIL")


def test_entry_gear_lower_or_equal_and_strictly_lower_at_80(results):
    for v in CASES:
        s = results[f"curve_s{v}"].metrics["gear_at_curve_entry_index"]
        b = results[f"curve_b{v}"].metrics["gear_at_curve_entry_index"]
        assert s <= b, v  # criterion 6
    assert results["curve_s80"].metrics["gear_at_curve_entry_index"] < results["curve_b80"].metrics["gear_at_curve_entry_index"]


def test_lift_off_upshift_only_without_strategy(results):
    for v in (65, 48):
        assert results[f"curve_b{v}"].metrics["upshifts_after_lift_off_count"] >= 1  # criterion 2
        assert results[f"curve_s{v}"].metrics["upshifts_signal_to_exit_count"] == 0  # criterion 1
    assert results["curve_pg_baseline"].metrics["upshifts_after_lift_off_count"] >= 1  # P13 4->5
    assert results["curve_pg"].metrics["upshifts_signal_to_exit_count"] == 0


def test_kj_classes_p12(results):
    m = {v: results[f"curve_s{v}"].metrics for v in CASES}
    assert m[80]["kj_advance_max_frac"] == 1.0 and m[80]["kj_used_max_ratio"] > 0  # kj = kj_max
    assert 0.0 < m[65]["kj_advance_max_frac"] < 1.0  # between
    assert m[48]["kj_used_max_ratio"] == 0.0  # zero
    assert results["curve_s70"].metrics["gear_drop_max_count"] >= 2  # skip shift, criterion 7


def test_proving_ground_downshift_earlier(results):
    """P13 with kj computed from the a_y of a 53 km/h passage (the paper's words): earlier than the normal schedule,
    but at the command (kj = kj_max on the R = 10 m hairpin), not at the paper's 27 km/h (a KNOWN FAIL). With the
    kj = 0.125 the paper's numbers imply (spec criterion 11) the closed loop gives 26.8 +/- 1 km/h (eq. 15)."""
    s = results["curve_pg"].metrics["downshift_4_3_speed_mps"] * 3.6
    b = results["curve_pg_baseline"].metrics["downshift_4_3_speed_mps"] * 3.6
    assert s > b and b == pytest.approx(24.0, abs=1.0)  # P13: normal schedule about 24 km/h
    assert results["curve_pg"].metrics["kj_advance_max_frac"] == 1.0  # a_y_pred = 21.7 m/s^2 > a_ys
    assert s == pytest.approx(53.0, abs=0.5)  # the downshift comes at the command, not at 27 km/h
    fixed = results["curve_pg_kj0125"].metrics["downshift_4_3_speed_mps"] * 3.6
    assert fixed == pytest.approx(23.8 * 1.125, abs=1.0)  # criterion 11


def test_downshifts_earlier_with_strategy(results):
    """The strategy's first downshift comes at a higher speed than the normal schedule's (P1 'late downshift')."""
    for v in (80, 70, 65):
        s = results[f"curve_s{v}"].metrics["downshift_4_3_speed_mps"]
        b = results[f"curve_b{v}"].metrics["downshift_4_3_speed_mps"]
        assert s > b, v


def test_negative_control_normal_schedule_fails_criterion_1():
    sc = va.load_scenario("curve_s48", ["vehicle.curve_shift.enabled_flag=0"])
    r = va.simulate(sc)
    failed = [c.metric for c in r.checks if not c.ok]
    assert "upshifts_signal_to_exit_count" in failed


def test_reproduction_entry():
    rep = [r for r in REPRODUCTIONS if r.paper == "003"]
    assert len(rep) == 1 and "curve_s80" in rep[0].scenarios and "curve_pg" in rep[0].scenarios


def test_figures_are_written(tmp_path, results):
    """The paper-style figure, the overlay with the normal schedule and the road with shift points render."""
    from vehicle_assist.procedures import curve_shift_study as study
    from vehicle_assist.report.plots import FIGURES

    p1 = FIGURES["curve_shift"](results["curve_s80"].trace, tmp_path / "a.png", "s80")
    p2 = study._overlay_png(results["curve_s80"].trace, results["curve_b80"].trace, tmp_path / "b.png", "s80 vs b80")
    p3 = study._road_png(results["curve_pg"].scenario, {"on": results["curve_pg"].trace}, tmp_path / "c.png", "pg")
    for p in (p1, p2, p3):
        assert p.stat().st_size > 10_000


@pytest.mark.parametrize("radius", [30.0, 150.0, 400.0])
def test_kj_map_cells_drive_their_own_road(radius):
    """The kj map (issue #11 'a map over curve radius x entry speed') varies the road itself: in every cell the
    plant's curvature and the map preview both give the cell's radius. Reference: the radius asked for, and
    a_y = u^2/R (steady turning) from the plant's own speed and yaw in the middle of the arc."""
    import numpy as np

    from vehicle_assist.procedures.curve_shift_study import road_for_radius

    sc = va.load_scenario("curve_envelope_base", [road_for_radius(radius), "run.initial_speed_kph=60",
                                                  "vehicle.curve_shift.command_needs_deceleration_flag=0"])
    tr = va.simulate(sc).trace
    valid = tr["preview_valid_flag"] > 0.5
    assert np.allclose(tr["preview_radius_m"][valid], radius)
    mid = np.abs(tr["position_m"] - 450.0) < 5.0
    assert np.allclose(1.0 / tr["curvature_per_m"][mid], radius)
    u = tr["speed_mps"][mid]
    assert np.median(np.abs(tr["lateral_accel_mps2"][mid])) == pytest.approx(np.median(u * u / radius), rel=0.05)


def test_known_fail_reasons_match_the_traces(results):
    """The KNOWN FAIL reasons must stay true (independent review: the baseline's reason said the 3->2 line was met in
    the hairpin at the curve throttle; the trace shows a kickdown at curve exit). Reference: the traces themselves
    and the spec's schedule table (3->2 at theta 0 / 0.2: 14.7 / 22.0 km/h; at 0.4 / 0.6: 34.5 / 47.0 km/h)."""
    import numpy as np

    tr = results["curve_pg_baseline"].trace
    g = tr["gear_command_index"]
    i = np.nonzero((g[:-1] == 3) & (g[1:] == 2))[0][0] + 1
    assert tr["driver_phase_index"][i] == 3.0  # EXIT: the driver's exit throttle, not the curve throttle
    assert tr["accelerator_frac"][i] >= 0.45 and tr["normal_downshift_speed_mps"][i] * 3.6 > 35.0
    inside = tr["driver_phase_index"] == 2.0
    assert np.all(g[inside] == 3)  # no 3->2 inside the hairpin
    assert np.all(tr["speed_mps"][inside] > tr["normal_downshift_speed_mps"][inside])  # line not met there
    assert np.max(tr["accelerator_frac"][inside]) < 0.2
    # curve_pg: the 4->3 at the curve command with kj at its maximum (frac = 1)
    on = results["curve_pg"].trace
    k = np.nonzero(np.diff(on["gear_command_index"]) != 0)[0][0] + 1
    assert on["curve_mode_flag"][k] == 1.0 and on["curve_mode_flag"][k - 2] == 0.0
    assert on["kj_frac"][k] == 1.0
