"""Commands on results already written: ``export`` (a run to MDF4, Parquet or CSV) and ``compare`` (runs side by
side: an overlay figure and a metric-delta table). Registered by ``cli.py``."""
from __future__ import annotations

from pathlib import Path
from typing import List

import typer


def _trace_of(text: str, fail):
    """A run directory or trace file (read_run), or a scenario name/file to simulate."""
    from vehicle_assist.io.results import read_run
    from vehicle_assist.scenarios.guards import check_path_text

    path = Path(text)
    if path.exists():
        try:
            check_path_text(text, "file")
            return read_run(path), path.name if path.is_dir() else path.stem
        except (OSError, ValueError) as exc:
            fail(f"{text}: cannot read it as a run ({exc.__class__.__name__}: {exc})")
    fail(f"{text!r}: no such run directory or trace file (.parquet, .csv, .mf4); write one with "
         "'vehicle-assist run NAME --out DIR'")


def parse_formats(text: str, fail) -> tuple[str, ...]:
    from vehicle_assist.io.results import TRACE_FORMATS

    formats = tuple(dict.fromkeys(f.strip().lower() for f in text.split(",") if f.strip()))
    bad = [f for f in formats if f not in TRACE_FORMATS]
    if bad or not formats:
        fail(f"--format {text!r}: use one or more of {', '.join(TRACE_FORMATS)} separated by commas")
    return formats


def register(app: typer.Typer) -> None:
    from vehicle_assist import cli as base

    @app.command()
    def export(
        run: str = typer.Argument(..., help="run directory (written by 'run') or a trace file .parquet/.csv/.mf4"),
        fmt: str = typer.Option("mdf4", "--format", "-f", help="mdf4, parquet or csv (comma-separated for several)"),
        out_text: str = typer.Option("", "--out", "-o", help="output directory (default: the run directory)"),
    ) -> None:
        """Convert a run's trace to MDF4 (units, descriptions, mode names, events), Parquet or CSV."""
        from vehicle_assist.io.results import _SUFFIX, write_trace

        formats = parse_formats(fmt, base._fail)
        trace, _ = _trace_of(run, base._fail)
        src = Path(run)
        out = base._out_dir(out_text) if out_text else (src if src.is_dir() else src.parent)
        written = []
        try:
            for f in formats:
                target = out / f"trace{_SUFFIX[f]}"
                if target.resolve() == src.resolve():
                    continue  # already in that format
                written.append(write_trace(trace, target, f))
        except OSError as exc:
            base._write_failed(exc, out)
        base._say(f"wrote {', '.join(str(p) for p in written) or 'nothing (already in that format)'} "
                  f"({len(trace)} samples, {len(trace.names)} channels, {len(trace.events)} events)")

    @app.command()
    def compare(
        runs: List[str] = typer.Argument(..., help="two or more run directories or trace files"),
        out_text: str = typer.Option("out/compare", "--out", "-o", help="output directory for compare.png"),
    ) -> None:
        """Overlay the key channels of runs (compare.png) and print each metric with its delta to the first run."""
        from rich.table import Table as RichTable

        from vehicle_assist.metrics import compute_metrics
        from vehicle_assist.report.compare import compare_png, display, metric_deltas

        if len(runs) < 2:
            base._fail("compare needs at least two runs")
        out = base._out_dir(out_text)
        loaded = [_trace_of(r, base._fail) for r in runs]
        labels = [label for _, label in loaded]
        if len(set(labels)) < len(labels):
            labels = list(runs)
        traces = [t for t, _ in loaded]
        metrics = [compute_metrics(t) for t in traces]
        table = RichTable(title="metrics (delta to the first run)")
        table.add_column("metric", no_wrap=True)
        for label in labels:
            table.add_column(base._plain(label), justify="right")
        for name, values, deltas in metric_deltas(metrics):
            cells = [base._fmt(values[0])]
            for v, d in zip(values[1:], deltas[1:]):
                shown, unit = display(name, d)
                extra = f" ({shown:+.3g} {unit})" if unit in ("rpm", "deg/s", "km/h", "bar") and d else ""
                cells.append(f"{base._fmt(v)} [{'+' if d >= 0 else ''}{base._fmt(d)}]{extra}")
            table.add_row(name, *cells)
        base.console.print(table)
        try:
            path = compare_png(traces, labels, out / "compare.png", "compare: " + " vs ".join(labels))
        except OSError as exc:
            base._write_failed(exc, out)
        base._say(f"wrote {path}")
