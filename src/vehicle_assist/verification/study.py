"""Envelope studies: the dense grid of issue #7 (every point with its no-assist twin), coverage by
quasi-random sampling with a pass/fail map, and global sensitivity (SALib Sobol indices).

* :func:`envelope_study` - a full-factorial grid over an envelope; for every point the assisted run and
  its no-assist twin. Reports runs, worst rollback (assisted vs baseline), worst jerk, stalls the assist
  causes, refusals by reason (``assist_refusal_code`` and the layout's ``REFUSAL_REASONS``), the
  counterexamples of "never worse than no assist" (issue #7 item 1), a table and a figure.
* :func:`coverage_study` - ``n`` Sobol/LHS points, robustness of one requirement at each, a pass/fail map.
* :func:`sensitivity_study` - Saltelli sampling and Sobol indices (first order S1, total ST) of the
  robustness with respect to every envelope dimension (discrete ones through their unit-cell coordinate).
"""
from __future__ import annotations

import io
import math
import time
from pathlib import Path

import numpy as np

from vehicle_assist.io.results import atomic_path, atomic_write_bytes, write_json
from vehicle_assist.verification.envelope import Envelope, load_envelope
from vehicle_assist.verification.requirements import get_requirement, no_worse_robustness

ROLLBACK_FLOOR_M = 0.01  # issue #7 item 1: rollback <= max(1 cm, the unassisted rollback)
JERK_BOUND_MPS3 = 0.1  # paper 001 P8, hill_start_ehb.md 5.2
PAPER_PEDAL_RATE_PER_S = 0.0225  # hill_start_ehb.md 4 S1


def _refusal_reasons(layout: str) -> tuple[str, ...]:
    from vehicle_assist.vehicles import layouts

    return tuple(getattr(layouts.get(layout), "REFUSAL_REASONS", ()) or ())


def _study_metrics(layout: str) -> tuple[list[str], list[str]]:
    """(metrics to compute, channels to keep for a max) available for the layout."""
    from vehicle_assist.metrics import METRICS
    from vehicle_assist.vehicles import layouts

    chans = layouts.get(layout).CHANNELS
    wanted = ["rollback_distance_m", "rollback_speed_mps", "engine_stalled_flag", "jerk_filtered_peak_mps3",
              "assist_refusal_code", "final_speed_mps"]
    names = [n for n in wanted if n in METRICS and all(c in chans for c in METRICS[n].requires)]
    keep = ["assist_refusal_code"] if "assist_refusal_code" not in names and "assist_refusal_code" in chans else []
    return names, keep


def braked_adhesion_holds(sc) -> bool:
    """Closed form: can the braked wheels hold the vehicle at rest on this grade? mu * F_z,braked >= m g sin(a),
    i.e. mu * r * cos(a) >= sin(a) with r the load share of the braked wheels (EV: all four wheels, r = 1;
    truck: the spring brake acts on the rear tandem, r from the axle-load split of the vehicle file); for the
    truck also the spring brake's rated force: m g sin(a) <= F_g_max + m g f cos(a) (a 40 t truck on 20 deg
    needs 134 kN, the 100 kN spring brake cannot hold it whatever the grip)."""
    a = math.radians(sc.model.road.slope_deg or 0.0)
    mu = sc.model.road.friction_mu if sc.model.road.friction_mu is not None else 1.0
    r = 1.0
    axles = getattr(sc.vehicle.model, "axles", None)
    if sc.layout == "truck_amt" and axles is not None and hasattr(axles, "empty_rear_load_frac"):
        m = sc.vehicle.model.body.mass_kg
        m0 = min(getattr(axles, "empty_mass_kg", m), m)
        r = (m0 * axles.empty_rear_load_frac + (m - m0) * axles.payload_rear_load_frac) / m
    if not mu * r * math.cos(a) >= math.sin(a):
        return False
    park = getattr(sc.vehicle.model, "park_brake", None)
    if sc.layout == "truck_amt" and park is not None and hasattr(park, "max_force_n"):
        # the spring brake's rated holding force at the ground (common.md 7.2) plus the rolling-resistance
        # reaction at rest (common.md 3.3) must carry the grade force: m g sin(a) <= F_g_max + m g f cos(a)
        m = sc.vehicle.model.body.mass_kg
        f = sc.model.road.rolling_resistance_coeff
        if f is None:
            f = sc.vehicle.model.body.rolling_resistance_coeff
        return m * 9.81 * math.sin(a) <= park.max_force_n + m * 9.81 * f * math.cos(a)
    return True


def run_points(env: Envelope, points: list[dict], baseline: bool = True, chunk: int = 256, progress=None
               ) -> tuple[list[dict], list[dict]]:
    """Metrics of each point's assisted run (and of its no-assist twin), in chunks on all cores (inside a
    ``distributed.session``: each chunk a task on the dask cluster, the same chunks, the same values)."""
    from vehicle_assist import distributed

    if distributed.active() is not None:
        return distributed.active().run_points(env, points, baseline, chunk, progress)
    from vehicle_assist.scenarios.runner import simulate_batch

    names, keep = _study_metrics(env.layout)
    assisted: list[dict] = []
    base: list[dict] = []
    for lo in range(0, len(points), chunk):
        part = points[lo:lo + chunk]
        scs = [env.scenario(p) for p in part]
        if baseline:
            scs += [env.scenario(p, baseline=True) for p in part]
        res = simulate_batch(scs, keep_channels=keep, keep_every=1, metric_names=names,
                             progress=(lambda n: progress(n / (2 if baseline else 1))) if progress else None)
        mets = [dict(m) for m in res.metrics]
        for m, ch in zip(mets, res.channels):
            if keep and ch:
                m["assist_refusal_code"] = float(np.max(ch["assist_refusal_code"])) if len(ch["assist_refusal_code"]) else 0.0
        assisted += mets[:len(part)]
        if baseline:
            base += mets[len(part):]
    return assisted, base


def no_worse_margin(m: dict, b: dict) -> float:
    """Robustness of "never worse than no assist" (m): max(1 cm, baseline rollback) - rollback, the stall penalty if
    the assist stalls an engine the baseline does not or has no rollback value where the baseline has one (issue #7
    item 1; the same rule as the requirement kind no_worse_than_baseline)."""
    return no_worse_robustness(m, b, "rollback_distance_m", ROLLBACK_FLOOR_M)


def envelope_study(envelope: str | Envelope, levels: dict, out: Path, sets: list[str] | None = None, console=None,
                   label: str | None = None) -> dict:
    """Grid study of one envelope (see module doc); writes ``<name>_grid.parquet``, ``<name>_grid.json`` and
    ``<name>_grid.png`` in ``out`` and returns the summary."""
    import pyarrow as pa
    import pyarrow.parquet as pq
    from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn

    env = envelope if isinstance(envelope, Envelope) else load_envelope(envelope)
    if sets:
        env = env.with_sets(sets)
    name = label or env.model.name
    points = env.grid(levels)
    t0 = time.perf_counter()
    with Progress(TextColumn("{task.description}"), BarColumn(), TextColumn("{task.completed:.0f}/{task.total}"),
                  TimeElapsedColumn(), console=console, transient=True) as bar:
        task = bar.add_task(f"envelope {name}: {len(points)} points x 2", total=len(points))
        assisted, base = run_points(env, points, progress=lambda n: bar.advance(task, n))
    wall = time.perf_counter() - t0
    reasons = _refusal_reasons(env.layout)
    margin = np.array([no_worse_margin(m, b) for m, b in zip(assisted, base)])
    rb = np.array([m.get("rollback_distance_m", np.nan) for m in assisted])
    rb0 = np.array([b.get("rollback_distance_m", np.nan) for b in base])
    stall = np.array([m.get("engine_stalled_flag", 0.0) for m in assisted]) >= 0.5
    stall0 = np.array([b.get("engine_stalled_flag", 0.0) for b in base]) >= 0.5
    jerk = np.array([m.get("jerk_filtered_peak_mps3", np.nan) for m in assisted])
    has_refusal = any("assist_refusal_code" in m for m in assisted)
    code = np.array([m.get("assist_refusal_code", 0.0) for m in assisted])
    refusals: dict[str, int] = {}
    for k in code[code >= 1]:
        idx = int(round(k)) - 1
        reason = reasons[idx] if 0 <= idx < len(reasons) else f"code {int(round(k))}"
        refusals[reason] = refusals.get(reason, 0) + 1
    holdable = np.array([braked_adhesion_holds(env.scenario(p)) for p in points]) if (code >= 1).any() else np.ones(len(points), bool)
    refused_rolled = int(np.sum((code >= 1) & (rb > ROLLBACK_FLOOR_M) & holdable))
    refused_sliding = int(np.sum((code >= 1) & ~holdable))
    bad = np.nonzero(margin < 0)[0]
    order = bad[np.argsort(margin[bad])]
    cex = [{"point": points[i], "margin_m": float(margin[i]), "rollback_m": float(rb[i]), "baseline_rollback_m": float(rb0[i]),
            "stalled": bool(stall[i]), "baseline_stalled": bool(stall0[i]), "refusal_code": float(code[i])}
           for i in order[:20]]
    i_worst = int(np.nanargmax(rb)) if len(rb) else 0
    summary = {
        "envelope": env.model.name, "label": name, "points": len(points), "runs": 2 * len(points), "wall_s": wall,
        "levels": {k: v for k, v in levels.items()}, "sets": list(sets or []),
        "min_no_worse_margin_m": float(np.nanmin(margin)) if len(margin) else math.nan,
        "counterexamples": int(len(bad)),
        "worst_rollback_assisted_m": float(np.nanmax(rb)), "worst_rollback_assisted_point": points[i_worst],
        "worst_rollback_baseline_m": float(np.nanmax(rb0)),
        "points_rollback_over_1cm_assisted": int(np.sum(rb > ROLLBACK_FLOOR_M)),
        "points_rollback_over_1cm_baseline": int(np.sum(rb0 > ROLLBACK_FLOOR_M)),
        "stalls_assisted": int(stall.sum()), "stalls_baseline": int(stall0.sum()),
        "stalls_caused": int(np.sum(stall & ~stall0)),
        "worst_jerk_mps3": float(np.nanmax(jerk)) if np.any(np.isfinite(jerk)) else math.nan,
        "refusal_metric_present": has_refusal, "refusal_reasons": list(reasons), "refusals": refusals,
        "refused_with_rollback": refused_rolled, "refused_beyond_braked_adhesion": refused_sliding,
        "worst_counterexamples": cex,
        "not_started_assisted": int(np.sum(np.array([m.get("final_speed_mps", np.nan) for m in assisted]) < 0.5)),
        "not_started_baseline": int(np.sum(np.array([b.get("final_speed_mps", np.nan) for b in base]) < 0.5)),
    }
    if "driver" in env.names and "accelerator.rate_per_s" in env.names:
        # where the assist acts: grades above its activation threshold (vehicle file slope_min_deg)
        slope_min = float(getattr(env.base_scenario.vehicle.model.hill_start_assist, "slope_min_deg", 0.0))
        sel = np.array([p["driver"] == "steady" and p["accelerator.rate_per_s"] <= 2 * PAPER_PEDAL_RATE_PER_S + 1e-12
                        and p.get("slope", 90.0) > slope_min for p in points])
        summary["jerk_slope_min_deg"] = slope_min
        summary["jerk_steady_upto_2x_paper_rate_mps3"] = float(np.nanmax(jerk[sel])) if sel.any() else math.nan
        summary["jerk_steady_upto_2x_paper_points"] = int(sel.sum())
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    cols: dict[str, list] = {}
    for d in env.dims:
        cols[d.name] = [p[d.name] for p in points]
    cols.update({"rollback_m": rb, "baseline_rollback_m": rb0, "stalled": stall, "baseline_stalled": stall0,
                 "jerk_filtered_peak_mps3": jerk, "assist_refusal_code": code, "no_worse_margin_m": margin})
    table_path = out / f"{name}_grid.parquet"
    with atomic_path(table_path) as tmp:
        pq.write_table(pa.table({k: list(v) for k, v in cols.items()}), tmp)
    summary["table"] = str(table_path)
    summary["figure"] = str(_grid_figure(env, points, summary, rb, rb0, margin, jerk, code, reasons, out / f"{name}_grid.png"))
    write_json(summary, out / f"{name}_grid.json")
    return summary


def _png(fig, path: Path) -> Path:
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png")
    return atomic_write_bytes(path, buffer.getvalue())


def _grid_figure(env, points, summary, rb, rb0, margin, jerk, code, reasons, path: Path) -> Path:
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(13, 9), dpi=90)
    FigureCanvasAgg(fig)
    (a, b), (c, d) = fig.subplots(2, 2)
    fig.suptitle(f"Envelope {summary['label']}: {summary['points']} points, each with its no-assist twin "
                 f"({summary['runs']} runs); {summary['counterexamples']} worse than no assist", fontsize=11)
    floor = 1e-4
    bad = margin < 0
    a.scatter(np.maximum(rb0[~bad], floor), np.maximum(rb[~bad], floor), s=6, c="tab:blue", alpha=0.5, label="never worse")
    a.scatter(np.maximum(rb0[bad], floor), np.maximum(rb[bad], floor), s=12, c="tab:red", label="worse than no assist")
    lim = max(1.0, float(np.nanmax(np.r_[rb, rb0, [1.0]])) * 2)
    xs = np.logspace(-4, math.log10(lim), 50)
    a.plot(xs, np.maximum(xs, ROLLBACK_FLOOR_M), "k--", lw=1, label="bound max(1 cm, baseline)")
    a.set_xscale("log"); a.set_yscale("log")
    a.set_xlabel("rollback without the assist [m] (floored at 0.1 mm)")
    a.set_ylabel("rollback with the assist [m]")
    a.legend(fontsize=8)
    a.set_title("worst rollback: assisted vs baseline", fontsize=10)
    # map: worst margin over all other dimensions, on slope x mass
    if "slope" in env.names and "mass" in env.names:
        slopes = sorted({p["slope"] for p in points})
        masses = sorted({p["mass"] for p in points})
        z = np.full((len(masses), len(slopes)), np.nan)
        for p, m in zip(points, margin):
            i, j = masses.index(p["mass"]), slopes.index(p["slope"])
            z[i, j] = m if np.isnan(z[i, j]) else min(z[i, j], m)
        zc = np.clip(z, -1.0, 0.05)
        im = b.pcolormesh(slopes, masses, zc, cmap="RdYlGn", vmin=-1.0, vmax=0.05, shading="nearest")
        for i in range(len(masses)):
            for j in range(len(slopes)):
                if z[i, j] < 0:
                    b.text(slopes[j], masses[i], "x", ha="center", va="center", fontsize=9)
        fig.colorbar(im, ax=b, label="worst margin [m] (clipped to -1 .. 0.05)")
        b.set_xlabel("slope [deg]"); b.set_ylabel("mass [kg]")
        b.set_title("never worse than no assist: worst margin over the other dimensions (x = violated)", fontsize=9)
    labels = ["none"] + list(reasons or [])
    counts = [int(np.sum(code < 1))] + [int(np.sum(np.round(code) == k + 1)) for k in range(len(reasons))]
    if not summary["refusal_metric_present"]:
        c.text(0.5, 0.5, "no refusal channel in this model yet\n(assist_refusal_code absent)", ha="center",
               va="center", transform=c.transAxes)
    c.barh(range(len(labels)), counts, color=["tab:gray"] + ["tab:orange"] * (len(labels) - 1))
    c.set_yticks(range(len(labels)), labels, fontsize=8)
    c.set_xlabel("points")
    c.set_title("refusals by reason (assisted runs)", fontsize=10)
    finite = jerk[np.isfinite(jerk)]
    if len(finite):
        d.hist(np.clip(finite, 1e-3, None), bins=np.logspace(-3, 2, 40), color="tab:purple")
        if env.layout == "ev_ehb":
            d.axvline(JERK_BOUND_MPS3, color="k", ls="--", lw=1, label="0.1 m/s^3 (paper 001 P8)")
            d.legend(fontsize=8)
        d.set_xscale("log")
    d.set_xlabel("peak filtered jerk, assisted [m/s^3]")
    d.set_ylabel("points")
    d.set_title(f"worst jerk {summary['worst_jerk_mps3']:.3g} m/s^3; stalls caused {summary.get('stalls_caused', 0)}",
                fontsize=10)
    fig.tight_layout(rect=(0, 0, 1, 0.95))
    return _png(fig, path)


# ------------------------------------------------------------------------------------------- coverage
def coverage_study(envelope: str | Envelope, requirement: str, n: int, method: str = "sobol", seed: int = 0,
                   sets: list[str] | None = None, out: Path = Path("out/study"), console=None) -> dict:
    from vehicle_assist.verification.falsify import evaluate_points

    env = envelope if isinstance(envelope, Envelope) else load_envelope(envelope)
    if sets:
        env = env.with_sets(sets)
    req = get_requirement(requirement)
    U, points = env.sample(n, method=method, seed=seed)
    robs: list[float] = []
    for lo in range(0, n, 128):
        r, _, _ = evaluate_points(env, req, points[lo:lo + 128])
        robs += r
    rob = np.array(robs)
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    fig_path = _pass_fail_map(env, U, rob, req, out / f"coverage_{env.model.name}_{req.id.split('.')[-1]}.png", method)
    result = {"envelope": env.model.name, "requirement": req.id, "unit": req.unit, "method": method, "seed": seed,
              "points": n, "violations": int(np.sum(rob < 0)), "min_robustness": float(np.nanmin(rob)),
              "worst_point": points[int(np.nanargmin(rob))], "figure": str(fig_path),
              "robustness": rob.tolist(), "unit_points": U.tolist()}
    write_json(result, out / f"coverage_{env.model.name}_{req.id.split('.')[-1]}.json")
    return result


def _pass_fail_map(env, U, rob, req, path: Path, method: str) -> Path:
    """Pairwise scatter of the envelope's dimensions (unit coordinates), green = pass, red = fail."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    dims = env.dims[:6]
    k = len(dims)
    fig = Figure(figsize=(2.2 * k, 2.2 * k), dpi=80)
    FigureCanvasAgg(fig)
    axes = fig.subplots(k, k, squeeze=False)
    fail = rob < 0
    for i in range(k):
        for j in range(k):
            ax = axes[i, j]
            ax.set_xticks([]); ax.set_yticks([])
            if i == j:
                ax.text(0.5, 0.5, f"{dims[i].name}\n{dims[i].describe()}", ha="center", va="center", fontsize=7,
                        transform=ax.transAxes)
                continue
            ax.scatter(U[~fail, j], U[~fail, i], s=3, c="tab:green", alpha=0.5)
            ax.scatter(U[fail, j], U[fail, i], s=5, c="tab:red")
            ax.set_xlim(0, 1); ax.set_ylim(0, 1)
    fig.suptitle(f"{env.model.name}, {req.id}: {len(rob)} {method} points, {int(fail.sum())} violate (red); "
                 "axes: unit coordinates of the dimensions", fontsize=9)
    return _png(fig, path)


# ------------------------------------------------------------------------------------------- sensitivity
def sensitivity_study(envelope: str | Envelope, requirement: str, n_base: int, seed: int = 0,
                      sets: list[str] | None = None, out: Path = Path("out/study"), console=None,
                      output: str = "robustness") -> dict:
    """SALib Sobol indices (Saltelli sampling without second order, N*(D+2) points) of the robustness
    (``output="robustness"``) or of the violation indicator (``"violated"``: 1 where robustness < 0). The
    indicator is the better-posed output when the robustness is heavy-tailed (rare violations of tens of
    metres next to a plateau of 0.01 m), where the variance-based indices of the raw value are unstable."""
    if output not in ("robustness", "violated"):
        from vehicle_assist.scenarios.errors import InputError

        raise InputError(f"sensitivity output {output!r}: use robustness or violated")
    from SALib.analyze import sobol as sobol_analyze
    from SALib.sample import sobol as sobol_sample

    from vehicle_assist.verification.falsify import evaluate_points

    env = envelope if isinstance(envelope, Envelope) else load_envelope(envelope)
    if sets:
        env = env.with_sets(sets)
    req = get_requirement(requirement)
    problem = {"num_vars": len(env.dims), "names": env.names, "bounds": [[0.0, 1.0]] * len(env.dims)}
    X = sobol_sample.sample(problem, n_base, calc_second_order=False, seed=seed)
    X = np.clip(X, 0.0, 1.0 - 1e-12)
    points = [env.unit_to_point(x) for x in X]
    robs: list[float] = []
    for lo in range(0, len(points), 128):
        r, _, _ = evaluate_points(env, req, points[lo:lo + 128])
        robs += r
    Y = np.array(robs, dtype=float)
    if output == "violated":
        Y = (Y < 0).astype(float)
    finite = np.isfinite(Y)
    if not finite.all():  # +-inf (a Boolean part) or NaN: clip to the finite range so the indices stay defined
        lo_, hi_ = (np.nanmin(Y[finite]), np.nanmax(Y[finite])) if finite.any() else (0.0, 0.0)
        Y = np.clip(np.nan_to_num(Y, nan=hi_), lo_, hi_)
    Si = sobol_analyze.analyze(problem, Y, calc_second_order=False, seed=seed, print_to_console=False)
    rows = [{"dimension": n, "S1": float(Si["S1"][i]), "S1_conf": float(Si["S1_conf"][i]), "ST": float(Si["ST"][i]),
             "ST_conf": float(Si["ST_conf"][i])} for i, n in enumerate(env.names)]
    rows.sort(key=lambda r: -r["ST"])
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    fig_path = _sobol_figure(env, req, rows, len(points), out / f"sensitivity_{env.model.name}_{req.id.split('.')[-1]}.png")
    result = {"envelope": env.model.name, "requirement": req.id, "output": output, "points": len(points), "n_base": n_base, "seed": seed,
              "indices": rows, "figure": str(fig_path), "violations": int(np.sum(np.array(robs) < 0))}
    write_json(result, out / f"sensitivity_{env.model.name}_{req.id.split('.')[-1]}.json")
    return result


def _sobol_figure(env, req, rows, n, path: Path) -> Path:
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(8, 0.45 * len(rows) + 1.6), dpi=90)
    FigureCanvasAgg(fig)
    ax = fig.subplots()
    y = np.arange(len(rows))
    ax.barh(y - 0.2, [r["S1"] for r in rows], 0.4, xerr=[r["S1_conf"] for r in rows], label="S1 (first order)")
    ax.barh(y + 0.2, [r["ST"] for r in rows], 0.4, xerr=[r["ST_conf"] for r in rows], label="ST (total)")
    ax.set_yticks(y, [r["dimension"] for r in rows], fontsize=8)
    ax.invert_yaxis()
    ax.legend(fontsize=8)
    ax.set_title(f"Sobol indices of {req.id} ({n} runs, SALib)", fontsize=10)
    fig.tight_layout()
    return _png(fig, path)
