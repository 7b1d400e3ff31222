"""Run the registered paper reproductions and write their table, figures, HTML page and summary."""
from __future__ import annotations

from pathlib import Path

from rich.console import Console
from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn
from rich.table import Table as RichTable

from vehicle_assist.io.results import write_json, write_trace_parquet
from vehicle_assist.procedures.reproduce import EXTRAS, REPRODUCTIONS
from vehicle_assist.report.html import write_reproduce_page
from vehicle_assist.report.plots import FIGURES
from vehicle_assist.scenarios.loader import load_scenario
from vehicle_assist.scenarios.runner import simulate
from vehicle_assist.units import unit_of


def run_reproductions(out: Path, console: Console | None = None) -> list[dict]:
    console = console or Console()
    out = Path(out)
    figures_dir = out / "figures"
    figures_dir.mkdir(parents=True, exist_ok=True)
    entries: list[dict] = []
    figures: list[tuple[str, Path]] = []
    jobs = [(rep, name) for rep in REPRODUCTIONS for name in rep.scenarios]
    with Progress(TextColumn("{task.description}"), BarColumn(), TextColumn("{task.completed}/{task.total}"),
                  TimeElapsedColumn(), console=console, transient=True) as progress:
        task = progress.add_task("reproducing", total=len(jobs))
        for rep, name in jobs:
            progress.update(task, description=f"{rep.paper}: {name}")
            sc = load_scenario(name)
            result = simulate(sc)
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
        for rep in REPRODUCTIONS:
            for extra in rep.extras:
                progress.update(task, description=f"{rep.paper}: {extra}")
                extra_figures, extra_entries = EXTRAS[extra](out / "studies")
                figures.extend(extra_figures)
                entries.extend(extra_entries)
    for rep in REPRODUCTIONS:
        table = RichTable(title=f"paper {rep.paper}: {rep.title}", title_justify="left")
        for col in ("scenario", "criterion", "value", "bound", "pass"):
            table.add_column(col, overflow="fold")
        for e in (e for e in entries if e["paper"] == rep.paper):
            bound = e["bound"] + (" must fail (negative control)" if e["negative_control"] else "")
            unit = "" if e["unit"] in ("1", "-") else f" {e['unit']}"
            table.add_row(e["scenario"], e["criterion"], f"{e['value']:.4g}{unit}", bound,
                          "[green]pass[/]" if e["pass"] else "[red]FAIL[/]")
        console.print(table)
    write_json(entries, out / "summary.json")
    page = write_reproduce_page(entries, figures, out / "index.html", "vehicle-assist: paper reproductions")
    console.print(f"wrote {out / 'summary.json'}, {page} and {len(figures)} figures in {figures_dir}")
    return entries
