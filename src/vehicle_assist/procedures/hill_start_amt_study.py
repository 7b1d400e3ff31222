"""Paper 000 criteria that compare runs (issue 7): load adaptation (hill_start_amt.md 9.7, paper P9), clutch
energy against the baselines (9.10, P6) and the Table-1 reproduction through the whole truck (9.12, P7).

Each criterion names its source; a criterion the model does not meet is reported as FAIL with the measured
numbers (an honest red, not a tuned green):

* **9.7** - for every empty/full pair of the shipped matrix (same slope, same reservoir pressure) the mean
  commanded clutch rate over the assist's slip engagement (``engage_rate_mean_per_s``) must be larger empty
  than full (P9: "empty: faster clutch engagement allowed; full: engagement must be slowed").
* **9.10** - the assisted start must not dissipate more clutch slip energy than the same truck without the
  assist, early (S5) or late (S6) release (P6: releasing too late costs extra clutch load); the negative
  control S6 must violate 9.2 or 9.3 and dissipate more clutch energy than S1 (spec: "much higher"; the spec
  gives no factor, so the weakest reading, W(S6) > W(S1), is used). S6 is the spec's run: the hand valve is
  opened only after x_c = 1 (``hsa_truck_full_14deg_s6_release_after_lockup``; the clutch never closes against
  the applied brake, so it is never opened); the hand valve at 3 s is a baseline, not S6 (it is opened at
  x_c = 0.61, before the clutch carries the grade). S5 must violate 9.1 (checked in its own scenario file).
* **9.12** - the truck kernel with the assist off, the hand valve opened at 1.0 s on a level road: the park
  lamp goes out within +/- 0.1 s of paper 000 Table 1 (2.5 / 2.3 / 2.0 / 1.8 s at 6.5 / 7.0 / 7.5 / 8.0 bar).
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

PAPER = "000"
TABLE_1 = {6.5: 2.5, 7.0: 2.3, 7.5: 2.0, 8.0: 1.8}  # paper 000 Table 1: reservoir bar -> release time s
TABLE_1_TOL_S = 0.1  # hill_start_amt.md 9.12
PAIRS = tuple((slope, bar) for slope in (11, 14) for bar in ("6p5", "7p0", "7p5", "8p0"))
S1, S2 = "hsa_truck_full_14deg_8p0bar", "hsa_truck_empty_11deg_8p0bar"
# the spec's S6 (hill_start_amt.md 8: park brake released only after x_c = 1); the 3-s late release is a baseline only
S6 = "hsa_truck_full_14deg_s6_release_after_lockup"
# the assisted start and its baselines without the assist (same truck, same slope, same driver pedal)
ENERGY_CASES = (
    (S1, "hsa_truck_full_14deg_no_assist_early_release", "S5: full, early release"),
    (S1, "hsa_truck_full_14deg_no_assist_late_release", "full, late release (hand valve at 3 s)"),
    (S1, "hsa_truck_full_14deg_s6_release_after_lockup", "S6: full, hand valve only after x_c = 1"),
    (S2, "truck_11deg_early_release", "empty, early release"),
    (S2, "truck_11deg_late_release", "empty, late release"),
)


def _entry(scenario, criterion, value, unit, bound, ok, why, negative=False) -> dict:
    return {"paper": PAPER, "scenario": scenario, "criterion": criterion, "negative_control": negative,
            "value": float(value), "unit": unit, "bound": bound, "pass": bool(ok), "why": why}


def load_adaptation_entries(metrics: dict) -> list[dict]:
    """9.7 for each empty/full pair."""
    out = []
    for slope, bar in PAIRS:
        m_e, m_f = metrics[f"hsa_truck_empty_{slope}deg_{bar}bar"], metrics[f"hsa_truck_full_{slope}deg_{bar}bar"]
        empty, full = m_e["engage_rate_mean_per_s"], m_f["engage_rate_mean_per_s"]
        law_e, law_f = m_e.get("engage_rate_law_mean_per_s", np.nan), m_f.get("engage_rate_law_mean_per_s", np.nan)
        out.append(_entry(f"hsa_truck_empty/full_{slope}deg_{bar}bar", "engage_rate_mean_per_s empty - full",
                          empty - full, "1/s", "> 0", empty > full,
                          f"hill_start_amt.md 9.7 / paper 000 P9: engagement faster empty than full "
                          f"(spec-literal, mean over phase B: empty {empty:.4f} /s, full {full:.4f} /s; diagnostic, not the "
                          f"criterion: over the time the law moves the clutch, without the waits at our phase-3 and "
                          f"engine-torque ceilings: empty {law_e:.4f} /s, full {law_f:.4f} /s. Why it fails: phase B is "
                          f"dominated by the wait for the spring chambers (the paper's release times, the same for both loads), and the "
                          f"engine-speed and input-shaft laws of P10 choose v_fast for both loads)"))
    return out


def clutch_energy_entries(metrics: dict) -> list[dict]:
    """9.10: assisted clutch energy against each baseline; the S6 negative control."""
    out = []
    for assisted, baseline, label in ENERGY_CASES:
        w_a = metrics[assisted]["clutch_slip_energy_j"]
        w_b = metrics[baseline]["clutch_slip_energy_j"]
        out.append(_entry(f"{assisted} vs {baseline}", "clutch_slip_energy_j assisted / baseline", w_a / w_b, "1",
                          "<= 1", w_a <= w_b,
                          f"hill_start_amt.md 9.10 / paper 000 P6 ({label}): the assist should not dissipate more clutch "
                          f"energy than the start without it (assisted {w_a / 1e3:.0f} kJ, baseline {w_b / 1e3:.0f} kJ)"))
    s6 = metrics[S6]
    w1 = metrics[S1]["clutch_slip_energy_j"]
    stalled_or_no_start = s6["engine_stalled_flag"] > 0 or not (s6["launch_time_s"] <= 15.0)
    out.append(_entry(S6, "S6: stall or no start, and W(S6) > W(S1)",
                      s6["clutch_slip_energy_j"] / w1, "1", "> 1 with a stall or no start",
                      stalled_or_no_start and s6["clutch_slip_energy_j"] > w1,
                      f"hill_start_amt.md 9.10 negative control S6 must violate 9.2 or 9.3 and have much higher clutch "
                      f"slip energy than S1; the spec gives no factor for 'much higher', the weakest reading W(S6) > W(S1) "
                      f"is used (stall {bool(s6['engine_stalled_flag'])}, launch {s6['launch_time_s']:.2f} s, "
                      f"W(S6) {s6['clutch_slip_energy_j'] / 1e3:.0f} kJ, W(S1) {w1 / 1e3:.0f} kJ)", negative=True))
    return out


def table_1_entries() -> list[dict]:
    """9.12 through the whole truck kernel (1 ms recording of the park lamp)."""
    import vehicle_assist as va
    from vehicle_assist.scenarios.runner import simulate_batch

    bars = sorted(TABLE_1)
    scs = [va.load_scenario(S2, ["vehicle.hill_start_assist.enabled_flag=0", "road.slope_deg=0", "run.duration_s=5",
                                 "run.record_period_s=0.001", "driver.accelerator={time_s=[0.0], frac=[0.0]}",
                                 "driver.hand_valve={time_s=[0.0, 1.0], released=[0, 1]}",
                                 f"vehicle.park_brake.reservoir_pressure_bar={bar}"]) for bar in bars]
    batch = simulate_batch(scs, keep_channels=["time_s", "park_lamp_flag"], metric_names=[])
    out = []
    for bar, ch in zip(bars, batch.channels):
        t, lamp = ch["time_s"], ch["park_lamp_flag"]
        k = int(np.argmax(lamp < 0.5))
        t_out = float(t[k] - 1.0) if k > 0 else float("nan")
        out.append(_entry(f"Table 1, {bar:g} bar (truck kernel, assist off)", "park lamp out after hand valve [s]",
                          t_out, "s", f"{TABLE_1[bar]:g} +/- {TABLE_1_TOL_S:g}",
                          abs(t_out - TABLE_1[bar]) <= TABLE_1_TOL_S + 1e-9,
                          "hill_start_amt.md 9.12 / paper 000 Table 1 (P7): release time, valve switch to lamp out"))
    return out


def run_study(out_dir: Path | None = None) -> tuple[list[tuple[str, Path]], list[dict]]:
    """All three criteria; returns (figures, summary entries)."""
    import vehicle_assist as va
    from vehicle_assist.scenarios.runner import simulate_batch

    names = [f"hsa_truck_{load}_{slope}deg_{bar}bar" for load in ("empty", "full") for slope, bar in PAIRS]
    names += sorted({b for _, b, _ in ENERGY_CASES})
    batch = simulate_batch([va.load_scenario(n) for n in names],
                           metric_names=["engage_rate_mean_per_s", "engage_rate_law_mean_per_s", "clutch_slip_energy_j",
                                         "engine_stalled_flag",
                                         "launch_time_s"])
    metrics = dict(zip(names, batch.metrics))
    entries = load_adaptation_entries(metrics) + clutch_energy_entries(metrics) + table_1_entries()
    figures = []
    if out_dir is not None:
        figures.append(("paper 000: load adaptation (9.7) and clutch energy (9.10)", _figure(metrics, Path(out_dir))))
    return figures, entries


def _figure(metrics: dict, out_dir: Path) -> Path:
    import io

    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    from vehicle_assist.io.results import atomic_write_bytes

    out_dir.mkdir(parents=True, exist_ok=True)
    fig = Figure(figsize=(12, 4.5), dpi=100)
    FigureCanvasAgg(fig)
    ax1, ax2 = fig.subplots(1, 2)
    labels = [f"{s}deg {b.replace('p', '.')}bar" for s, b in PAIRS]
    x = np.arange(len(PAIRS))
    for off, load in ((-0.2, "empty"), (0.2, "full")):
        ax1.bar(x + off, [metrics[f"hsa_truck_{load}_{s}deg_{b}bar"]["engage_rate_mean_per_s"] for s, b in PAIRS], 0.4,
                label=load)
    ax1.set_xticks(x, labels, rotation=45, ha="right", fontsize=8)
    ax1.set_ylabel("mean clutch rate in slip engagement [1/s]")
    ax1.set_title("9.7: engagement empty vs full (P9)")
    ax1.legend()
    names = [S1, S2] + [b for _, b, _ in ENERGY_CASES]
    ax2.barh(range(len(names)), [metrics[n]["clutch_slip_energy_j"] / 1e3 for n in names])
    ax2.set_yticks(range(len(names)), names, fontsize=7)
    ax2.set_xlabel("clutch slip energy [kJ]")
    ax2.set_title("9.10: assisted (top two) vs baselines")
    fig.tight_layout()
    buf = io.BytesIO()
    fig.savefig(buf, format="png")
    path = out_dir / "hill_start_amt_study.png"
    atomic_write_bytes(path, buf.getvalue())
    return path


def hill_start_amt_extra(out_dir):
    """reproduce EXTRA: figures and criteria of this study."""
    return run_study(out_dir)
