"""MDF4 (ASAM MDF 4.10) export and import of traces, with asammdf.

Layout of a file written by :func:`write_trace_mdf4` (readable by asammdf, CANape, MDA, Vector tools):

* one channel group ``vehicle-assist`` with every trace channel as float64 on the master ``time`` (s);
  each channel carries its unit (``unit_of`` the name suffix) and its description as the channel comment;
* mode channels (``*_mode_index``) carry a value-to-text conversion (0 -> ``STANDBY`` ...), so a viewer
  shows the mode names; ``read_trace_mdf4`` reads the raw index back and the mapping into ``meta``;
* every state-machine transition is an MDF4 event block (name ``machine FROM->TO``, comment = guard, time
  synchronised) and also a line of the text channel ``events`` in a second group (for tools that do not
  show event blocks);
* the trace's provenance (``meta``: package version, scenario and parameter hashes, overrides) is the JSON
  text of the file-header comment.

asammdf is an optional dependency (``pip install 'vehicle-assist[mdf]'``, installed by ``make setup``).
"""
from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np

from vehicle_assist.core.trace import Event, Trace
from vehicle_assist.units import unit_of

__all__ = ["write_trace_mdf4", "read_trace_mdf4", "MODE_NAMES_KEY"]

MODE_NAMES_KEY = "mode_names"  # meta key: JSON {channel: [mode name of index 0, 1, ...]}
_GROUP_COMMENT = "vehicle-assist"
_EVENTS_CHANNEL = "events"
_META_TAG = "vehicle_assist_meta"


def _asammdf():
    try:
        import asammdf
    except ImportError:  # pragma: no cover - the dependency is installed by make setup
        from vehicle_assist.scenarios.errors import InputError

        raise InputError("MDF4 needs the optional dependency asammdf: pip install 'vehicle-assist[mdf]'") from None
    return asammdf


def mode_names(trace: Trace) -> dict[str, list[str]]:
    """{mode channel: names by index} from the trace's meta (empty if the trace has none)."""
    try:
        return {k: list(v) for k, v in json.loads(trace.meta.get(MODE_NAMES_KEY, "{}")).items()}
    except (TypeError, ValueError):
        return {}


def _value_to_text(names: list[str]) -> dict:
    conv: dict = {}
    for i, name in enumerate(names):
        conv[f"val_{i}"] = float(i)
        conv[f"text_{i}"] = name.encode("utf-8")
    conv["default"] = b""
    return conv


def write_trace_mdf4(trace: Trace, path: str | Path) -> Path:
    """Write ``trace`` (one run) as an MDF 4.10 file, atomically; see the module docstring for the layout."""
    from vehicle_assist.io.results import atomic_path

    asammdf = _asammdf()
    from asammdf.blocks.v4_blocks import EventBlock

    if trace.batch_size is not None:
        raise ValueError("write one run at a time (trace.row(i) of a batch trace)")
    time = np.ascontiguousarray(trace.time_s, dtype=np.float64)
    modes = mode_names(trace)
    signals = []
    for name in trace.names:
        if name == "time_s":
            continue
        conversion = _value_to_text(modes[name]) if name in modes else None
        signals.append(asammdf.Signal(np.ascontiguousarray(trace[name], dtype=np.float64), time, unit=unit_of(name),
                                      name=name, comment=trace.descriptions.get(name, ""), conversion=conversion))
    mdf = asammdf.MDF(version="4.10")
    try:
        meta = {k: str(v) for k, v in trace.meta.items()}
        mdf.header.comment = f"<HDcomment><TX>{_escape(json.dumps({_META_TAG: meta}))}</TX></HDcomment>"
        if signals:
            mdf.append(signals, comment=_GROUP_COMMENT)
        if trace.events:
            lines = np.array([f"{e.machine}: {e.from_mode}->{e.to_mode} ({e.reason})".encode("utf-8")
                              for e in trace.events])
            stamps = np.array([e.time_s for e in trace.events], dtype=np.float64)
            mdf.append([asammdf.Signal(lines, stamps, name=_EVENTS_CHANNEL, encoding="utf-8",
                                       comment="state-machine transitions: machine: FROM->TO (guard)")],
                       comment="events")
        for e in trace.events:
            block = EventBlock(event_type=5, sync_type=1, range_type=0, cause=1,  # marker, time-synchronised, tool
                               sync_base=int(round(e.time_s * 1e9)), sync_factor=1e-9)
            block.name = f"{e.machine} {e.from_mode}->{e.to_mode}"
            block.comment = e.reason
            mdf.events.append(block)
        target = Path(path)
        with atomic_path(target) as tmp:
            # asammdf gives the file its own suffix (.mf4): save under that name, then move it to tmp
            written = Path(mdf.save(tmp.with_suffix(".mf4"), overwrite=True))
            os.replace(written, tmp)
    finally:
        mdf.close()
    return target


def _escape(text: str) -> str:
    return text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")


def _header_meta(comment: str) -> dict[str, str]:
    import re
    from html import unescape

    match = re.search(r"<TX>(.*?)</TX>", comment or "", re.S)
    if not match:
        return {}
    try:
        doc = json.loads(unescape(match.group(1)))
    except ValueError:
        return {}
    return {str(k): str(v) for k, v in doc.get(_META_TAG, {}).items()} if isinstance(doc, dict) else {}


def read_trace_mdf4(path: str | Path) -> Trace:
    """Read an MDF4 measurement as a :class:`Trace`.

    A file written by :func:`write_trace_mdf4` comes back exactly (float64 samples, descriptions, meta, events,
    mode-name tables). Any other MDF file is read with every numeric channel resampled onto the master of its
    first channel group (``time_s``); value-to-text channels keep their raw values, their tables go to
    ``meta['mode_names']``; MDF events become events of machine ``mdf``."""
    asammdf = _asammdf()
    mdf = asammdf.MDF(str(path))
    try:
        meta = _header_meta(mdf.header.comment)
        channels: dict[str, np.ndarray] = {}
        descriptions: dict[str, str] = {}
        modes: dict[str, list[str]] = {}
        events: list[Event] = []
        time = None
        for name in mdf.channels_db:
            if name in ("time", "t") or name in channels:
                continue
            sig = mdf.get(name, raw=True)
            if sig.samples.dtype.kind not in "fiub" or sig.samples.ndim != 1:
                if name == _EVENTS_CHANNEL:
                    continue
                continue
            if time is None:
                time = np.asarray(sig.timestamps, dtype=np.float64)
            values = np.asarray(sig.samples, dtype=np.float64)
            if len(sig.timestamps) != len(time) or not np.array_equal(sig.timestamps, time):
                values = np.interp(time, sig.timestamps, values)
            channels[name] = values
            if sig.comment:
                descriptions[name] = sig.comment
            table = _conversion_names(sig.conversion)
            if table:
                modes[name] = table
        if time is None:
            raise ValueError(f"{path}: no numeric channel")
        exact = None  # our own files: the text channel's float64 time stamps are exact, the blocks' are to 1 ns
        if _EVENTS_CHANNEL in mdf.channels_db:
            stamps = np.asarray(mdf.get(_EVENTS_CHANNEL).timestamps, dtype=np.float64)
            if len(stamps) == len(mdf.events):
                exact = stamps
        for k, block in enumerate(mdf.events):
            name = block.name or ""
            machine, _, change = name.partition(" ")
            src, _, dst = change.partition("->")
            when = float(exact[k]) if exact is not None else round(float(block.sync_base) * float(block.sync_factor), 9)
            events.append(Event(when, machine if dst else "mdf", src if dst else "", dst if dst else name,
                                block.comment or ""))
        events.sort(key=lambda e: e.time_s)  # stable: same-time events keep the file's order
    finally:
        mdf.close()
    if modes:
        meta[MODE_NAMES_KEY] = json.dumps(modes)
    return Trace({"time_s": time, **channels}, descriptions, meta, events)


def _conversion_names(conversion) -> list[str]:
    """Names by index of a value-to-text conversion with values 0..n-1 (else [])."""
    if conversion is None:
        return []
    try:
        n = int(conversion.val_param_nr) if hasattr(conversion, "val_param_nr") else 0
        out = []
        for i in range(n):
            if float(conversion[f"val_{i}"]) != i:
                return []
            text = conversion.referenced_blocks.get(f"text_{i}")
            text = getattr(text, "text", text)
            out.append(text.decode("utf-8") if isinstance(text, bytes) else str(text or ""))
        return out
    except (KeyError, AttributeError, TypeError, ValueError):
        return []
