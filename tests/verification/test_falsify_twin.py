"""A counterexample of an absolute requirement says what the no-assist twin does at the same point (falsify.json
``counterexample.baseline_robustness``, the CLI line, the reproduce entry), so a reader tells a violation the assist
causes from one the car has anyway (reproduce 004 listed a lane departure on a 0.31-friction curve with no word on
the car without compensation).

Reference (closed form, as test_falsify.py): ``always(abs(slope_rad - 0.25) > 0.01)`` reads only the grade, which
the twin (assist off) shares, so the twin's robustness is ``|slope_rad - 0.25| - 0.01`` too."""
import json
import math

import pytest

from vehicle_assist.scenarios.schema import RequirementSpec
from vehicle_assist.verification.envelope import load_envelope
from vehicle_assist.verification.falsify import run_falsification, twin_text, write_falsification
from vehicle_assist.verification.requirements import make_requirement
from tests.support import PLANTED_ENVELOPE


@pytest.fixture()
def planted(tmp_path):
    path = tmp_path / "planted.toml"
    path.write_text(PLANTED_ENVELOPE)
    return path


def _req(formula):
    return make_requirement(RequirementSpec(id="planted", formula=formula, why="planted"), "truck_amt", "test",
                            "requirements.0")


def test_twin_of_a_grade_only_violation_is_the_closed_form(planted, tmp_path):
    env = load_envelope(str(planted)).restrict_text(["slope=14.3"])
    res = run_falsification(env, _req("always(abs(slope_rad - 0.25) > 0.01)"), budget=1, seed=0, optimizer="random",
                            batch=1, progress=False)
    paths = write_falsification(res, tmp_path / "out")
    ref = abs(math.radians(14.3) - 0.25) - 0.01
    assert res.counterexample_twin_robustness == pytest.approx(ref, abs=1e-9)
    doc = json.loads(paths["summary"].read_text())
    assert doc["counterexample"]["baseline_robustness"] == pytest.approx(ref, abs=1e-9)
    assert "violates it too" in twin_text(res) and "enabled_flag=0" in twin_text(res)


def test_no_counterexample_no_twin_run(planted, tmp_path):
    req = _req("always(abs(slope_rad - 0.25) > 0.01)")
    env = load_envelope(str(planted)).restrict_text(["slope=3"])  # 3 deg: robustness 0.19 rad, no violation
    res = run_falsification(env, req, budget=1, seed=0, optimizer="random", batch=1, progress=False)
    write_falsification(res, tmp_path / "out")
    assert res.counterexample is None and res.counterexample_twin_robustness is None and twin_text(res) == ""
