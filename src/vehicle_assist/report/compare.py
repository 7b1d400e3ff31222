"""Figures and tables that put several runs or a sweep side by side: run overlays, metric deltas, sweep plots.

Display units as in :mod:`vehicle_assist.report.plots` (km/h, rpm, kN, bar); the numbers in tables stay SI.
"""
from __future__ import annotations

import io
import math
from html import escape
from pathlib import Path

import numpy as np

from vehicle_assist.core.trace import Trace
from vehicle_assist.io.results import atomic_write_bytes, atomic_write_text
from vehicle_assist.report.plots import DPI, FIGURE_WIDTH_IN, PANELS, _plain
from vehicle_assist.units import BAR_TO_PA, KPH_TO_MPS, RPM_TO_RADPS, unit_of

__all__ = ["compare_png", "metric_deltas", "sweep_png", "sweep_html", "display"]


def display(name: str, value: float) -> tuple[float, str]:
    """``value`` of the SI quantity ``name`` in the unit an engineer reads (rpm, km/h, bar), else SI."""
    if name.endswith("_radps") and ("yaw" in name or "steer" in name):  # body/steering rates: deg/s, not rpm
        return math.degrees(value), "deg/s"
    if name.endswith("_radps"):
        return value / RPM_TO_RADPS, "rpm"
    if name.endswith("_mps"):
        return value / KPH_TO_MPS, "km/h"
    if name.endswith("_pa"):
        return value / BAR_TO_PA, "bar"
    return value, unit_of(name)


def metric_deltas(metrics: list[dict[str, float]]) -> list[tuple[str, list[float], list[float]]]:
    """Rows (metric, values per run, value - first run's value) over the metrics every run has."""
    names = [n for n in metrics[0] if all(n in m for m in metrics[1:])]
    rows = []
    for name in names:
        values = [float(m[name]) for m in metrics]
        rows.append((name, values, [v - values[0] for v in values]))
    return rows


def compare_png(traces: list[Trace], labels: list[str], path: str | Path, title: str = "compare") -> Path:
    """Overlay the key channels of several runs, one panel per signal group any run has (run = colour,
    channel = line style)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    panels = [p for p in PANELS if any(p.present(t) for t in traces)]
    n = max(len(panels), 1)
    height_in = 2.2 * n + 0.9
    fig = Figure(figsize=(FIGURE_WIDTH_IN, height_in), dpi=DPI)
    fig.subplots_adjust(left=0.08, right=0.97, top=1.0 - 0.8 / height_in, bottom=0.45 / height_in, hspace=0.45)
    FigureCanvasAgg(fig)
    axes = fig.subplots(n, 1, sharex=True, squeeze=False)[:, 0]
    fig.text(0.01, 1.0 - 0.12 / height_in, _plain(title), fontsize=11, va="top", ha="left", parse_math=False)
    styles = ["-", "--", ":", "-."]
    run_handles = []
    for ax, panel in zip(axes, panels):
        lines = [line for line in panel.lines + panel.right_lines if any(line.channel in t for t in traces)]
        for k, (trace, label) in enumerate(zip(traces, labels)):
            for j, line in enumerate(lines):
                if line.channel not in trace:
                    continue
                (h,) = ax.plot(trace.time_s, np.asarray(trace[line.channel]) * line.scale, styles[j % 4],
                               color=f"C{k % 10}", lw=1.1, label=f"{line.label}" if k == 0 else None)
                if ax is axes[0] and j == 0:
                    run_handles.append((h, label))
        ax.set_title(panel.title + "  (" + ", ".join(f"{styles[j % 4]} {l.label}" for j, l in enumerate(lines)) + ")",
                     fontsize=8, loc="left")
        ax.set_ylabel(panel.ylabel if not panel.right_lines else f"{panel.ylabel} / {panel.right_ylabel}", fontsize=8)
        ax.grid(True, lw=0.4, alpha=0.6)
    if run_handles:
        fig.legend([h for h, _ in run_handles], [_plain(l) for _, l in run_handles], loc="upper right",
                   bbox_to_anchor=(0.97, 1.0 - 0.05 / height_in), ncols=min(len(run_handles), 3), fontsize=8,
                   frameon=False)
    axes[-1].set_xlabel("time [s]")
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=DPI)
    return atomic_write_bytes(path, buffer.getvalue())


def sweep_png(df, x: str, y: str | None, metric: str, path: str | Path, title: str = "") -> Path:
    """A sweep as a heat map of ``metric`` over axes ``x`` and ``y`` (mean over any other axes), or as lines of
    ``metric`` over ``x`` (one line per value of ``y`` if given and the plot is asked as lines)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(7.5, 5.2), dpi=DPI)
    FigureCanvasAgg(fig)
    ax = fig.subplots()
    scale_value, metric_unit = display(metric, 1.0)
    label = f"{metric} [{metric_unit}]" if metric_unit not in ("", "1") else metric
    if y is None:
        g = df.groupby(x, sort=True)[metric].mean()
        ax.plot(_numeric(g.index), g.values * scale_value, "o-")
        ax.set_xlabel(x)
        ax.set_ylabel(label)
        ax.grid(True, lw=0.4, alpha=0.6)
    else:
        table = df.pivot_table(index=y, columns=x, values=metric, aggfunc="mean").sort_index()
        values = table.values * scale_value
        im = ax.imshow(values, origin="lower", aspect="auto", cmap="viridis")
        ax.set_xticks(range(len(table.columns)), [_tick(v) for v in table.columns], fontsize=7, rotation=45)
        ax.set_yticks(range(len(table.index)), [_tick(v) for v in table.index], fontsize=7)
        ax.set_xlabel(x)
        ax.set_ylabel(y)
        if values.size <= 200:
            for (i, j), v in np.ndenumerate(values):
                if math.isfinite(v):
                    ax.text(j, i, f"{v:.3g}", ha="center", va="center", fontsize=6, color="w")
        fig.colorbar(im, ax=ax, label=label)
    ax.set_title(_plain(title or metric), fontsize=10, loc="left")
    fig.tight_layout()
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=DPI)
    return atomic_write_bytes(path, buffer.getvalue())


def _numeric(index):
    try:
        return np.asarray(index, dtype=float)
    except (TypeError, ValueError):
        return np.arange(len(index))


def _tick(v) -> str:
    return f"{v:g}" if isinstance(v, (int, float, np.floating, np.integer)) else _plain(str(v))


def sweep_html(df, record: dict, figure: Path | None, path: str | Path) -> Path:
    """A sweep report: provenance (the sweep record), the figure and the table of every variant."""
    prov = "".join(f"<tr><th>{escape(str(k))}</th><td>{escape(str(v))}</td></tr>" for k, v in record.items())
    fig = f'<img src="{escape(figure.name)}" alt="sweep plot">' if figure is not None else ""
    body = df.to_html(index=False, float_format=lambda v: f"{v:.4g}", border=0)
    html = (f"<!doctype html><html><head><meta charset='utf-8'><title>sweep {escape(str(record.get('scenario', '')))}"
            "</title><style>body{font-family:sans-serif;margin:1.5em}table{border-collapse:collapse;font-size:12px}"
            "td,th{border:1px solid #ccc;padding:2px 6px}</style></head><body>"
            f"<h1>Sweep of {escape(str(record.get('scenario', '')))}</h1><h2>Provenance</h2><table>{prov}</table>"
            f"<h2>Plot</h2>{fig}<h2>Variants ({len(df)})</h2>{body}</body></html>")
    return atomic_write_text(path, html)
