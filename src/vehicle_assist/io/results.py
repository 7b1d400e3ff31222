"""Writing and reading simulation results: traces (Parquet, CSV), metrics (JSON) and the run bundle.

Why this module exists: a run's outputs are evidence (paper reproductions, golden traces), so they must
be exact and never half-written.

* **Atomic.** Every file is written to a temporary file in the target's directory, flushed, fsync'ed and
  then moved over the target with :func:`os.replace`. A crash or an exception leaves either the old file
  or the new one, never a truncated mix, and no temporary file behind.
* **Exact.** Parquet stores float64 bit for bit; CSV prints every float with ``%.17g``, which round-trips
  through ``float()`` exactly.
* **Self-describing.** Parquet carries each channel's unit and description in the field metadata and the
  trace's ``meta`` and events in the schema metadata (:meth:`Trace.to_arrow`); CSV has a second header
  row with the units (``unit_of``; ``1`` for dimensionless, empty if the suffix is unknown).
* **Strict JSON.** NaN and infinities become ``null`` (JSON has no NaN), numpy scalars/arrays become
  plain numbers/lists.

Channels stay in SI here; conversion to rpm, bar or km/h happens only in plots and tables (``report/``).
"""
from __future__ import annotations

import contextlib
import dataclasses
import io
import json
import math
import os
import tempfile
from collections.abc import Iterator, Mapping
from pathlib import Path
from typing import Any

import numpy as np

from vehicle_assist.core.trace import Event, Trace
from vehicle_assist.units import unit_of

__all__ = [
    "atomic_write_bytes",
    "atomic_write_text",
    "atomic_path",
    "write_trace_parquet",
    "read_trace_parquet",
    "write_trace_csv",
    "trace_csv_text",
    "write_json",
    "jsonable",
    "write_run_outputs",
]

# Schema-metadata key under which Trace.to_arrow stores the events (everything else is ``meta``).
_EVENTS_KEY = "events"


def _current_umask() -> int:
    # os.umask can only be read by setting it; done once, at import, so threads never race on it.
    mask = os.umask(0)
    os.umask(mask)
    return mask


_FILE_MODE = 0o666 & ~_current_umask()


# -- atomic writing --------------------------------------------------------------------------------
def _final_mode(path: Path) -> int:
    """Mode for the new file: the old file's mode if it exists, else what ``open()`` would give."""
    try:
        return os.stat(path).st_mode & 0o7777
    except FileNotFoundError:
        return _FILE_MODE


def _fsync_dir(directory: Path) -> None:
    """Make the rename itself durable (POSIX); a no-op where directories cannot be opened."""
    try:
        fd = os.open(directory, os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:
        pass
    finally:
        os.close(fd)


def _remove_quietly(path: str | Path) -> None:
    with contextlib.suppress(FileNotFoundError):
        os.remove(path)


@contextlib.contextmanager
def atomic_path(path: str | Path) -> Iterator[Path]:
    """Yield a temporary path next to ``path``; on a clean exit it replaces ``path`` atomically.

    For writers that want a file name rather than bytes (e.g. ``pyarrow.parquet.write_table``). On any
    exception the temporary file is removed, ``path`` is left untouched and the exception propagates.
    """
    target = Path(path)
    target.parent.mkdir(parents=True, exist_ok=True)
    with tempfile.NamedTemporaryFile(
        delete=False, dir=target.parent, prefix=f".{target.name}.", suffix=".tmp"
    ) as handle:
        tmp = Path(handle.name)
    try:
        yield tmp
        with open(tmp, "rb+") as handle:
            os.fsync(handle.fileno())
        os.chmod(tmp, _final_mode(target))
        os.replace(tmp, target)
    except BaseException:
        _remove_quietly(tmp)
        raise
    _fsync_dir(target.parent)


def atomic_write_bytes(path: str | Path, data: bytes) -> Path:
    """Write ``data`` to ``path`` atomically (temp file in the same directory, fsync, ``os.replace``)."""
    target = Path(path)
    target.parent.mkdir(parents=True, exist_ok=True)
    handle = tempfile.NamedTemporaryFile(
        delete=False, dir=target.parent, prefix=f".{target.name}.", suffix=".tmp"
    )
    try:
        with handle:
            handle.write(data)
            handle.flush()
            os.fsync(handle.fileno())
        os.chmod(handle.name, _final_mode(target))
        os.replace(handle.name, target)
    except BaseException:
        _remove_quietly(handle.name)
        raise
    _fsync_dir(target.parent)
    return target


def atomic_write_text(path: str | Path, text: str, encoding: str = "utf-8") -> Path:
    """Write ``text`` to ``path`` atomically; newlines are written as given (no platform translation)."""
    return atomic_write_bytes(path, text.encode(encoding))


# -- traces ----------------------------------------------------------------------------------------
def write_trace_parquet(trace: Trace, path: str | Path) -> Path:
    """Write ``trace`` as Parquet (float64 columns, units/descriptions/meta/events in metadata), atomically."""
    import pyarrow.parquet as pq

    table = trace.to_arrow()
    target = Path(path)
    with atomic_path(target) as tmp:
        pq.write_table(table, tmp)
    return target


def _decode(raw: Mapping[bytes, bytes] | None) -> dict[str, str]:
    if not raw:
        return {}
    return {k.decode("utf-8"): v.decode("utf-8") for k, v in raw.items()}


def read_trace_parquet(path: str | Path) -> Trace:
    """Read a trace written by :func:`write_trace_parquet`: channels, descriptions, meta and events."""
    import pyarrow.parquet as pq

    table = pq.read_table(Path(path))
    channels: dict[str, np.ndarray] = {}
    descriptions: dict[str, str] = {}
    for field in table.schema:
        channels[field.name] = np.array(table.column(field.name).to_numpy(), dtype=np.float64)
        description = _decode(field.metadata).get("description", "")
        if description:
            descriptions[field.name] = description
    meta = _decode(table.schema.metadata)
    events_json = meta.pop(_EVENTS_KEY, "[]")
    events = [Event(**{**e, "time_s": float(e["time_s"])}) for e in json.loads(events_json)]
    return Trace(channels, descriptions, meta, events)


def trace_csv_text(trace: Trace) -> str:
    """The CSV text of ``trace``: names row, units row, then rows of ``%.17g`` floats (exact round trip)."""
    names = trace.names
    units = [unit_of(name) for name in names]
    buffer = io.StringIO()
    buffer.write(",".join(names) + "\n")
    buffer.write(",".join(units) + "\n")
    if len(trace):
        data = np.column_stack([np.asarray(trace.channels[n], dtype=np.float64) for n in names])
        np.savetxt(buffer, data, fmt="%.17g", delimiter=",", newline="\n")
    return buffer.getvalue()


def write_trace_csv(trace: Trace, path: str | Path) -> Path:
    """Write ``trace`` as CSV (see :func:`trace_csv_text`), atomically."""
    return atomic_write_text(path, trace_csv_text(trace))


# -- JSON ------------------------------------------------------------------------------------------
def jsonable(obj: Any) -> Any:
    """``obj`` as plain JSON types; NaN/inf -> None, numpy -> Python, Path -> str, Event -> dict."""
    if obj is None or isinstance(obj, (bool, str)):
        return obj
    if isinstance(obj, (float, np.floating)):
        value = float(obj)
        return value if math.isfinite(value) else None
    if isinstance(obj, (int, np.integer)):
        return int(obj)
    if isinstance(obj, np.bool_):
        return bool(obj)
    if isinstance(obj, np.ndarray):
        return jsonable(obj.tolist())
    if isinstance(obj, Event):
        return jsonable(obj.as_dict())
    if isinstance(obj, Path):
        return str(obj)
    if isinstance(obj, Mapping):
        return {str(k): jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [jsonable(v) for v in obj]
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        return jsonable(dataclasses.asdict(obj))
    raise TypeError(f"cannot write {type(obj).__name__} as JSON")


def write_json(obj: Any, path: str | Path) -> Path:
    """Write ``obj`` as indented JSON (key order kept, NaN/inf as ``null``), atomically."""
    text = json.dumps(jsonable(obj), indent=2, sort_keys=False, allow_nan=False, ensure_ascii=False)
    return atomic_write_text(path, text + "\n")


# -- one run ---------------------------------------------------------------------------------------
def write_run_outputs(
    trace: Trace,
    metrics: Mapping[str, float],
    out_dir: str | Path,
    title: str,
    checks: list[dict] | None = None,
    plot: bool = True,
    requirements: list[dict] | None = None,
) -> dict[str, Path]:
    """Write the outputs of one run into ``out_dir`` and return their paths.

    Keys: ``parquet`` (trace.parquet), ``csv`` (trace.csv), ``metrics`` (metrics.json holding
    ``{"metrics", "checks", "events", "meta"}``) and ``overview`` (overview.png).
    """
    from vehicle_assist.report.plots import overview_png

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    paths = {
        "parquet": write_trace_parquet(trace, out / "trace.parquet"),
        "csv": write_trace_csv(trace, out / "trace.csv"),
        "metrics": write_json(
            {
                "metrics": dict(metrics),
                "checks": list(checks or []),
                "requirements": list(requirements or []),
                "events": [e.as_dict() for e in trace.events],
                "meta": dict(trace.meta),
            },
            out / "metrics.json",
        ),
    }
    if plot:
        paths["overview"] = overview_png(trace, out / "overview.png", title)
    return paths
