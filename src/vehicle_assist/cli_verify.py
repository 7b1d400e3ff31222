"""Command line of the verification engine: ``falsify``, ``study``, ``requirements``, ``envelope``.

Registered into the main typer app by :func:`register` (cli.py). Heavy imports happen inside the
commands, so ``vehicle-assist --help`` stays fast. Bad input: one line naming the field, exit 2.
"""
from __future__ import annotations

import math
from pathlib import Path
from typing import List, Optional

import typer
from rich.console import Console
from rich.markup import escape
from rich.table import Table as RichTable

console = Console()
err_console = Console(stderr=True)


def _fail(message: str, code: int = 2) -> None:
    err_console.print(f"error: {message}", markup=False, highlight=False, soft_wrap=True)
    raise typer.Exit(code)


def _num(value) -> str:
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return "nan"
    if isinstance(value, float) and math.isinf(value):
        return "+inf" if value > 0 else "-inf"
    return f"{value:.4g}"


def requirements_table(results, title: str = "requirements (robustness: signed distance to violation)") -> RichTable:
    table = RichTable(title=title)
    for col in ("requirement", "robustness", "unit", "expect", "result", "source"):
        table.add_column(col, overflow="fold")
    for r in results:
        mark = "[green]ok[/]" if r.ok else "[red]FAIL[/]"
        table.add_row(r.id, _num(r.robustness), r.unit, r.expect, mark, r.why)
    return table


def _out(out: Path) -> Path:
    """--out checked before anything runs (not empty, not '/', not a file or under one, writable)."""
    from vehicle_assist.scenarios.errors import InputError
    from vehicle_assist.scenarios.guards import check_out_dir

    try:
        return check_out_dir(str(out))
    except InputError as exc:
        _fail(str(exc))


def _write_failed(exc: OSError, out: Path) -> None:
    _fail(f"cannot write results to {exc.filename or out} ({exc.strerror or exc.__class__.__name__}); "
          "free space or give another --out")


def _memory_guard(envelope: str, sets: list[str], batch: int) -> None:
    """Refuse a search whose runs cannot fit in memory (issue #14: duration x step combinations that each pass
    their range can ask for tens of GiB): a batch of the envelope's longest run (max_duration_s) with --set."""
    import os

    from vehicle_assist.scenarios.errors import InputError
    from vehicle_assist.scenarios.guards import Estimate, estimate_sweep, refuse_past_bounds
    from vehicle_assist.verification.envelope import load_envelope

    try:
        env = load_envelope(envelope, validate=False)
        sc = env.base_scenario.with_sets(*sets, f"run.duration_s={env.model.max_duration_s}")
        est = estimate_sweep(sc, batch, workers=min(batch, os.cpu_count() or 1), chunk=batch)
        refuse_past_bounds(Estimate(f"a batch of {batch} runs of up to {env.model.max_duration_s:g} s",
                                    est.memory_bytes, 0.0), yes=False)
    except InputError as exc:
        _fail(str(exc))


SCHEDULER_HELP = ("dask scheduler address (tcp://host:8786), 'local' (a cluster of processes here) or 'threads'; default "
                  "$VEHICLE_ASSIST_SCHEDULER, else local for >= 20,000 runs (needs the [dist] extra)")


def _session(scheduler: str | None, n_runs: int, envelope: str, sets: list[str]):
    """The backend the runs go to (distributed.session); the envelope's base scenario warms the compile cache."""
    from vehicle_assist import distributed

    warm = None
    if distributed.choose(scheduler, n_runs) == "local":
        from vehicle_assist.verification.envelope import load_envelope

        warm = load_envelope(envelope, validate=False).base_scenario.with_sets(*sets)
    return distributed.session(scheduler, n_runs, say=lambda text: console.print(text, markup=False, highlight=False),
                               warm=warm)


# the files in data/envelopes (a test keeps this list equal to them; reading the folder here would slow --help)
SHIPPED_ENVELOPES = "brake_assist, curve_shift, hill_start_amt, hill_start_ehb, tire_blowout, tire_blowout_closed_loop, tire_blowout_false_alarm, tire_blowout_false_alarm_right, tire_blowout_faults, tire_blowout_faults_right, tire_blowout_right"
RESTRICT_HELP = ("narrow a dimension for every point (repeatable): NAME=LO..HI, NAME=VALUE (pinned) or "
                 "NAME=OPTION[,OPTION...], e.g. braking=brakes")


def _envelope(envelope: str, restrict: list[str]):
    """The envelope object with --restrict applied (checked before anything runs)."""
    from vehicle_assist.scenarios.errors import InputError
    from vehicle_assist.verification.envelope import load_envelope

    try:
        return load_envelope(envelope).restrict_text(restrict)
    except InputError as exc:
        _fail(str(exc))


def _check_budget(name: str, value: int, lo: int, hi: int) -> None:
    if not lo <= value <= hi:
        _fail(f"{name} = {value}: must be between {lo} and {hi}")


def falsify(
    envelope: str = typer.Argument(..., help=f"shipped envelope ({SHIPPED_ENVELOPES}) or an envelope .toml"),
    requirement: str = typer.Option(..., "--requirement", "-r", help="requirement id, e.g. hill_start_amt.no_worse_than_no_assist"),
    budget: int = typer.Option(200, "--budget", "-n", help="maximum number of evaluated points"),
    seed: int = typer.Option(0, "--seed", help="seed of the search (same seed, same result)"),
    optimizer: str = typer.Option("cma", "--optimizer", help="cma (CMA-ES, the cma package) or random"),
    batch: int = typer.Option(8, "--batch", "-b", help="points per batch (run on all cores)"),
    set_: Optional[List[str]] = typer.Option(None, "--set", "-s", help="fixed override for every point (repeatable), e.g. a seeded defect"),
    restrict: Optional[List[str]] = typer.Option(None, "--restrict", "-R", help=RESTRICT_HELP),
    out: Path = typer.Option(Path("out/falsify"), "--out", "-o", help="output directory"),
    keep_going: bool = typer.Option(False, "--keep-going", help="use the whole budget even after a violation; "
                                    "counterexample.toml is then the worst violation, and the log gives their count"),
    scheduler: Optional[str] = typer.Option(None, "--scheduler", help=SCHEDULER_HELP),
) -> None:
    """Search the envelope for the input that minimises a requirement's robustness (stops at the first violation; --keep-going: the worst over the whole budget)."""
    from vehicle_assist.scenarios.errors import InputError
    from vehicle_assist.verification.falsify import OPTIMIZERS, run_falsification, twin_text, write_falsification

    _check_budget("--budget", budget, 1, 1_000_000)
    _check_budget("--batch", batch, 1, 10_000)
    if seed < 0:
        _fail(f"--seed = {seed}: must be >= 0")
    if optimizer not in OPTIMIZERS:
        _fail(f"--optimizer = {optimizer!r}: use one of {', '.join(OPTIMIZERS)}")
    out = _out(out)
    env = _envelope(envelope, list(restrict or []))
    _memory_guard(envelope, list(set_ or []), batch)
    try:
        with _session(scheduler, 2 * budget, envelope, list(set_ or [])):  # 2: a comparative point runs its twin
            result = run_falsification(env, requirement, budget=budget, seed=seed, optimizer=optimizer, batch=batch,
                                       sets=list(set_ or []), stop_at_violation=not keep_going, console=console)
        paths = write_falsification(result, out)
    except InputError as exc:
        _fail(str(exc))
    except OSError as exc:
        _write_failed(exc, out)
    best = result.best
    unit = result.requirement.unit
    cex = result.counterexample
    if cex is not None and keep_going:
        n = len(result.violations)
        console.print(f"[red]{n} violation{'s' if n != 1 else ''}[/], worst after {cex.index + 1}: robustness "
                      f"{_num(cex.robustness)} {escape(unit)} (first after {result.evaluations_to_first} of "
                      f"{len(result.evaluations)} evaluations)\n  {escape(result.envelope.point_name(cex.point))}")
        console.print(f"reproduce it: vehicle-assist run {paths['scenario']}", markup=False)
        if twin_text(result):
            console.print(twin_text(result), markup=False)
    elif cex is not None:
        console.print(f"[red]counterexample[/] after {result.evaluations_to_first} evaluations: robustness "
                      f"{_num(cex.robustness)} {escape(unit)}\n  {escape(result.envelope.point_name(cex.point))}")
        console.print(f"reproduce it: vehicle-assist run {paths['scenario']}", markup=False)
        if twin_text(result):
            console.print(twin_text(result), markup=False)
    else:
        console.print(f"[green]no counterexample[/] in {len(result.evaluations)} evaluations; minimum robustness "
                      f"{_num(best.robustness)} {escape(unit)} at\n  {escape(result.envelope.point_name(best.point))}")
    console.print(f"wrote {', '.join(str(p) for p in paths.values())}", markup=False)


def study(
    envelope: str = typer.Argument(..., help=f"shipped envelope ({SHIPPED_ENVELOPES}) or an envelope .toml"),
    requirement: str = typer.Option(..., "--requirement", "-r", help="requirement id"),
    samples: int = typer.Option(256, "--samples", "-n", help="coverage: number of quasi-random points"),
    method: str = typer.Option("sobol", "--method", help="coverage sampling: sobol, lhs or random"),
    sensitivity: int = typer.Option(0, "--sensitivity", help="Sobol sensitivity: base sample size N (0 = skip; runs N*(D+2) points)"),
    output: str = typer.Option("violated", "--output", help="sensitivity of: violated (1 where robustness < 0) or robustness"),
    seed: int = typer.Option(0, "--seed"),
    set_: Optional[List[str]] = typer.Option(None, "--set", "-s", help="fixed override for every point (repeatable)"),
    restrict: Optional[List[str]] = typer.Option(None, "--restrict", "-R", help=RESTRICT_HELP),
    out: Path = typer.Option(Path("out/study"), "--out", "-o", help="output directory"),
    scheduler: Optional[str] = typer.Option(None, "--scheduler", help=SCHEDULER_HELP),
) -> None:
    """Coverage (Sobol/LHS sampling, pass/fail map) and global sensitivity (SALib Sobol indices) of a requirement."""
    from vehicle_assist.scenarios.errors import InputError
    from vehicle_assist.verification.study import coverage_study, sensitivity_study

    _check_budget("--samples", samples, 1, 1_000_000)
    _check_budget("--sensitivity", sensitivity, 0, 100_000)
    if method not in ("sobol", "lhs", "random"):
        _fail(f"--method = {method!r}: use sobol, lhs or random")
    if output not in ("violated", "robustness"):  # checked before the coverage run writes anything
        _fail(f"--output = {output!r}: use violated or robustness")
    out = _out(out)
    env = _envelope(envelope, list(restrict or []))
    _memory_guard(envelope, list(set_ or []), 16)  # runner.BATCH_CHUNK variants at once
    try:
        with _session(scheduler, 2 * (samples + sensitivity * 10), envelope, list(set_ or [])):  # runs: upper estimate
            cov = coverage_study(env, requirement, samples, method=method, seed=seed, sets=list(set_ or []), out=out,
                                 console=console)
            console.print(f"coverage: {cov['points']} points ({method}), {cov['violations']} violate "
                          f"{requirement}; minimum robustness {_num(cov['min_robustness'])} {cov['unit']}; figure {cov['figure']}")
            if sensitivity:
                sens = sensitivity_study(env, requirement, sensitivity, seed=seed, sets=list(set_ or []), out=out,
                                         console=console, output=output)
                table = RichTable(title=f"Sobol indices of {output} for {requirement} ({sens['points']} points)")
                for col in ("dimension", "S1", "S1 conf", "ST", "ST conf"):
                    table.add_column(col)
                for row in sens["indices"]:
                    table.add_row(row["dimension"], _num(row["S1"]), _num(row["S1_conf"]), _num(row["ST"]), _num(row["ST_conf"]))
                console.print(table)
                console.print(f"figure {sens['figure']}")
    except InputError as exc:
        _fail(str(exc))
    except OSError as exc:
        _write_failed(exc, out)


def requirements_cmd() -> None:
    """List the shipped requirements (id, formula, unit, source clause)."""
    from vehicle_assist.verification.requirements import all_shipped

    table = RichTable(title="shipped requirements")
    for col in ("id", "formula", "unit", "source"):
        table.add_column(col, overflow="fold")
    for rid, r in all_shipped().items():
        table.add_row(rid, r.formula, r.unit, r.why)
    console.print(table)


def envelope_cmd(name: str = typer.Argument(..., help=f"shipped envelope ({SHIPPED_ENVELOPES}) or an envelope .toml")) -> None:
    """Show an envelope's dimensions, ranges and sources (validates the file)."""
    from vehicle_assist.scenarios.errors import InputError
    from vehicle_assist.verification.envelope import load_envelope

    try:
        env = load_envelope(name)
    except InputError as exc:
        _fail(str(exc))
    table = RichTable(title=f"envelope {env.model.name}: base {env.model.base}, baseline {' '.join(env.model.baseline)}")
    for col in ("dimension", "kind", "values", "source"):
        table.add_column(col, overflow="fold")
    for row in env.table_rows():
        table.add_row(row["dimension"], row["kind"], row["values"], row["source"])
    console.print(table)


def register(app: typer.Typer) -> None:
    app.command("falsify")(falsify)
    app.command("study")(study)
    app.command("requirements")(requirements_cmd)
    app.command("envelope")(envelope_cmd)
