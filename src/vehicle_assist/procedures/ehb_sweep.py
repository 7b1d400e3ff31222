"""Calibration map of the EV hill-start assist (issue: "a sweep of slope 0-20 deg x mass (empty to full)
x accelerator rate, reported as a heat map of max rollback and max jerk").

The shipped paper-001 scenario (``hsa_ev_5deg_paper``) is varied in grade, vehicle mass (the assist keeps
its calibrated 1500 kg: the map shows where the function holds for a heavier car) and the rate at which
the driver presses the accelerator (pedal ramp from 2 s up to 1.0). The driver holds the car with 60 bar
before releasing the brake pedal at 1-1.3 s, enough for every grade and mass of the map. Every variant runs in one batch on
all cores; the result is a parquet table and a figure with one heat map per accelerator rate.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from vehicle_assist.io.results import atomic_path, atomic_write_bytes

SLOPES_DEG = tuple(range(0, 21, 2))
MASSES_KG = (1500, 1650, 1800, 1950)  # curb + driver .. + 4 passengers and luggage (assumed)
RATES_PER_S = (0.01, 0.0225, 0.05, 0.1)  # 0.0225 /s is the paper case (hill_start_ehb.md 4 S1)
BASE = "hsa_ev_5deg_paper"


def variants():
    import vehicle_assist as va

    base = va.load_scenario(BASE)
    out = []
    for rate in RATES_PER_S:
        t_full = 2.0 + 1.0 / rate
        for mass in MASSES_KG:
            for slope in SLOPES_DEG:
                out.append(((slope, mass, rate), base.with_sets(
                    f"road.slope_deg={slope}", f"vehicle.body.mass_kg={mass}",
                    # the driver holds 60 bar (10.7 kN, more than 1950 kg on 20 deg needs) before the start
                    "driver.brake_pedal={time_s=[0.0, 1.0, 1.3], frac=[0.6, 0.6, 0.0]}",
                    f"driver.accelerator={{time_s=[2.0, {t_full:.4f}], frac=[0.0, 1.0]}}",
                    f"run.duration_s={t_full + 6.0:.4f}")))
    return out


def run_ehb_sweep(out_dir: Path) -> tuple[Path, Path, dict]:
    """Run the map; returns (figure, table, summary numbers)."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    from vehicle_assist.scenarios.runner import simulate_batch

    keys_and_variants = variants()
    keys = [k for k, _ in keys_and_variants]
    batch = simulate_batch([v for _, v in keys_and_variants], metric_names=["rollback_distance_m", "jerk_filtered_peak_mps3"])
    rollback = np.array([m["rollback_distance_m"] for m in batch.metrics])
    jerk = np.array([m["jerk_filtered_peak_mps3"] for m in batch.metrics])
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    table = pa.table({"slope_deg": [k[0] for k in keys], "mass_kg": [k[1] for k in keys],
                      "accelerator_rate_per_s": [k[2] for k in keys], "rollback_distance_m": rollback,
                      "jerk_filtered_peak_mps3": jerk})
    table_path = out_dir / "ehb_sweep.parquet"
    with atomic_path(table_path) as tmp:
        pq.write_table(table, tmp)
    figure = _heat_maps(keys, rollback, jerk, out_dir / "ehb_sweep_heatmap.png")
    summary = {
        "variants": len(keys),
        "max_rollback_m": float(np.nanmax(rollback)),
        "worst_rollback_case": keys[int(np.nanargmax(rollback))],
        "jerk_ok_frac": float(np.mean(jerk <= 0.1)),
        "rollback_ok_frac": float(np.mean(rollback <= 0.01)),
    }
    return figure, table_path, summary


def _heat_maps(keys, rollback, jerk, path: Path) -> Path:
    import io

    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.colors import LogNorm
    from matplotlib.figure import Figure

    fig = Figure(figsize=(14, 6.4), dpi=100)
    FigureCanvasAgg(fig)
    axes = fig.subplots(2, len(RATES_PER_S), sharex=True, sharey=True)
    fig.subplots_adjust(left=0.06, right=0.93, top=0.88, bottom=0.09, wspace=0.08, hspace=0.25)
    fig.suptitle("EV hill-start assist (paper 001): where it holds. Rows: max rollback, max filtered jerk; "
                 "columns: accelerator rate", fontsize=11)
    grid = {k: i for i, k in enumerate(keys)}
    for row, (values, label, norm) in enumerate((
            (rollback, "max rollback [m]", LogNorm(vmin=1e-4, vmax=max(1e-3, float(np.nanmax(rollback)) or 1e-3))),
            (jerk, "max |jerk| [m/s^3] (bound 0.1)", LogNorm(vmin=0.01, vmax=max(0.2, float(np.nanmax(jerk))))))):
        for col, rate in enumerate(RATES_PER_S):
            z = np.array([[values[grid[(s, m, rate)]] for s in SLOPES_DEG] for m in MASSES_KG])
            ax = axes[row, col]
            image = ax.pcolormesh(SLOPES_DEG, MASSES_KG, np.clip(z, norm.vmin, None), norm=norm, cmap="viridis",
                                  shading="nearest")
            bad = (z > (0.01 if row == 0 else 0.1))
            for (i, j) in zip(*np.nonzero(bad)):
                ax.text(SLOPES_DEG[j], MASSES_KG[i], "x", ha="center", va="center", color="white", fontsize=8)
            if row == 0:
                ax.set_title(f"accelerator {rate:g} /s", fontsize=9)
            if row == 1:
                ax.set_xlabel("slope [deg]")
            if col == 0:
                ax.set_ylabel("mass [kg]")
        fig.colorbar(image, ax=list(axes[row, :]), label=label, fraction=0.02, pad=0.01)
    axes[0, 0].text(0.0, -0.02, "x = bound exceeded (rollback > 0.01 m / jerk > 0.1 m/s^3)",
                    transform=fig.transFigure, fontsize=8)
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png")
    return atomic_write_bytes(path, buffer.getvalue())
