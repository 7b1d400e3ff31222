"""core/fsm.py: modes as data (conventions.md "Modes are data").

Checks the table semantics the compiled controllers rely on: the first matching row leaving the current
mode wins, rows of other modes are ignored, no true guard keeps the mode (guard id -1); StateMachine
validation, the Mermaid rendering and decoding of the event buffer into named events.
"""
from __future__ import annotations

import numpy as np
import pytest

from vehicle_assist.core.fsm import EVENT_FIELDS, StateMachine, Transition, decode_events, log_event, next_mode
from vehicle_assist.core.trace import Event

SM = StateMachine("demo", ("A", "B", "C"), (
    Transition("A", "B", "go_b"),
    Transition("A", "C", "go_c"),
    Transition("B", "A", "back"),
    Transition("C", "A", "go_b"),  # a guard may label several rows
))


def guards(**true) -> np.ndarray:
    g = np.zeros(len(SM.guards), dtype=np.bool_)
    for name, value in true.items():
        g[SM.guard(name)] = value
    return g


def test_table_layout_and_guard_ids() -> None:
    """table() rows are (from, to, guard id) in declaration order; guards are de-duplicated in first-use order."""
    assert SM.guards == ("go_b", "go_c", "back")
    np.testing.assert_array_equal(SM.table(), [[0, 1, 0], [0, 2, 1], [1, 0, 2], [2, 0, 0]])
    assert SM.table().dtype == np.int64


def test_first_matching_row_wins() -> None:
    """Both rows leaving A are true: the first one (A -> B, go_b) is taken."""
    assert tuple(next_mode(SM.table(), SM.mode("A"), guards(go_b=True, go_c=True))) == (1, 0)
    assert tuple(next_mode(SM.table(), SM.mode("A"), guards(go_c=True))) == (2, 1)


def test_rows_of_other_modes_are_ignored() -> None:
    """'back' is true but only leaves B: in A nothing fires -> (A, -1); in B it fires."""
    assert tuple(next_mode(SM.table(), SM.mode("A"), guards(back=True))) == (0, -1)
    assert tuple(next_mode(SM.table(), SM.mode("B"), guards(back=True, go_b=True))) == (0, 2)


def test_no_true_guard_keeps_mode() -> None:
    for mode in range(3):
        assert tuple(next_mode(SM.table(), mode, guards())) == (mode, -1)


def test_next_mode_py_func_agrees() -> None:
    """The uncompiled function gives the same answers (debugging path of conventions.md)."""
    for mode in range(3):
        for bits in range(8):
            g = np.array([(bits >> i) & 1 for i in range(3)], dtype=np.bool_)
            assert tuple(next_mode(SM.table(), mode, g)) == tuple(next_mode.py_func(SM.table(), mode, g))


def test_unknown_mode_rejected() -> None:
    with pytest.raises(ValueError, match="unknown mode 'D'"):
        StateMachine("bad", ("A", "B"), (Transition("A", "D", "g"),))
    with pytest.raises(ValueError, match="unknown mode 'Z'"):
        StateMachine("bad", ("A", "B"), (Transition("Z", "A", "g"),))


def test_mermaid_output() -> None:
    """The diagram lists the initial mode and every row with its guard, in table order."""
    assert SM.mermaid() == "\n".join([
        "stateDiagram-v2",
        "    [*] --> A",
        "    A --> B: go_b",
        "    A --> C: go_c",
        "    B --> A: back",
        "    C --> A: go_b",
    ])


def test_log_and_decode_events_names() -> None:
    """log_event writes rows the decoder turns into named events; a reason of -1 decodes as 'initial'."""
    other = StateMachine("other", ("OFF", "ON"), (Transition("OFF", "ON", "switch_on"),))
    buf = np.zeros((4, EVENT_FIELDS))
    n = 0
    n = log_event(buf, n, 0.5, 0, SM.mode("A"), SM.mode("C"), SM.guard("go_c"))
    n = log_event(buf, n, 1.25, 1, 0, 1, 0)
    n = log_event(buf, n, 2.0, 0, SM.mode("C"), SM.mode("A"), -1)
    events = decode_events(buf, n, [SM, other])
    assert events == [
        Event(0.5, "demo", "A", "C", "go_c"),
        Event(1.25, "other", "OFF", "ON", "switch_on"),
        Event(2.0, "demo", "C", "A", "initial"),
    ]


def test_event_buffer_overflow_is_reported() -> None:
    """Beyond capacity log_event drops rows but keeps counting; decode_events says how many were lost."""
    buf = np.zeros((2, EVENT_FIELDS))
    n = 0
    for k in range(5):
        n = log_event(buf, n, 0.1 * k, 0, 0, 1, 0)
    assert n == 5
    events = decode_events(buf, n, [SM])
    assert len(events) == 3
    assert events[-1].machine == "simulation" and "3 events not recorded" in events[-1].reason
