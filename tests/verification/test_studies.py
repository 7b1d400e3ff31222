"""Coverage, sensitivity and envelope grid studies.

References: the planted requirement of test_falsify (robustness depends on the grade only, closed form),
so its Sobol total index is ~1 for the slope and ~0 for every other dimension (variance decomposition of
a function of one variable); the coverage violations are exactly the sampled points whose slope lies in
[13.75, 14.90] deg. The grid study's counts are checked against the table it writes."""
import math

import numpy as np
import pyarrow.parquet as pq
import pytest

from vehicle_assist.verification import study as st
from tests.support import PLANTED_ENVELOPE

ENVELOPE = PLANTED_ENVELOPE


@pytest.fixture()
def planted(tmp_path, monkeypatch):
    from vehicle_assist.scenarios.schema import RequirementSpec
    from vehicle_assist.verification import requirements as rq

    path = tmp_path / "planted.toml"
    path.write_text(ENVELOPE)
    req = rq.make_requirement(RequirementSpec(id="test.planted", formula="always(abs(slope_rad - 0.25) > 0.01)", why="planted"),
                              "truck_amt", "test", "requirements.0")
    shipped = rq.all_shipped()
    monkeypatch.setattr(st, "get_requirement", lambda rid: req if rid == "test.planted" else shipped[rid])
    return path


def test_coverage_counts_match_closed_form(planted, tmp_path):
    cov = st.coverage_study(str(planted), "test.planted", 32, method="sobol", seed=1, out=tmp_path)
    U = np.array(cov["unit_points"])
    slope = U[:, 0] * 20
    expect = int(np.sum(np.abs(np.radians(slope) - 0.25) <= 0.01))
    assert cov["violations"] == expect
    assert cov["min_robustness"] == pytest.approx(float(np.min(np.abs(np.radians(slope) - 0.25) - 0.01)), abs=1e-9)
    assert (tmp_path / "coverage_planted_planted.png").exists()


def test_sobol_indices_single_variable(planted, tmp_path):
    sens = st.sensitivity_study(str(planted), "test.planted", 64, seed=0, out=tmp_path)
    by = {r["dimension"]: r for r in sens["indices"]}
    assert sens["points"] == 64 * (3 + 2)  # Saltelli without second order: N (D + 2)
    assert by["slope"]["ST"] == pytest.approx(1.0, abs=0.1)
    assert abs(by["mass"]["ST"]) < 0.05 and abs(by["surface"]["ST"]) < 0.05


def test_coarse_grid_study_counts(tmp_path):
    """A coarse grid of both envelopes runs with its twins; the summary agrees with its table, and every
    twin has the assist off (the baseline rolls back on a steep grade where the assisted start is held)."""
    for name, levels in (("hill_start_amt", {"mass": [30000], "slope": [0, 14], "reservoir": [8.0], "accelerator.start_s": [1.2],
                                             "accelerator.duration_s": [0.5], "accelerator.level_frac": [0.7],
                                             "hand_valve.at_s": [0.5], "start_gear": ["crawler"], "surface": ["gravel", "wet"]}),
                         ("hill_start_ehb", {"mass": [1500], "slope": [0, 10], "mu": [1.0], "accelerator.rate_per_s": [0.045], "accelerator.level_frac": [0.5],
                                             "driver": ["steady", "impatient"]})):
        s = st.envelope_study(name, levels, tmp_path)
        assert s["points"] == 4 and s["runs"] == 8
        table = pq.read_table(s["table"]).to_pandas()
        assert len(table) == 4
        assert s["counterexamples"] == int((table["no_worse_margin_m"] < 0).sum())
        assert s["worst_rollback_assisted_m"] == pytest.approx(table["rollback_m"].max())
        margin = np.maximum(0.01, table["baseline_rollback_m"]) - table["rollback_m"]
        assert np.all((table["no_worse_margin_m"] <= margin + 1e-12))
        steep = table[table["slope"] > 5]
        assert (steep["baseline_rollback_m"] > 0.01).all(), "the no-assist twin should roll back on a grade"


def test_no_worse_margin_counts_a_missing_assisted_value_as_worse():
    """An assisted run without a rollback value where its no-assist twin has one must not vanish from the
    counterexample count (a NaN margin is never < 0)."""
    from vehicle_assist.verification.requirements import STALL_PENALTY

    assert st.no_worse_margin({}, {"rollback_distance_m": 0.0}) == STALL_PENALTY
    assert math.isnan(st.no_worse_margin({}, {}))
    # closed form: floor 1 cm, baseline 0.5 m, assisted 0.2 m -> margin 0.3 m
    assert st.no_worse_margin({"rollback_distance_m": 0.2}, {"rollback_distance_m": 0.5}) == pytest.approx(0.3)
