"""Flat numeric records that the compiled kernels read by name (``p.mass_kg``).

A parameter set is a flat mapping of SI names to floats and :class:`Table` objects. It is packed into
a numpy structured record (scalars as ``f8`` fields; a table ``t`` as ``t_x``, ``t_y`` arrays of a fixed
capacity plus ``t_n``, ``t_extrap``, ``t_interp``). A batch of variants is an array of such records
with one dtype, so the same kernel serves one run and ten thousand.
"""
from __future__ import annotations

from typing import Mapping

import numpy as np

from vehicle_assist.core.tables import EXTRAPOLATION, INTERPOLATION, Table

Flat = Mapping[str, "float | Table | np.ndarray"]


def record_dtype(flat: Flat, capacities: Mapping[str, int] | None = None) -> np.dtype:
    fields: list[tuple] = []
    for name, value in flat.items():
        if isinstance(value, Table):
            cap = max(2, (capacities or {}).get(name, len(value.x)))
            fields += [(f"{name}_x", "f8", (cap,)), (f"{name}_y", "f8", (cap,)), (f"{name}_n", "i8"),
                       (f"{name}_extrap", "i8"), (f"{name}_interp", "i8")]
        elif isinstance(value, np.ndarray):
            cap = max(1, (capacities or {}).get(name, len(value)))
            fields.append((name, "f8", (cap,)))
        else:
            fields.append((name, "f8"))
    return np.dtype(fields, align=True)


def table_capacities(flats: list[Flat]) -> dict[str, int]:
    caps: dict[str, int] = {}
    for flat in flats:
        for name, value in flat.items():
            if isinstance(value, Table):
                caps[name] = max(caps.get(name, 2), len(value.x))
            elif isinstance(value, np.ndarray):
                caps[name] = max(caps.get(name, 1), len(value))
    return caps


def pack(flats: list[Flat], capacities: Mapping[str, int] | None = None) -> np.recarray:
    """Pack one or more flat parameter sets (same keys) into a record array.

    ``capacities`` pads tables and arrays to at least that many entries (one dtype for many batches)."""
    if not flats:
        raise ValueError("nothing to pack")
    keys = list(flats[0])
    for f in flats[1:]:
        if list(f) != keys:
            missing = set(keys) ^ set(f)
            raise ValueError(f"parameter sets differ in their keys: {sorted(missing)}")
    caps = table_capacities(flats)
    for name, cap in (capacities or {}).items():
        caps[name] = max(caps.get(name, 0), cap)
    dtype = record_dtype(flats[0], caps)
    arr = np.zeros(len(flats), dtype=dtype)
    first = flats[0]
    scalars = [k for k, v in first.items() if not isinstance(v, (Table, np.ndarray))]
    for name in scalars:  # column-wise: one assignment per field for the whole batch
        arr[name] = [float(f[name]) for f in flats]
    shared = [k for k in first if k not in scalars and all(f[k] is first[k] for f in flats)]
    for i, flat in enumerate(flats):
        for name, value in flat.items():
            if name in scalars or (i > 0 and name in shared):
                continue
            if isinstance(value, Table):
                n = len(value.x)
                arr[f"{name}_x"][i, :n] = value.x
                arr[f"{name}_y"][i, :n] = value.y
                # pad with increasing breakpoints so stray reads stay monotonic
                if n < arr[f"{name}_x"].shape[1]:
                    arr[f"{name}_x"][i, n:] = value.x[-1] + np.arange(1, arr[f"{name}_x"].shape[1] - n + 1)
                    arr[f"{name}_y"][i, n:] = value.y[-1]
                arr[f"{name}_n"][i] = n
                arr[f"{name}_extrap"][i] = EXTRAPOLATION[value.extrapolation]
                arr[f"{name}_interp"][i] = INTERPOLATION[value.interpolation]
            else:
                arr[name][i, :] = np.nan
                arr[name][i, : len(value)] = value
    for name in shared:  # the same table object in every variant: packed once, copied to all rows
        for field in ([f"{name}_x", f"{name}_y", f"{name}_n", f"{name}_extrap", f"{name}_interp"]
                      if isinstance(first[name], Table) else [name]):
            arr[field][1:] = arr[field][0]
    return arr.view(np.recarray)
