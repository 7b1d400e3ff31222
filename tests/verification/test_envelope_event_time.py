"""A range on an appended event's field (the fault time of tire_blowout_faults.toml, review RK2 / session l L3) and the
inactive marker of conditional ranges.

References: the event written out by hand (actuator_fault, inlet_valve_<w>, stuck_energized, at the point's time); the
plant's conservation (an inlet valve held closed passes no flow: the wheel cylinder's pressure cannot rise after the
fault time, and a wheel braked before it keeps a pressure > 0 - trapped - while a fault from t = 0 leaves it empty);
the no-compensation twin carries the same fault at the same time (the baseline adds only enabled_flag=0); counting
(a full factorial without the repeats of inactive dimensions)."""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from vehicle_assist.scenarios.errors import InputError
from vehicle_assist.verification.envelope import Envelope, EnvelopeModel, load_envelope, shipped_envelopes

BAR = 1e5
WHEELS = ("fl", "fr", "rl", "rr")
# 60 km/h on the paper's road, blown FL, the driver brakes 200 N from 1.2 s (reaching it at 1.3 s)
POINT = {"speed": 60.0, "mu": 0.684, "delay": 0.05, "wheel_speed_noise": 0.0, "noise_seed": 1, "brake_gain": 1.0,
         "accumulator": 40.0, "fault_time": 1.7, "brake.start_s": 1.2, "brake.level_frac": 0.2, "brake.rate_per_s": 2.0,
         "braking": "brakes", "wheel": "fl", "driver": "fixed", "curve": "straight", "fault": "inlet_stuck_rr"}


def stuck(w: str, t: float) -> dict:
    return {"at_s": t, "action": "actuator_fault", "actuator": f"inlet_valve_{w}", "fault": "stuck_energized"}


@pytest.fixture(scope="module")
def env():
    return load_envelope("tire_blowout_faults")


def _edited(tmp_path: Path, old: str, new: str) -> Path:
    text = shipped_envelopes()["tire_blowout_faults"].read_text(encoding="utf-8")
    assert old in text
    p = tmp_path / "faults.toml"
    p.write_text(text.replace(old, new), encoding="utf-8")
    return p


@pytest.mark.parametrize("old, new, says", [
    ('path = "append_events[0].at_s"', 'path = "append_events[1].at_s"', "appends 1 event(s); no event at index 1"),
    ('path = "append_events[0].at_s"', 'path = "append_events[0].at"', "has no field 'at' (did you mean 'at_s'?)"),
    ('path = "append_events[0].at_s"', 'path = "append_events.at_s"', "append_events[I].FIELD"),
    ('path = "append_events[0].at_s"', 'path = "events[0].at_s"', "append_events[I].FIELD"),
    ('when = { fault = ["inlet_stuck_fl", "inlet_stuck_fr", "inlet_stuck_rl", "inlet_stuck_rr"] }\nsource = "the time',
     'when = { fault = ["inlet_stuck_fl", "low_accumulator"] }\nsource = "the time',
     "options.low_accumulator appends 0 event(s)"),
    ('when = { fault = ["inlet_stuck_fl", "inlet_stuck_fr", "inlet_stuck_rl", "inlet_stuck_rr"] }\nsource = "the time',
     'source = "the time', "needs when"),
])
def test_bad_event_path_is_a_one_line_load_error(tmp_path, old, new, says):
    with pytest.raises(InputError) as exc:
        load_envelope(_edited(tmp_path, old, new))
    text = str(exc.value)
    assert "fault_time" in text and says in text and "\n" not in text, text


def test_fault_time_range_is_sourced_and_covers_t0_and_the_event(env):
    d = env.dim("fault_time")
    assert (d.lo, d.hi) == (0.0, 4.0)  # 0 = the latent fault (the case before); 4 s = t_b + 3 s
    assert env.model.ranges["fault_time"].when == {"fault": [f"inlet_stuck_{w}" for w in WHEELS]}
    assert len(d.source) > 200


@pytest.mark.parametrize("baseline", [False, True])
def test_fault_time_moves_the_appended_event_in_the_run_and_its_twin(env, baseline):
    for w in WHEELS:
        for t in (0.0, 1.7, 4.0):
            sc = env.scenario(dict(POINT, fault=f"inlet_stuck_{w}", fault_time=t), baseline=baseline)
            assert sc.raw["events"] == [stuck(w, t)]  # written by hand
            assert sc.flat["event_time_s"][0] == t
    # the twin differs from the function's run ONLY by the baseline override (same fault, same time)
    a, b = env.sets(POINT), env.sets(POINT, baseline=True)
    assert b == a + ["vehicle.blowout_compensation.enabled_flag=0"]
    # the option itself is not changed by a point (a copy is edited): the next point starts from at_s = 0
    assert env.model.choices["fault"].options["inlet_stuck_rr"]["append_events"][0]["at_s"] == 0.0


def test_t0_stays_reachable_and_an_older_point_without_fault_time_is_the_latent_fault(env):
    pinned = env.restrict_text(["fault_time=0"])
    p = pinned.unit_to_point(np.full(len(pinned.dims), 0.37))
    assert p["fault_time"] == 0.0
    old = {k: v for k, v in POINT.items() if k != "fault_time"}  # a point of a falsify.json written before L3
    assert env.scenario(old).raw["events"] == [stuck("rr", 0.0)]
    assert env.sets(old) == env.sets(dict(POINT, fault_time=0.0))
    assert "fault_time" not in env.point_name(old) and "fault=inlet_stuck_rr" in env.point_name(old)


def test_a_valve_stuck_mid_event_traps_its_pressure_in_both_runs(env):
    """Conservation: the RR inlet closes at 1.7 s while the driver brakes (from 1.2 s): RR was braked before (> 5 bar)
    and its pressure cannot rise afterwards; with the fault at t = 0 RR stays empty (0.5 bar = sensor-level zero).
    Fails if fault_time does not reach the plant (RR empty throughout) or the twin lost it."""
    from vehicle_assist.scenarios.runner import simulate_batch

    runs = [env.scenario(dict(POINT, fault_time=t), baseline=b).with_sets("run.duration_s=2.0")
            for t in (1.7, 0.0) for b in (False, True)]
    batch = simulate_batch(runs, keep_channels=["time_s", "wheel_pressure_rr_pa", "wheel_pressure_rl_pa"], metric_names=[])
    for k, ch in enumerate(batch.channels):
        t, p_rr, p_rl = (np.asarray(ch[c]) for c in ("time_s", "wheel_pressure_rr_pa", "wheel_pressure_rl_pa"))
        if k < 2:  # stuck at 1.7 s
            before = p_rr[t <= 1.7]
            after = p_rr[t >= 1.7 + 0.01]  # (one valve step)
            assert before.max() > 5 * BAR, (k, before.max())
            assert after.max() <= before[-1] + 0.1 * BAR, (k, after.max(), before[-1])
            assert after.min() > 5 * BAR, (k, after.min())  # trapped, not dumped
        else:  # stuck from the start
            assert p_rr.max() < 0.5 * BAR, (k, p_rr.max())
        assert p_rl.max() > 5 * BAR  # the open inlets pass the driver's pressure


def test_inactive_marks_the_conditional_ranges_not_written(env):
    for w in WHEELS:
        assert env.inactive(dict(POINT, fault=f"inlet_stuck_{w}")) == ["accumulator"]
    assert env.inactive(dict(POINT, fault="low_accumulator")) == ["fault_time"]
    assert load_envelope("tire_blowout", validate=False).inactive(dict(POINT)) == []
    # an inactive dimension does nothing: two points that differ only there make the same scenario
    low = dict(POINT, fault="low_accumulator")
    assert env.sets(low) == env.sets(dict(low, fault_time=3.3))
    assert env.sets(POINT) == env.sets(dict(POINT, accumulator=111.0))


def test_grid_does_not_repeat_points_that_differ_only_in_inactive_dimensions(env):
    levels = {d.name: 1 for d in env.continuous}
    levels.update(accumulator=3, fault_time=3)
    g = env.grid(levels)
    # per (braking 2 x wheel 4 x driver 2 x curve 3 = 48): 4 inlet faults x 3 fault times + 3 accumulators (not 5 x 9)
    assert len(g) == 48 * (4 * 3 + 3)
    scen = {tuple(env.sets(p)) for p in g}
    assert len(scen) == len(g)  # every grid point is a different scenario (none lost, none repeated)
    # the nominal envelope (no conditional range) keeps its full factorial
    blow = load_envelope("tire_blowout", validate=False)
    assert len(blow.grid({d.name: 2 for d in blow.continuous})) == 2 ** len(blow.continuous) * 48


def test_falsify_json_lists_the_inactive_dimensions_per_point(env, tmp_path):
    from vehicle_assist.verification.falsify import run_falsification, write_falsification

    short = env.restrict_text(["speed=40..50", "fault_time=0..1"]).with_sets(["run.duration_s=1.2"])
    res = run_falsification(short, "tire_blowout.no_worse_than_no_compensation", budget=6, seed=3, optimizer="random",
                            batch=6, progress=False, stop_at_violation=False)
    write_falsification(res, tmp_path / "f")
    doc = json.loads((tmp_path / "f" / "falsify.json").read_text())
    assert len(doc["history"]) == 6
    for h in doc["history"]:
        want = ["fault_time"] if h["point"]["fault"] == "low_accumulator" else ["accumulator"]
        assert h["inactive"] == want, h
        assert set(h["point"]) == set(env.names)  # the value stays (the unit coordinate and the search's point)
    assert doc["best_point_inactive"] == env.inactive(doc["best_point"])


def test_a_range_on_an_event_of_a_user_envelope(tmp_path):
    """The feature is general: a user envelope ranges the time of a sensor fault its choice appends."""
    raw = load_envelope("tire_blowout_faults", validate=False).model.model_dump(exclude_none=True)
    raw["choices"] = dict(raw["choices"], fault={"source": "test: a yaw-rate sensor lost at a time", "options": {
        "gyro": {"append_events": [{"at_s": 0.5, "action": "sensor_fault", "sensor": "yaw_rate", "fault": "lost"},
                                   {"at_s": 0.0, "action": "sensor_fault", "sensor": "tpms_alarm_wheel", "fault": "lost"}]},
        "none": {}}})
    raw["ranges"] = {k: v for k, v in raw["ranges"].items() if k not in ("accumulator", "fault_time")}
    raw["ranges"]["lost_at"] = {"path": "append_events[-2].at_s", "min": 0.5, "max": 3.0, "when": {"fault": ["gyro"]},
                                "source": "test: the time the gyro is lost"}
    env = Envelope(EnvelopeModel.model_validate(raw), None)
    env.validate_points()
    sc = env.scenario(dict(env.center(), fault="gyro", lost_at=2.25))
    assert [e["at_s"] for e in sc.raw["events"]] == [2.25, 0.0]
