"""Variants of one scenario over a grid of dotted paths, written straight into packed records.

``build_variants(base, {"vehicle.body.mass_kg": [...], "road.slope_deg": [...]})`` validates every axis
value once (``base.with_sets`` of that one assignment: the same checks, errors and derived values as a
``--set``), packs those few scenarios, and finds which record fields each axis changes. A variant is then the
base record with each axis' fields copied from the record of its value: no pydantic, no dict per variant.
For 10,000 truck variants that is ~20 ms instead of ~3.5 s of ``with_sets``.

The shortcut is taken only when it is exact: the axes change disjoint record fields, the corner variant (every
axis at its last value, built the slow way) packs to exactly the composed record, and no axis touches what
a record does not hold (run timing and seed, checks, requirements, events count). Otherwise the variants are
built one by one with ``with_sets`` (same results, the old speed). ``simulate_batch`` accepts the returned
:class:`VariantSet` wherever it accepts a list of scenarios; ``VariantSet[a:b]`` is a picklable slice (for
workers), and ``scenario(k)`` builds variant ``k`` as a :class:`LoadedScenario` when one is needed.
"""
from __future__ import annotations

import itertools
import json
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from vehicle_assist.scenarios.loader import LoadedScenario


def assignment(path: str, value) -> str:
    """``path=value`` as a ``--set`` (strings, booleans, lists and tables as JSON, numbers as Python prints them)."""
    return f"{path}={json.dumps(value) if isinstance(value, (str, bool, list, dict)) else value}"


@dataclass
class VariantSet:
    """The product of ``axes`` (last axis fastest, as ``itertools.product``) over ``base``, or a slice of it."""

    base: LoadedScenario
    axes: list[tuple[str, list]]
    start: int = 0
    stop: int | None = None
    # filled by build_variants: per axis, the packed (vehicle, scenario) records of each value and the fields it sets
    _p_axis: list = field(default_factory=list, repr=False)
    _s_axis: list = field(default_factory=list, repr=False)
    _p_fields: list = field(default_factory=list, repr=False)
    _s_fields: list = field(default_factory=list, repr=False)
    _p_base: np.ndarray | None = field(default=None, repr=False)
    _s_base: np.ndarray | None = field(default=None, repr=False)
    fast: bool = False
    _slow: list | None = field(default=None, repr=False)  # the variants as scenarios when the shortcut is not exact

    @property
    def total(self) -> int:
        n = 1
        for _, values in self.axes:
            n *= len(values)
        return n

    def __len__(self) -> int:
        stop = self.total if self.stop is None else self.stop
        return max(0, stop - self.start)

    @property
    def layout(self) -> str:
        return self.base.layout

    def __getitem__(self, key):
        if isinstance(key, slice):
            lo, hi, step = key.indices(len(self))
            if step != 1:
                raise ValueError("a VariantSet slice takes consecutive variants")
            out = VariantSet(**{**self.__dict__})
            out.start, out.stop = self.start + lo, self.start + max(lo, hi)
            return out
        k = range(len(self))[key]
        return self.scenario(k)

    def indices(self, k: int) -> tuple[int, ...]:
        """Per-axis value index of variant ``k`` (of this slice)."""
        return tuple(int(i) for i in np.unravel_index(self.start + k, [len(v) for _, v in self.axes]))

    def sets(self, k: int) -> tuple[str, ...]:
        """The ``--set`` assignments of variant ``k`` (after the base scenario's own)."""
        return tuple(assignment(path, values[i]) for (path, values), i in zip(self.axes, self.indices(k)))

    def overrides(self) -> list[tuple[str, ...]]:
        """``base.sets + sets(k)`` of every variant (each axis value's ``--set`` text formatted once)."""
        base = tuple(self.base.sets)
        texts = [[assignment(path, v) for v in values] for path, values in self.axes]
        idx = np.unravel_index(np.arange(self.start, self.start + len(self)), [len(v) for _, v in self.axes])
        return [base + tuple(t[i] for t, i in zip(texts, combo)) for combo in zip(*[a.tolist() for a in idx])]

    def scenario(self, k: int) -> LoadedScenario:
        """Variant ``k`` as a scenario (built and validated the slow way)."""
        if self._slow is not None:
            return self._slow[self.start + k]
        return self.base.with_sets(*self.sets(k))

    def scenarios(self) -> list[LoadedScenario]:
        return [self.scenario(k) for k in range(len(self))]

    def records(self, lo: int = 0, hi: int | None = None) -> tuple[np.ndarray, np.ndarray]:
        """Packed (vehicle, scenario) records of variants lo..hi of this slice (one dtype for the whole set)."""
        hi = len(self) if hi is None else hi
        n = hi - lo
        if not self.fast:
            from vehicle_assist.scenarios.runner import pack_records

            scs = [self.scenario(k) for k in range(lo, hi)]
            return pack_records([sc.vehicle.flat() for sc in scs]), pack_records([sc.flat for sc in scs])
        shape = [len(v) for _, v in self.axes]
        idx = np.unravel_index(np.arange(self.start + lo, self.start + hi), shape)
        p = np.repeat(self._p_base, n)
        s = np.repeat(self._s_base, n)
        for a in range(len(self.axes)):
            for name in self._p_fields[a]:
                p[name] = self._p_axis[a][name][idx[a]]
            for name in self._s_fields[a]:
                s[name] = self._s_axis[a][name][idx[a]]
        return p.view(np.recarray), s.view(np.recarray)


def _axes_list(axes) -> list[tuple[str, list]]:
    items = list(axes.items()) if isinstance(axes, Mapping) else [(p, v) for p, v in axes]
    out = []
    for path, values in items:
        values = list(values)
        if not values:
            raise ValueError(f"axis {path}: no values")
        out.append((str(path), values))
    if not out:
        raise ValueError("no axes: give at least one path with its values (a single run is simulate(base))")
    return out


def _same(a: np.ndarray, b: np.ndarray) -> bool:
    return a.tobytes() == b.tobytes()


def _changed(rec: np.ndarray, name: str, rows: int) -> bool:
    col = rec[name]
    ref = col[0].tobytes()
    return any(col[r].tobytes() != ref for r in range(1, rows))


def build_variants(base: LoadedScenario, axes: Mapping[str, Sequence] | Sequence[tuple[str, Sequence]]) -> VariantSet:
    """All combinations of the axis values over ``base`` (see the module doc). Each value is validated once;
    a bad value raises the same one-line error as ``--set``."""
    from vehicle_assist.scenarios.runner import pack_records

    axes = _axes_list(axes)
    vs = VariantSet(base, axes)
    per_axis = [[base.with_sets(assignment(path, v)) for v in values] for path, values in axes]
    every = [base] + [sc for scs in per_axis for sc in scs]
    exact = all(sc.model.run == base.model.run and sc.model.checks == base.model.checks
                and sc.model.requirements == base.model.requirements and len(sc.model.events) == len(base.model.events)
                and sc.layout == base.layout for sc in every)
    if exact:
        p_all = pack_records([sc.vehicle.flat() for sc in every])
        s_all = pack_records([sc.flat for sc in every])
        vs._p_base, vs._s_base = np.array(p_all[:1]), np.array(s_all[:1])
        row = 1
        seen_p: set[str] = set()
        seen_s: set[str] = set()
        for a, scs in enumerate(per_axis):
            sel = np.r_[0, np.arange(row, row + len(scs))]
            pa, sa = np.array(p_all[sel]), np.array(s_all[sel])
            pf = [n for n in pa.dtype.names if _changed(pa, n, len(sel))]
            sf = [n for n in sa.dtype.names if _changed(sa, n, len(sel))]
            if seen_p & set(pf) or seen_s & set(sf):
                exact = False  # two axes write the same field (a derived value of both): build one by one
                break
            seen_p |= set(pf)
            seen_s |= set(sf)
            vs._p_axis.append(pa[1:])
            vs._s_axis.append(sa[1:])
            vs._p_fields.append(pf)
            vs._s_fields.append(sf)
            row += len(scs)
    if exact:
        vs.fast = True
        corner = base.with_sets(*[assignment(path, values[-1]) for path, values in axes])
        pc, sc_ = pack_records([base.vehicle.flat(), corner.vehicle.flat()] + [s.vehicle.flat() for s in every[1:]]), \
            pack_records([base.flat, corner.flat] + [s.flat for s in every[1:]])
        p_last, s_last = vs.records(len(vs) - 1, len(vs)) if len(vs) else (None, None)
        exact = (pc.dtype == p_last.dtype and sc_.dtype == s_last.dtype
                 and _same(np.array(pc[1:2]), np.array(p_last)) and _same(np.array(sc_[1:2]), np.array(s_last)))
    if not exact:
        vs.fast = False
        vs._p_axis, vs._s_axis, vs._p_fields, vs._s_fields = [], [], [], []
        vs._slow = [base.with_sets(*[assignment(path, v) for (path, _), v in zip(axes, combo)])
                    for combo in itertools.product(*[values for _, values in axes])]
    return vs
