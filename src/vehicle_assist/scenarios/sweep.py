"""Parameter sweeps: the product of value lists over dotted paths, run as batches on all cores.

Results go to ``OUT/parts/part-NNNNN.parquet`` (one per chunk, written atomically) and are merged into
``OUT/sweep.parquet``. A sweep that is interrupted resumes: finished parts are kept and skipped; the
grid is stored in ``OUT/sweep.json`` and a resume with a different grid is refused. Every value of
every axis is validated before anything is written.
"""
from __future__ import annotations

import itertools
import json
from pathlib import Path

import pyarrow as pa
import pyarrow.parquet as pq

from vehicle_assist.io.results import atomic_path, write_json
from vehicle_assist.scenarios.errors import InputError
from vehicle_assist.scenarios.loader import LoadedScenario, parse_value
from vehicle_assist.scenarios.runner import simulate_batch


def parse_grid(grid: list[str]) -> list[tuple[str, list]]:
    axes = []
    for item in grid:
        if "=" not in item:
            raise InputError(f"--grid {item!r}: write it as dotted.path=v1,v2,...")
        path, values = item.split("=", 1)
        parsed = [parse_value(v.strip()) for v in values.split(",") if v.strip()]
        if not parsed:
            raise InputError(f"--grid {item!r}: no values")
        axes.append((path.strip(), parsed))
    return axes


def run_sweep(base: LoadedScenario, grid: list[str], out: Path, chunk: int = 500, workers: int | None = None, console=None):
    axes = parse_grid(grid)
    # validate every value of every axis before anything is written (a typo must not leave files behind)
    for path, values in axes:
        for v in values:
            base.with_sets(f"{path}={json.dumps(v) if isinstance(v, str) else v}")
    out = Path(out)
    parts = out / "parts"
    spec = {"scenario": base.name, "sets": list(base.sets), "grid": [[p, v] for p, v in axes], "chunk": chunk}
    spec_path = out / "sweep.json"
    if spec_path.exists():
        old = json.loads(spec_path.read_text())
        if old != spec:
            raise InputError(f"{out}: holds a different sweep ({old.get('scenario')}, {old.get('grid')}); use another --out or delete it")
    else:
        write_json(spec, spec_path)
    parts.mkdir(parents=True, exist_ok=True)
    combos = list(itertools.product(*[v for _, v in axes]))
    n_parts = (len(combos) + chunk - 1) // chunk
    from rich.progress import Progress

    with Progress(console=console, transient=True) as progress:
        task = progress.add_task("sweep", total=len(combos))
        for k in range(n_parts):
            part = parts / f"part-{k:05d}.parquet"
            lo, hi = k * chunk, min((k + 1) * chunk, len(combos))
            if part.exists():
                progress.advance(task, hi - lo)
                continue
            variants = [base.with_sets(*[f"{p}={json.dumps(v) if isinstance(v, str) else v}" for (p, _), v in zip(axes, combos[i])])
                        for i in range(lo, hi)]
            res = simulate_batch(variants, workers=workers, progress=lambda n: progress.advance(task, n))
            columns: dict[str, list] = {"variant": list(range(lo, hi))}
            for j, (path, _) in enumerate(axes):
                columns[path] = [combos[i][j] for i in range(lo, hi)]
            names = sorted({m for d in res.metrics for m in d})
            for name in names:
                columns[name] = [d.get(name, float("nan")) for d in res.metrics]
            columns["checks_ok"] = res.checks_ok
            table = pa.table(columns)
            with atomic_path(part) as tmp:
                pq.write_table(table, tmp)
    tables = [pq.read_table(parts / f"part-{k:05d}.parquet") for k in range(n_parts)]
    merged = pa.concat_tables(tables, promote_options="default")
    final = out / "sweep.parquet"
    with atomic_path(final) as tmp:
        pq.write_table(merged, tmp)
    return final, merged.num_rows
