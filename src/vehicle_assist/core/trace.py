"""Simulation results: a table of named, unit-carrying channels plus the mode-change events.

A :class:`Trace` is what every metric, writer and plot reads. Channel names carry their unit in the
suffix (``speed_mps``, ``engine_speed_radps``); :func:`vehicle_assist.units.unit_of` gives the unit.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Iterator

import numpy as np

from vehicle_assist.units import unit_of


@dataclass(frozen=True)
class Event:
    """One mode change of a state machine: at ``time_s`` ``machine`` went ``from_mode`` -> ``to_mode``."""

    time_s: float
    machine: str
    from_mode: str
    to_mode: str
    reason: str

    def as_dict(self) -> dict:
        return {
            "time_s": self.time_s,
            "machine": self.machine,
            "from_mode": self.from_mode,
            "to_mode": self.to_mode,
            "reason": self.reason,
        }


@dataclass(repr=False)
class Trace:
    """Channels sampled on a common time base ``time_s``.

    ``channels`` maps name -> 1-D float array (all of one length); ``descriptions`` says what each
    channel is; ``meta`` holds provenance (package version, scenario and parameter hashes, steps).
    """

    channels: dict[str, np.ndarray]
    descriptions: dict[str, str] = field(default_factory=dict)
    meta: dict[str, str] = field(default_factory=dict)
    events: list[Event] = field(default_factory=list)

    def __post_init__(self) -> None:
        if "time_s" not in self.channels:
            raise ValueError("a trace needs a 'time_s' channel")
        n = len(self.channels["time_s"])
        for name, values in self.channels.items():
            if np.shape(values)[-1] != n:
                raise ValueError(f"channel {name!r} has {np.shape(values)[-1]} samples, time_s has {n}")

    @property
    def batch_size(self) -> int | None:
        """None for one run; k when the channels are (k, samples) arrays of k runs on one time base
        (metrics then return one value per run)."""
        for name, values in self.channels.items():
            if name != "time_s" and np.ndim(values) == 2:
                return int(np.shape(values)[0])
        return None

    def __repr__(self) -> str:
        n = len(self)
        span = f"{self.time_s[0]:g}-{self.time_s[-1]:g} s" if n else "empty"
        return (f"<Trace {self.meta.get('scenario', '')!s} {n} samples x {len(self.channels)} channels, {span}, "
                f"{len(self.events)} events>")

    # -- access -------------------------------------------------------------------------------
    def __getitem__(self, name: str) -> np.ndarray:
        try:
            return self.channels[name]
        except KeyError:
            import difflib

            close = difflib.get_close_matches(name, self.channels, n=1)
            hint = f" (did you mean {close[0]!r}?)" if close else ""
            raise KeyError(f"no channel {name!r} in the trace{hint}") from None

    def __contains__(self, name: object) -> bool:
        return name in self.channels

    def __iter__(self) -> Iterator[str]:
        return iter(self.channels)

    def __len__(self) -> int:
        return len(self.channels["time_s"])

    @property
    def names(self) -> list[str]:
        return list(self.channels)

    @property
    def time_s(self) -> np.ndarray:
        return self.channels["time_s"]

    def unit(self, name: str) -> str:
        return unit_of(name)

    @property
    def units(self) -> dict[str, str]:
        return {name: unit_of(name) for name in self.channels}

    def events_of(self, machine: str) -> list[Event]:
        return [e for e in self.events if e.machine == machine]

    # -- conversion ---------------------------------------------------------------------------
    def to_arrow(self):
        """A pyarrow Table; each field carries ``unit`` and ``description`` metadata, the schema ``meta``."""
        import json

        import pyarrow as pa

        fields = []
        arrays = []
        for name, values in self.channels.items():
            md = {"unit": unit_of(name), "description": self.descriptions.get(name, "")}
            fields.append(pa.field(name, pa.float64(), metadata=md))
            data = np.ascontiguousarray(values, dtype=np.float64)
            # from_buffers, not pa.array: pa.array imports pandas (0.3 s) to check the input type
            arrays.append(pa.Array.from_buffers(pa.float64(), len(data), [None, pa.py_buffer(data)]))
        schema_md = {k: str(v) for k, v in self.meta.items()}
        schema_md["events"] = json.dumps([e.as_dict() for e in self.events])
        schema = pa.schema(fields, metadata=schema_md)
        return pa.Table.from_arrays(arrays, schema=schema)

    def to_pandas(self):
        """A pandas DataFrame indexed by nothing special; units in ``df.attrs['units']``."""
        import pandas as pd

        df = pd.DataFrame({k: np.asarray(v) for k, v in self.channels.items()})
        df.attrs["units"] = self.units
        df.attrs["meta"] = dict(self.meta)
        return df

    def row(self, i: int) -> "Trace":
        """Run ``i`` of a batch trace as a trace of its own (views, no copies, no re-validation)."""
        out = object.__new__(Trace)
        out.channels = {n: (v[i] if np.ndim(v) == 2 else v) for n, v in self.channels.items()}
        out.descriptions, out.meta, out.events = self.descriptions, self.meta, []
        return out

    def select(self, names: list[str]) -> "Trace":
        keep = ["time_s"] + [n for n in names if n != "time_s"]
        return Trace({n: self[n] for n in keep}, {n: self.descriptions.get(n, "") for n in keep}, dict(self.meta), list(self.events))
