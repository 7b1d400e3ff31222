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
    figures: tuple[str, ...] = ("overview", "forces")  # plot kinds (report.plots.FIGURES)
    figure_scenarios: tuple[str, ...] | None = None  # which scenarios get figures (None: all)


HSA_MATRIX = tuple(f"hsa_truck_{load}_{slope}deg_{bar}bar" for load in ("empty", "full") for slope in (11, 14)
                   for bar in ("65", "70", "75", "80"))

REPRODUCTIONS: list[Reproduction] = [
    Reproduction(
        "000",
        "Hill-start assist, heavy AMT truck (Wang, Zhao, Liu 2009): 11/14 deg x empty/full x 6.5-8.0 bar, "
        "normal start, and the baselines without the assist",
        HSA_MATRIX + ("hsa_truck_empty_flat_normal_start", "hsa_truck_full_14deg_no_assist_early_release",
                      "hsa_truck_full_14deg_no_assist_late_release", "truck_11deg_early_release",
                      "truck_11deg_late_release"),
        figures=("hill_start",),
        figure_scenarios=("hsa_truck_full_14deg_80bar", "hsa_truck_empty_11deg_80bar", "hsa_truck_full_14deg_65bar",
                          "hsa_truck_full_14deg_no_assist_early_release", "hsa_truck_full_14deg_no_assist_late_release",
                          "truck_11deg_late_release"),
    ),
    Reproduction(
        "examples",
        "Example scenario of the EV (paper 001 not yet implemented): a baseline that must show the failure",
        ("ev_5deg_hold_and_pull_away",),
    ),
]


def register(reproduction: Reproduction) -> None:
    REPRODUCTIONS.append(reproduction)
