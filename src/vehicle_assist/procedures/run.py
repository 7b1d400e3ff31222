"""Run the registered paper reproductions and write their table, figures, HTML page and summary."""
from __future__ import annotations

from pathlib import Path
from typing import Sequence

from rich.console import Console
from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn

from vehicle_assist.io.results import write_json, write_trace_parquet
from vehicle_assist.procedures.reproduce import EXTRAS, REPRODUCTIONS
from vehicle_assist.report.html import write_reproduce_page
from vehicle_assist.report.plots import FIGURES
from vehicle_assist.scenarios.loader import load_scenario
from vehicle_assist.scenarios.runner import simulate
from vehicle_assist.units import unit_of


def run_reproductions(out: Path, console: Console | None = None, papers: Sequence[str] | None = None,
                      extras: Sequence[str] | None = None) -> list[dict]:
    """Run the registered reproductions (all, or only ``papers``) with their studies (all of them, or only
    those named in ``extras``) and write summary.json, index.html and the figures into ``out``."""
    console = console or Console()
    selected = [rep for rep in REPRODUCTIONS if papers is None or rep.paper in papers]
    out = Path(out)
    figures_dir = out / "figures"
    figures_dir.mkdir(parents=True, exist_ok=True)
    entries: list[dict] = []
    figures: list[tuple[str, Path]] = []
    hashes: dict[str, dict[str, str]] = {}
    jobs = [(rep, name) for rep in selected for name in rep.scenarios]
    with Progress(TextColumn("{task.description}"), BarColumn(), TextColumn("{task.completed}/{task.total}"),
                  TimeElapsedColumn(), console=console, transient=True) as progress:
        task = progress.add_task("reproducing", total=len(jobs))
        for rep, name in jobs:
            progress.update(task, description=f"{rep.paper}: {name}")
            sc = load_scenario(name)
            result = simulate(sc)
            hashes[name] = {"scenario_hash": result.trace.meta.get("scenario_hash", ""),
                            "parameter_hash": result.trace.meta.get("parameter_hash", "")}
            write_trace_parquet(result.trace, out / "traces" / f"{name}.parquet")
            if rep.figure_scenarios is None or name in rep.figure_scenarios:
                for kind in rep.figures:
                    path = figures_dir / f"{name}_{kind}.png"
                    figures.append((f"paper {rep.paper}, {name}: {kind.replace('_', ' ')}",
                                    FIGURES[kind](result.trace, path, f"paper {rep.paper}: {name}")))
            for c in result.checks:
                entries.append({
                    "paper": rep.paper,
                    "scenario": name,
                    "criterion": c.metric,
                    "negative_control": c.expect == "fail",
                    "value": c.value,
                    "unit": unit_of(c.metric) or "-",
                    "bound": c.bound,
                    "pass": bool(c.ok),
                    "why": c.why,
                })
            for r in result.requirements:  # STL requirements attached to the scenario (robustness >= 0 holds)
                entries.append({
                    "paper": rep.paper,
                    "scenario": name,
                    "criterion": f"requirement {r.id}: {r.formula} (robustness)",
                    "negative_control": r.expect == "fail",
                    "value": r.robustness,
                    "unit": r.unit or "-",
                    "bound": ">= 0",
                    "pass": bool(r.ok),
                    "why": r.why,
                })
            progress.advance(task)
        for rep in selected:
            for extra in (x for x in rep.extras if extras is None or x in extras):
                progress.update(task, description=f"{rep.paper}: {extra}")
                extra_figures, extra_entries = EXTRAS[extra](out / "studies")
                figures.extend(extra_figures)
                entries.extend({**e, "section": e.get("section") or f"study: {extra.replace('_', ' ')}"}
                               for e in extra_entries)
    print_entries(console, selected, entries)
    write_json(entries, out / "summary.json")
    page = write_reproduce_page(entries, figures, out / "index.html", "vehicle-assist: paper reproductions",
                                papers={rep.paper: rep.title for rep in selected}, scenario_hashes=hashes)
    console.print(f"wrote {out / 'summary.json'}, {page} and {len(figures)} figures in {figures_dir}")
    return entries


def print_entries(console: Console, reproductions, entries: list[dict]) -> None:
    """The criteria per paper on the terminal: each scenario name on a line of its own, its criteria indented
    below, so the names a user copies are never cut or wrapped, whatever the terminal width."""
    for rep in reproductions:
        # one line per scenario name, its criteria indented below: names a user copies are never cut or
        # wrapped, whatever the terminal width
        console.print(f"[bold]paper {rep.paper}: {rep.title}[/]", highlight=False, soft_wrap=True)
        last = None
        for e in (e for e in entries if e["paper"] == rep.paper):
            if e["scenario"] != last:
                console.print(f"  {e['scenario']}", highlight=False, markup=False, soft_wrap=True)
                last = e["scenario"]
            unit = "" if e["unit"] in ("1", "-") else f" {e['unit']}"
            value = f"{e['value']:.4g}" if isinstance(e["value"], (int, float)) else str(e["value"])
            if e.get("negative_control"):
                mark = "[green]fails as required[/]" if e["pass"] else "[red]FAIL (should fail)[/]"
                bound = f"must fail: {e['bound']}"
            else:
                mark = "[green]pass[/]" if e["pass"] else "[red]FAIL[/]"
                bound = e["bound"]
            console.print(f"    {mark} ", end="", highlight=False, soft_wrap=True)
            console.print(f"{e['criterion']} = {value}{unit} ({bound})", highlight=False, markup=False, soft_wrap=True)
