"""``vehicle-assist r139``: the UN R139 brake-assist test of the ESP sedan (procedures/r139.py), with its verdict.

Registered into the main typer app by :func:`register` (cli.py). Exit code 0 when the verdict passes, 1 when it
fails, 2 on bad input (one line).
"""
from __future__ import annotations

import json
from pathlib import Path
from typing import List, Optional

import typer
from rich.console import Console
from rich.markup import escape
from rich.table import Table as RichTable

console = Console()


def register(app: typer.Typer) -> None:
    @app.command("r139")
    def r139(
        set_: Optional[List[str]] = typer.Option(None, "--set", help="override, e.g. vehicle.brake_assist.on_rate_bar_per_s=3000"),
        out: Optional[Path] = typer.Option(None, "--out", help="write r139.json here"),
    ) -> None:
        """UN R139 brake-assist procedure (reference tests for F_ABS and a_ABS, category B activation test)."""
        from vehicle_assist.procedures.r139 import NOT_CONFIRMED, run_r139
        from vehicle_assist.scenarios.errors import InputError

        err = Console(stderr=True)
        try:
            if out is not None:  # --out checked before anything runs (not '/', not a file or under one, writable)
                from vehicle_assist.scenarios.guards import check_out_dir

                out = check_out_dir(str(out))
            res = run_r139(list(set_ or []))
        except InputError as exc:
            err.print(f"error: {exc}", markup=False, highlight=False, soft_wrap=True)
            raise typer.Exit(2)
        table = RichTable(title="UN R139 brake-assist test (category B), sedan_1p8t with HBA of paper 002")
        for col in ("quantity", "value", "bound", "result", "clause"):
            table.add_column(col, overflow="fold")
        for row in res.rows:
            mark = "-" if not row.get("verdict", True) else ("[green]pass[/]" if row["pass"] else "[red]FAIL[/]")
            unit = "" if row["unit"] == "-" else f" {row['unit']}"
            table.add_row(escape(row["quantity"]), f"{row['value']:.4g}{unit}", escape(row["bound"]), mark,
                          escape(row["clause"]))
        console.print(table)
        w, b = res.window, res.baseline
        console.print(f"HBA on : activation {1000 * w['hba_activation_time_s']:.0f} ms after t0, stopping distance "
                      f"{w['stopping_distance_m']:.1f} m; HBA off: {b['stopping_distance_m']:.1f} m (from 100 km/h)")
        console.print("not confirmed against the official text: " + "; ".join(NOT_CONFIRMED), markup=False)
        verdict = "PASS" if res.passed else "FAIL"
        console.print(f"verdict: {verdict} (regulation mode 0.85*a_ABS [recollection] and paper mode 0.70*a_ABS)",
                      markup=False)
        if out is not None:
            try:
                out.mkdir(parents=True, exist_ok=True)
                (out / "r139.json").write_text(json.dumps({"f_abs_n": res.f_abs_n, "a_abs_mps2": res.a_abs_mps2,
                                                           "rows": res.rows, "hba_on": w, "hba_off": b,
                                                           "verdict": verdict, "not_confirmed": list(NOT_CONFIRMED)},
                                                          indent=2, default=float))
            except OSError as exc:
                err.print(f"error: cannot write {exc.filename or out} ({exc.strerror or exc.__class__.__name__}); "
                          "free space or give another --out", markup=False, highlight=False, soft_wrap=True)
                raise typer.Exit(2)
        raise typer.Exit(0 if res.passed else 1)
