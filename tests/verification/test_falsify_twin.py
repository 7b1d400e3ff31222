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


def test_twin_is_the_assist_off_run(planted, tmp_path):
    """The twin is the point with the envelope's baseline overrides (hill-start assist off), not the assisted run
    again: ``hsa_mode_index`` is -1 with the function disabled (vehicles/truck_amt.py records -1 then) and 0 (IDLE)
    with it on, so ``always(hsa_mode_index < -0.5)`` has robustness -0.5 on the assisted run (a counterexample) and
    +0.5 on the twin, which meets it (independent review r2: the grade-only reference above is the same for the
    assisted run and the twin, so it could not tell them apart)."""
    env = load_envelope(str(planted)).restrict_text(["slope=10"])
    res = run_falsification(env, _req("always(hsa_mode_index < -0.5)"), budget=1, seed=0, optimizer="random", batch=1,
                            progress=False)
    write_falsification(res, tmp_path / "out")
    assert res.counterexample.robustness == pytest.approx(-0.5, abs=1e-12)
    assert res.counterexample_twin_robustness == pytest.approx(0.5, abs=1e-12)
    assert "meets it" in twin_text(res)


def test_twin_not_a_number_is_not_met(planted, tmp_path):
    """A twin robustness that is not a number (a NaN channel) is no verdict: it compared False with 0 and was
    reported as "the same point without the assist meets it" (independent review r2)."""
    env = load_envelope(str(planted)).restrict_text(["slope=14.3"])
    res = run_falsification(env, _req("always(abs(slope_rad - 0.25) > 0.01)"), budget=1, seed=0, optimizer="random",
                            batch=1, progress=False)
    write_falsification(res, tmp_path / "out")
    res.counterexample_twin_robustness = float("nan")
    text = twin_text(res)
    assert "meets it" not in text and "violates" not in text and "cannot be judged" in text
