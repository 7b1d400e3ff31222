"""ABS and HBA state machines (functions/abs.py, functions/brake_assist.py, functions/esp.py): every row fires
on hand-made inputs, the thresholds are the paper's, and the arbitration table is the spec's.

References: the rule set of brake_assist.md 4.3 (L_DUMP 0.20, L_HOLD 0.10, A_DUMP 30 m/s^2) and the entry/exit
conditions of paper 002 P3/P4/P10 (30 bar, 3500 bar/s, 15 km/h; exit 5 km/h, 6 bar) with spec 3 (T_WIN,
N_RISE, K_DROP, DP_DROP); the paper's valve states (P6-P8) for the arbitration.
"""
from __future__ import annotations

import numpy as np
import pytest

import vehicle_assist as va
from vehicle_assist.functions import abs as A
from vehicle_assist.functions import brake_assist as H
from vehicle_assist.functions import esp as E
from vehicle_assist.scenarios.runner import pack_records
from tests.support import machine_rows


def abs_decide(mode, slip, decel, allowed=True, build_s=0.0):
    g = A.guard_buffer()
    new, reason = A.abs_step(mode, build_s, slip, decel, allowed, 0.20, 0.10, 30.0, 15.0, 0.3, A.TABLE, g)
    return A.MODES[new], (A.machine("fl").guards[reason] if reason >= 0 else None)


ABS_CASES = [
    (A.OFF, 0.25, 0.0, True, 0.0, ("DUMP", "lock_threatened")),
    (A.OFF, 0.05, 40.0, True, 0.0, ("DUMP", "lock_threatened")),
    (A.OFF, 0.15, 0.0, True, 0.0, ("HOLD", "slip_high")),
    (A.OFF, 0.15, 0.0, False, 0.0, ("OFF", None)),
    (A.HOLD, 0.15, 0.0, False, 0.0, ("OFF", "abs_off")),
    (A.HOLD, 0.21, 0.0, True, 0.0, ("DUMP", "lock_threatened")),
    (A.HOLD, 0.08, 10.0, True, 0.0, ("BUILD", "slip_recovered")),
    (A.HOLD, 0.08, 20.0, True, 0.0, ("HOLD", None)),
    (A.DUMP, 0.5, 0.0, False, 0.0, ("OFF", "abs_off")),
    (A.DUMP, 0.15, 0.0, True, 0.0, ("HOLD", "slip_recovering")),
    (A.BUILD, 0.05, 0.0, False, 0.0, ("OFF", "abs_off")),
    (A.BUILD, 0.3, 0.0, True, 0.0, ("DUMP", "lock_threatened")),
    (A.BUILD, 0.12, 0.0, True, 0.0, ("HOLD", "slip_high")),
    (A.BUILD, 0.05, 0.0, True, 0.3, ("OFF", "build_idle")),
    (A.BUILD, 0.05, 0.0, True, 0.1, ("BUILD", None)),
]


@pytest.mark.parametrize("start, slip, decel, allowed, build_s, expected", ABS_CASES)
def test_every_abs_row(start, slip, decel, allowed, build_s, expected) -> None:
    assert abs_decide(start, slip, decel, allowed, build_s) == expected


def test_abs_rows_all_covered_by_the_cases_above() -> None:
    rows = {(t.source, t.target, t.guard) for t in A.MACHINE_ROWS}
    assert len(rows) == 11
    # (issue #9 review: this test only counted the rows; it now checks that the cases fire every one of them)
    fired = {(A.MODES[c[0]], c[5][0], c[5][1]) for c in ABS_CASES if c[5][1] is not None}
    assert rows <= fired, rows - fired


@pytest.fixture(scope="module")
def params():
    sc = va.load_scenario("hba_paper_110kph_dry")
    return pack_records([sc.vehicle.flat()])[0]


def feed(params, samples, state=None, dt=0.005):
    """samples: (p_mc bar, speed km/h, pedal, sensor_ok, abs_ok, ramp_done); returns the state and (mode, reason) list."""
    st = H.initial_state() if state is None else state
    out = []
    g = H.guard_buffer()
    for p_bar, v_kph, pedal, sok, aok, done in samples:
        new, reason = H.hba_step(st, p_bar * 1e5, v_kph / 3.6, pedal, sok, aok, done, dt, params, g)
        out.append((H.MODES[new], H.GUARDS[reason] if reason >= 0 else None))
    return st, out


def panic(v=100.0, sok=True, aok=True):
    # 5 ms samples of a panic application: 0, 20, 40, 60 bar (4000 bar/s)
    return [(0.0, v, True, sok, aok, True), (20.0, v, True, sok, aok, True), (40.0, v, True, sok, aok, True),
            (60.0, v, True, sok, aok, True)]


def test_hba_entry_needs_every_condition(params) -> None:
    _, out = feed(params, panic())
    assert out[-2] == ("ACTIVE", "entry_conditions_met")  # 40 bar, 4000 bar/s, two rising samples
    for kwargs in ({"v": 14.0}, {"sok": False}, {"aok": False}):
        _, out = feed(params, panic(**kwargs))
        assert all(m == "INACTIVE" for m, _ in out), kwargs
    slow = [(p, 100.0, True, True, True, True) for p in np.arange(0, 80, 1.0)]  # 200 bar/s: normal braking
    _, out = feed(params, slow)
    assert all(m == "INACTIVE" for m, _ in out)
    # fast (4000 bar/s) to 20 bar, then 1000 bar/s: 30 bar 10 ms after the fast sample -> inside T_WIN = 20 ms
    late = [(0.0, 100, True, True, True, True), (20.0, 100, True, True, True, True)] + \
           [(20.0 + 5.0 * k, 100, True, True, True, True) for k in range(1, 6)]
    _, out = feed(params, late)
    assert out.index(("ACTIVE", "entry_conditions_met")) == 3
    # then 400 bar/s: 30 bar only 25 ms after the fast sample -> the latch has expired, no activation
    later = late[:2] + [(20.0 + 2.0 * k, 100, True, True, True, True) for k in range(1, 10)]
    _, out = feed(params, later)
    assert all(m == "INACTIVE" for m, _ in out)


@pytest.mark.parametrize("exit_sample, reason", [
    ((60.0, 4.0, True, True, True, False), "speed_below_exit"),
    ((60.0, 80.0, False, True, True, False), "pedal_released"),
    ((5.0, 80.0, True, True, True, False), "pressure_below_exit"),
    ((20.0, 80.0, True, True, True, False), "pressure_dropped"),
    ((60.0, 80.0, True, False, True, False), "sensor_failed"),
    ((60.0, 80.0, True, True, False, False), "abs_unavailable"),
])
def test_every_hba_exit_row(params, exit_sample, reason) -> None:
    st, out = feed(params, panic() + [(60.0, 90.0, True, True, True, False)])
    assert out[-1][0] == "ACTIVE"
    st, out = feed(params, [exit_sample], st)
    assert out[-1] == ("TERMINATING", reason)
    # an easing driver (60 -> 36 bar, into the R139 corridor) does not end the assist (spec 3, K_DROP)
    st, out = feed(params, panic() + [(36.0, 90.0, True, True, True, False)])
    assert out[-1][0] == "ACTIVE"


def test_terminating_rows(params) -> None:
    st, _ = feed(params, panic() + [(5.0, 80.0, True, True, True, False)])
    st, out = feed(params, [(5.0, 80.0, True, True, True, False)], st)
    assert out[-1] == ("TERMINATING", None)
    st, out = feed(params, [(5.0, 80.0, True, True, True, True)], st)
    assert out[-1] == ("INACTIVE", "ramp_out_complete")
    st, _ = feed(params, panic() + [(5.0, 80.0, True, True, True, False)])
    st, out = feed(params, panic(), st)  # a new panic application re-enters through the full test
    assert ("ACTIVE", "entry_conditions_met") in out


def test_arbitration_table_follows_the_paper() -> None:
    """P6: no ABS request during HBA -> active build B; P7: hold with the circuit isolated, re-build by the pump;
    P8/spec 3: terminating ramps out, a dump (lock threatened) always wins; without HBA plain ABS on the driver."""
    M = E.WHEEL_MODES
    row = lambda hba_mode: [M[E.ARBITRATION[hba_mode, r]] for r in range(len(E.REQUESTS))]
    assert row(H.INACTIVE) == ["N", "H", "D", "BPM", "H", "BPM"]
    assert row(H.ACTIVE) == ["B", "HI", "D", "BP", "HI", "BP"]
    assert row(H.TERMINATING) == ["T", "T", "D", "T", "T", "T"]


def test_scenario_rows_logged_in_the_paper_run() -> None:
    r = va.simulate(va.load_scenario("hba_paper_110kph_dry"))
    rows = machine_rows(r, "hba")
    assert rows[0] == ("INACTIVE", "ACTIVE", "entry_conditions_met")
    assert ("ACTIVE", "TERMINATING", "speed_below_exit") in rows
    assert rows[-1] == ("TERMINATING", "INACTIVE", "ramp_out_complete")
    abs_rows = {row for w in ("fl", "fr", "rl", "rr") for row in machine_rows(r, f"abs_{w}")}
    for row in (("OFF", "DUMP", "lock_threatened"), ("DUMP", "HOLD", "slip_recovering"), ("HOLD", "BUILD", "slip_recovered"),
                ("BUILD", "HOLD", "slip_high"), ("HOLD", "DUMP", "lock_threatened"), ("BUILD", "OFF", "build_idle")):
        assert row in abs_rows, row


def test_hba_thresholds_are_inclusive_as_the_paper_states(params) -> None:
    """Reference: paper 002 P10 / brake_assist.md 3 - entry at master pressure >= 30 bar and speed >= 15 km/h,
    exit at speed <= 5 km/h and master pressure <= 6 bar: exactly at each threshold the condition holds, a
    little beyond it does not. (25 bar in 5 ms = 5000 bar/s latches the rate; the next sample is the probe.)"""
    def entry(p_bar, v_kph):
        return feed(params, [(0.0, v_kph, True, True, True, True), (25.0, v_kph, True, True, True, True),
                             (p_bar, v_kph, True, True, True, True)])[1][-1][0]

    assert entry(30.0, 100.0) == "ACTIVE"
    assert entry(29.9, 100.0) == "INACTIVE"
    assert entry(40.0, 15.0) == "ACTIVE"
    assert entry(40.0, 14.9) == "INACTIVE"

    def exit_(p_bar, v_kph):
        st, out = feed(params, panic() + [(60.0, 90.0, True, True, True, False)])
        assert out[-1][0] == "ACTIVE"
        return feed(params, [(p_bar, v_kph, True, True, True, False)], st)[1][-1]

    assert exit_(60.0, 5.0) == ("TERMINATING", "speed_below_exit")
    assert exit_(60.0, 5.1)[0] == "ACTIVE"
    assert exit_(6.0, 80.0)[0] == "TERMINATING"  # 6 bar also meets the drop rule; either guard is an exit
    assert exit_(6.0, 80.0)[1] in ("pressure_below_exit", "pressure_dropped")
