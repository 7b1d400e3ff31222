"""Run scenarios: one at a time (full trace) or as a batch of variants on both cores.

The compiled kernel of the scenario's layout does the stepping; this module packs the records, draws
the seeded sensor noise, turns the kernel's buffers into a :class:`Trace` with events, and evaluates
metrics and checks. Batches pack every variant into one record array (one dtype, so one compiled
kernel), split it across threads (the kernels release the GIL) and keep only the asked-for channels.
"""
from __future__ import annotations

import json
import math
import os
import re
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from typing import Callable, Iterable, Sequence

import numpy as np

import vehicle_assist
from vehicle_assist.core.fsm import EVENT_FIELDS, StateMachine, Transition, decode_events
from vehicle_assist.core.records import pack
from vehicle_assist.core.tables import Table
from vehicle_assist.core.trace import Trace
from vehicle_assist.metrics import compute_metrics
from vehicle_assist.scenarios.loader import LoadedScenario
from vehicle_assist.vehicles import layouts
from vehicle_assist.vehicles.common import EVENT_BUFFER

TABLE_CAPACITY_STEP = 32  # table and array fields are padded to multiples of this: one dtype, one compile
BATCH_CHUNK = 16  # variants per metrics evaluation in a batch (memory: 64 x samples x channels x 8 B)


@dataclass
class CheckResult:
    metric: str
    value: float
    min: float | None
    max: float | None
    expect: str
    passed: bool  # the bound holds
    ok: bool  # the outcome is what the scenario expects (a negative control expects a failed bound)
    why: str = ""

    @property
    def bound(self) -> str:
        parts = []
        if self.min is not None:
            parts.append(f">= {self.min:g}")
        if self.max is not None:
            parts.append(f"<= {self.max:g}")
        return " and ".join(parts)

    def as_dict(self) -> dict:
        return {"metric": self.metric, "value": self.value, "min": self.min, "max": self.max, "bound": self.bound,
                "expect": self.expect, "bound_holds": self.passed, "ok": self.ok, "why": self.why}


@dataclass(repr=False)
class Result:
    """One run: ``trace`` (channels, events, meta), ``metrics``, ``checks`` and ``requirements``."""

    scenario: LoadedScenario
    trace: Trace
    metrics: dict[str, float]
    checks: list[CheckResult] = field(default_factory=list)
    requirements: list = field(default_factory=list)  # verification.requirements.RequirementResult, one per attached requirement

    @property
    def events(self):
        return self.trace.events

    @property
    def ok(self) -> bool:
        return all(c.ok for c in self.checks) and all(r.ok for r in self.requirements)

    def to_pandas(self):
        """The trace as a pandas DataFrame (one float column per channel; units in ``df.attrs['units']``)."""
        return self.trace.to_pandas()

    def __repr__(self) -> str:
        failed = sum(not c.ok for c in self.checks) + sum(not r.ok for r in self.requirements)
        verdict = "ok" if failed == 0 else f"{failed} FAILED"
        return (f"<Result {self.scenario.name}: {len(self.trace)} samples, {len(self.metrics)} metrics, "
                f"{len(self.checks)} checks ({verdict}), {len(self.trace.events)} events>")

    def _repr_html_(self) -> str:
        """Notebook view: the checks and the metrics as two small tables."""
        from html import escape

        rows = "".join(
            f"<tr><td>{escape(c.metric)}</td><td>{c.value:.4g}</td><td>{escape(c.bound)}</td>"
            f"<td>{escape(c.expect)}</td><td style='color:{'green' if c.ok else 'red'}'>"
            f"{'ok' if c.ok else 'FAIL'}</td></tr>" for c in self.checks)
        metrics = "".join(f"<tr><td>{escape(k)}</td><td>{v:.4g}</td></tr>" for k, v in self.metrics.items())
        return (f"<div><b>{escape(self.scenario.name)}</b>: {len(self.trace)} samples, "
                f"{len(self.trace.events)} events"
                f"<table><tr><th>check</th><th>value</th><th>bound</th><th>expect</th><th>result</th></tr>{rows}</table>"
                f"<details><summary>{len(self.metrics)} metrics</summary><table>{metrics}</table></details></div>")


def _capacities(flats: Sequence[dict]) -> dict[str, int]:
    caps: dict[str, int] = {}
    for flat in flats:
        for name, value in flat.items():
            n = len(value.x) if isinstance(value, Table) else len(value) if isinstance(value, np.ndarray) else 0
            if n:
                caps[name] = max(caps.get(name, 0), n)
    return {k: TABLE_CAPACITY_STEP * math.ceil(v / TABLE_CAPACITY_STEP) for k, v in caps.items()}


def pack_records(flats: Sequence[dict]) -> np.recarray:
    """Pack flat records with table capacities rounded up to TABLE_CAPACITY_STEP (stable dtype)."""
    return pack(list(flats), _capacities(flats))


def _noise(sc: LoadedScenario, n_sensors: int) -> np.ndarray:
    """Seeded standard-normal draws, one row per controller tick (one zero row if no sensor is noisy)."""
    run = sc.model.run
    if not np.any(sc.flat["sensor_noise_std"]):
        return np.zeros((1, n_sensors))
    ticks = int(round(run.duration_s / run.controller_period_s)) + 2
    return np.random.default_rng(run.seed).standard_normal((ticks, n_sensors))


def _n_records(sc: LoadedScenario) -> int:
    run = sc.model.run
    return int(math.floor(run.duration_s / run.record_period_s + 1e-9)) + 1


def scenario_machines(sc: LoadedScenario) -> list[StateMachine]:
    lay = layouts.get(sc.layout)
    names = []
    for i, e in enumerate(sc.model.events):
        what = {"set_input": e.input, "sensor_fault": f"{e.sensor} {e.fault}",
                "actuator_fault": f"{e.actuator} {e.fault}"}.get(e.action, "")
        names.append(f"event {i}: {e.action} {what}")
    trans = tuple(Transition("PENDING", "FIRED", n) for n in names) or (Transition("PENDING", "FIRED", "none"),)
    return list(lay.MACHINES) + [StateMachine("scenario", ("PENDING", "FIRED"), trans)]


def mode_tables(channels: dict[str, str], machines: Sequence[StateMachine]) -> dict[str, list[str]]:
    """{mode channel: mode names by index} for the ``*_mode_index`` channels of a layout.

    A channel names its machine in its description ("... see the amt_launch state machine") or by its
    prefix (``hba_mode_index`` -> ``hba``); a channel whose machine cannot be told is left out."""
    by_name = {m.name: m for m in machines}
    out: dict[str, list[str]] = {}
    for channel, description in channels.items():
        if not channel.endswith("_mode_index"):
            continue
        named = re.search(r"the (\w+) state machine", description or "")
        machine = by_name.get(named.group(1)) if named else by_name.get(channel[: -len("_mode_index")])
        if machine is not None:
            out[channel] = list(machine.modes)
    return out


def evaluate_checks(sc: LoadedScenario, metrics: dict[str, float]) -> list[CheckResult]:
    out = []
    for c in sc.model.checks:
        value = metrics.get(c.metric, float("nan"))
        holds = math.isfinite(value) and (c.min is None or value >= c.min) and (c.max is None or value <= c.max)
        ok = holds if c.expect == "pass" else not holds
        out.append(CheckResult(c.metric, value, c.min, c.max, c.expect, holds, ok, c.why))
    return out


def _meta(sc: LoadedScenario) -> dict[str, str]:
    run = sc.model.run
    return {
        "package_version": vehicle_assist.__version__,
        "scenario": sc.name,
        "scenario_file": str(sc.path) if sc.path else "",
        "scenario_hash": sc.scenario_hash(),
        "parameter_hash": sc.parameter_hash(),
        "vehicle": sc.vehicle.model.name,
        "layout": sc.layout,
        "plant_step_s": repr(run.plant_step_s),
        "controller_period_s": repr(run.controller_period_s),
        "record_period_s": repr(run.record_period_s),
        "seed": str(run.seed),
        "overrides": ";".join(sc.sets),
    }


def evaluate_requirements(sc: LoadedScenario, trace: Trace, metrics: dict[str, float]) -> list:
    """Robustness of each requirement attached to the scenario; a comparative one ("never worse than no
    assist") runs the scenario's no-assist twin (the requirement's baseline overrides) once."""
    from vehicle_assist.verification.requirements import evaluate, resolve

    where = str(sc.path) if sc.path else sc.name
    reqs = resolve(sc.model.requirements, sc.layout, where)
    out = []
    twins: dict[tuple, dict] = {}
    for r in reqs:
        base_metrics = None
        if r.comparative:
            if r.baseline not in twins:
                twins[r.baseline] = simulate(sc.with_sets(*r.baseline), requirements=False).metrics
            base_metrics = twins[r.baseline]
        out += evaluate([r], trace, metrics, base_metrics)
    return out


def simulate(sc: LoadedScenario, requirements: bool = True) -> Result:
    """Run one scenario and return its full trace, metrics, events, checks and requirement robustness."""
    lay = layouts.get(sc.layout)
    p = pack_records([sc.vehicle.flat()])
    s = pack_records([sc.flat])
    from vehicle_assist.scenarios.guards import estimate_run, refuse_past_bounds

    refuse_past_bounds(estimate_run(sc, write=False), yes=True)  # API callers too: never past the machine's memory
    trace_rows = np.zeros(_n_records(sc), dtype=lay.TRACE_DTYPE).view(np.recarray)
    events = np.zeros((EVENT_BUFFER, EVENT_FIELDS))
    n_rec, n_ev = lay.run_kernel(p[0], s[0], _noise(sc, len(lay.SENSORS)), trace_rows, events)
    channels = {name: np.array(trace_rows[name][:n_rec]) for name in lay.CHANNELS}
    machines = scenario_machines(sc)
    meta = _meta(sc)
    meta["mode_names"] = json.dumps(mode_tables(lay.CHANNELS, machines))
    trace = Trace(channels, dict(lay.CHANNELS), meta, decode_events(events, n_ev, machines))
    metrics = compute_metrics(trace)
    reqs = evaluate_requirements(sc, trace, metrics) if requirements and sc.model.requirements else []
    return Result(sc, trace, metrics, evaluate_checks(sc, metrics), reqs)


@dataclass(repr=False)
class BatchResult:
    """Per-variant metrics (and the kept channels, decimated) of a batch; ``overrides`` are the dotted
    ``--set`` assignments of each variant (its parameters)."""

    metrics: list[dict[str, float]]
    channels: list[dict[str, np.ndarray]]
    checks_ok: list[bool]
    overrides: list[tuple[str, ...]] = field(default_factory=list)

    def parameters(self) -> list[dict]:
        """Each variant's overrides as {dotted path: value} (values parsed as TOML, e.g. numbers, lists)."""
        from vehicle_assist.scenarios.loader import parse_value

        out = []
        for sets in self.overrides or [()] * len(self.metrics):
            row = {}
            for a in sets:
                key, _, text = a.partition("=")
                row[key.strip()] = parse_value(text.strip())
            out.append(row)
        return out

    def to_pandas(self):
        """One row per variant: its parameters (overridden paths, lists as text), metrics and ``checks_ok``."""
        import pandas as pd

        rows = []
        for params, metrics, ok in zip(self.parameters(), self.metrics, self.checks_ok):
            row = {k: (json.dumps(v) if isinstance(v, (list, dict)) else v) for k, v in params.items()}
            row.update(metrics)
            row["checks_ok"] = ok
            rows.append(row)
        return pd.DataFrame(rows)

    def __len__(self) -> int:
        return len(self.metrics)

    def __repr__(self) -> str:
        return f"<BatchResult {len(self.metrics)} variants, {sum(self.checks_ok)} with checks ok>"


def simulate_batch(
    scenarios: Sequence[LoadedScenario],
    keep_channels: Iterable[str] = (),
    keep_every: int = 1,
    metric_names: Iterable[str] | None = None,
    workers: int | None = None,
    progress: Callable[[int], None] | None = None,
) -> BatchResult:
    """Run many variants of one layout in one call, on ``workers`` threads (default: all cores).

    Memory stays bounded: each worker reuses one trace buffer; only ``keep_channels`` (every
    ``keep_every``-th record) and the metrics of each variant are kept.
    """
    if not scenarios:
        return BatchResult([], [], [], [])
    layout = scenarios[0].layout
    if any(sc.layout != layout for sc in scenarios):
        raise ValueError("a batch must use one vehicle layout; split it by layout")
    lay = layouts.get(layout)
    keep = [c for c in keep_channels]
    for c in keep:
        if c not in lay.CHANNELS:
            raise ValueError(f"unknown channel {c!r} for {layout}")
    names = list(metric_names) if metric_names is not None else None
    p_all = pack_records([sc.vehicle.flat() for sc in scenarios])
    s_all = pack_records([sc.flat for sc in scenarios])
    n = len(scenarios)
    metrics: list[dict] = [{} for _ in range(n)]
    kept: list[dict] = [{} for _ in range(n)]
    oks: list[bool] = [True] * n
    workers = workers or min(os.cpu_count() or 1, n)

    def work(indices: list[int]) -> None:
        # kernels fill a (chunk, samples) buffer; metrics then run once per chunk on (chunk, samples)
        # arrays, so the Python cost per variant (which holds the GIL) stays small
        for lo in range(0, len(indices), BATCH_CHUNK):
            part = indices[lo:lo + BATCH_CHUNK]
            n_recs = [_n_records(scenarios[i]) for i in part]
            rows = np.zeros((len(part), max(n_recs)), dtype=lay.TRACE_DTYPE)
            events = np.zeros((EVENT_BUFFER, EVENT_FIELDS))
            written = []
            for j, i in enumerate(part):
                trace_rows = rows[j].view(np.recarray)
                n_rec, _ = lay.run_kernel(p_all[i], s_all[i], _noise(scenarios[i], len(lay.SENSORS)), trace_rows, events)
                written.append(n_rec)
            if len(set(written)) == 1:
                n_rec = written[0]
                channels = {name: rows[name][:, :n_rec] for name in lay.CHANNELS}
                channels["time_s"] = rows["time_s"][0, :n_rec]
                chunk_metrics = compute_metrics(Trace(channels), names)
                per_variant = [{k: float(v[j]) for k, v in chunk_metrics.items()} for j in range(len(part))]
            else:  # runs of different length (e.g. a stop event): one trace each
                per_variant = [compute_metrics(Trace({name: rows[name][j, :written[j]] for name in lay.CHANNELS}), names)
                               for j in range(len(part))]
            for j, i in enumerate(part):
                metrics[i] = per_variant[j]
                oks[i] = all(c.ok for c in evaluate_checks(scenarios[i], per_variant[j]))
                if keep:
                    kept[i] = {c: np.array(rows[c][j, :written[j]:keep_every]) for c in ["time_s"] + keep}
            if progress is not None:
                progress(len(part))

    chunks = [list(range(w, n, workers)) for w in range(workers)]
    if workers == 1:
        work(chunks[0])
    else:
        with ThreadPoolExecutor(workers) as pool:
            list(pool.map(work, chunks))
    return BatchResult(metrics, kept, oks, [tuple(sc.sets) for sc in scenarios])
