"""Paper reproductions: which scenarios reproduce which paper, and the summary they produce.

Each function issue adds a :class:`Reproduction` (paper seed number, scenario names); until the first
function lands, the example scenarios of the foundation stand in (paper ``examples``). Every check of
every listed scenario becomes one summary entry: paper, scenario, criterion, value, unit, bound, pass.
"""
from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Reproduction:
    paper: str
    title: str
    scenarios: tuple[str, ...]


REPRODUCTIONS: list[Reproduction] = [
    Reproduction(
        "examples",
        "Foundation example scenarios (no assistance function yet): baselines that must show the failures",
        ("truck_11deg_early_release", "truck_11deg_late_release", "ev_5deg_hold_and_pull_away"),
    ),
]


def register(reproduction: Reproduction) -> None:
    REPRODUCTIONS.append(reproduction)
