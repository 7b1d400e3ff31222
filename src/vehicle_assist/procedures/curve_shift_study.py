"""Paper 003 in ``vehicle-assist reproduce``: scenarios, paper-style figures and studies (issue #11).

* figure ``curve_shift`` (paper 003 Fig. 7-11 style): speed, gear (with the normal schedule's run of the same
  case dashed when given), throttle, brake, lateral acceleration with a_ypot/a_ys, and kj over time;
* extra ``curve_shift_pairs``: the issue's cross-scenario claims (gear at curve entry lower or equal with the
  strategy, strictly lower at 80 km/h; the proving-ground 4->3 earlier), with the shift speeds of each twin,
  an overlay figure per case and the road drawn from the .xodr with the shift points marked;
* extra ``curve_falsify``: CMA-ES falsification over data/envelopes/curve_shift.toml of each requirement of
  data/requirements/curve_shift.toml (no over-speed, no upshift in curve mode, a_y below a_ys);
* extra ``curve_kj_map``: kj (fraction of kj_max at the command) and the gear at curve entry over curve radius x
  speed at the command, run as a batch; every cell drives its own road (400 m straight, a 100 m arc of that
  radius, straight: the geometry of curve_r65.xodr as a radius table), so the plant and the map agree; bounds
  checked at every cell: engine speed after any downshift <= n_guard, no upshift in curve mode, kj/kj_max
  monotone in speed;
* extra ``curve_single_track``: the single-track mode against CommonRoad's ``vehicle_dynamics_st`` (an
  independent implementation of the same equations, the dev extra) on a step steer at 15/25/35 m/s: the yaw-rate
  figure and the largest difference (issue #11: within 1 %).
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from vehicle_assist.report.plots import FIGURES, Line, Panel, _render
from vehicle_assist.units import KPH_TO_MPS, RPM_TO_RADPS

CASES = (80, 70, 65, 48)
N_GUARD_RADPS = 3800 * RPM_TO_RADPS  # curve_shift.md 5.2 / 8 criterion 4
SCENARIOS = tuple(f"curve_{k}{v}" for v in CASES for k in ("s", "b")) + (
    "curve_pg", "curve_pg_baseline", "curve_pg_kj0125", "curve_s80_map_missing", "curve_s80_map_dropout",
    "curve_s80_map_late", "curve_s80_map_radius_wrong", "curve_s80_map_radius_small")

CURVE_PANELS = [
    Panel("Speed (Fig. 7-11 style)", "speed [km/h]",
          (Line("speed_mps", "speed", 1.0 / KPH_TO_MPS),
           Line("normal_downshift_speed_mps", "normal downshift u_a", 1.0 / KPH_TO_MPS, "--"),
           Line("advanced_downshift_speed_mps", "advanced u'", 1.0 / KPH_TO_MPS, ":"))),
    Panel("Gear", "gear", (Line("gear_command_index", "TCU command"), Line("gear_index", "engaged (0 = shifting)", 1.0, ":"))),
    Panel("Driver", "pedal [0..1]", (Line("accelerator_frac", "throttle"), Line("brake_pedal_frac", "brake", 1.0, "--"))),
    Panel("Lateral acceleration", "a_y [m/s^2]",
          (Line("lateral_accel_mps2", "a_y"), Line("tolerable_accel_true_mps2", "a_ypot(R)", 1.0, "--"),
           Line("safety_accel_mps2", "a_ys (at the command)", 1.0, ":"))),
    Panel("Downshift advance", "kj [-]", (Line("kj_ratio", "kj"), Line("kj_max_ratio", "kj_max", 1.0, ":")),
          right_ylabel="curve mode", right_lines=(Line("curve_mode_flag", "curve mode", 1.0, "--"),)),
]


def curve_shift_png(trace, path, title) -> Path:
    return _render(trace, [p for p in CURVE_PANELS if p.present(trace)], path, title)


FIGURES["curve_shift"] = curve_shift_png


def reproduction():
    from vehicle_assist.procedures.reproduce import Reproduction

    return Reproduction(
        "003",
        "Curve-aware AMT shifting with map preview (Cong, Wang, Cheng 2016): curve command at 80/70/65/48 km/h with the "
        "strategy on and off, the proving-ground case, map-preview faults, the kj map over radius x speed",
        SCENARIOS, figures=("curve_shift",),
        figure_scenarios=("curve_s80", "curve_s65", "curve_s48", "curve_pg", "curve_pg_baseline"),
        extras=("curve_shift_pairs", "curve_kj_map", "curve_single_track", "curve_falsify"))


def _shifts(trace) -> list[tuple[float, int, int, float, float]]:
    g = trace["gear_command_index"]
    idx = np.nonzero(np.diff(g) != 0)[0] + 1
    return [(float(trace["time_s"][i]), int(g[i - 1]), int(g[i]), float(trace["speed_mps"][i]), float(trace["position_m"][i]))
            for i in idx]


def _shift_text(trace) -> str:
    return ", ".join(f"{a}->{b} at {v / KPH_TO_MPS:.1f} km/h" for _, a, b, v, _ in _shifts(trace)) or "none"


def _overlay_png(on, off, path: Path, title: str) -> Path:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(6, 1, figsize=(9, 12), sharex=True)
    for tr, style, label in ((on, "-", "curve strategy"), (off, "--", "normal schedule")):
        t = tr["time_s"]
        axes[0].plot(t, tr["speed_mps"] / KPH_TO_MPS, style, label=label)
        axes[1].step(t, tr["gear_command_index"], style, where="post", label=label)
        axes[2].plot(t, tr["accelerator_frac"], style, label=label)
        axes[3].plot(t, tr["brake_pedal_frac"], style, label=label)
        axes[4].plot(t, tr["lateral_accel_mps2"], style, label=label)
        axes[5].plot(t, tr["kj_ratio"], style, label=label)
        for ts, a, b, v, _ in _shifts(tr):
            axes[0].annotate(f"{a}>{b}", (ts, v / KPH_TO_MPS), fontsize=7)
    for ax, lab in zip(axes, ("speed [km/h]", "gear", "throttle", "brake", "a_y [m/s^2]", "kj")):
        ax.set_ylabel(lab)
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8)
    axes[-1].set_xlabel("time [s]")
    fig.suptitle(title)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=90)
    plt.close(fig)
    return path


def _road_png(sc, traces: dict, path: Path, title: str) -> Path:
    """The road from its .xodr (x-y, top) and its curvature over distance (bottom), with each run's shift points
    (strategy 'on' circles, normal schedule 'off' crosses) marked where the TCU commanded them."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from vehicle_assist.vehicles.amt_car import road_geometry

    geo = road_geometry(sc)
    fig, (ax, ax2) = plt.subplots(2, 1, figsize=(9, 9), gridspec_kw={"height_ratios": [3, 2]})
    styles = {0: ("o", "tab:blue"), 1: ("x", "tab:orange")}
    s_end = max(float(np.max(tr["position_m"])) for tr in traces.values()) if traces else float(geo["s_m"][-1])
    if "x_m" in geo:
        seen = geo["s_m"] <= s_end + 20.0
        ax.plot(geo["x_m"][seen], geo["y_m"][seen], color="0.6", lw=3, label=f"road ({Path(geo['source']).name})")
        span_x = np.ptp(geo["x_m"][seen]) or 1.0
        span_y = np.ptp(geo["y_m"][seen]) or 1.0
        if max(span_x, span_y) / min(span_x, span_y) < 5.0:
            ax.set_aspect("equal")
        else:
            ax.set_title("(axes not to scale)", fontsize=8, loc="right")
        for k, (name, tr) in enumerate(traces.items()):
            marker, color = styles[k % 2]
            for n, (_, a, b, v, pos) in enumerate(_shifts(tr)):
                x = np.interp(pos, geo["s_m"], geo["x_m"])
                y = np.interp(pos, geo["s_m"], geo["y_m"])
                ax.plot(x, y, marker, color=color, ms=8, label=name if n == 0 else None)
                ax.annotate(f"{a}>{b} {v / KPH_TO_MPS:.0f}", (x, y), fontsize=7, color=color,
                            xytext=(6, 8 if k == 0 else -12), textcoords="offset points")
        for c in geo["curves"]:
            if c.start_m > s_end:
                continue
            x = np.interp(c.start_m, geo["s_m"], geo["x_m"])
            y = np.interp(c.start_m, geo["s_m"], geo["y_m"])
            ax.plot(x, y, "k|", ms=14)
            ax.annotate(f"curve R={c.radius_m:.0f} m", (x, y), fontsize=8, xytext=(-60, -16), textcoords="offset points")
        ax.set_xlabel("x [m]")
        ax.set_ylabel("y [m]")
        ax.legend(fontsize=8)
    seen = geo["s_m"] <= s_end + 20.0
    ax2.plot(geo["s_m"][seen], 1000.0 * geo["curvature_per_m"][seen], color="0.4", label="road curvature")
    top = 1000.0 * float(np.max(np.abs(geo["curvature_per_m"][seen]))) or 1.0
    for k, (name, tr) in enumerate(traces.items()):
        marker, color = styles[k % 2]
        for n, (_, a, b, v, pos) in enumerate(_shifts(tr)):
            level = top * (1.15 + 0.25 * (n % 3)) if k == 0 else -top * (0.15 + 0.25 * (n % 3))
            ax2.axvline(pos, color=color, lw=0.6, alpha=0.6)
            ax2.plot(pos, level, marker, color=color, label=name if n == 0 else None)
            ax2.annotate(f"{a}>{b} {v / KPH_TO_MPS:.0f}", (pos, level), fontsize=7, color=color, xytext=(3, 2),
                         textcoords="offset points")
    ax2.set_ylim(-top * 0.9, top * 2.0)
    ax2.set_xlabel("distance along the road [m]")
    ax2.set_ylabel("curvature [1/km]")
    ax2.grid(alpha=0.3)
    ax2.legend(fontsize=8, loc="upper left")
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=90)
    plt.close(fig)
    return path


def pairs_extra(out_dir: Path):
    from vehicle_assist.scenarios.loader import load_scenario
    from vehicle_assist.scenarios.runner import simulate

    out_dir = Path(out_dir)
    figures = []
    entries = []
    for v in CASES + ("pg",):
        s_name, b_name = (f"curve_s{v}", f"curve_b{v}") if v != "pg" else ("curve_pg", "curve_pg_baseline")
        s_sc = load_scenario(s_name)
        on = simulate(s_sc)
        off = simulate(load_scenario(b_name))
        figures.append((f"paper 003: {s_name} vs {b_name} (strategy vs normal schedule)",
                        _overlay_png(on.trace, off.trace, out_dir / f"{s_name}_vs_normal.png", f"{s_name} vs {b_name}")))
        figures.append((f"paper 003: road of {s_name} with the shift points",
                        _road_png(s_sc, {"on": on.trace, "off": off.trace}, out_dir / f"{s_name}_road.png",
                                  f"{s_name}: shift points on the road (on = strategy, off = normal)")))
        shifts = f"strategy: {_shift_text(on.trace)}; normal: {_shift_text(off.trace)}"
        if v == "pg":
            s43 = on.metrics["downshift_4_3_speed_mps"]
            b43 = off.metrics["downshift_4_3_speed_mps"]
            entries.append({"paper": "003", "scenario": f"{s_name} vs {b_name}",
                            "criterion": "4->3 downshift speed, strategy minus normal schedule", "negative_control": False,
                            "value": s43 - b43, "unit": "m/s", "bound": "> 0", "pass": bool(s43 > b43),
                            "why": f"paper 003 P13: 4->3 earlier (about 27 instead of about 24 km/h; the 27 itself is "
                                   f"checked in {s_name} and fails, see there); {shifts}"})
            s32 = on.metrics["downshift_3_2_speed_mps"]
            b32 = off.metrics["downshift_3_2_speed_mps"]
            entries.append({"paper": "003", "scenario": f"{s_name} vs {b_name}",
                            "criterion": "3->2 downshift speed, strategy minus normal schedule", "negative_control": False,
                            "value": s32 - b32, "unit": "m/s", "bound": ">= 0", "pass": bool(s32 >= b32),
                            "why": "paper 003 P13: 3->2 'advanced' with the strategy (the printed 15 -> 13 km/h is a "
                                   "later shift; curve_shift.md 9 reads it as swapped, so the direction is checked "
                                   f"here and the printed 13 km/h in {s_name}, where it fails)"})
            entries.append(_pg_radius_entry(on))
            continue
        gs = on.metrics["gear_at_curve_entry_index"]
        gb = off.metrics["gear_at_curve_entry_index"]
        strict = v == 80
        entries.append({"paper": "003", "scenario": f"{s_name} vs {b_name}",
                        "criterion": "gear at curve entry, strategy minus normal schedule", "negative_control": False,
                        "value": gs - gb, "unit": "1", "bound": "< 0" if strict else "<= 0",
                        "pass": bool(gs < gb if strict else gs <= gb),
                        "why": f"curve_shift.md 8 criterion 6 (issue #11: lower or equal, strictly lower at 80 km/h); {shifts}"})
        work_on = on.metrics["engine_work_per_distance_n"]
        work_off = off.metrics["engine_work_per_distance_n"]
        entries.append({"paper": "003", "scenario": f"{s_name} vs {b_name}",
                        "criterion": "engine work per km, strategy / normal schedule (fuel proxy, reported)",
                        "negative_control": False, "value": work_on / work_off, "unit": "1", "bound": "report only",
                        "pass": True,
                        "why": f"issue #11: the cost of holding low gears ({work_on:.0f} vs {work_off:.0f} kJ/km)"})
    return figures, entries


def _pg_radius_entry(on) -> dict:
    """Report: the curve radius at which the model's computed kj would give the paper's 27 km/h 4->3 (P13)."""
    from scipy.optimize import brentq

    from vehicle_assist.functions import curve_shift as cs

    u = 53.0 * KPH_TO_MPS  # P13: kj chosen assuming a 53 km/h passage
    a_ys = float(on.trace["safety_accel_mps2"].max())
    u_a = 23.8 * KPH_TO_MPS  # curve_shift.md 6: coasting 4->3 line
    kj_max = (76.6 - 23.8) / 23.8  # eq. 14 with u_max(3rd) = 76.6 km/h (curve_shift.md 6)

    def speed_kph(radius):
        frac = cs.advance_fraction(u * u / radius, cs.tolerable_lateral_accel_mps2(radius, 0.75, 20.0, 500.0), a_ys)
        return u_a * (1.0 + frac * kj_max) / KPH_TO_MPS

    r27 = brentq(lambda r: speed_kph(r) - 27.0, 40.0, 44.99)
    return {"paper": "003", "scenario": "curve_pg (analysis)", "negative_control": False,
            "criterion": "curve radius at which the computed kj gives the paper's 4->3 at 27 km/h (report only)",
            "value": r27, "unit": "m", "bound": "report only", "pass": True,
            "why": (f"paper 003 P13 gives no radius; with a 53 km/h passage, a_ys = {a_ys:.2f} m/s^2 and k = 0.75 the "
                    f"4->3 is at {speed_kph(43.0):.1f} km/h for R = 43 m, {speed_kph(r27):.1f} for {r27:.1f} m and "
                    f"{speed_kph(45.0):.1f} for 45 m (and at the command for R = 10 m): the paper's number fixes R "
                    "within 1 m, so it is not used to choose the proving-ground radius")}


RADII_M = (30.0, 45.0, 65.0, 100.0, 150.0, 250.0, 400.0)
SPEEDS_KPH = (40.0, 50.0, 60.0, 70.0, 80.0, 90.0, 100.0)


def road_for_radius(radius_m: float) -> str:
    """Dotted override: the curve_r65.xodr geometry (400 m straight, a 100 m arc, straight) with radius R."""
    return (f"road.curve_radius={{distance_m = [0.0, 399.99, 400.0, 500.0, 500.01, 2000.0], "
            f"radius_m = [1e6, 1e6, {radius_m!r}, {radius_m!r}, 1e6, 1e6]}}")


def kj_map(radii=RADII_M, speeds=SPEEDS_KPH):
    """Batch over curve radius (each cell drives its own road, :func:`road_for_radius`) x speed at the command;
    returns (kj_frac, entry gear, max engine speed after a downshift, upshifts in curve mode) arrays of shape
    (radii, speeds)."""
    from vehicle_assist.scenarios.loader import load_scenario
    from vehicle_assist.scenarios.runner import simulate_batch

    base = load_scenario("curve_envelope_base", ["vehicle.curve_shift.command_needs_deceleration_flag=0",
                                                 "run.duration_s=30"])
    variants = []
    for r in radii:
        for v in speeds:
            gear = 5 if v >= 60 else (4 if v >= 50 else 3)
            variants.append(base.with_sets(road_for_radius(r), f"run.initial_speed_kph={v!r}",
                                           f'driver.gear_lever={{time_s=[0], gear=["{gear}"]}}'))
    res = simulate_batch(variants, metric_names=["kj_advance_max_frac", "gear_at_curve_entry_index",
                                                 "engine_speed_after_downshift_max_radps", "upshifts_in_curve_mode_count",
                                                 "preview_fallback_count"])
    shape = (len(radii), len(speeds))
    get = lambda k: np.array([m[k] for m in res.metrics]).reshape(shape)  # noqa: E731
    return (get("kj_advance_max_frac"), get("gear_at_curve_entry_index"), get("engine_speed_after_downshift_max_radps"),
            get("upshifts_in_curve_mode_count"), get("preview_fallback_count"))


def kj_map_extra(out_dir: Path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out_dir = Path(out_dir)
    frac, gear, w_after, ups, fallbacks = kj_map()
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5))
    for ax, data, label, cmap in ((axes[0], frac, "kj / kj_max at the command", "viridis"),
                                  (axes[1], gear, "gear at curve entry", "plasma")):
        im = ax.imshow(data, origin="lower", aspect="auto", cmap=cmap)
        ax.set_xticks(range(len(SPEEDS_KPH)), [f"{v:.0f}" for v in SPEEDS_KPH])
        ax.set_yticks(range(len(RADII_M)), [f"{r:.0f}" for r in RADII_M])
        ax.set_xlabel("speed at the curve command [km/h]")
        ax.set_ylabel("curve radius (road and map) [m]")
        ax.set_title(label)
        for i in range(data.shape[0]):
            for j in range(data.shape[1]):
                ax.text(j, i, f"{data[i, j]:.2f}" if data is frac else f"{data[i, j]:.0f}", ha="center", va="center",
                        fontsize=7, color="w")
        fig.colorbar(im, ax=ax)
    fig.suptitle("paper 003: downshift advance and entry gear over radius x speed (each cell on its own road)")
    fig.tight_layout()
    out_dir.mkdir(parents=True, exist_ok=True)
    path = out_dir / "curve_kj_map.png"
    fig.savefig(path, dpi=90)
    plt.close(fig)
    n = frac.size
    scen = f"curve_kj_map ({n} variants: road radius {RADII_M[0]:.0f}-{RADII_M[-1]:.0f} m x {SPEEDS_KPH[0]:.0f}-{SPEEDS_KPH[-1]:.0f} km/h)"
    entries = [
        {"paper": "003", "scenario": scen, "criterion": "largest engine speed right after a downshift over the map",
         "negative_control": False, "value": float(np.nanmax(w_after)), "unit": "rad/s", "bound": f"<= {N_GUARD_RADPS:.1f}",
         "pass": bool(np.nanmax(w_after) <= N_GUARD_RADPS), "why": "curve_shift.md 8 criterion 4 at every cell"},
        {"paper": "003", "scenario": scen, "criterion": "upshifts in curve mode over the map", "negative_control": False,
         "value": float(np.nansum(ups)), "unit": "1", "bound": "<= 0", "pass": bool(np.nansum(ups) == 0),
         "why": "curve_shift.md 8 criterion 1 at every cell"},
        {"paper": "003", "scenario": scen, "criterion": "fallbacks (preview rejected) over the map", "negative_control": False,
         "value": float(np.nansum(fallbacks)), "unit": "1", "bound": "<= 0", "pass": bool(np.nansum(fallbacks) == 0),
         "why": "issue #11 faults, the other side: road and map agree in every cell, so the plausibility check must "
                "never reject the preview"},
        {"paper": "003", "scenario": scen, "criterion": "kj/kj_max never decreases with speed at a fixed radius",
         "negative_control": False, "value": float(np.min(np.diff(frac, axis=1))), "unit": "1", "bound": ">= 0",
         "pass": bool(np.all(np.diff(frac, axis=1) >= -1e-9)),
         "why": "paper 003 P2/P12: a more demanding curve (higher a_y_pred = u^2/R) gets at least the same advance"},
    ]
    return [("paper 003: kj and entry gear over radius x speed", path)], entries


FALSIFY_BUDGET = 64  # evaluations per requirement (CMA-ES, fixed seed): the campaign of issue #11
FALSIFY_SEED = 2026
REQUIREMENTS = ("curve_shift.no_overspeed", "curve_shift.no_upshift_in_curve_mode", "curve_shift.handling_limit")


def falsify_extra(out_dir: Path, budget: int = FALSIFY_BUDGET, seed: int = FALSIFY_SEED):
    """Falsification campaign over data/envelopes/curve_shift.toml for each shipped requirement."""
    from vehicle_assist.verification.falsify import run_falsification, twin_text, write_falsification

    figures, entries = [], []
    for rid in REQUIREMENTS:
        res = run_falsification("curve_shift", rid, budget=budget, seed=seed, optimizer="cma", batch=8, progress=False)
        paths = write_falsification(res, Path(out_dir) / f"falsify_{rid.replace('.', '_')}")
        cex = res.counterexample
        found = cex if cex is not None else res.best
        if cex is not None:
            figures.append((f"paper 003: counterexample of {rid}", paths["plot"]))
        entries.append({"paper": "003", "scenario": f"falsification of {rid} (budget {budget}, seed {seed})",
                        "criterion": "no counterexample (robustness: minimum found)", "negative_control": False,
                        "value": float(found.robustness), "unit": res.requirement.unit or "-", "bound": ">= 0",
                        "pass": cex is None,
                        "why": (f"issue #11 envelope; {'counterexample' if cex is not None else 'worst point'} at "
                                f"[{res.envelope.point_name(found.point)}]; "
                                f"{(twin_text(res) + '; ') if cex is not None and twin_text(res) else ''}"
                                f"requirement: {res.requirement.why}")})
    # negative controls: the same search must find counterexamples when the function under test is removed
    for rid, sets, reason in NEGATIVE_CONTROLS:
        res = run_falsification("curve_shift", rid, budget=budget, seed=seed, optimizer="cma", batch=8, sets=list(sets),
                                progress=False)
        found = res.counterexample if res.counterexample is not None else res.best
        entries.append({"paper": "003", "scenario": f"falsification of {rid} with {'; '.join(sets)} (budget {budget}, "
                                                    f"seed {seed})",
                        "criterion": "counterexample found (robustness < 0)", "negative_control": True,
                        "value": float(found.robustness), "unit": res.requirement.unit or "-", "bound": "< 0",
                        "pass": res.counterexample is not None,
                        "why": f"{reason}; found at [{res.envelope.point_name(found.point)}] after "
                               f"{len(res.evaluations)} evaluations"})
    return figures, entries


NEGATIVE_CONTROLS = (
    ("curve_shift.no_upshift_in_curve_mode", ("vehicle.curve_shift.enabled_flag=0",),
     "curve_shift.md 8 criterion 2 / paper P1, P13: the normal schedule alone upshifts on lift-off inside the curve "
     "command window"),
)


SINGLE_TRACK_CASES = ((15.0, 0.03), (25.0, 0.02), (35.0, 0.01))  # (speed m/s, step steer rad)
SINGLE_TRACK_BOUND_FRAC = 0.01  # issue #11: yaw rate within 1 % of an independent implementation


def single_track_comparison(cases=SINGLE_TRACK_CASES, t_end: float = 3.0):
    """Step steer with CommonRoad's vehicle 2 (``vehiclemodels.vehicle_dynamics_st``, solve_ivp, rtol 1e-10) and
    our backward-Euler single-track mode at 1 ms with the same mass, geometry, inertia and the per-axle cornering
    stiffness of CommonRoad's tire model at a_x = 0. Returns [(u, delta, t, r_ref, r_ours, max |diff| / peak)]."""
    from scipy.integrate import solve_ivp
    from vehiclemodels.parameters_vehicle2 import parameters_vehicle2
    from vehiclemodels.vehicle_dynamics_st import vehicle_dynamics_st

    from vehicle_assist.plant.chassis import single_track as st

    p = parameters_vehicle2()
    mu = p.tire.p_dy1
    c_s = -p.tire.p_ky1 / p.tire.p_dy1
    m, lf, lr, iz = p.m, p.a, p.b, p.I_z
    k_f = mu * c_s * m * 9.81 * lr / (lf + lr)
    k_r = mu * c_s * m * 9.81 * lf / (lf + lr)
    times = np.linspace(0.0, t_end, 301)
    out = []
    for u, delta in cases:
        ref = solve_ivp(lambda t, x: vehicle_dynamics_st(x, [0.0, 0.0], p), (0.0, t_end),
                        [0.0, 0.0, delta, u, 0.0, 0.0, 0.0], t_eval=times, rtol=1e-10, atol=1e-12, method="LSODA")
        beta = r = 0.0
        ours = [0.0]
        for k in range(1, int(round(t_end / 1e-3)) + 1):
            beta, r, _ = st.step(beta, r, u, delta, m, iz, lf, lr, k_f, k_r, 1e-3)
            if k % 10 == 0:
                ours.append(r)
        ours = np.array(ours)
        out.append((u, delta, times, ref.y[5], ours, float(np.max(np.abs(ours - ref.y[5])) / np.max(np.abs(ref.y[5])))))
    return out


def single_track_extra(out_dir: Path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    scen = "single-track step steer vs CommonRoad vehicle_dynamics_st (vehicle 2)"
    why = ("issue #11: the single-track mode against an independent published implementation of the same equations "
           "(CommonRoad, TUM), yaw rate within 1 % of the peak on a step steer")
    try:
        res = single_track_comparison()
    except ImportError as exc:
        return [], [{"paper": "003", "scenario": scen, "criterion": "largest yaw-rate difference / peak",
                     "negative_control": False, "value": float("nan"), "unit": "1", "bound": "<= 0.01", "pass": False,
                     "why": f"{why}; reference not installed ({exc.name}): pip install -e '.[dev]'"}]
    fig, axes = plt.subplots(2, 1, figsize=(8, 7), sharex=True)
    entries = []
    for u, delta, t, r_ref, r_ours, err in res:
        line, = axes[0].plot(t, r_ref, lw=3, alpha=0.4, label=f"CommonRoad {u:.0f} m/s, {delta:g} rad")
        axes[0].plot(t, r_ours, "--", color=line.get_color(), label=f"vehicle-assist {u:.0f} m/s")
        axes[1].plot(t, 100.0 * (r_ours - r_ref) / np.max(np.abs(r_ref)), color=line.get_color(),
                     label=f"{u:.0f} m/s: max {100 * err:.2f} %")
        entries.append({"paper": "003", "scenario": f"{scen}, {u:.0f} m/s, {delta:g} rad",
                        "criterion": "largest yaw-rate difference / peak", "negative_control": False, "value": err,
                        "unit": "1", "bound": f"<= {SINGLE_TRACK_BOUND_FRAC:g}",
                        "pass": bool(err <= SINGLE_TRACK_BOUND_FRAC), "why": why})
    axes[0].set_ylabel("yaw rate [rad/s]")
    axes[1].set_ylabel("difference [% of peak]")
    axes[1].axhline(1.0, color="r", lw=0.8, ls=":")
    axes[1].axhline(-1.0, color="r", lw=0.8, ls=":", label="issue #11 bound 1 %")
    axes[1].set_xlabel("time after the step [s]")
    for ax in axes:
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    fig.suptitle("paper 003 car platform: single-track mode vs CommonRoad vehicle_dynamics_st (step steer)")
    fig.tight_layout()
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    path = out_dir / "curve_single_track_vs_commonroad.png"
    fig.savefig(path, dpi=90)
    plt.close(fig)
    return [("paper 003: single-track mode vs CommonRoad (yaw rate, step steer)", path)], entries


EXTRAS = {"curve_shift_pairs": pairs_extra, "curve_kj_map": kj_map_extra, "curve_single_track": single_track_extra,
          "curve_falsify": falsify_extra}
