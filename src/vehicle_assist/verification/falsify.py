"""Falsification: search an envelope for the input that minimises a requirement's robustness.

The search works on the unit cube of the envelope (``Envelope.unit_to_point``): continuous dimensions
are scaled to [0, 1]; a discrete dimension of k options is relaxed to [0, 1] and rounded to one of k
equal cells (the optimiser sees a piecewise-constant coordinate). Optimisers:

* ``cma``: a first space-filling batch (scrambled Sobol), then CMA-ES of the ``cma`` package (Hansen)
  from its best point, box-bounded to [0, 1]^d, population = batch size, restarted from a new seeded
  random mean when it converges (budget left);
* ``random``: uniform random points (the reference the benchmark compares against).

Each batch of candidates runs on all cores (:func:`simulate_batch`, keeping only the channels the
formula reads); the robustness is evaluated by rtamt (``verification.requirements``). A comparative
requirement runs each point together with its no-assist twin. The search stops at the first point with
robustness < 0 (a counterexample) or at the budget; it is deterministic for a given seed. With
``stop_at_violation=False`` (CLI ``--keep-going``) it uses the whole budget and the counterexample it
reports and writes is the WORST violation (minimum robustness, the earliest on a tie), not the first;
the number of violations and each one's index and robustness are in ``falsify.json``.
"""
from __future__ import annotations

import math
import time
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from vehicle_assist.scenarios.errors import InputError
from vehicle_assist.verification.envelope import Envelope, load_envelope
from vehicle_assist.verification.requirements import (
    Requirement,
    comparative_robustness,
    get_requirement,
    robustness,
)

OPTIMIZERS = ("cma", "random")
SUMMARY_METRICS = ("rollback_distance_m", "engine_stalled_flag", "jerk_filtered_peak_mps3", "assist_refusal_code")


@dataclass
class Evaluation:
    index: int
    point: dict
    unit: np.ndarray
    robustness: float
    metrics: dict = field(default_factory=dict)
    baseline_metrics: dict = field(default_factory=dict)


@dataclass
class FalsifyResult:
    envelope: Envelope
    requirement: Requirement
    optimizer: str
    seed: int
    budget: int
    sets: list[str]
    evaluations: list[Evaluation]
    wall_s: float
    stop_at_violation: bool = True
    counterexample_twin_robustness: float | None = None  # set by write_falsification (twin_robustness)

    @property
    def best(self) -> Evaluation:
        finite = [e for e in self.evaluations if not math.isnan(e.robustness)]
        return min(finite or self.evaluations, key=lambda e: e.robustness)

    @property
    def violations(self) -> list[Evaluation]:
        """Every evaluation with robustness < 0, in search order (NaN never counts)."""
        return [e for e in self.evaluations if e.robustness < 0]

    @property
    def first_counterexample(self) -> Evaluation | None:
        v = self.violations
        return v[0] if v else None

    @property
    def worst_counterexample(self) -> Evaluation | None:
        """The violation with the minimum robustness (the earliest of equal ones): the one to debug first."""
        v = self.violations
        return min(v, key=lambda e: e.robustness) if v else None

    @property
    def counterexample(self) -> Evaluation | None:
        """The counterexample this search reports and writes: the first violation when it stops at one, the
        worst when it kept going over the whole budget (--keep-going)."""
        return self.first_counterexample if self.stop_at_violation else self.worst_counterexample

    @property
    def evaluations_to_first(self) -> int | None:
        c = self.first_counterexample
        return None if c is None else c.index + 1


def _metric_names(layout: str) -> list[str]:
    from vehicle_assist.metrics import METRICS
    from vehicle_assist.vehicles import layouts

    chans = layouts.get(layout).CHANNELS
    return [n for n in SUMMARY_METRICS if n in METRICS and all(c in chans for c in METRICS[n].requires)]


def twin_robustness(env: Envelope, req: Requirement, point: dict) -> float | None:
    """Robustness of an absolute (non-comparative) requirement at ``point`` for the point's no-assist twin
    (the envelope's ``baseline`` overrides): tells a counterexample the assist causes from one the car without
    it has too (e.g. a lane departure on ice). None for a comparative requirement (its robustness is already
    the difference to the twin)."""
    if req.comparative:
        return None
    from vehicle_assist.core.trace import Trace
    from vehicle_assist.scenarios.runner import simulate_batch

    batch = simulate_batch([env.scenario(point, baseline=True)], keep_channels=list(req.channels), metric_names=[],
                           workers=1)
    return float(robustness(req, Trace(dict(batch.channels[0]))))


def twin_text(result: "FalsifyResult") -> str:
    """One clause for a log line or a reproduce entry: what the no-assist twin does at the counterexample."""
    r = result.counterexample_twin_robustness
    if r is None or result.counterexample is None:
        return ""
    if math.isnan(r):  # (a NaN compares False with 0: it was reported as "meets it")
        verdict = "cannot be judged (its robustness is not a number)"
    else:
        verdict = "violates it too" if r < 0 else "meets it"
    return (f"the same point without the assist ({' '.join(result.envelope.model.baseline)}) {verdict}: robustness "
            f"{r:.4g} {result.requirement.unit}")


def evaluate_points(env: Envelope, req: Requirement, points: list[dict], workers: int | None = None
                    ) -> tuple[list[float], list[dict], list[dict]]:
    """Robustness of ``req`` at each point (and the points' metrics, and their baseline twins' metrics).
    Inside a ``distributed.session`` the points run on the dask cluster (same values, see distributed.py)."""
    from vehicle_assist import distributed

    if distributed.active() is not None:
        return distributed.active().evaluate_points(env, req, points)
    from vehicle_assist.core.trace import Trace
    from vehicle_assist.scenarios.runner import simulate_batch

    names = _metric_names(env.layout)
    if req.comparative:
        from vehicle_assist.verification.requirements import comparative_metrics

        names = [*names, *[m for m in comparative_metrics(req) if m not in names]]
    scenarios = [env.scenario(p) for p in points]
    if req.comparative:
        twins = [env.scenario(p, baseline=True) for p in points]
        batch = simulate_batch(scenarios + twins, metric_names=names, workers=workers)
        n = len(points)
        metrics, base = batch.metrics[:n], batch.metrics[n:]
        robs = [comparative_robustness(req, m, b) for m, b in zip(metrics, base)]
        return robs, metrics, base
    batch = simulate_batch(scenarios, keep_channels=list(req.channels), metric_names=names, workers=workers)
    robs = [robustness(req, Trace(dict(ch))) for ch in batch.channels]
    return robs, batch.metrics, [{} for _ in points]


def run_falsification(envelope: str | Envelope, requirement: str | Requirement, budget: int = 200, seed: int = 0,
                      optimizer: str = "cma", batch: int = 8, sets: list[str] | None = None,
                      stop_at_violation: bool = True, console=None, workers: int | None = None,
                      progress: bool = True) -> FalsifyResult:
    env = envelope if isinstance(envelope, Envelope) else load_envelope(envelope)
    if sets:
        env = env.with_sets(sets)
    req = requirement if isinstance(requirement, Requirement) else get_requirement(requirement)
    if optimizer not in OPTIMIZERS:
        raise InputError(f"optimizer {optimizer!r}: use one of {', '.join(OPTIMIZERS)}")
    if budget < 1:
        raise InputError(f"budget = {budget}: must be >= 1")
    if batch < 1:
        raise InputError(f"batch = {batch}: must be >= 1")
    if not req.comparative:
        from vehicle_assist.verification.requirements import known_channels

        missing = [c for c in req.channels if c not in known_channels(env.layout)]
        if missing:
            raise InputError(f"requirement {req.id} reads {missing[0]!r}, which the {env.layout} vehicle of envelope "
                             f"{env.model.name} does not record")
    d = len(env.dims)
    rng = np.random.default_rng(seed)
    evals: list[Evaluation] = []
    t0 = time.perf_counter()

    def run_batch(U: np.ndarray) -> list[float]:
        pts = [env.unit_to_point(u) for u in U]
        robs, mets, bases = evaluate_points(env, req, pts, workers)
        for u, p, r, m, b in zip(U, pts, robs, mets, bases):
            evals.append(Evaluation(len(evals), p, np.array(u), float(r), m, b))
        return [float(r) if not math.isnan(r) else 1e9 for r in robs]

    bar = None
    if progress:
        from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn

        bar = Progress(TextColumn("{task.description}"), BarColumn(), TextColumn("{task.completed}/{task.total}"),
                       TimeElapsedColumn(), console=console, transient=True)
        bar.start()
        task = bar.add_task(f"falsify {req.id} ({optimizer})", total=budget)

    def report():
        if bar is not None:
            best = min((e.robustness for e in evals if not math.isnan(e.robustness)), default=float("nan"))
            bar.update(task, completed=len(evals),
                       description=f"falsify {req.id} ({optimizer}): best robustness {best:.4g} {req.unit}")

    def done() -> bool:
        return len(evals) >= budget or (stop_at_violation and any(e.robustness < 0 for e in evals))

    try:
        if optimizer == "random":
            while not done():
                k = min(batch, budget - len(evals))
                run_batch(rng.random((k, d)))
                report()
        else:
            import cma

            # first generation: a space-filling batch (scrambled Sobol); CMA-ES then starts from its best
            # point with a step of 0.2 of the box; a restart (budget left after convergence) starts from a
            # new random point with the initial step 0.3
            from scipy.stats import qmc

            k = min(max(batch, 2), budget)
            with warnings.catch_warnings():  # a batch that is not a power of 2 loses Sobol's balance: fine here
                warnings.simplefilter("ignore", UserWarning)
                U0 = qmc.Sobol(d, scramble=True, seed=int(rng.integers(0, 2**31 - 1))).random(k)
            f0 = run_batch(U0)
            report()
            x0, sigma0 = U0[int(np.argmin(f0))], 0.2
            while not done():
                opts = {"bounds": [0.0, 1.0], "popsize": max(batch, 2), "seed": int(rng.integers(1, 2**31 - 1)),
                        "verbose": -9, "tolfun": 1e-9, "tolx": 1e-4}
                es = cma.CMAEvolutionStrategy(x0, sigma0, opts)
                while not es.stop() and not done():
                    X = es.ask()
                    k = min(len(X), budget - len(evals))
                    f = run_batch(np.clip(np.array(X[:k]), 0.0, 1.0))
                    report()
                    if k < len(X):
                        break
                    es.tell(X, f)
                x0, sigma0 = rng.random(d), 0.3
    finally:
        if bar is not None:
            bar.stop()
    return FalsifyResult(env, req, optimizer, seed, budget, list(sets or []), evals, time.perf_counter() - t0,
                         stop_at_violation=stop_at_violation)


# ------------------------------------------------------------------------------------------- outputs
def counterexample_document(result: FalsifyResult, ev: Evaluation) -> dict:
    """A standalone scenario (TOML dict) that reproduces the point with ``vehicle-assist run``."""
    sc = result.envelope.scenario(ev.point)
    raw = {k: v for k, v in sc.raw.items() if k not in ("checks", "requirements")}
    raw["name"] = f"cex_{result.envelope.model.name}_{result.requirement.id.split('.')[-1]}"
    which = ("" if result.stop_at_violation
             else f", the worst of {len(result.violations)} violations in {len(result.evaluations)} evaluations")
    raw["description"] = (f"counterexample of {result.requirement.id} found by vehicle-assist falsify "
                          f"({result.optimizer}, seed {result.seed}, evaluation {ev.index + 1}{which}): robustness "
                          f"{ev.robustness:.6g} {result.requirement.unit}")
    raw["source"] = (f"envelope {result.envelope.model.name} point: {result.envelope.point_name(ev.point)}"
                     + (f"; fixed overrides: {'; '.join(result.sets)}" if result.sets else ""))
    raw["requirements"] = [result.requirement.id] if "." in result.requirement.id else [
        {"id": result.requirement.id, "formula": result.requirement.formula, "why": result.requirement.why}]
    return raw


COUNTEREXAMPLE_FILES = ("counterexample.toml", "counterexample_trace.parquet", "counterexample.png")


def write_falsification(result: FalsifyResult, out: Path) -> dict[str, Path]:
    """falsify.json (settings, best, counterexample, the violations, every evaluation) and, for a
    counterexample (the first violation, or the worst one when the search kept going), a standalone scenario
    ``counterexample.toml`` with its trace and overview plot. Every file is written atomically; the
    counterexample files of an earlier search in the same directory are removed first, so a directory never
    pairs this search's falsify.json with another search's counterexample."""
    import tomli_w

    from vehicle_assist.io.results import atomic_write_text, write_json, write_trace_parquet

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    for name in COUNTEREXAMPLE_FILES:
        (out / name).unlink(missing_ok=True)
    paths: dict[str, Path] = {}
    cex = result.counterexample
    first = result.first_counterexample
    env = result.envelope
    result.counterexample_twin_robustness = (None if cex is None else
                                             twin_robustness(result.envelope, result.requirement, cex.point))
    summary = {
        "envelope": result.envelope.model.name, "requirement": result.requirement.as_dict(),
        "optimizer": result.optimizer, "seed": result.seed, "budget": result.budget, "sets": result.sets,
        "restrict": {k: list(v) for k, v in result.envelope.narrowed.items()},
        "stop_at_violation": result.stop_at_violation,
        "evaluations": len(result.evaluations), "wall_s": result.wall_s,
        "evaluations_to_first_counterexample": result.evaluations_to_first,
        "min_robustness": result.best.robustness, "best_point": result.best.point,
        # the conditional ranges (``when``) a point did not write: their value in "point" did nothing there (the
        # accumulator at an inlet-fault point); absent from files written before (read them as an empty list)
        "best_point_inactive": env.inactive(result.best.point),
        "violation_count": len(result.violations),
        "violations": [{"index": e.index, "robustness": e.robustness} for e in result.violations],
        "first_counterexample": None if first is None else {"index": first.index, "robustness": first.robustness},
        "counterexample": None if cex is None else {
            "selected": "first" if result.stop_at_violation else "worst", "index": cex.index,
            "point": cex.point, "inactive": env.inactive(cex.point), "robustness": cex.robustness,
            "metrics": cex.metrics, "baseline_metrics": cex.baseline_metrics,
            "baseline_robustness": result.counterexample_twin_robustness},
        "history": [{"index": e.index, "robustness": e.robustness, "point": e.point, "inactive": env.inactive(e.point),
                     **e.metrics} for e in result.evaluations],
    }
    paths["summary"] = write_json(summary, out / "falsify.json")
    target = cex
    if target is not None:
        from vehicle_assist.report.plots import overview_png
        from vehicle_assist.scenarios.loader import load_scenario
        from vehicle_assist.scenarios.runner import simulate

        doc = counterexample_document(result, target)
        scenario_path = out / "counterexample.toml"
        paths["scenario"] = atomic_write_text(scenario_path, tomli_w.dumps(doc))
        rerun = simulate(load_scenario(scenario_path))
        paths["trace"] = write_trace_parquet(rerun.trace, out / "counterexample_trace.parquet")
        paths["plot"] = overview_png(rerun.trace, out / "counterexample.png", f"counterexample of {result.requirement.id}")
    return paths
