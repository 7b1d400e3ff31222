"""Calibration map of the EV hill-start assist (issue: "a sweep of slope 0-20 deg x mass (empty to full)
x accelerator rate, reported as a heat map of max rollback and max jerk").

The shipped paper-001 scenario (``hsa_ev_5deg_paper``) is varied in grade, vehicle mass (1300-2100 kg, the
envelope of issue #7; the assist keeps its calibration, it does not know the load) and the rate at which
the driver presses the accelerator (pedal ramp from 2 s up to 1.0). The driver holds the car with 60 bar
before releasing the brake pedal at 1-1.3 s, enough for every grade and mass of the map. Every variant runs
in one batch on all cores; the result is a parquet table and a figure with one heat map per accelerator rate.

Criterion: the paper's own, speed never below -1 mm/s (paper 001 P8 Fig. 8c, hill_start_ehb.md 5.1), at
every variant the motor can start (motor force > grade + rolling resistance, computed here from the
vehicle data; the others must end in a refusal with the brake held). Reported alongside: the filtered
jerk (P8, 5.2: +-0.1 m/s^3) while the assist is engaged and 1 s after (``assist_jerk_peak_mps3``: later the
driver's pedal and the motor's power limit shape the acceleration, not the assist) and the rollback distance.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from vehicle_assist.io.results import atomic_path, atomic_write_bytes

SLOPES_DEG = tuple(range(0, 21, 2))
MASSES_KG = (1300, 1500, 1700, 1900, 2100)  # issue #7 envelope: 1,300-2,100 kg (curb to gross)
RATES_PER_S = (0.01, 0.0225, 0.045, 0.1)  # 0.0225 /s is the paper case (hill_start_ehb.md 4 S1), 0.045 twice it
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
                    f"run.duration_s={max(t_full + 6.0, 40.0):.4f}")))
    return out


def run_ehb_sweep(out_dir: Path) -> tuple[Path, Path, dict]:
    """Run the map; returns (figure, table, summary numbers)."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    from vehicle_assist.scenarios.runner import simulate_batch

    keys_and_variants = variants()
    keys = [k for k, _ in keys_and_variants]
    batch = simulate_batch([v for _, v in keys_and_variants],
                           metric_names=["rollback_distance_m", "rollback_speed_mps", "assist_jerk_peak_mps3",
                                         "assist_refusal_code", "peak_speed_mps", "assist_idle_after_start_s"])
    rollback = np.array([m["rollback_distance_m"] for m in batch.metrics])
    back_speed = np.array([m["rollback_speed_mps"] for m in batch.metrics])
    jerk = np.array([m["assist_jerk_peak_mps3"] for m in batch.metrics])
    refusal = np.array([m["assist_refusal_code"] for m in batch.metrics])
    started = np.array([m["peak_speed_mps"] > 0.05 for m in batch.metrics])  # v_start (hill_start_ehb.md 3)
    idle_after = np.array([m["assist_idle_after_start_s"] for m in batch.metrics])  # NaN: not back in Step1 in the run
    startable = np.array([motor_can_start(k[1], k[0], keys_and_variants[0][1]) for k in keys])
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    table = pa.table({"slope_deg": [k[0] for k in keys], "mass_kg": [k[1] for k in keys],
                      "accelerator_rate_per_s": [k[2] for k in keys], "rollback_distance_m": rollback,
                      "rollback_speed_mps": back_speed, "assist_jerk_peak_mps3": jerk,
                      "assist_refusal_code": refusal, "motor_can_start_flag": startable.astype(float),
                      "assist_idle_after_start_s": idle_after})
    table_path = out_dir / "ehb_sweep.parquet"
    with atomic_path(table_path) as tmp:
        pq.write_table(table, tmp)
    figure = _heat_maps(keys, back_speed, jerk, out_dir / "ehb_sweep_heatmap.png")
    speed_ok = back_speed <= SPEED_BOUND_MPS
    summary = {
        "variants": len(keys),
        "startable": int(startable.sum()),
        "max_backward_speed_startable_mps": float(np.max(back_speed[startable])) if startable.any() else 0.0,
        "speed_violations_startable": int(np.sum(~speed_ok & startable)),
        "unstartable_refused": int(np.sum(~startable & (refusal > 0))),
        "unstartable_max_rollback_m": float(np.max(rollback[~startable])) if (~startable).any() else 0.0,
        "max_rollback_m": float(np.nanmax(rollback)),
        "worst_rollback_case": keys[int(np.nanargmax(rollback))],
        "jerk_ok_frac": float(np.mean(jerk[startable] <= 0.1)) if startable.any() else 1.0,
        "max_jerk_mps3": float(np.max(jerk[startable])) if startable.any() else 0.0,
        # hill_start_ehb.md 5.5, state half: back in Step1 within 2 s after v > v_start (NaN = never in the run)
        "started": int(started.sum()),
        "step1_late": int(np.sum(started & ~(idle_after <= STEP1_BOUND_S))),
        "max_idle_after_start_s": float(np.nanmax(idle_after[started])) if np.isfinite(idle_after[started]).any() else 0.0,
    }
    return figure, table_path, summary


STEP1_BOUND_S = 2.0  # hill_start_ehb.md 5.5: within 2 s after v first exceeds v_start, EHB state = Step1
SPEED_BOUND_MPS = 1e-3  # paper 001 P8 (Fig. 8c): speed never negative; hill_start_ehb.md 5.1: v >= -1e-3 m/s


def motor_can_start(mass_kg: float, slope_deg: float, scenario) -> bool:
    """Whether the motor alone can carry grade + rolling resistance of this car (dry road, mu = 1): the
    variants where it cannot must end in a refusal, not a start (independent of the controller)."""
    import math

    p = scenario.vehicle.flat()
    g = 9.81
    gam = math.radians(slope_deg)
    f_max = p["motor_max_torque_nm"] * p["motor_reduction_ratio"] * p["motor_efficiency_frac"] / p["body_wheel_radius_m"]
    l_r = p["chassis_wheelbase_m"] - p["chassis_cg_to_front_axle_m"]
    f_zf = mass_kg * g * (math.cos(gam) * l_r - math.sin(gam) * p["chassis_cg_height_m"]) / p["chassis_wheelbase_m"]
    driven = f_zf if p["chassis_driven_axle"] < 0.5 else mass_kg * g * math.cos(gam) - f_zf
    need = mass_kg * g * (math.sin(gam) + p["body_rolling_resistance_coeff"] * math.cos(gam))
    return min(f_max, driven) > need


def _heat_maps(keys, rollback, jerk, path: Path) -> Path:
    import io

    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.colors import LogNorm
    from matplotlib.figure import Figure

    fig = Figure(figsize=(14, 6.4), dpi=100)
    FigureCanvasAgg(fig)
    axes = fig.subplots(2, len(RATES_PER_S), sharex=True, sharey=True)
    fig.subplots_adjust(left=0.06, right=0.93, top=0.88, bottom=0.09, wspace=0.08, hspace=0.25)
    fig.suptitle("EV hill-start assist (paper 001): rows: largest backward speed (bound 1 mm/s, P8), max filtered "
                 "jerk (bound 0.1 m/s^3, P8); columns: accelerator rate", fontsize=11)
    grid = {k: i for i, k in enumerate(keys)}
    for row, (values, label, norm) in enumerate((
            (rollback, "max backward speed [m/s]", LogNorm(vmin=1e-4, vmax=max(1e-2, float(np.nanmax(rollback)) or 1e-2))),
            (jerk, "max |jerk| [m/s^3] (bound 0.1)", LogNorm(vmin=0.01, vmax=max(0.2, float(np.nanmax(jerk))))))):
        for col, rate in enumerate(RATES_PER_S):
            z = np.array([[values[grid[(s, m, rate)]] for s in SLOPES_DEG] for m in MASSES_KG])
            ax = axes[row, col]
            image = ax.pcolormesh(SLOPES_DEG, MASSES_KG, np.clip(z, norm.vmin, None), norm=norm, cmap="viridis",
                                  shading="nearest")
            bad = (z > (SPEED_BOUND_MPS if row == 0 else 0.1))
            for (i, j) in zip(*np.nonzero(bad)):
                ax.text(SLOPES_DEG[j], MASSES_KG[i], "x", ha="center", va="center", color="white", fontsize=8)
            if row == 0:
                ax.set_title(f"accelerator {rate:g} /s", fontsize=9)
            if row == 1:
                ax.set_xlabel("slope [deg]")
            if col == 0:
                ax.set_ylabel("mass [kg]")
        fig.colorbar(image, ax=list(axes[row, :]), label=label, fraction=0.02, pad=0.01)
    axes[0, 0].text(0.0, -0.02, "x = bound exceeded (backward speed > 1 mm/s / jerk > 0.1 m/s^3)",
                    transform=fig.transFigure, fontsize=8)
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png")
    return atomic_write_bytes(path, buffer.getvalue())
