"""Parameter sweeps: the product of value lists over dotted paths, run as batches on all cores.

Results go to ``OUT/parts/part-NNNNN.parquet`` (one per chunk, written atomically) and are merged into
``OUT/sweep.parquet``. A sweep that is interrupted resumes: finished parts are kept and skipped.

* ``OUT/sweep.json`` records the sweep: scenario name, ``--set``s, grid, chunk, the scenario hash, the
  parameter hash of the resolved vehicle, the package version and a digest of the package source. A resume
  whose record differs in any of them is refused (an edited scenario or vehicle file, or another version
  of the code, would mix stale rows with new ones).
* Each part carries in its Parquet metadata the digest of the sweep record, its variant range and the
  parameter hash of every variant it holds; a part that does not match (or cannot be read) is recomputed.
* ``OUT/.vehicle-assist.lock`` (O_EXCL, ``pid host``) keeps a second sweep out of the directory while one
  runs; a lock left by a dead process is taken over.
* Every option and every value of every axis is validated, and the time and memory are estimated, before
  anything is written; a sweep that fails before its first part leaves nothing behind.
* Backends (``scheduler``, see :mod:`vehicle_assist.distributed`): this process's threads, or dask workers
  (a local cluster of processes, or any scheduler address). Both compute a part with :func:`compute_part`
  (variants built from the grid indices by :func:`combo_at`), so they write the same files bit for bit and
  a sweep begun on one resumes on the other. On dask, at most two parts per worker thread are in flight and
  each is written by the client as it arrives; ``sweep.parquet`` is streamed from the parts one at a time.
"""
from __future__ import annotations

import hashlib
import json
import math
import shutil
from pathlib import Path

import pyarrow as pa
import pyarrow.parquet as pq

from vehicle_assist.io.results import atomic_path, write_json
from vehicle_assist.scenarios.errors import InputError, plain
from vehicle_assist.scenarios.guards import MAX_DEPTH, OutputLock, estimate_sweep, refuse_past_bounds
from vehicle_assist.scenarios.loader import LoadedScenario, parse_value
from vehicle_assist.scenarios.runner import simulate_batch

MAX_CHUNK = 100_000
MAX_WORKERS = 64
PART_META_KEY = b"vehicle_assist.sweep_part"


def parse_grid(grid: list[str]) -> list[tuple[str, list]]:
    axes: list[tuple[str, list]] = []
    for item in grid:
        if "=" not in item:
            raise InputError(f"--grid {item!r}: write it as dotted.path=v1,v2,...")
        path, values = item.split("=", 1)
        path = path.strip()
        if not path or path.count(".") >= MAX_DEPTH:
            raise InputError(f"--grid {item[:60]!r}: give a dotted path of at most {MAX_DEPTH} levels before '='")
        parsed = [parse_value(v.strip()) for v in _split_top(values) if v.strip()]
        if not parsed:
            raise InputError(f"--grid {item!r}: no values")
        if any(path == p for p, _ in axes):
            raise InputError(f"--grid {path}: the axis is given twice; give each path once with all its values")
        axes.append((path, parsed))
    return axes


def _split_top(text: str) -> list[str]:
    """Split on commas outside brackets and quotes: ``[1,2],[3,4]`` -> ``["[1,2]", "[3,4]"]`` (a list-valued
    parameter such as ``driver.accelerator.frac`` can be an axis)."""
    out, depth, quote, start = [], 0, "", 0
    for i, ch in enumerate(text):
        if quote:
            if ch == quote:
                quote = ""
        elif ch in "\"'":
            quote = ch
        elif ch in "[{":
            depth += 1
        elif ch in "]}":
            depth -= 1
        elif ch == "," and depth == 0:
            out.append(text[start:i])
            start = i + 1
    out.append(text[start:])
    return out


def _assignment(path: str, value) -> str:
    return f"{path}={json.dumps(value) if isinstance(value, (str, bool, list, dict)) else value}"


def _column(values: list) -> list:
    """An axis column: list/dict values as their JSON text (one Parquet type per column)."""
    if any(isinstance(v, (list, dict)) for v in values):
        return [json.dumps(v) for v in values]
    return values


def _with_units_and_provenance(table: pa.Table, spec: dict) -> pa.Table:
    """Each column carries its ``unit`` (from the name suffix; an axis in file units such as ``_deg`` keeps
    that unit) and the schema carries the sweep record (scenario, sets, grid, hashes, package version and
    source digest) under ``vehicle_assist.sweep`` plus the date it was merged."""
    import datetime

    from vehicle_assist.units import unit_of

    fields = [pa.field(f.name, f.type, metadata={"unit": unit_of(f.name.rsplit(".", 1)[-1])}) for f in table.schema]
    meta = {b"vehicle_assist.sweep": json.dumps(spec).encode(),
            b"created_utc": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds").encode()}
    return table.cast(pa.schema(fields, metadata=meta))


def _package_source_digest() -> str:
    import vehicle_assist

    root = Path(vehicle_assist.__file__).resolve().parent
    digest = hashlib.sha256()
    for p in sorted(root.rglob("*.py")):
        digest.update(p.relative_to(root).as_posix().encode())
        digest.update(p.read_bytes())
    return digest.hexdigest()[:16]


def sweep_record(base: LoadedScenario, axes: list[tuple[str, list]], chunk: int) -> dict:
    import vehicle_assist

    return {"scenario": base.name, "sets": list(base.sets), "grid": [[p, v] for p, v in axes], "chunk": chunk,
            "scenario_hash": base.scenario_hash(), "parameter_hash": base.parameter_hash(),
            "package_version": vehicle_assist.__version__, "package_source": _package_source_digest()}


def _digest(obj) -> str:
    return hashlib.sha256(json.dumps(obj, sort_keys=True, default=str).encode()).hexdigest()[:16]


def _check_options(chunk: int, workers: int | None) -> None:
    if isinstance(chunk, bool) or not isinstance(chunk, int) or not 1 <= chunk <= MAX_CHUNK:
        raise InputError(f"--chunk {chunk}: give the number of variants per part file, 1 to {MAX_CHUNK}")
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int) or not 1 <= workers <= MAX_WORKERS):
        raise InputError(f"--workers {workers}: give 0 (all cores) or a thread count from 1 to {MAX_WORKERS}")


def _compare_record(old, spec: dict, out: Path, spec_path: Path) -> None:
    if not isinstance(old, dict) or not {"scenario", "grid", "chunk"} <= set(old):
        raise InputError(f"{plain(str(spec_path))}: not a sweep record (corrupt or edited); delete {plain(str(out))} or use another --out")
    if any(old.get(k) != spec[k] for k in ("scenario", "sets", "grid", "chunk")):
        raise InputError(f"{plain(str(out))}: holds a different sweep ({plain(str(old.get('scenario')))}, "
                         f"{plain(str(old.get('grid')))[:200]}); use another --out or delete it")
    # package_source is recorded for provenance but not compared: any edit of the working tree would
    # refuse every resume during development; the released version is the contract
    changed = [k for k in ("scenario_hash", "parameter_hash", "package_version") if old.get(k) != spec[k]]
    if changed:
        what = {"scenario_hash": "the scenario file", "parameter_hash": "the vehicle parameters",
                "package_version": "the package version", "package_source": "the package source"}
        raise InputError(f"{plain(str(out))}: its parts were computed with another version of "
                         f"{', '.join(what[k] for k in changed)} ({', '.join(f'{k} {old.get(k)} != {spec[k]}' for k in changed)}); "
                         "resuming would mix stale rows; delete it or use another --out")


def _part_found(part: Path) -> dict | str:
    """The variant record a part file carries in its metadata, or the reason it cannot be read."""
    try:
        meta = pq.read_schema(part).metadata or {}
        found = json.loads(meta.get(PART_META_KEY, b"{}"))
    except Exception as exc:  # pyarrow raises several types for a damaged file
        return f"unreadable ({exc.__class__.__name__})"
    return found if isinstance(found, dict) else "computed for another sweep or other parameters"


def _part_ok(part: Path, expected: dict) -> str:
    """'' if ``part`` is a readable part of this sweep with these variants, else the reason it is not."""
    found = _part_found(part)
    if isinstance(found, str):
        return found
    return "" if found == expected else "computed for another sweep or other parameters"


def combo_at(axes: list[tuple[str, list]], i: int) -> list:
    """The values of variant ``i`` (the order of ``itertools.product``: the last axis varies fastest)."""
    out = []
    for _, values in reversed(axes):
        i, r = divmod(i, len(values))
        out.append(values[r])
    return out[::-1]


def compute_part(base: LoadedScenario, axes: list[tuple[str, list]], spec_digest: str, lo: int, hi: int,
                 found: dict | str | None = None, workers: int | None = None, progress=None):
    """Variants ``lo..hi-1`` of the sweep: ``(expected part record, table)``, or ``(expected, None)`` when
    ``found`` (the record of an existing part file) already matches. One function for the thread path and
    for the dask workers, so both write the same part files."""
    block = [combo_at(axes, i) for i in range(lo, hi)]
    try:
        variants = [base.with_sets(*[_assignment(p, v) for (p, _), v in zip(axes, combo)]) for combo in block]
    except InputError as exc:
        raise InputError(f"variants {lo}..{hi - 1}: {exc}") from None
    expected = {"sweep": spec_digest, "lo": lo, "hi": hi,
                "parameters": _digest([v.parameter_hash() for v in variants])}
    if found == expected:
        return expected, None
    res = simulate_batch(variants, workers=workers, progress=progress)
    columns: dict[str, list] = {"variant": list(range(lo, hi))}
    for j, (path, _) in enumerate(axes):
        columns[path] = _column([combo[j] for combo in block])
    names = sorted({m for d in res.metrics for m in d})
    for name in names:
        columns[name] = [d.get(name, float("nan")) for d in res.metrics]
    columns["checks_ok"] = res.checks_ok
    table = pa.table(columns).replace_schema_metadata({PART_META_KEY: json.dumps(expected).encode()})
    return expected, table


def _part_task(base: LoadedScenario, axes, spec_digest: str, lo: int, hi: int, found):
    """On a dask worker: one part, on the worker's one thread."""
    _, table = compute_part(base, axes, spec_digest, lo, hi, found, workers=1)
    return lo, hi, table


def _write_part(table: pa.Table, part: Path) -> None:
    with atomic_path(part) as tmp:
        pq.write_table(table, tmp)


def _progress_bar(console):
    from rich.progress import (BarColumn, MofNCompleteColumn, Progress, ProgressColumn, TextColumn,
                               TimeElapsedColumn, TimeRemainingColumn)
    from rich.text import Text

    class Rate(ProgressColumn):
        def render(self, task):
            speed = task.finished_speed or task.speed
            return Text(f"{speed:,.0f} variants/s" if speed else "", style="progress.data.speed")

    return Progress(TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(), Rate(),
                    TimeElapsedColumn(), TextColumn("eta"), TimeRemainingColumn(), console=console, transient=True)


def _merge_parts(parts: Path, n_parts: int, spec: dict, final: Path) -> int:
    """Stream the parts into ``final`` one at a time (memory: one part), columns unified over all parts."""
    paths = [parts / f"part-{k:05d}.parquet" for k in range(n_parts)]
    schemas = []
    for part in paths:
        try:
            schemas.append(pq.read_schema(part).remove_metadata())
        except Exception as exc:
            raise InputError(f"{plain(str(part))}: cannot read it back ({exc.__class__.__name__}); delete it and run the "
                             "sweep again to recompute it") from None
    unified = pa.unify_schemas(schemas, promote_options="default")
    target = _with_units_and_provenance(unified.empty_table(), spec).schema
    rows = 0
    with atomic_path(final) as tmp:
        with pq.ParquetWriter(tmp, target) as writer:
            for part in paths:
                try:
                    t = pq.read_table(part).replace_schema_metadata(None)
                except Exception as exc:
                    raise InputError(f"{plain(str(part))}: cannot read it back ({exc.__class__.__name__}); delete it and "
                                     "run the sweep again to recompute it") from None
                cols = [t.column(f.name) if f.name in t.column_names else pa.nulls(t.num_rows, f.type) for f in unified]
                writer.write_table(pa.Table.from_arrays(cols, schema=unified).cast(target))
                rows += t.num_rows
    return rows


def run_sweep(base: LoadedScenario, grid: list[str], out: Path, chunk: int = 500, workers: int | None = None, console=None,
              yes: bool = True, say=None, scheduler: str | None = None):
    """Run the sweep; return (path of sweep.parquet, rows). ``yes=False`` refuses past the stated bounds.

    ``scheduler``: a dask scheduler address, ``local`` or ``threads`` (default: ``$VEHICLE_ASSIST_SCHEDULER``,
    else a local dask cluster for ``distributed.LARGE_RUNS`` variants or more, threads below; see
    :mod:`vehicle_assist.distributed`). Every backend writes the same part files, so a sweep started on one
    resumes on another."""
    from vehicle_assist import distributed

    _check_options(chunk, workers)
    axes = parse_grid(grid)
    # validate every value of every axis before anything is written (a typo must not leave files behind)
    for path, values in axes:
        for v in values:
            if path == "vehicle.base" and isinstance(v, str):  # another layout fails on its inputs first: say why
                from vehicle_assist.scenarios.loader import load_vehicle

                layout = load_vehicle(v).layout
                if layout != base.layout:
                    raise InputError(f"--grid {path}={plain(v)}: that vehicle has layout {layout} but the sweep's scenario "
                                     f"uses {base.layout}; a sweep runs one layout (sweep each layout separately)")
            variant = base.with_sets(_assignment(path, v))
            if variant.layout != base.layout:
                raise InputError(f"--grid {path}={plain(str(v))}: that vehicle has layout {variant.layout} but the sweep's "
                                 f"scenario uses {base.layout}; a sweep runs one layout (sweep each layout separately)")
    n_total = math.prod(len(v) for _, v in axes)
    target = distributed.choose(scheduler, n_total)  # a bad --scheduler fails here, before anything is written
    import os

    n_workers = workers or min(os.cpu_count() or 1, max(n_total, 1))
    estimate = estimate_sweep(base, n_total, n_workers, chunk)
    refuse_past_bounds(estimate, yes, Path(out))
    if say is not None:
        say(f"estimate: {estimate.describe()}")
    out = Path(out)
    created = not out.exists()
    out.mkdir(parents=True, exist_ok=True)
    parts = out / "parts"
    spec = sweep_record(base, axes, chunk)
    spec_digest = _digest(spec)
    spec_path = out / "sweep.json"
    computed = 0
    n_parts = (n_total + chunk - 1) // chunk
    with OutputLock(out):
        wrote_spec = False
        try:
            if spec_path.exists():
                try:
                    old = json.loads(spec_path.read_text(encoding="utf-8"))
                except (OSError, UnicodeDecodeError, ValueError):
                    raise InputError(f"{plain(str(spec_path))}: not a sweep record (corrupt); delete {plain(str(out))} "
                                     "or use another --out") from None
                _compare_record(old, spec, out, spec_path)
            else:
                write_json(spec, spec_path)
                wrote_spec = True
            parts.mkdir(parents=True, exist_ok=True)

            def found_at(part: Path):
                return _part_found(part) if part.exists() else None

            def recomputing(part: Path, found) -> None:
                if found is not None and say is not None:
                    say(f"{part}: {found if isinstance(found, str) else 'computed for another sweep or other parameters'}; "
                        "recomputing it")

            with _progress_bar(console) as progress:
                task = progress.add_task("sweep", total=n_total)
                if target is None:
                    for k in range(n_parts):
                        part = parts / f"part-{k:05d}.parquet"
                        lo, hi = k * chunk, min((k + 1) * chunk, n_total)
                        found = found_at(part)
                        _, table = compute_part(base, axes, spec_digest, lo, hi, found, workers,
                                                progress=lambda n: progress.advance(task, n))
                        if table is None:
                            progress.advance(task, hi - lo)
                            continue
                        recomputing(part, found)
                        _write_part(table, part)
                        computed += 1
                else:
                    with distributed.session(scheduler, n_total, workers=workers, say=say, warm=base) as backend:
                        progress.update(task, description=f"sweep on {backend.describe()}")
                        base_f = backend.scatter(base)
                        found_of: dict[int, object] = {}

                        def args():
                            for k in range(n_parts):
                                found_of[k] = found_at(parts / f"part-{k:05d}.parquet")
                                yield base_f, axes, spec_digest, k * chunk, min((k + 1) * chunk, n_total), found_of[k]

                        for lo, hi, table in backend.imap_unordered(_part_task, args(), key_prefix="sweep-part"):
                            k = lo // chunk
                            found = found_of.pop(k, None)
                            if table is not None:
                                part = parts / f"part-{k:05d}.parquet"
                                recomputing(part, found)
                                _write_part(table, part)
                                computed += 1
                            progress.advance(task, hi - lo)
        except BaseException:
            if computed == 0 and wrote_spec:  # nothing of value written: leave nothing behind
                spec_path.unlink(missing_ok=True)
                if parts.is_dir() and not any(parts.iterdir()):
                    parts.rmdir()
            raise
        finally:
            if created and computed == 0 and not spec_path.exists():
                shutil.rmtree(out, ignore_errors=True)
        final = out / "sweep.parquet"
        rows = _merge_parts(parts, n_parts, spec, final)
    return final, rows
