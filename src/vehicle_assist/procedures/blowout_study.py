"""Paper 004 (tire blowout, issue #10) in ``vehicle-assist reproduce``: scenarios, a blowout figure kind, and
two studies:

* ``blowout_fig4``: the paper's Fig. 4 (yaw rate after a left-front blowout at 60 km/h, with and without the
  counter-moment) plus the path; then every wheel at 60/80/100 km/h with and without compensation, one
  summary entry per case for criterion 9.5 (yaw-rate RMS over 2 s reduced by >= 30 %, and a smaller lateral
  deviation at +3 s), and a table (blowout_wheel_speed.csv).
* ``blowout_sweep``: speed x blown wheel x detection delay (0.05/0.2/0.5 s): lateral deviation at +3 s (and the
  largest over the run) with and without compensation, table (blowout_sweep.csv) and plot; the entry counts the
  cases where the compensation is worse than none over the whole run (developer guide: never worse than no assist).
* the per-wheel/speed table also as a figure (blowout_wheel_speed.png: yaw-rate peak, RMS, deviation, on/off).
"""
from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np

from vehicle_assist.report.plots import FIGURES, Line, Panel, _render
from vehicle_assist.units import BAR_TO_PA, KPH_TO_MPS

_W = ("fl", "fr", "rl", "rr")
PAPER_ON, PAPER_OFF = "blowout_lf_60kph_paper", "blowout_lf_60kph_off"
SPEEDS_KPH = (60, 80, 100)
DELAYS_S = (0.05, 0.2, 0.5)
RMS_REDUCTION_FRAC = 0.30  # tire_blowout.md 9.5 (target, assumed by the spec)
BLOWOUT_PANELS = [
    Panel("Yaw rate (paper 004 Fig. 4)", "yaw rate [deg/s]", (Line("yaw_rate_radps", "yaw rate", float(np.degrees(1.0))),)),
    Panel("Path", "lane offset [m]", (Line("lane_offset_m", "lateral offset"),)),
    Panel("Pressures", "pressure [bar]", tuple(Line(f"wheel_pressure_{w}_pa", w, 1.0 / BAR_TO_PA) for w in _W)),
    Panel("Blowout", "-", (Line("blowout_frac", "deflation phi"), Line("blowout_mode_index", "compensation mode", 1.0, "--"))),
    Panel("Vehicle", "speed [km/h]", (Line("speed_mps", "speed", 1.0 / KPH_TO_MPS),)),
]



def limit_code_legend() -> str:
    """Every ``blowout_limit_code`` with its reason, from the function's own table (LIMIT_REASONS): the report's
    "says why" (issue #10 'Faults') cannot miss a code added later (review RL2: code 6, blown_side_fault_flag, was
    missing from the hand-written list)."""
    from vehicle_assist.functions.blowout_compensation import LIMIT_REASONS

    return "; ".join(f"{k} {why}" for k, why in enumerate(LIMIT_REASONS))

def blowout_png(trace, path, title) -> Path:
    return _render(trace, [p for p in BLOWOUT_PANELS if p.present(trace)], path, title)


FIGURES["tire_blowout"] = blowout_png

SCENARIOS = ("blowout_lf_60kph_paper", "blowout_lf_60kph_off", "blowout_rf_60kph", "blowout_rr_60kph",
             "blowout_lf_80kph_curve", "blowout_rf_80kph_right_curve", "blowout_rf_80kph_right_curve_off",
             "blowout_lf_60kph_low_mu", "blowout_lf_60kph_closed_loop",
             "blowout_lf_60kph_lane_keeper", "blowout_panic_stop_80kph", "blowout_false_detection_60kph",
             "blowout_false_detection_ws_only_60kph", "blowout_low_accumulator_60kph", "blowout_inlet_stuck_60kph",
             "blowout_braking_60kph", "blowout_braking_60kph_off", "blowout_panic_stop_immediate_80kph",
             "blowout_false_tpms_braking_60kph")


def reproduction():
    from vehicle_assist.procedures.reproduce import Reproduction

    return Reproduction(
        "004",
        "Tire-blowout stabilisation by differential braking (paper 004): BJ2500 left-front blowout at 60 km/h with "
        "and without compensation, mirror and rear blowouts, left and right curves, low friction, panic stop, faults",
        SCENARIOS, figures=("tire_blowout",),
        figure_scenarios=("blowout_lf_60kph_paper", "blowout_lf_60kph_off", "blowout_panic_stop_80kph"),
        extras=("blowout_fig4", "blowout_sweep", "falsify_004"))


def _variants(on: bool, wheel: int, speed_kph: float, delay_s: float | None = None):
    from vehicle_assist.scenarios.loader import load_scenario

    sets = [f"vehicle.blowout.wheel_index={wheel}", f"run.initial_speed_kph={speed_kph}"]
    if delay_s is not None:
        sets.append(f"vehicle.blowout_compensation.detection_delay_s={delay_s}")
    return load_scenario(PAPER_ON if on else PAPER_OFF, sets=sets)


def _batch(scenarios, keep=()):
    from vehicle_assist.scenarios.runner import simulate_batch

    return simulate_batch(scenarios, keep_channels=keep)


def wheel_speed_table():
    """Rows (wheel, speed, on/off metrics) for every wheel at 60/80/100 km/h."""
    cases = [(w, v) for w in range(4) for v in SPEEDS_KPH]
    scs = [_variants(True, w, v) for w, v in cases] + [_variants(False, w, v) for w, v in cases]
    res = _batch(scs).metrics
    n = len(cases)
    rows = []
    for k, (w, v) in enumerate(cases):
        on, off = res[k], res[n + k]
        rows.append({"wheel": _W[w], "speed_kph": v,
                     "rms_off_radps": off["blowout_yaw_rate_rms_radps"], "rms_on_radps": on["blowout_yaw_rate_rms_radps"],
                     "peak_off_radps": off["blowout_yaw_rate_peak_radps"], "peak_on_radps": on["blowout_yaw_rate_peak_radps"],
                     "dev3_off_m": off["blowout_lateral_deviation_3s_m"], "dev3_on_m": on["blowout_lateral_deviation_3s_m"],
                     "devrun_off_m": off["blowout_lateral_deviation_run_max_m"],
                     "devrun_on_m": on["blowout_lateral_deviation_run_max_m"],
                     "pressure_req_bar": on["blowout_pressure_req_pa"] / BAR_TO_PA, "valve_time_s": on["blowout_valve_time_s"],
                     "decel_on_mps2": on["blowout_decel_mean_mps2"], "departure_off": off["blowout_lane_departure_flag"],
                     "departure_on": on["blowout_lane_departure_flag"]})
    return rows


def _write_csv(path: Path, rows):
    with path.open("w", newline="") as fh:
        wr = csv.DictWriter(fh, fieldnames=list(rows[0]))
        wr.writeheader()
        for r in rows:
            wr.writerow({k: (f"{v:.4g}" if isinstance(v, float) else v) for k, v in r.items()})


def fig4_extra(out_dir: Path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    from vehicle_assist.scenarios.loader import load_scenario
    from vehicle_assist.scenarios.runner import simulate

    on = simulate(load_scenario(PAPER_ON))
    off = simulate(load_scenario(PAPER_OFF))
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(8, 7))
    for r, lab, st in ((off, "without counter-moment (Fig. 4 curve 2)", "-"), (on, "with counter-moment (curve 3)", "--")):
        t = np.asarray(r.trace["time_s"])
        ax1.plot(t, np.degrees(np.asarray(r.trace["yaw_rate_radps"])), st, label=lab)
        ax2.plot(np.asarray(r.trace["x_m"]), np.asarray(r.trace["y_m"]), st, label=lab)
    ax1.axvline(1.0, color="k", lw=0.5)
    ax1.set_xlabel("time [s]")
    ax1.set_ylabel("yaw rate [deg/s]")
    ax1.set_title("Paper 004 Fig. 4 style: LF blowout at 1 s, 60 km/h, BJ2500, wheel held straight")
    ax1.legend()
    from vehicle_assist.metrics.blowout import LANE_MARGIN_M

    for s in (-1, 1):
        ax2.axhline(s * LANE_MARGIN_M, color="r", lw=0.6, ls=":")
    ax2.set_xlabel("x [m]")
    ax2.set_ylabel("y [m] (lane margin dotted)")
    ax2.legend()
    fig.tight_layout()
    fig_path = out_dir / "blowout_fig4.png"
    fig.savefig(fig_path, dpi=110)
    plt.close(fig)

    mo, mf = on.metrics, off.metrics
    red = 1.0 - mo["blowout_yaw_rate_rms_radps"] / mf["blowout_yaw_rate_rms_radps"]
    entries = [
        {"paper": "004", "scenario": f"{PAPER_ON} vs {PAPER_OFF}", "criterion": "yaw-rate RMS reduction over 2 s",
         "negative_control": False, "value": red, "unit": "1", "bound": f">= {RMS_REDUCTION_FRAC:g}",
         "pass": red >= RMS_REDUCTION_FRAC,
         "why": f"tire_blowout.md 9.5 / paper 004 P10: RMS {mf['blowout_yaw_rate_rms_radps']:.4f} -> "
                f"{mo['blowout_yaw_rate_rms_radps']:.4f} rad/s, peak {mf['blowout_yaw_rate_peak_radps']:.4f} -> "
                f"{mo['blowout_yaw_rate_peak_radps']:.4f} rad/s; M_z_blow estimate {mo['blowout_moment_est_nm']:.0f} N*m, "
                f"p_w {mo['blowout_pressure_req_pa'] / 1e6:.2f} MPa, valve {1000 * mo['blowout_valve_time_s']:.0f} ms"},
        {"paper": "004", "scenario": f"{PAPER_ON} vs {PAPER_OFF}", "criterion": "lateral deviation at +3 s, with minus without",
         "negative_control": False,
         "value": mo["blowout_lateral_deviation_3s_m"] - mf["blowout_lateral_deviation_3s_m"], "unit": "m", "bound": "< 0",
         "pass": mo["blowout_lateral_deviation_3s_m"] < mf["blowout_lateral_deviation_3s_m"],
         "why": f"tire_blowout.md 9.5: {mf['blowout_lateral_deviation_3s_m']:.2f} m without, "
                f"{mo['blowout_lateral_deviation_3s_m']:.2f} m with compensation"},
    ]
    rows = wheel_speed_table()
    table = out_dir / "blowout_wheel_speed.csv"
    _write_csv(table, rows)
    ws_path = _wheel_speed_png(rows, out_dir / "blowout_wheel_speed.png")
    for r in rows:
        red = 1.0 - r["rms_on_radps"] / r["rms_off_radps"]
        entries.append({"paper": "004", "scenario": f"{r['wheel']} blowout at {r['speed_kph']} km/h (on vs off)",
                        "criterion": "yaw-rate RMS reduction and smaller deviation", "negative_control": False,
                        "value": red, "unit": "1", "bound": f">= {RMS_REDUCTION_FRAC:g} and dev_on < dev_off",
                        "pass": bool(red >= RMS_REDUCTION_FRAC and r["dev3_on_m"] < r["dev3_off_m"]),
                        "why": f"tire_blowout.md 9.5 at each wheel and speed (issue #10): RMS {r['rms_off_radps']:.4f} -> "
                               f"{r['rms_on_radps']:.4f} rad/s, deviation {r['dev3_off_m']:.2f} -> {r['dev3_on_m']:.2f} m "
                               f"(table {table.name})"})
    return [("paper 004: Fig. 4 yaw rate with/without counter-moment, and path", fig_path),
            ("paper 004: yaw-rate peak/RMS and lateral deviation per wheel and speed, with/without compensation",
             ws_path)], entries


def _wheel_speed_png(rows, path: Path) -> Path:
    """Grouped bars per wheel and speed: yaw-rate peak and RMS over 2 s, lateral deviation at +3 s, on vs off."""
    import matplotlib.pyplot as plt

    labels = [f"{r['wheel']} {r['speed_kph']}" for r in rows]
    x = np.arange(len(rows))
    fig, axes = plt.subplots(3, 1, figsize=(11, 8), sharex=True)
    for ax, key, unit, scale in ((axes[0], "peak", "yaw-rate peak [deg/s]", float(np.degrees(1.0))),
                                 (axes[1], "rms", "yaw-rate RMS [deg/s]", float(np.degrees(1.0))),
                                 (axes[2], "dev3", "lateral deviation +3 s [m]", 1.0)):
        suffix = "_radps" if key != "dev3" else "_m"
        ax.bar(x - 0.2, [scale * r[f"{key}_off{suffix}"] for r in rows], 0.4, label="without compensation", color="0.6")
        ax.bar(x + 0.2, [scale * r[f"{key}_on{suffix}"] for r in rows], 0.4, label="with compensation", color="C0")
        ax.set_ylabel(unit)
    axes[0].legend(fontsize=8)
    axes[0].set_title("Paper 004: blowout on each wheel at 60/80/100 km/h (BJ2500, wheel held, 0.05 s detection delay)")
    axes[2].set_xticks(x)
    axes[2].set_xticklabels(labels, rotation=45)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def sweep_rows():
    cases = [(v, w, d) for v in SPEEDS_KPH for w in range(4) for d in DELAYS_S]
    offs = [(v, w) for v in SPEEDS_KPH for w in range(4)]
    scs = [_variants(True, w, v, d) for v, w, d in cases] + [_variants(False, w, v) for v, w in offs]
    res = _batch(scs).metrics
    off_dev = {offs[k]: (res[len(cases) + k]["blowout_lateral_deviation_3s_m"],
                         res[len(cases) + k]["blowout_lateral_deviation_run_max_m"]) for k in range(len(offs))}
    rows = []
    for k, (v, w, d) in enumerate(cases):
        rows.append({"speed_kph": v, "wheel": _W[w], "detection_delay_s": d,
                     "dev3_on_m": res[k]["blowout_lateral_deviation_3s_m"], "dev3_off_m": off_dev[(v, w)][0],
                     "devrun_on_m": res[k]["blowout_lateral_deviation_run_max_m"], "devrun_off_m": off_dev[(v, w)][1],
                     "rms_on_radps": res[k]["blowout_yaw_rate_rms_radps"]})
    return rows


def sweep_extra(out_dir: Path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    rows = sweep_rows()
    table = out_dir / "blowout_sweep.csv"
    _write_csv(table, rows)
    fig, axes = plt.subplots(1, 4, figsize=(14, 4), sharey=True)
    for wi, w in enumerate(_W):
        ax = axes[wi]
        for d in DELAYS_S:
            sel = [r for r in rows if r["wheel"] == w and r["detection_delay_s"] == d]
            ax.plot([r["speed_kph"] for r in sel], [r["dev3_on_m"] for r in sel], "o-", label=f"on, delay {d:g} s")
        sel = [r for r in rows if r["wheel"] == w and r["detection_delay_s"] == DELAYS_S[0]]
        ax.plot([r["speed_kph"] for r in sel], [r["dev3_off_m"] for r in sel], "k--", label="off")
        ax.set_title(f"{w} blowout")
        ax.set_xlabel("speed [km/h]")
    axes[0].set_ylabel("lateral deviation at +3 s [m]")
    axes[0].legend(fontsize=7)
    fig.tight_layout()
    fig_path = out_dir / "blowout_sweep.png"
    fig.savefig(fig_path, dpi=110)
    plt.close(fig)
    worse = [r for r in rows if r["devrun_on_m"] > r["devrun_off_m"]]
    entry = {"paper": "004", "scenario": f"sweep {len(rows)} cases: speed 60/80/100 x wheel x detection delay 0.05/0.2/0.5 s",
             "criterion": "cases where the compensation goes farther off the lane than no compensation (whole run)",
             "negative_control": False, "value": float(len(worse)), "unit": "1", "bound": "== 0", "pass": not worse,
             "why": "developer guide: never worse than no assist anywhere in the envelope (largest |offset change| from "
                    "t_b to the end of the run); largest deviation at +3 s with "
                    f"compensation {max(r['dev3_on_m'] for r in rows):.2f} m, without {max(r['dev3_off_m'] for r in rows):.2f} m "
                    f"(table {table.name})"}
    return [("paper 004: lateral deviation sweep (speed x wheel x detection delay)", fig_path)], [entry]


FALSIFY_BUDGET = 48  # CMA-ES evaluations per requirement (5-s runs; keeps reproduce within a minute)
FALSIFY_SEED = 2026


def _lane_counts(res) -> str:
    """The absolute lane result of a false-alarm campaign's evaluations (requirement stay_in_lane's boundary): how many
    points left the lane with the function, how many without it (the twin), and the largest exceedance of each - read
    from the per-side lane metrics the campaign's requirement (no_lane_departure_caused) had computed at every point and
    its twin; a point without them is reported as not judged, never counted as inside the lane."""
    from vehicle_assist.verification.requirements import comparative_metrics

    names = comparative_metrics(res.requirement)

    def beyond(values: dict) -> float:
        v = [float(values.get(n, float("nan"))) for n in names]
        return float("nan") if not v or any(math.isnan(x) for x in v) else max(v)

    a = [beyond(e.metrics) for e in res.evaluations]
    b = [beyond(e.baseline_metrics) for e in res.evaluations]
    missing = sum(1 for x, y in zip(a, b) if math.isnan(x) or math.isnan(y))
    if missing:
        return f"; absolute lane (stay_in_lane) not judged: the lane metrics {names} missing at {missing} of {len(a)} points"
    out_a = [x for x in a if x > 0.0]
    out_b = [x for x in b if x > 0.0]
    both = sum(1 for x, y in zip(a, b) if x > 0.0 and y > 0.0)
    return (f"; absolute lane (stay_in_lane) over the {len(a)} points: out of the lane with the function at "
            f"{len(out_a)} (max {max(out_a, default=0.0):.3f} m beyond the marking), without it at {len(out_b)} (max "
            f"{max(out_b, default=0.0):.3f} m), both at {both}")


def falsify_extra(out_dir: Path):
    """Falsification of data/requirements/tire_blowout.toml over data/envelopes/tire_blowout.toml (the paper's
    feed-forward) and tire_blowout_closed_loop.toml (the optional yaw-rate correction) (issue #10: requirements
    and an envelope for the falsification engine, with a campaign in reproduce), the lane bound over
    tire_blowout_false_alarm.toml (a false TPMS alarm, no blowout; issue #10 'Faults'), and never-worse over
    tire_blowout_faults.toml (an inlet valve stuck closed or a low accumulator in both runs; issue #10 'Faults')."""
    from vehicle_assist.verification.falsify import run_falsification, twin_text, write_falsification

    figures, entries = [], []
    # the paper's feed-forward (the shipped default), then the optional closed loop over the same envelope
    for env, rid in (("tire_blowout", "tire_blowout.no_worse_than_no_compensation"),
                     # session n: the road-departure half of never-worse (which car leaves the road first)
                     ("tire_blowout", "tire_blowout.no_earlier_road_departure"),
                     ("tire_blowout", "tire_blowout.stay_in_lane"),
                     ("tire_blowout_closed_loop", "tire_blowout.no_worse_than_no_compensation"),
                     ("tire_blowout_closed_loop", "tire_blowout.stay_in_lane"),
                     # issue #10 'Faults': a FALSE TPMS alarm (no blowout) over data/envelopes/tire_blowout_false_alarm.toml
                     # must not pull the car off its lane: the departure the function adds to its twin's (the envelope
                     # holds braking drivers with the wheel fixed in low-friction curves who leave the lane without any
                     # function; the absolute exceedance of both is reported in the entry)
                     ("tire_blowout_false_alarm", "tire_blowout.no_lane_departure_caused"),
                     # issue #10 'Faults' (low accumulator; inlet valve stuck closed) over data/envelopes/
                     # tire_blowout_faults.toml: the same blowout envelope with one fault in BOTH runs (an inlet fault
                     # from its fault_time 0 .. 4 s, session l L3; the twin has the same fault at the same time): never
                     # worse than the car without the function
                     ("tire_blowout_faults", "tire_blowout.no_worse_than_no_compensation"),
                     ("tire_blowout_faults", "tire_blowout.no_earlier_road_departure")):
        res = run_falsification(env, rid, budget=FALSIFY_BUDGET, seed=FALSIFY_SEED, optimizer="cma", batch=8,
                                progress=False)
        paths = write_falsification(res, Path(out_dir) / f"falsify_{env}_{rid.split('.')[-1]}")
        cex = res.counterexample
        lane = _lane_counts(res) if env == "tire_blowout_false_alarm" else ""
        if cex is not None:
            figures.append((f"paper 004: counterexample of {rid} ({env})", paths["plot"]))
            why = (f"counterexample after {res.evaluations_to_first} evaluations at [{res.envelope.point_name(cex.point)}]; "
                   f"reproduce: vehicle-assist run {paths['scenario']}; {twin_text(res) or 'compared with its twin'}; "
                   f"requirement: {res.requirement.why}")
            if env == "tire_blowout_false_alarm":
                why += ("; no blowout happened: the faulty TPMS alarm alone made the compensation act (issue #10 "
                        "'Faults'; review RG2's 640-point grid: 16 points where the compensated car leaves the lane and "
                        "the car without the function stays in it; tests/verification/test_blowout_false_alarm_envelope.py "
                        "strict xfail at RG2 k=664)")
            if env == "tire_blowout_faults":
                from vehicle_assist.scenarios.runner import simulate

                code = simulate(res.envelope.scenario(cex.point), requirements=False).metrics["blowout_limit_code"]
                why += ("; the function's run and its twin carry the same fault (the point's fault choice, "
                        f"{cex.point['fault']}, blown {cex.point['wheel']}); highest limit code of the function's run: {code:g} "
                        f"({limit_code_legend()}; the highest over the run, so a later code hides an earlier one)")
            why += lane
            value = cex.robustness
        else:
            why = (f"CMA-ES seed {FALSIFY_SEED}, {len(res.evaluations)} evaluations; minimum robustness at "
                   f"[{res.envelope.point_name(res.best.point)}]; requirement: {res.requirement.why}{lane}")
            value = res.best.robustness
        entries.append({"paper": "004", "scenario": f"falsification of {rid} over {env} (budget {FALSIFY_BUDGET}, seed {FALSIFY_SEED})",
                        "criterion": f"no counterexample in {FALSIFY_BUDGET} evaluations (robustness: minimum found)",
                        "negative_control": False, "value": value, "unit": res.requirement.unit, "bound": ">= 0",
                        "pass": cex is None, "why": why})
    return figures, entries


EXTRAS = {"blowout_fig4": fig4_extra, "blowout_sweep": sweep_extra, "falsify_004": falsify_extra}
