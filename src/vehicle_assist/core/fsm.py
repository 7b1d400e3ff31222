"""State machines as data: modes, and a transition table of (from, to, guard) rows.

"Modes are data" (conventions.md): each assistance function and each hybrid plant element declares a
:class:`StateMachine`. The compiled step code evaluates the named guards of the current mode in table
order (first matching row wins) through :func:`next_mode`, and records each change in the event buffer
with the row that fired. Python turns the buffer back into :class:`~vehicle_assist.core.trace.Event`
objects with mode and guard names, and :meth:`StateMachine.mermaid` prints the table as a diagram.
"""
from __future__ import annotations

from dataclasses import dataclass

import numba as nb
import numpy as np

from vehicle_assist.core.trace import Event

EVENT_FIELDS = 5  # time_s, machine id, from mode, to mode, reason id


@dataclass(frozen=True)
class Transition:
    source: str
    target: str
    guard: str
    doc: str = ""


@dataclass(frozen=True)
class StateMachine:
    name: str
    modes: tuple[str, ...]
    transitions: tuple[Transition, ...]
    doc: str = ""

    def __post_init__(self) -> None:
        for t in self.transitions:
            for m in (t.source, t.target):
                if m not in self.modes:
                    raise ValueError(f"{self.name}: transition {t.source}->{t.target} names unknown mode {m!r}")

    @property
    def guards(self) -> tuple[str, ...]:
        seen: list[str] = []
        for t in self.transitions:
            if t.guard not in seen:
                seen.append(t.guard)
        return tuple(seen)

    def mode(self, name: str) -> int:
        return self.modes.index(name)

    def guard(self, name: str) -> int:
        return self.guards.index(name)

    def table(self) -> np.ndarray:
        """int64 rows (from, to, guard id) in priority order, for the compiled step code."""
        return np.array(
            [(self.mode(t.source), self.mode(t.target), self.guard(t.guard)) for t in self.transitions], dtype=np.int64
        ).reshape(-1, 3)

    def mermaid(self) -> str:
        lines = ["stateDiagram-v2", f"    [*] --> {self.modes[0]}"]
        for t in self.transitions:
            lines.append(f"    {t.source} --> {t.target}: {t.guard}")
        return "\n".join(lines)


@nb.njit(cache=True, nogil=True, error_model="numpy")
def next_mode(table, mode, guard_values):
    """First row of ``table`` leaving ``mode`` whose guard is true: returns (new mode, guard id or -1)."""
    for row in range(table.shape[0]):
        if table[row, 0] == mode and guard_values[table[row, 2]]:
            return table[row, 1], table[row, 2]
    return mode, -1


# explicit signature: one compiled version whatever literal ints or float modes the callers pass
# (without it numba compiled eleven specialisations, ~1.5 s of every cold start)
@nb.njit(nb.int64(nb.float64[:, ::1], nb.int64, nb.float64, nb.int64, nb.int64, nb.int64, nb.int64),
         cache=True, nogil=True, error_model="numpy")
def log_event(events, n_events, time_s, machine, from_mode, to_mode, reason):
    """Append a mode change to the event buffer (silently drops beyond its capacity; the count says so)."""
    if n_events < events.shape[0]:
        events[n_events, 0] = time_s
        events[n_events, 1] = machine
        events[n_events, 2] = from_mode
        events[n_events, 3] = to_mode
        events[n_events, 4] = reason
    return n_events + 1


def decode_events(buffer: np.ndarray, count: int, machines: list[StateMachine]) -> list[Event]:
    """Turn an event buffer into Events, naming machines, modes and the guard (reason) that fired."""
    out = []
    for row in buffer[: min(count, len(buffer))]:
        sm = machines[int(row[1])]
        reason = sm.guards[int(row[4])] if 0 <= int(row[4]) < len(sm.guards) else "initial"
        out.append(Event(float(row[0]), sm.name, sm.modes[int(row[2])], sm.modes[int(row[3])], reason))
    if count > len(buffer):
        out.append(Event(float(buffer[-1, 0]), "simulation", "", "", f"event buffer full: {count - len(buffer)} events not recorded"))
    return out
