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
from vehicle_assist.vehicles.common import ACT_STOP, EVENT_BUFFER

TABLE_CAPACITY_STEP = 32  # table and array fields are padded to multiples of this: one dtype, one compile
BATCH_CHUNK = 32  # at most this many variants per compiled call and metrics evaluation (one trace buffer per worker)


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


def _noise_key(run, noisy: bool) -> tuple:
    return (run.seed, run.duration_s, run.controller_period_s, noisy)


def _checks_ok(checks, metrics: dict[str, np.ndarray], n: int) -> np.ndarray:
    """:func:`evaluate_checks` of one check list for a chunk of runs at once (one bool per run)."""
    ok = np.ones(n, dtype=bool)
    for c in checks:
        value = np.asarray(metrics.get(c.metric, np.full(n, np.nan)), dtype=np.float64)
        with np.errstate(invalid="ignore"):
            holds = np.isfinite(value)
            if c.min is not None:
                holds &= value >= c.min
            if c.max is not None:
                holds &= value <= c.max
        ok &= holds if c.expect == "pass" else ~holds
    return ok


def _may_stop(s_rec: np.ndarray, idx: np.ndarray) -> bool:
    """Some variant ``idx`` of the scenario records ``s_rec`` has a stop event (its run may end early)."""
    try:
        count = np.asarray(s_rec["event_count"])[idx]
        action = np.asarray(s_rec["event_action"]).reshape(len(s_rec), -1)[idx]
    except (KeyError, ValueError):
        return True
    live = np.arange(action.shape[1])[None, :] < count[:, None]
    return bool(np.any(live & (action == ACT_STOP)))


def _chunk_size(n_rec: int, itemsize: int) -> int:
    """Variants per chunk: up to BATCH_CHUNK, a trace buffer of at most ~32 MB per worker."""
    return int(max(4, min(BATCH_CHUNK, 32_000_000 // max(1, n_rec * itemsize))))


def simulate_batch(
    scenarios,
    keep_channels: Iterable[str] = (),
    keep_every: int = 1,
    metric_names: Iterable[str] | None = None,
    workers: int | None = None,
    progress: Callable[[int], None] | None = None,
) -> BatchResult:
    """Run many variants of one layout in one call, on ``workers`` threads (default: all cores).

    ``scenarios``: a list of scenarios of one layout, or a :class:`~vehicle_assist.scenarios.variants.VariantSet`
    from :func:`~vehicle_assist.scenarios.variants.build_variants` (its records are written per chunk, no
    scenario object per variant). Memory stays bounded: each worker reuses one trace buffer; only
    ``keep_channels`` (every ``keep_every``-th record) and the metrics of each variant are kept.

    Each chunk of variants is one compiled call (``run_chunk`` of the layout) and its metrics are computed by
    the compiled twins of :mod:`vehicle_assist.metrics.fast` (identical values to :func:`compute_metrics`).
    """
    from vehicle_assist.metrics.fast import compute_metrics_fast, gather, plan
    from vehicle_assist.scenarios.variants import VariantSet

    vset = scenarios if isinstance(scenarios, VariantSet) else None
    if not len(scenarios):
        return BatchResult([], [], [], [])
    if vset is not None:
        layout = vset.layout
        base = vset.base
    else:
        scenarios = list(scenarios)
        layout = scenarios[0].layout
        if any(sc.layout != layout for sc in scenarios):
            raise ValueError("a batch must use one vehicle layout; split it by layout")
        base = None
    lay = layouts.get(layout)
    keep = [c for c in keep_channels]
    for c in keep:
        if c not in lay.CHANNELS:
            raise ValueError(f"unknown channel {c!r} for {layout}")
    names = list(metric_names) if metric_names is not None else None
    n = len(scenarios)
    n_sens = len(lay.SENSORS)
    if vset is None:
        p_all = pack_records([sc.vehicle.flat() for sc in scenarios])
        s_all = pack_records([sc.flat for sc in scenarios])
        noisy = np.any(np.nan_to_num(np.asarray(s_all["sensor_noise_std"]).reshape(n, -1)) != 0.0, axis=1)  # NaN: padding
        n_records = [_n_records(sc) for sc in scenarios]
        runs = [sc.model.run for sc in scenarios]
        same_checks = all(sc.model.checks is scenarios[0].model.checks for sc in scenarios)
        overrides = [tuple(sc.sets) for sc in scenarios]
    else:
        p_all = s_all = None
        n_records = None
        same_checks = True
        overrides = vset.overrides()
    metrics: list[dict] = [{} for _ in range(n)]
    kept: list[dict] = [{} for _ in range(n)]
    oks: list[bool] = [True] * n
    workers = max(1, min(workers or (os.cpu_count() or 1), n))
    rec_max = max(n_records) if n_records is not None else _n_records(base)
    chunk = _chunk_size(rec_max, lay.TRACE_DTYPE.itemsize)
    blocks = [(lo, min(n, lo + chunk)) for lo in range(0, n, chunk)]
    noises: dict[tuple, np.ndarray] = {}
    run_chunk = getattr(lay, "run_chunk", None)

    def noise_for(run, is_noisy: bool) -> np.ndarray:
        key = _noise_key(run, bool(is_noisy))
        arr = noises.get(key)
        if arr is None:
            if is_noisy:
                ticks = int(round(run.duration_s / run.controller_period_s)) + 2
                arr = np.random.default_rng(run.seed).standard_normal((ticks, n_sens))
            else:
                arr = np.zeros((1, n_sens))
            noises[key] = arr
        return arr

    selected, reads = plan(lay.CHANNELS, names)
    field_index = {name: i for i, name in enumerate(lay.TRACE_DTYPE.names)}
    read_cols = np.array([field_index[c] for c in reads], dtype=np.int64)
    all_f8 = all(lay.TRACE_DTYPE.fields[f][0] == np.float64 for f in lay.TRACE_DTYPE.names) and \
        lay.TRACE_DTYPE.itemsize == 8 * len(lay.TRACE_DTYPE.names)

    # the in-call copy (layouts with a chunk call and an all-float64 trace): the chunk call copies the fields the
    # metrics read and the kept channels out of each run's trace right after the run, while it is in the core's cache,
    # into a (fields, chunk, records) buffer per worker; every run of the chunk then writes its trace into one reused
    # row (cache-resident), and no chunk-sized trace buffer is streamed through the cache between the runs and the
    # metrics. A chunk whose runs may end early (a stop event: lengths may differ, and the per-run fallback below reads
    # every channel) gets full trace rows instead.
    in_call = all_f8 and run_chunk is not None
    copied = list(reads) + [c for c in ["time_s"] + keep if c not in reads]
    copy_cols = np.array([field_index[c] for c in copied], dtype=np.int64)
    copy_at = {name: c for c, name in enumerate(copied)}

    def work(blocks_iter) -> None:
        rows = flat_rows = gather_buf = None  # full trace rows of a chunk: allocated when a chunk needs them
        scratch = np.zeros((1, rec_max), dtype=lay.TRACE_DTYPE) if in_call else None
        scratch_flat = scratch.view(np.float64).reshape(1, rec_max, -1) if in_call else None
        copy_buf = np.empty((len(copy_cols), chunk, rec_max)) if in_call else None
        events = np.zeros((EVENT_BUFFER, EVENT_FIELDS))
        for lo, hi in blocks_iter:
            m = hi - lo
            if vset is None:
                p, s = p_all, s_all
                idx = np.arange(lo, hi)
                part_runs = runs[lo:hi]
                part_noisy = noisy[lo:hi]
            else:
                p, s = vset.records(lo, hi)
                idx = np.arange(m)
                part_runs = [base.model.run] * m
                part_noisy = np.any(np.nan_to_num(np.asarray(s["sensor_noise_std"]).reshape(m, -1)) != 0.0, axis=1)
            groups: dict[tuple, list[int]] = {}
            for j in range(m):
                groups.setdefault(_noise_key(part_runs[j], bool(part_noisy[j])), []).append(j)
            use_copy = in_call and not _may_stop(s, idx)
            for attempt in range(2):
                if not use_copy and rows is None:
                    rows = np.zeros((chunk, rec_max), dtype=lay.TRACE_DTYPE)
                    if all_f8:
                        flat_rows = rows.view(np.float64).reshape(chunk, rec_max, -1)
                        gather_buf = np.empty(len(read_cols) * chunk * rec_max)
                written = np.zeros(chunk, dtype=np.int64)
                for key, slots in groups.items():
                    noise = noise_for(part_runs[slots[0]], bool(part_noisy[slots[0]]))
                    if run_chunk is not None:
                        sl = np.asarray(slots, dtype=np.int64)
                        if use_copy:
                            run_chunk(p, s, idx[sl], sl, noise, scratch, events, written, scratch_flat, copy_cols,
                                      copy_buf)
                        else:
                            run_chunk(p, s, idx[sl], sl, noise, rows, events, written)
                    else:
                        for j in slots:
                            written[j], _ = lay.run_kernel(p[idx[j]], s[idx[j]], noise, rows[j].view(np.recarray),
                                                           events)
                lengths = written[:m]
                if not use_copy or np.all(lengths == lengths[0]):
                    break
                use_copy = False  # not expected without a stop event: the chunk again, into full trace rows
            if np.all(lengths == lengths[0]):
                n_rec = int(lengths[0])
                if use_copy:
                    channels = {name: copy_buf[c, :m] if n_rec == rec_max else
                                np.ascontiguousarray(copy_buf[c, :m, :n_rec]) for c, name in enumerate(reads)}
                    t_s = np.array(copy_buf[copy_at["time_s"], 0, :n_rec])
                elif flat_rows is not None:  # the read channels made contiguous in one pass (into a reused buffer:
                    # a fresh 10 MB array per chunk cost more in page faults than the copy itself)
                    gathered = gather_buf[:len(read_cols) * m * n_rec].reshape(len(read_cols), m, n_rec)
                    gather(flat_rows, m, n_rec, read_cols, gathered)
                    channels = {name: gathered[c] for c, name in enumerate(reads)}
                    t_s = np.array(rows["time_s"][0, :n_rec])
                else:
                    channels = {name: rows[name][:m, :n_rec] for name in lay.CHANNELS if name != "time_s"}
                    t_s = np.array(rows["time_s"][0, :n_rec])
                chunk_metrics = compute_metrics_fast(channels, t_s, selected)
                keys = list(chunk_metrics)
                columns = [np.asarray(chunk_metrics[k], dtype=np.float64).tolist() for k in keys]
                per_variant = [dict(zip(keys, vals)) for vals in zip(*columns)] if keys else [{} for _ in range(m)]
            else:  # runs of different length (e.g. a stop event): one trace each
                chunk_metrics = None
                per_variant = [compute_metrics(Trace({name: rows[name][j, :lengths[j]] for name in lay.CHANNELS}), selected)
                               for j in range(m)]
            if same_checks:
                checks = (base or scenarios[0]).model.checks
                if chunk_metrics is None:
                    chunk_metrics = {k: np.array([pv[k] for pv in per_variant]) for k in per_variant[0]} if m else {}
                ok = _checks_ok(checks, chunk_metrics, m).tolist()
            else:
                ok = [all(c.ok for c in evaluate_checks(scenarios[lo + j], per_variant[j])) for j in range(m)]
            for j in range(m):
                i = lo + j
                metrics[i] = per_variant[j]
                oks[i] = bool(ok[j])
                if keep:
                    kept[i] = ({c: np.array(copy_buf[copy_at[c], j, :lengths[j]:keep_every]) for c in ["time_s"] + keep}
                               if use_copy else
                               {c: np.array(rows[c][j, :lengths[j]:keep_every]) for c in ["time_s"] + keep})
            if progress is not None:
                progress(m)

    if workers == 1:
        work(iter(blocks))
    else:
        import threading

        lock = threading.Lock()
        shared = iter(blocks)

        def pull():
            while True:
                with lock:
                    item = next(shared, None)
                if item is None:
                    return
                yield item

        with ThreadPoolExecutor(workers) as pool:
            list(pool.map(lambda _: work(pull()), range(workers)))
    return BatchResult(metrics, kept, oks, overrides)
