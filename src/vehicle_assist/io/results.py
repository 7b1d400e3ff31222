"""Writing and reading simulation results: traces (Parquet, CSV), metrics (JSON) and the run bundle.

Why this module exists: a run's outputs are evidence (paper reproductions, golden traces), so they must
be exact and never half-written.

* **Atomic.** Every file is written to a temporary file in the target's directory, flushed, fsync'ed and
  then moved over the target with :func:`os.replace`. A crash or an exception leaves either the old file
  or the new one, never a truncated mix, and no temporary file behind.
* **Exact.** Parquet stores float64 bit for bit; CSV prints every float with ``%.17g``, which round-trips
  through ``float()`` exactly.
* **Self-describing.** Parquet carries each channel's unit and description in the field metadata and the
  trace's ``meta`` and events in the schema metadata (:meth:`Trace.to_arrow`); CSV has one header row
  (``pandas.read_csv`` gives float columns) and a JSON sidecar ``<stem>.units.json`` with the units
  (``unit_of``; ``1`` for dimensionless, empty if the suffix is unknown), descriptions, mode names, meta
  and events; MDF4 (:mod:`vehicle_assist.io.mdf`) carries all of them in the file.
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
    "read_trace_csv",
    "csv_sidecar_path",
    "trace_csv_text",
    "write_trace",
    "read_run",
    "TRACE_FORMATS",
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
    """The CSV text of ``trace``: one names row, then rows of ``%.17g`` floats (exact round trip).

    No units row: ``pandas.read_csv`` gives float columns. Units, descriptions, mode names, meta and
    events are in the JSON sidecar written next to the file (:func:`csv_sidecar_path`)."""
    names = trace.names
    buffer = io.StringIO()
    buffer.write(",".join(names) + "\n")
    if len(trace):
        data = np.column_stack([np.asarray(trace.channels[n], dtype=np.float64) for n in names])
        np.savetxt(buffer, data, fmt="%.17g", delimiter=",", newline="\n")
    return buffer.getvalue()


def csv_sidecar_path(path: str | Path) -> Path:
    """``trace.csv`` -> ``trace.units.json`` (units, descriptions, mode names, meta and events of the CSV)."""
    path = Path(path)
    return path.with_name(path.stem + ".units.json")


def write_trace_csv(trace: Trace, path: str | Path) -> Path:
    """Write ``trace`` as CSV (see :func:`trace_csv_text`) and its JSON sidecar, atomically."""
    target = atomic_write_text(path, trace_csv_text(trace))
    write_json({"units": trace.units, "descriptions": dict(trace.descriptions),
                "mode_names": _mode_names(trace), "meta": dict(trace.meta),
                "events": [e.as_dict() for e in trace.events]}, csv_sidecar_path(target))
    return target


def _mode_names(trace: Trace) -> dict:
    from vehicle_assist.io.mdf import mode_names

    return mode_names(trace)


def read_trace_csv(path: str | Path) -> Trace:
    """Read a CSV written by :func:`write_trace_csv` (with its sidecar, if present) as a :class:`Trace`."""
    path = Path(path)
    with open(path, encoding="utf-8") as handle:
        names = handle.readline().strip().split(",")
        data = np.loadtxt(handle, delimiter=",", ndmin=2, dtype=np.float64)
    data = data.reshape(-1, len(names))
    channels = {name: np.ascontiguousarray(data[:, j]) for j, name in enumerate(names)}
    descriptions: dict[str, str] = {}
    meta: dict[str, str] = {}
    events: list[Event] = []
    sidecar = csv_sidecar_path(path)
    if sidecar.is_file():
        doc = json.loads(sidecar.read_text(encoding="utf-8"))
        descriptions = dict(doc.get("descriptions", {}))
        meta = {k: str(v) for k, v in doc.get("meta", {}).items()}
        events = [Event(**{**e, "time_s": float(e["time_s"])}) for e in doc.get("events", [])]
    return Trace(channels, descriptions, meta, events)


TRACE_FORMATS = ("parquet", "csv", "mdf4")
_SUFFIX = {"parquet": ".parquet", "csv": ".csv", "mdf4": ".mf4"}


def write_trace(trace: Trace, path: str | Path, fmt: str) -> Path:
    """Write ``trace`` in format ``fmt`` (parquet, csv or mdf4) to ``path``."""
    if fmt == "parquet":
        return write_trace_parquet(trace, path)
    if fmt == "csv":
        return write_trace_csv(trace, path)
    if fmt == "mdf4":
        from vehicle_assist.io.mdf import write_trace_mdf4

        return write_trace_mdf4(trace, path)
    raise ValueError(f"unknown format {fmt!r}; use one of {', '.join(TRACE_FORMATS)}")


def read_run(path: str | Path) -> Trace:
    """Read a run's trace: a ``.parquet``, ``.csv`` or ``.mf4``/``.mdf`` file, or a run directory written by
    ``vehicle-assist run`` (trace.parquet, else trace.mf4, else trace.csv)."""
    path = Path(path)
    if path.is_dir():
        for name in ("trace.parquet", "trace.mf4", "trace.csv"):
            if (path / name).is_file():
                return read_run(path / name)
        raise FileNotFoundError(f"{path}: no trace.parquet, trace.mf4 or trace.csv in this directory")
    suffix = path.suffix.lower()
    if suffix == ".parquet":
        return read_trace_parquet(path)
    if suffix == ".csv":
        return read_trace_csv(path)
    if suffix in (".mf4", ".mdf"):
        from vehicle_assist.io.mdf import read_trace_mdf4

        return read_trace_mdf4(path)
    raise ValueError(f"{path}: unknown trace format {suffix!r}; use .parquet, .csv or .mf4")


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
    formats: tuple[str, ...] = ("parquet", "csv"),
) -> dict[str, Path]:
    """Write the outputs of one run into ``out_dir`` and return their paths.

    Keys: one per trace format in ``formats`` (``parquet`` trace.parquet, ``csv`` trace.csv with its sidecar
    trace.units.json, ``mdf4`` trace.mf4), ``metrics`` (metrics.json holding ``{"metrics", "checks",
    "requirements", "events", "meta"}``) and ``overview`` (overview.png).
    """
    from vehicle_assist.report.plots import overview_png

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    paths = {fmt: write_trace(trace, out / f"trace{_SUFFIX[fmt]}", fmt) for fmt in formats}
    paths.update({
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
    })
    if plot:
        paths["overview"] = overview_png(trace, out / "overview.png", title)
    return paths
