"""STL requirements: robustness on synthetic traces against the quantitative semantics worked out by hand
(Donze & Maler 2010: always -> min over t, eventually -> max over the window, a -> b = max(-a, b),
x >= c -> x - c), malformed formulas as one-line errors, and requirements attached to scenarios.

Independent references: the hand values below; the 2nd-order Butterworth step overshoot exp(-pi) = 4.32 %
(closed form, zeta = 1/sqrt 2) for the jerk channel; numpy minima of the trace for a scenario run."""
import json
import math

import numpy as np
import pytest

from vehicle_assist.core.trace import Trace
from vehicle_assist.scenarios.errors import InputError
from vehicle_assist.scenarios.schema import RequirementSpec
from vehicle_assist.verification.requirements import (
    comparative_robustness,
    get_requirement,
    make_requirement,
    robustness,
)


def req(formula, layout="truck_amt"):
    return make_requirement(RequirementSpec(id="t", formula=formula), layout, "test", "requirements.0")


def trace(**channels):
    n = len(next(iter(channels.values())))
    return Trace({"time_s": np.arange(n) * 0.01, **{k: np.asarray(v, float) for k, v in channels.items()}})


def test_always_is_min_distance():
    tr = trace(speed_mps=[0.0, -0.003, 0.002, 0.0])
    assert robustness(req("always(speed_mps >= -0.001)"), tr) == pytest.approx(-0.002)
    assert robustness(req("always(speed_mps <= 0.01)"), tr) == pytest.approx(0.008)


def test_bounded_eventually_is_max_over_window():
    v = [0.0, 0.1, 0.3, 0.9, 2.0]
    tr = trace(speed_mps=v)
    # window [0, 0.02 s] = samples 0..2 at 10 ms: max 0.3 - 0.5
    assert robustness(req("eventually[0s:0.02s](speed_mps > 0.5)"), tr) == pytest.approx(-0.2)
    assert robustness(req("eventually[0s:0.03s](speed_mps > 0.5)"), tr) == pytest.approx(0.4)


def test_flag_antecedent_is_qualitative():
    # held at samples 0-2 only: the robustness is min over held samples of v + 0.001, in m/s
    tr = trace(vehicle_held_flag=[1, 1, 1, 0, 0], speed_mps=[0.0, -0.0005, 0.0, -5.0, -5.0])
    r = robustness(req("always((vehicle_held_flag > 0.5) -> (speed_mps >= -0.001))"), tr)
    assert r == pytest.approx(0.0005)


def test_displacement_is_relative_to_start():
    tr = trace(position_m=[5.0, 4.99, 4.98, 5.1])
    assert robustness(get_requirement("hill_start_amt.no_rollback"), tr) == pytest.approx(-0.01)


def test_start_completes_counts_from_brake_release():
    # released (pedal < 0.05) from sample 100 (1.0 s); speed reaches 0.6 m/s within 15 s: 0.6 - 0.5
    n = 1800
    pedal = np.where(np.arange(n) < 100, 0.6, 0.0)
    v = np.clip((np.arange(n) - 300) * 0.001, 0, 0.6)
    tr = trace(brake_pedal_frac=pedal, speed_mps=v)
    assert robustness(get_requirement("hill_start_amt.start_completes"), tr) == pytest.approx(0.1)
    tr = trace(brake_pedal_frac=pedal, speed_mps=v * 0.5)  # never above 0.3 m/s: 0.3 - 0.5
    assert robustness(get_requirement("hill_start_amt.start_completes"), tr) == pytest.approx(-0.2)


def test_jerk_channel_overshoot_of_butterworth():
    # acceleration ramp with jerk 0.09 m/s^3 from 1 s: the 2nd-order Butterworth's derivative overshoots
    # by exp(-pi) = 4.32 %, so the peak filtered jerk is 0.0939 and the robustness 0.1 - 0.0939
    n = 2000
    t = np.arange(n) * 0.01
    a = np.where(t > 1.0, 0.09 * (t - 1.0), 0.0)
    tr = trace(accel_mps2=a, vehicle_held_flag=np.zeros(n))
    r = robustness(get_requirement("hill_start_ehb.jerk"), tr)
    assert r == pytest.approx(0.1 - 0.09 * (1 + math.exp(-math.pi)), abs=0.0015)


def test_comparative_by_hand():
    r = get_requirement("hill_start_amt.no_worse_than_no_assist")
    assert comparative_robustness(r, {"rollback_distance_m": 0.004}, {"rollback_distance_m": 0.0}) == pytest.approx(0.006)
    assert comparative_robustness(r, {"rollback_distance_m": 3.0}, {"rollback_distance_m": 10.0}) == pytest.approx(7.0)
    assert comparative_robustness(r, {"rollback_distance_m": 3.0}, {"rollback_distance_m": 1.0}) == pytest.approx(-2.0)
    stall = {"rollback_distance_m": 0.0, "engine_stalled_flag": 1.0}
    assert comparative_robustness(r, stall, {"rollback_distance_m": 0.0, "engine_stalled_flag": 0.0}) < 0
    assert comparative_robustness(r, stall, {"rollback_distance_m": 0.0, "engine_stalled_flag": 1.0}) == pytest.approx(0.01)


@pytest.mark.parametrize("formula, needle", [
    ("always(sped_mps >= 0)", "unknown channel 'sped_mps' (did you mean 'speed_mps'?)"),
    ("always(speed_mps >> 0)", "STL syntax"),
    ("always(speed_mps >= 0", "STL syntax"),
])
def test_malformed_formula_one_line_error(formula, needle):
    import vehicle_assist as va

    with pytest.raises(InputError) as exc:
        va.load_scenario("hsa_truck_full_14deg_8p0bar", [f"requirements=[{{id='x', formula='{formula}'}}]"])
    msg = str(exc.value)
    assert "\n" not in msg and "hsa_truck_full_14deg_8p0bar.toml" in msg and "requirements.0.formula" in msg and needle in msg


def test_unknown_shipped_requirement():
    import vehicle_assist as va

    with pytest.raises(InputError, match=r"requirements.0 = 'hill_start_amt.no_rolback'.*did you mean"):
        va.load_scenario("hsa_truck_full_14deg_8p0bar", ['requirements=["hill_start_amt.no_rolback"]'])


def test_scenario_run_reports_requirement_robustness(tmp_path):
    """Robustness of 'always engine speed > 400 rpm' equals the trace's minimum engine speed - 41.888 rad/s
    (numpy min of the channel), and it reaches metrics.json and the run's exit code."""
    from typer.testing import CliRunner

    import vehicle_assist as va
    from vehicle_assist.cli import app

    sets = ["run.duration_s=4", 'requirements=["hill_start_amt.no_stall", {id="slow", formula="always(speed_mps < 0.2)", why="planted"}]']
    res = va.simulate(va.load_scenario("hsa_truck_full_14deg_8p0bar", sets))
    by_id = {r.id: r for r in res.requirements}
    assert by_id["hill_start_amt.no_stall"].robustness == pytest.approx(float(np.min(res.trace["engine_speed_radps"])) - 41.888)
    assert by_id["slow"].robustness == pytest.approx(0.2 - float(np.max(res.trace["speed_mps"])))
    out = tmp_path / "run"
    cli = CliRunner().invoke(app, ["run", "hsa_truck_full_14deg_8p0bar", "--out", str(out), "--no-plot"]
                             + [a for s in sets for a in ("--set", s)])
    doc = json.loads((out / "metrics.json").read_text())
    ids = [r["id"] for r in doc["requirements"]]
    assert ids == ["hill_start_amt.no_stall", "slow"]
    expect_fail = by_id["slow"].robustness < 0
    assert cli.exit_code == (1 if expect_fail or not res.ok else 0)


@pytest.mark.parametrize("dt", [0.001, 0.002, 0.005, 0.01])
def test_bounded_formula_at_any_recording_period(dt):
    """Reviewer (issue #8): runs recorded at 1 ms crashed rtamt ("bound must be a multiple of the sampling
    period": 0.001 * 1e9 is not an exact integer in floating point). Reference: by hand, speed = 0.1 (t - 5)
    after 5 s, released at t = 3 s, window [3, 18] s: max 1.3 m/s - 0.5 = 0.8; the dip of -0.004 m/s gives
    always(v >= -0.01) = 0.006."""
    t = np.round(np.arange(0.0, 30.0 + dt / 2, dt), 9)
    v = np.where(t < 5, -0.004 * np.sin(np.pi * t / 5), 0.1 * (t - 5))
    tr = Trace({"time_s": t, "speed_mps": v, "brake_pedal_frac": np.where(t < 3, 1.0, 0.0)})
    assert robustness(get_requirement("hill_start_amt.start_completes"), tr) == pytest.approx(0.8)
    assert robustness(req("always(speed_mps >= -0.01)"), tr) == pytest.approx(0.006)


def test_bound_not_a_whole_number_of_samples_is_one_line():
    t = np.arange(0, 400) * 0.007  # 15 s / 7 ms is not a whole number of samples
    tr = Trace({"time_s": t, "speed_mps": np.ones_like(t), "brake_pedal_frac": np.zeros_like(t)})
    with pytest.raises(InputError) as err:
        robustness(get_requirement("hill_start_amt.start_completes"), tr)
    assert "\n" not in str(err.value) and "record_period_s" in str(err.value)


@pytest.mark.parametrize("metric", ["rollback_distnce_m", "rollback_distance_m,engine_stalled_flg"])
def test_comparative_unknown_metric_one_line_error(metric):
    """Review RI3 (session i): a comparative requirement naming an unknown metric (one, or one of several) is refused
    at load with one line; before, both runs read NaN for it and the requirement was silently 'not judged' (with
    several metrics its NaN also hid the other metrics' violations)."""
    import vehicle_assist as va

    with pytest.raises(InputError) as exc:
        va.load_scenario("hsa_truck_full_14deg_8p0bar",
                         [f"requirements=[{{id='x', kind='no_worse_than_baseline', metric='{metric}'}}]"])
    msg = str(exc.value)
    assert "\n" not in msg and "requirements.0.metric" in msg and "is no metric" in msg and "did you mean" in msg


def test_comparative_violation_stands_next_to_an_unjudged_metric():
    """Review RI3 (session i): per side, the function 0.3 m beyond the LEFT marking where the twin stayed in (left:
    max(0, 0) - 0.3 = -0.3 m, a violation by hand) while the twin has no value for the right side (NaN: cannot be
    judged). The conjunction is violated whatever the unjudged part: -0.3 m, not NaN ('not counted'). With nothing
    violated the NaN stays NaN (no pass is invented)."""
    r = get_requirement("tire_blowout.no_lane_departure_caused")
    left, right = "blowout_lane_overshoot_left_m", "blowout_lane_overshoot_right_m"
    nan = float("nan")
    assert comparative_robustness(r, {left: 0.3, right: -0.5}, {left: -0.2, right: nan}) == pytest.approx(-0.3)
    assert math.isnan(comparative_robustness(r, {left: -0.1, right: -0.2}, {left: 0.2, right: nan}))
