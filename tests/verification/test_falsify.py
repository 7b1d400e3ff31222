"""Falsification: finds a planted violation, is deterministic for a seed, writes a counterexample that
reruns to the same robustness; bad budgets and names get one-line errors (exit 2).

Planted violation (independent reference, closed form): the requirement
``always(abs(slope_rad - 0.25) > 0.01)`` fails exactly when the grade lies within 0.01 rad of 0.25 rad,
i.e. slope in [13.75, 14.90] deg, about 6 % of the 0-20 deg range; its robustness at a point is
``|slope_rad - 0.25| - 0.01`` whatever the other dimensions are. Runs last 0.3 s (cheap)."""
import json
import math

import numpy as np
import pytest
from typer.testing import CliRunner

from vehicle_assist.cli import app
from vehicle_assist.scenarios.schema import RequirementSpec
from vehicle_assist.verification.falsify import run_falsification, write_falsification
from vehicle_assist.verification.requirements import make_requirement
from tests.support import PLANTED_ENVELOPE

ENVELOPE = PLANTED_ENVELOPE


@pytest.fixture()
def planted(tmp_path):
    path = tmp_path / "planted.toml"
    path.write_text(ENVELOPE)
    req = make_requirement(RequirementSpec(id="planted", formula="always(abs(slope_rad - 0.25) > 0.01)", why="planted"),
                           "truck_amt", "test", "requirements.0")
    return path, req


def test_finds_planted_violation_and_is_deterministic(planted, tmp_path):
    path, req = planted
    a = run_falsification(str(path), req, budget=96, seed=3, optimizer="cma", batch=8, progress=False)
    assert a.counterexample is not None, f"no violation found; best {a.best.robustness}"
    slope = a.counterexample.point["slope"]
    assert 13.75 <= slope <= 14.90
    # robustness is the closed form at the point
    assert a.counterexample.robustness == pytest.approx(abs(math.radians(slope) - 0.25) - 0.01, abs=1e-9)
    b = run_falsification(str(path), req, budget=96, seed=3, optimizer="cma", batch=8, progress=False)
    assert [e.robustness for e in a.evaluations] == [e.robustness for e in b.evaluations]
    # the counterexample file reruns to the same robustness with 'vehicle-assist run'
    paths = write_falsification(a, tmp_path / "out")
    out = tmp_path / "rerun"
    res = CliRunner().invoke(app, ["run", str(paths["scenario"]), "--out", str(out), "--no-plot"])
    assert res.exit_code == 1, res.output  # the requirement is violated: the run fails
    doc = json.loads((out / "metrics.json").read_text())
    assert doc["requirements"][0]["robustness"] == pytest.approx(a.counterexample.robustness, abs=1e-12)
    assert paths["plot"].exists() and paths["trace"].exists()


def test_random_search_stops_at_budget_without_violation(planted):
    path, _ = planted
    req = make_requirement(RequirementSpec(id="never", formula="always(slope_rad < 1.0)"), "truck_amt", "t", "r")
    r = run_falsification(str(path), req, budget=10, seed=0, optimizer="random", batch=4, progress=False)
    assert len(r.evaluations) == 10 and r.counterexample is None
    # minimum robustness = 1 - the steepest grade sampled
    steepest = max(p.point["slope"] for p in r.evaluations)
    assert r.best.robustness == pytest.approx(1.0 - math.radians(steepest))


@pytest.mark.parametrize("args, needle", [
    (["--budget", "0"], "--budget = 0"),
    (["--batch", "0"], "--batch = 0"),
    (["--optimizer", "genetic"], "--optimizer = 'genetic'"),
    (["--requirement", "hill_start_amt.no_rolback"], "did you mean 'hill_start_amt.no_rollback'"),
])
def test_bad_falsify_input_one_line(args, needle, tmp_path):
    base = ["falsify", "hill_start_amt", "--out", str(tmp_path / "f")]
    if "--requirement" not in args:
        base += ["--requirement", "hill_start_amt.no_rollback"]
    res = CliRunner().invoke(app, base + args)
    assert res.exit_code == 2
    lines = [ln for ln in res.output.splitlines() if ln.strip()]
    assert len(lines) == 1 and needle in lines[0], res.output


def test_unknown_envelope_one_line(tmp_path):
    res = CliRunner().invoke(app, ["falsify", "hill_start_am", "-r", "hill_start_amt.no_rollback", "--out", str(tmp_path)])
    assert res.exit_code == 2 and "did you mean 'hill_start_amt'" in res.output
