"""Every row of the AMT start program's transition table fires (conventions.md: "tests make every row fire").

functions/amt_launch.py declares MACHINE (modes and (from, to, guard) rows). Each scenario below is the
shipped late-release truck scenario (empty truck, 1st gear, 11 deg) changed by overrides and events so
that specific rows fire; the events of machine 'amt_launch' are collected as (from, to, reason) and
compared with the table. Every scenario also checks the event chain is consistent with the mode trace.
"""
from __future__ import annotations

import numpy as np
import pytest

import vehicle_assist as va
from vehicle_assist.functions.amt_launch import MACHINE

SCENARIO = "truck_11deg_late_release"
FLAT = ["road.slope_deg=0", 'driver.hand_valve={time_s=[0.0], released=[1]}',
        'driver.brake_pedal={time_s=[0.0, 1.0, 1.2], frac=[0.6, 0.6, 0.0]}']

HSA_ON = ["vehicle.hill_start_assist.enabled_flag=1", 'driver.hand_valve={time_s=[0.0, 2.0], released=[0, 1]}',
          "run.duration_s=8"]

CASES = {
    # lever moved to crawler while stopped with the clutch open, then a normal flat launch to CLOSED
    "gear_change_then_launch": FLAT + [
        'driver.accelerator={time_s=[0.0, 3.0, 3.5], frac=[0.0, 0.0, 0.27]}', "run.duration_s=7",
        'events=[{at_s=0.5, action="set_input", input="gear_lever", value="C"}]'],
    # pedal tapped and released within the 0.23 s clutch approach (0.35/1.5 per s)
    "abandoned_in_approach": FLAT + ['driver.accelerator={time_s=[0.0, 1.0, 1.02, 1.1], frac=[0.0, 0.0, 0.3, 0.0]}',
                                     "run.duration_s=2"],
    # late release: clutch drags against the park brake (anti-stall back-off in ENGAGE), pedal released at 6 s
    "abandoned_in_engage": ["run.duration_s=7", 'events=[{at_s=6.0, action="set_input", input="accelerator", value=0.0}]'],
    # launched and closed on the flat, then full brake with the pedal off pulls the engine below 550 rpm
    "engine_pulled_down": FLAT + [
        'driver.accelerator={time_s=[0.0, 1.0, 1.5], frac=[0.0, 0.0, 0.27]}', "run.duration_s=7",
        'events=[{at_s=5.0, action="set_input", input="brake_pedal", value=1.0}, '
        '{at_s=5.0, action="set_input", input="accelerator", value=0.0}]'],
    # hill-start assist on: the start program begins a launch on the accelerator, the assist takes the
    # clutch when the service brake is released on the applied park brake, and hands it back closed
    "assist_takes_over_in_approach": HSA_ON + ['driver.accelerator={time_s=[0.0, 0.9, 1.4], frac=[0.0, 0.0, 0.27]}'],
    # the same with the accelerator pressed long before the brake release: the start program is in ENGAGE
    "assist_takes_over_in_engage": HSA_ON + ['driver.accelerator={time_s=[0.0, 0.2, 0.7], frac=[0.0, 0.0, 0.27]}'],
    # issue 7: 28 t on 13 deg in 1st at pedal 0.5 with the assist's lock-up check removed (seeded defect): after
    # the hand-over the engine is pulled down on the grade, the assist's rollback catch takes the closed clutch
    "assist_takes_over_when_closed": HSA_ON + [
        "vehicle.body.mass_kg=28000", "road.slope_deg=13", 'driver.accelerator={time_s=[0.0, 1.0, 1.5], frac=[0.0, 0.0, 0.5]}',
        "vehicle.hill_start_assist.lockup_engine_check_flag=0", "run.duration_s=10"],
}

EXPECTED = {
    "gear_change_then_launch": [("OPEN", "SHIFTING", "gear_change_requested"), ("SHIFTING", "OPEN", "gear_engaged"),
                                ("OPEN", "APPROACH", "launch_requested"), ("APPROACH", "ENGAGE", "kiss_point_reached"),
                                ("ENGAGE", "LOCKUP", "slip_small"), ("LOCKUP", "CLOSED", "clutch_closed")],
    "abandoned_in_approach": [("OPEN", "APPROACH", "launch_requested"), ("APPROACH", "OPEN", "launch_abandoned")],
    "abandoned_in_engage": [("OPEN", "APPROACH", "launch_requested"), ("APPROACH", "ENGAGE", "kiss_point_reached"),
                            ("ENGAGE", "OPEN", "launch_abandoned")],
    "engine_pulled_down": [("OPEN", "APPROACH", "launch_requested"), ("APPROACH", "ENGAGE", "kiss_point_reached"),
                           ("ENGAGE", "LOCKUP", "slip_small"), ("LOCKUP", "CLOSED", "clutch_closed"),
                           ("CLOSED", "OPEN", "engine_pulled_down")],
    "assist_takes_over_in_approach": [("OPEN", "APPROACH", "launch_requested"), ("APPROACH", "OPEN", "assist_took_over"),
                                      ("OPEN", "CLOSED", "assist_handed_over")],
    "assist_takes_over_in_engage": [("OPEN", "APPROACH", "launch_requested"), ("APPROACH", "ENGAGE", "kiss_point_reached"),
                                    ("ENGAGE", "OPEN", "assist_took_over"), ("OPEN", "CLOSED", "assist_handed_over")],
    "assist_takes_over_when_closed": [("OPEN", "APPROACH", "launch_requested"), ("APPROACH", "OPEN", "assist_took_over"),
                                      ("OPEN", "CLOSED", "assist_handed_over"), ("CLOSED", "OPEN", "assist_took_over")],
}


@pytest.fixture(scope="module")
def results():
    return {name: va.simulate(va.load_scenario(SCENARIO, sets)) for name, sets in CASES.items()}


def fired(result) -> list[tuple[str, str, str]]:
    return [(e.from_mode, e.to_mode, e.reason) for e in result.events if e.machine == "amt_launch"]


@pytest.mark.parametrize("name", list(CASES))
def test_scenario_fires_expected_rows_in_order(results, name) -> None:
    """Each constructed scenario produces exactly its intended chain of transitions."""
    assert fired(results[name]) == EXPECTED[name]


@pytest.mark.parametrize("name", list(CASES))
def test_event_chain_matches_mode_trace(results, name) -> None:
    """Events form a chain from OPEN (each from_mode is the previous to_mode) and the recorded
    amt_mode_index equals the mode of the last event at or before each sample (events are logged at
    controller ticks, which are record instants at the 10 ms default)."""
    r = results[name]
    events = [e for e in r.events if e.machine == "amt_launch"]
    mode = "OPEN"
    for e in events:
        assert e.from_mode == mode
        mode = e.to_mode
    t = r.trace["time_s"]
    expected = np.full(len(t), float(MACHINE.mode("OPEN")))
    for e in events:
        expected[t >= e.time_s - 1e-9] = MACHINE.mode(e.to_mode)
    np.testing.assert_array_equal(r.trace["amt_mode_index"], expected)


def test_every_row_fires(results) -> None:
    """Union over the scenarios covers every row of MACHINE (no row is dead)."""
    rows = {(t.source, t.target, t.guard) for t in MACHINE.transitions}
    seen = set()
    for r in results.values():
        seen.update(fired(r))
    assert seen <= rows, f"transitions not in the table: {seen - rows}"
    assert rows == seen, f"rows never fired: {sorted(rows - seen)}"


def test_gear_change_engages_requested_gear(results) -> None:
    """After the lever moves to C the gearbox passes through neutral for shift_time_s (0.8 s) and then
    reports the crawler gear (index 1); the launch happens in crawler. The shift duration is taken from the
    gearbox events (1 ms resolution) and must be 0.8 s within 2 plant steps (the shift timer starts
    counting in the step that receives the request, so 0.799 s is measured)."""
    r = results["gear_change_then_launch"]
    gear = r.trace["gear_index"]
    assert gear[0] == 2 and gear[-1] == 1
    box = [e for e in r.events if e.machine == "gearbox"]
    assert [(e.from_mode, e.to_mode) for e in box] == [("IN_GEAR", "SHIFTING"), ("SHIFTING", "IN_GEAR")]
    assert box[1].time_s - box[0].time_s == pytest.approx(0.8, abs=2.0e-3)
    launch = [e for e in r.events if e.machine == "amt_launch" and e.reason == "launch_requested"][0]
    assert launch.time_s > box[1].time_s


def test_abandoned_launch_leaves_clutch_open(results) -> None:
    """launch_abandoned -> OPEN commands the clutch open; it never reached the kiss point, so no torque."""
    r = results["abandoned_in_approach"]
    assert r.trace["clutch_command_frac"][-1] == 0.0
    assert r.trace["clutch_torque_nm"].max() == 0.0
    assert np.all(r.trace["speed_mps"] == 0.0)
