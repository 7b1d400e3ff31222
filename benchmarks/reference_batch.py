"""The batch path as it was before issue 13, kept as the benchmark's reference implementation.

``make bench`` times it in the same process as the current path, so the ratio (current / reference CPU per
variant) is measured under the same machine load. What it does per variant, as the code did then:
``with_sets`` builds each variant (pydantic validation of the touched subsystem), every variant's flat records
are packed, the layout's ``run_kernel`` is called once per variant (record unboxing per call), the numpy
metrics run per chunk of 16 variants and the checks are evaluated per variant. It shares today's kernel, so the
ratio measures the batch machinery only; the kernel's own change is measured against the kernel-only loop.
"""
from __future__ import annotations

import os
from concurrent.futures import ThreadPoolExecutor

import numpy as np

from vehicle_assist.core.fsm import EVENT_FIELDS
from vehicle_assist.core.trace import Trace
from vehicle_assist.metrics import compute_metrics
from vehicle_assist.scenarios.runner import _n_records, _noise, evaluate_checks, pack_records
from vehicle_assist.vehicles import layouts
from vehicle_assist.vehicles.common import EVENT_BUFFER

CHUNK = 16


def build_reference(sc, mass, pressure, rate):
    return [sc.with_sets(f"vehicle.body.mass_kg={m}", f"vehicle.park_brake.reservoir_pressure_bar={p}",
                         f"vehicle.amt_launch.engage_rate_per_s={r}") for m, p, r in zip(mass, pressure, rate)]


def reference_batch(scenarios, keep_channels=(), keep_every=1, workers=None):
    lay = layouts.get(scenarios[0].layout)
    keep = list(keep_channels)
    p_all = pack_records([sc.vehicle.flat() for sc in scenarios])
    s_all = pack_records([sc.flat for sc in scenarios])
    n = len(scenarios)
    metrics, kept, oks = [{} for _ in range(n)], [{} for _ in range(n)], [True] * n
    workers = workers or min(os.cpu_count() or 1, n)

    def work(indices):
        for lo in range(0, len(indices), CHUNK):
            part = indices[lo:lo + CHUNK]
            n_recs = [_n_records(scenarios[i]) for i in part]
            rows = np.zeros((len(part), max(n_recs)), dtype=lay.TRACE_DTYPE)
            events = np.zeros((EVENT_BUFFER, EVENT_FIELDS))
            written = []
            for j, i in enumerate(part):
                n_rec, _ = lay.run_kernel(p_all[i], s_all[i], _noise(scenarios[i], len(lay.SENSORS)),
                                          rows[j].view(np.recarray), events)
                written.append(n_rec)
            n_rec = written[0]
            channels = {name: rows[name][:, :n_rec] for name in lay.CHANNELS}
            channels["time_s"] = rows["time_s"][0, :n_rec]
            chunk_metrics = compute_metrics(Trace(channels))
            per_variant = [{k: float(v[j]) for k, v in chunk_metrics.items()} for j in range(len(part))]
            for j, i in enumerate(part):
                metrics[i] = per_variant[j]
                oks[i] = all(c.ok for c in evaluate_checks(scenarios[i], per_variant[j]))
                if keep:
                    kept[i] = {c: np.array(rows[c][j, :written[j]:keep_every]) for c in ["time_s"] + keep}

    chunks = [list(range(w, n, workers)) for w in range(workers)]
    with ThreadPoolExecutor(workers) as pool:
        list(pool.map(work, chunks))
    return metrics, kept, oks
