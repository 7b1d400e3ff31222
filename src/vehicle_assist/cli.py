"""Command line: ``vehicle-assist list | run | check | show | reproduce | sweep | fsm | metrics``.

Bad input never shows a traceback: the one-line message names the file, the field, the value and the
fix, and the exit code is 2. A run whose checks do not come out as expected exits 1.
"""
from __future__ import annotations

import os

# The compiled kernels use no BLAS; OpenBLAS's idle worker threads spin and steal the cores that batch runs
# need (measured: ~15 % slower batches on 2 cores). Set for the command line's own process only, before
# numpy is imported (the package itself sets nothing process-wide at import).
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import json  # noqa: E402
import math  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402
from typing import List, Optional  # noqa: E402

import typer  # noqa: E402
from rich.console import Console  # noqa: E402
from rich.table import Table as RichTable  # noqa: E402

app = typer.Typer(add_completion=False, no_args_is_help=True, help="Vehicle assistance functions: simulate, calibrate, verify.")
console = Console()
err_console = Console(stderr=True)

def _version(value: bool) -> None:
    if value:
        import vehicle_assist

        print(f"vehicle-assist {vehicle_assist.__version__}")
        raise typer.Exit(0)


@app.callback()
def _root(version: bool = typer.Option(False, "--version", callback=_version, is_eager=True,
                                       help="print the version and exit")) -> None:
    """Vehicle assistance functions: simulate, calibrate, verify."""


SetOpt = typer.Option(None, "--set", "-s", help="override by dotted path, e.g. vehicle.body.mass_kg=30000 (repeatable)")


def _plain(text) -> str:
    """User-derived text for the terminal: control characters shown escaped (never sent raw)."""
    from vehicle_assist.scenarios.errors import plain

    return plain(text)


def _say(text: str, con: Console | None = None) -> None:
    """Print text that may hold user input: no markup, no highlighting, control characters escaped."""
    (con or console).print(_plain(text), markup=False, highlight=False, soft_wrap=True)


def _fail(message: str, code: int = 2) -> None:
    from rich.text import Text

    err_console.print(Text.assemble(("error:", "bold red"), " ", _plain(message)), highlight=False, soft_wrap=True)
    raise typer.Exit(code)


def _out_dir(text: str) -> Path:
    """--out checked before anything runs (not empty, not '/', not a file or under one, writable)."""
    from vehicle_assist.scenarios.errors import InputError
    from vehicle_assist.scenarios.guards import check_out_dir

    try:
        return check_out_dir(text)
    except InputError as exc:
        _fail(str(exc))


def _write_failed(exc: OSError, out: Path) -> None:
    where = exc.filename if exc.filename else out
    _fail(f"cannot write results to {where} ({exc.strerror or exc.__class__.__name__}); files already written are "
          "complete (atomic writes); free space or give another --out")


YesOpt = typer.Option(False, "--yes", "-y", help="run even past the stated memory (2 GiB) and time (10 min) bounds")


def _fmt(value: float) -> str:
    if value is None or (isinstance(value, float) and not math.isfinite(value)):
        return "nan"
    if value == 0 or 1e-3 <= abs(value) < 1e6:
        return f"{value:.4g}"
    return f"{value:.3e}"


def _external(name: str, value: float) -> str:
    """Same value in the unit an engineer reads (rpm, km/h, bar), for tables."""
    from vehicle_assist.units import BAR_TO_PA, KPH_TO_MPS, RPM_TO_RADPS

    if not isinstance(value, float) or not math.isfinite(value):
        return ""
    if name.endswith("_radps") and ("yaw" in name or "steer" in name):  # body/steering rates: deg/s, not rpm
        return f"{math.degrees(value):.2f} deg/s"
    if name.endswith("_radps"):
        return f"{value / RPM_TO_RADPS:.0f} rpm"
    if name.endswith("_mps"):
        return f"{value / KPH_TO_MPS:.2f} km/h"
    if name.endswith("_pa"):
        return f"{value / BAR_TO_PA:.2f} bar"
    if name.endswith("_j") and abs(value) >= 1000:
        return f"{value / 1000:.1f} kJ"
    return ""


@app.command("list")
def list_cmd() -> None:
    """Shipped scenarios and vehicles, one line each."""
    from vehicle_assist.scenarios.loader import _read_toml, _vehicle_raw, shipped

    width = max(console.width, 60)
    for kind in ("scenarios", "vehicles"):
        files = shipped(kind)
        key = "paper" if kind == "scenarios" else "layout"
        name_w = max(map(len, files), default=4)
        console.print(f"[bold]shipped {kind}[/] ({len(files)})", highlight=False)
        for name, path in files.items():
            raw = _read_toml(path) if kind == "scenarios" else _vehicle_raw(name)[0]
            line = f"  {name:<{name_w}}  {str(raw.get(key, '')):<9}  {raw.get('description', '')}"
            console.print(line if len(line) <= width else line[: width - 1] + "…", highlight=False, markup=False,
                          soft_wrap=True)


def _load(scenario: str, sets: Optional[List[str]]):
    from vehicle_assist.scenarios.errors import InputError
    from vehicle_assist.scenarios.loader import load_scenario

    try:
        return load_scenario(scenario, list(sets or []))
    except InputError as exc:
        _fail(str(exc))


@app.command()
def check(scenario: str = typer.Argument(..., help="shipped scenario name or a .toml file"), set_: Optional[List[str]] = SetOpt) -> None:
    """Validate a scenario or vehicle file without running it."""
    if _is_vehicle(scenario) and not set_:
        from vehicle_assist.scenarios.errors import InputError
        from vehicle_assist.scenarios.loader import load_vehicle

        try:
            v = load_vehicle(scenario)
        except InputError as exc:
            _fail(str(exc))
        _say(f"ok: vehicle {v.model.name} (layout {v.model.layout}), {len(v.sources)} parameters with sources")
        return
    sc = _load(scenario, set_)
    _say(f"ok: {sc.name} ({sc.vehicle.model.name}, layout {sc.layout}), {len(sc.model.checks)} checks, "
         f"{len(sc.model.events)} events, {sc.model.run.duration_s:g} s")
    if sc.model.road.curve_radius is not None and sc.layout != "amt_car":
        console.print("note: road.curve_radius is used by the amt_car layout only; the longitudinal plants ignore it")


def _is_vehicle(name: str) -> bool:
    """A shipped vehicle name, or a .toml file that is a vehicle (a layout or a base, and no run section)."""
    from vehicle_assist.scenarios.errors import InputError
    from vehicle_assist.scenarios.loader import _read_toml, shipped

    if name in shipped("vehicles"):
        return True
    if name in shipped("scenarios") or not name.endswith(".toml"):
        return False
    try:
        raw = _read_toml(Path(name))
    except (InputError, OSError):
        return False  # the scenario loader says what is wrong with it
    return "layout" in raw or ("base" in raw and "run" not in raw)


def _metrics_table(title: str, metrics: dict) -> RichTable:
    from rich.text import Text

    table = RichTable(title=Text(_plain(title)))
    table.add_column("metric", no_wrap=True)
    table.add_column("value (SI)", justify="right")
    table.add_column("", justify="right")
    for name, value in metrics.items():
        table.add_row(name, _fmt(value), _external(name, value))
    return table


def _bound_display(metric: str, c) -> str:
    """The bound in SI and, for rpm / km/h / bar quantities, in that unit too: '<= 0.01 (<= 0.04 km/h)'."""
    from vehicle_assist.report.compare import display

    parts = []
    for op, value in ((">=", c.min), ("<=", c.max)):
        if value is not None:
            shown, unit = display(metric, float(value))
            parts.append(f"{op} {shown:.4g} {unit}" if unit in ("rpm", "deg/s", "km/h", "bar") else "")
    extra = " and ".join(p for p in parts if p)
    return f"{c.bound} ({extra})" if extra else c.bound


def _checks_table(title: str, checks) -> RichTable:
    table = RichTable(title=title)
    for col in ("check", "value", "bound", "expect", "result"):
        table.add_column(col, no_wrap=col == "check")
    for c in checks:
        mark = "[green]ok[/]" if c.ok else ("[green]fails as required[/]" if c.expect == "fail" else "[red]FAIL[/]")
        if c.expect == "fail" and not c.ok:
            mark = "[red]FAIL (should fail)[/]"
        table.add_row(c.metric, _fmt(c.value), _bound_display(c.metric, c), c.expect, mark)
    return table


def _events_table(events) -> RichTable:
    from rich.text import Text

    from vehicle_assist.report.plots import debounced_events

    table = RichTable(title="events (changes < 50 ms apart merged; all of them in metrics.json)")
    for col in ("time s", "machine", "from", "to", "guard"):
        table.add_column(col, justify="right" if col == "time s" else "left")
    for t0, t1, *texts in debounced_events(events):
        when = f"{t0:.3f}" if t1 == t0 else f"{t0:.3f}-{t1:.3f}"
        table.add_row(when, *(Text(_plain(x)) for x in texts))
    return table


@app.command()
def run(
    scenario: str = typer.Argument(..., help="shipped scenario name or a .toml file"),
    set_: Optional[List[str]] = SetOpt,
    out_text: str = typer.Option("out/run", "--out", "-o", help="output directory"),
    plot: bool = typer.Option(True, help="write overview.png"),
    fmt: str = typer.Option("parquet,csv", "--format", "-f",
                            help="trace formats: parquet, csv, mdf4 (comma-separated)"),
    yes: bool = YesOpt,
) -> None:
    """Run one scenario: print metrics, checks and events; write the trace (trace.parquet and trace.csv, or
    --format mdf4 for trace.mf4), metrics.json and overview.png."""
    from vehicle_assist.cli_results import parse_formats

    formats = parse_formats(fmt, _fail)
    from rich.text import Text

    from vehicle_assist.io.results import write_run_outputs
    from vehicle_assist.scenarios.errors import InputError
    from vehicle_assist.scenarios.guards import estimate_run, refuse_past_bounds
    from vehicle_assist.scenarios.runner import simulate

    out = _out_dir(out_text)
    sc = _load(scenario, set_)
    try:
        refuse_past_bounds(estimate_run(sc), yes, out)
    except InputError as exc:
        _fail(str(exc))
    t0 = time.perf_counter()
    with console.status(Text(_plain(f"simulating {sc.name} ({sc.model.run.duration_s:g} s)..."))):
        result = simulate(sc)
    elapsed = time.perf_counter() - t0
    console.print(_metrics_table(f"{sc.name}: metrics ({elapsed:.2f} s wall)", result.metrics))
    if result.checks:
        console.print(_checks_table("checks", result.checks))
    if result.requirements:
        from vehicle_assist.cli_verify import requirements_table

        console.print(requirements_table(result.requirements))
    if result.trace.events:
        console.print(_events_table(result.trace.events))
    try:
        with console.status("writing results..."):
            paths = write_run_outputs(result.trace, result.metrics, out, sc.name, [c.as_dict() for c in result.checks], plot=plot,
                                      requirements=[r.as_dict() for r in result.requirements], formats=formats)
    except OSError as exc:
        _write_failed(exc, out)
    _say(f"wrote {', '.join(str(p) for p in paths.values())}")
    if not result.ok:
        raise typer.Exit(1)


@app.command()
def show(
    name: str = typer.Argument(..., help="vehicle or scenario (shipped name or .toml file)"),
    fmt: str = typer.Option("toml", "--format", "-f", help="toml or json"),
    set_: Optional[List[str]] = SetOpt,
) -> None:
    """Print the fully resolved parameters with units and sources."""
    from vehicle_assist.scenarios.errors import InputError
    from vehicle_assist.scenarios.loader import _read_toml, load_vehicle, shipped
    from vehicle_assist.scenarios.show import resolved_scenario, resolved_vehicle

    if fmt not in ("toml", "json"):
        _fail(f"--format {fmt!r}: use toml or json")
    try:
        is_vehicle = name in shipped("vehicles")
        if not is_vehicle and name not in shipped("scenarios"):
            from vehicle_assist.scenarios.errors import did_you_mean
            from vehicle_assist.scenarios.guards import check_path_text

            check_path_text(name, "file")
            if not name.endswith(".toml") and "/" not in name:
                known = list(shipped("scenarios")) + list(shipped("vehicles"))
                _fail(f"{name!r}: no shipped vehicle or scenario of that name{did_you_mean(name, known)}; a file must be "
                      "given as a path ending in .toml; see 'vehicle-assist list'")
            raw = _read_toml(Path(name))  # bounded, regular .toml files only
            is_vehicle = "layout" in raw or ("base" in raw and "run" not in raw)
        if is_vehicle and not set_:
            doc = resolved_vehicle(load_vehicle(name))
        else:
            doc = resolved_scenario(_load(name, set_))
    except InputError as exc:
        _fail(str(exc))
    if fmt == "json":
        console.print_json(json.dumps(doc))
    else:
        import tomli_w

        sys.stdout.write(tomli_w.dumps(doc))


@app.command()
def reproduce(out_text: str = typer.Option("out/reproduce", "--out", "-o", help="output directory")) -> None:
    """Run every paper reproduction: table of criteria, figures, HTML page and summary.json."""
    from vehicle_assist.procedures.run import run_reproductions

    out = _out_dir(out_text)
    try:
        entries = run_reproductions(out, console)
    except OSError as exc:
        _write_failed(exc, out)
    failed = [e for e in entries if not e["pass"]]
    if failed:
        err_console.print(f"[red]{len(failed)} of {len(entries)} criteria failed[/]")
        raise typer.Exit(1)


@app.command()
def sweep(
    scenario: str = typer.Argument(..., help="shipped scenario name or a .toml file"),
    grid: List[str] = typer.Option(..., "--grid", "-g", help="dotted.path=v1,v2,... (repeatable; the full product is run)"),
    set_: Optional[List[str]] = SetOpt,
    out_text: str = typer.Option("out/sweep", "--out", "-o", help="output directory (an interrupted sweep resumes here)"),
    chunk: int = typer.Option(500, help="variants per part file (1 to 100000)"),
    workers: int = typer.Option(0, help="threads, or worker processes of a local dask cluster (0 = all cores, at most 64)"),
    scheduler: Optional[str] = typer.Option(None, "--scheduler", help="dask scheduler address (tcp://host:8786), 'local' "
                                            "(a cluster of processes here) or 'threads'; default $VEHICLE_ASSIST_SCHEDULER, "
                                            "else local for >= 20,000 variants (needs the [dist] extra)"),
    plot: Optional[List[str]] = typer.Option(None, "--plot", help="X Y METRIC: heat map of METRIC over grid axes "
                                             "X and Y (Y '-' for a line plot over X), to sweep.png and sweep.html"),
    yes: bool = YesOpt,
) -> None:
    """Run a grid of variants of one scenario on all cores; results to sweep.parquet (resumable, locked).
    With --plot "X Y METRIC" also a plot and a sweep report (sweep.png, sweep.html)."""
    plot_spec = _plot_spec(plot)
    from vehicle_assist.scenarios.errors import InputError
    from vehicle_assist.scenarios.sweep import run_sweep

    out = _out_dir(out_text)
    sc = _load(scenario, set_)
    try:
        path, n = run_sweep(sc, grid, out, chunk=chunk, workers=workers or None, console=console, yes=yes,
                            say=_say, scheduler=scheduler)
    except InputError as exc:
        _fail(str(exc))
    except OSError as exc:
        _write_failed(exc, out)
    _say(f"wrote {path} ({n} variants)")
    if plot_spec:
        _sweep_plot(path, *plot_spec)


def _plot_spec(plot) -> tuple[str, str | None, str] | None:
    if not plot:
        return None
    words = [w for item in plot for w in item.split()]
    if len(words) != 3:
        _fail(f"--plot {' '.join(plot)!r}: give three words X Y METRIC (Y '-' for a line plot), e.g. "
              "--plot 'road.slope_deg vehicle.body.mass_kg rollback_distance_m'")
    x, y, metric = words
    return x, (None if y == "-" else y), metric


def _sweep_plot(path: Path, x: str, y: str | None, metric: str) -> None:
    import pyarrow.parquet as pq

    from vehicle_assist.report.compare import sweep_html, sweep_png

    table = pq.read_table(path)
    df = table.to_pandas()
    for col, what in ((x, "X"), (y, "Y"), (metric, "METRIC")):
        if col is not None and col not in df.columns:
            from vehicle_assist.scenarios.errors import did_you_mean

            _fail(f"--plot {what} {col!r}: not a column of {path}{did_you_mean(col, list(df.columns))}")
    record = json.loads((table.schema.metadata or {}).get(b"vehicle_assist.sweep", b"{}"))
    record["created_utc"] = (table.schema.metadata or {}).get(b"created_utc", b"").decode()
    title = f"{record.get('scenario', '')}: {metric}"
    figure = sweep_png(df, x, y, metric, path.parent / "sweep.png", title)
    page = sweep_html(df, record, figure, path.parent / "sweep.html")
    _say(f"wrote {figure}, {page}")


@app.command()
def fsm(name: str = typer.Argument(..., help="state machine name, e.g. amt_launch")) -> None:
    """Print a state machine's transition table as a Mermaid diagram."""
    from vehicle_assist.vehicles import layouts

    machines = {}
    for layout in layouts.names():
        for m in layouts.get(layout).MACHINES:
            machines.setdefault(m.name, m)
    if name not in machines:
        from vehicle_assist.scenarios.errors import did_you_mean

        _fail(f"no state machine {name!r}{did_you_mean(name, machines)}; known: {', '.join(machines)}")
    print(machines[name].mermaid())


@app.command()
def metrics() -> None:
    """List the metrics that checks can name."""
    from vehicle_assist.metrics import METRICS

    table = RichTable(title="metrics", show_lines=True)
    table.add_column("name", no_wrap=True)  # names a user copies: never cut or wrapped
    table.add_column("needs channels", no_wrap=True)
    table.add_column("description", ratio=1)
    for name, m in sorted(METRICS.items()):
        table.add_row(name, "\n".join(m.requires), m.description)
    console.print(table)


from vehicle_assist.cli_verify import register as _register_verify  # noqa: E402  (falsify, study, requirements)

_register_verify(app)

from vehicle_assist.cli_r139 import register as _register_r139  # noqa: E402  (UN R139 brake-assist test)

_register_r139(app)

from vehicle_assist.cli_results import register as _register_results  # noqa: E402  (export, compare)

_register_results(app)


def main() -> None:
    from vehicle_assist.scenarios.errors import InputError

    try:
        app()
    except InputError as exc:  # a last net: bad input is one line, never a traceback
        err_console.print(f"error: {exc}", markup=False, highlight=False, soft_wrap=True)
        sys.exit(2)
    except (RecursionError, MemoryError) as exc:
        err_console.print(f"error: the input is too large or too deeply nested ({exc.__class__.__name__})", markup=False)
        sys.exit(2)
    except KeyboardInterrupt:
        err_console.print("interrupted; files already written are complete (atomic writes)")
        sys.exit(130)


if __name__ == "__main__":
    main()
