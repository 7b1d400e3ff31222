"""Quick-look figures of a trace, for a human checking a run at a glance.

:func:`overview_png` stacks shared-time panels for whichever signal groups the trace has (speed and
position; engine / input-shaft / motor speed; pedals and clutch; forces; pressures) and marks the
mode-change events as thin vertical lines. Plots are the edge of the package, so this is where SI
channels are shown in workshop units: km/h, rpm, kN and bar.

Figures are drawn on a :class:`matplotlib.figure.Figure` with the Agg canvas, without pyplot: no global
figure registry to leak, no change of the user's interactive backend, safe in worker processes. The PNG
goes to memory first and is then written atomically.
"""
from __future__ import annotations

import io
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from vehicle_assist.core.trace import Trace
from vehicle_assist.io.results import atomic_write_bytes
from vehicle_assist.units import BAR_TO_PA, KPH_TO_MPS, RPM_TO_RADPS

__all__ = ["overview_png", "force_history_png", "hill_start_png", "FIGURES", "PANELS"]

DPI = 110
PANEL_HEIGHT_IN = 2.2
FIGURE_WIDTH_IN = 10.0


@dataclass(frozen=True)
class Line:
    """One curve: channel, legend label, factor from SI to the panel unit, line style."""

    channel: str
    label: str
    scale: float = 1.0
    style: str = "-"


@dataclass(frozen=True)
class Panel:
    """One axes: a title, the y-axis label with unit, its lines and optional lines on a right axis."""

    title: str
    ylabel: str
    lines: tuple[Line, ...]
    right_ylabel: str = ""
    right_lines: tuple[Line, ...] = ()
    ylim: tuple[float, float] | None = None

    def present(self, trace: Trace) -> bool:
        return any(line.channel in trace for line in self.lines + self.right_lines)


_KN = 1.0e-3
PANELS: tuple[Panel, ...] = (
    Panel(
        "Vehicle motion", "speed [km/h]",
        (Line("speed_mps", "speed", 1.0 / KPH_TO_MPS),),
        right_ylabel="position [m]",
        right_lines=(Line("position_m", "position", 1.0, "--"),),
    ),
    Panel(
        "Rotational speeds", "speed [rpm]",
        (
            Line("engine_speed_radps", "engine", 1.0 / RPM_TO_RADPS),
            Line("input_shaft_speed_radps", "input shaft", 1.0 / RPM_TO_RADPS, "--"),
            Line("motor_speed_radps", "motor", 1.0 / RPM_TO_RADPS),
        ),
    ),
    Panel(
        "Pedals and clutch", "position [0..1]",
        (
            Line("accelerator_frac", "accelerator"),
            Line("brake_pedal_frac", "brake pedal"),
            Line("clutch_position_frac", "clutch position", 1.0, "--"),
        ),
        ylim=(-0.05, 1.05),
    ),
    Panel(
        "Longitudinal forces", "force [kN]",
        (
            Line("drive_force_n", "drive", _KN),
            Line("grade_resistance_n", "grade resistance", _KN),
            Line("park_brake_force_n", "park brake", _KN),
            Line("service_brake_force_n", "service brake", _KN),
        ),
    ),
    Panel(
        "Brake pressures", "pressure [bar]",
        (
            Line("park_chamber_pressure_pa", "park chamber", 1.0 / BAR_TO_PA),
            Line("brake_pressure_pa", "brake pressure", 1.0 / BAR_TO_PA),
            Line("brake_pressure_command_pa", "brake pressure command", 1.0 / BAR_TO_PA, "--"),
        ),
    ),
)

FORCE_PANEL = Panel(
    "Longitudinal forces", "force [kN]",
    (
        Line("drive_force_n", "drive", _KN),
        Line("grade_resistance_n", "grade resistance", _KN),
        Line("aero_drag_n", "aero drag", _KN),
        Line("rolling_resistance_force_n", "rolling resistance", _KN),
        Line("service_brake_force_n", "service brake", _KN),
        Line("service_brake_capacity_n", "service brake capacity", _KN, ":"),
        Line("park_brake_force_n", "park brake", _KN),
        Line("park_brake_capacity_n", "park brake capacity", _KN, ":"),
    ),
)


def _draw_lines(ax, trace: Trace, lines: tuple[Line, ...], color_offset: int = 0) -> list:
    time_s = np.asarray(trace.time_s)
    handles = []
    for i, line in enumerate(l for l in lines if l.channel in trace):
        with np.errstate(over="ignore", invalid="ignore"):
            values = np.asarray(trace[line.channel], dtype=np.float64) * line.scale
        values = np.where(np.isfinite(values), values, np.nan)  # non-finite samples show as gaps
        (handle,) = ax.plot(time_s, values, line.style, lw=1.2, label=line.label,
                            color=f"C{(i + color_offset) % 10}")
        handles.append(handle)
    return handles


DEBOUNCE_S = 0.05  # display only: mode segments shorter than this are drawn as one hatched "chatter" span


@dataclass(frozen=True)
class Segment:
    """One span of a machine's mode in the display; ``changes`` > 1 marks merged chatter."""

    start_s: float
    end_s: float
    label: str
    changes: int = 1


def mode_segments(trace: Trace, machine: str, debounce_s: float = DEBOUNCE_S) -> list[Segment]:
    """The modes of ``machine`` over the trace as segments, with runs of segments shorter than ``debounce_s``
    merged into one ``A<->B`` chatter segment that says how many changes it holds (display only; the trace
    and its events keep every change)."""
    events = [e for e in trace.events if e.machine == machine]
    if not events or not len(trace):
        return []
    t0, t1 = float(trace.time_s[0]), float(trace.time_s[-1])
    raw: list[Segment] = []
    start, mode = t0, events[0].from_mode
    for e in events:
        raw.append(Segment(start, max(e.time_s, start), mode))
        start, mode = e.time_s, e.to_mode
    raw.append(Segment(start, max(t1, start), mode))
    out: list[Segment] = []
    run: list[Segment] = []

    def flush() -> None:
        if not run:
            return
        if len(run) == 1:
            out.append(run[0])
        else:
            names = list(dict.fromkeys(s.label for s in run))
            out.append(Segment(run[0].start_s, run[-1].end_s, "<->".join(names), len(run) + 1))  # changes at both ends
        run.clear()

    for seg in raw:
        if seg.end_s - seg.start_s < debounce_s:
            run.append(seg)
        else:
            flush()
            out.append(seg)
    flush()
    return [s for s in out if s.end_s > s.start_s or len(out) == 1]


def debounced_events(events, debounce_s: float = DEBOUNCE_S) -> list[tuple[float, float, str, str, str, str]]:
    """Rows (start s, end s, machine, from, to, guard) for a table: a run of changes of one machine each within
    ``debounce_s`` of the previous becomes one row "A<->B" whose guard says how many changes it holds."""
    rows: list[list] = []
    last: dict[str, int] = {}
    for e in events:
        k = last.get(e.machine)
        if k is not None and e.time_s - rows[k][1] < debounce_s and rows[k][6] == len(rows) - 1:
            row = rows[k]
            row[1] = e.time_s
            row[4] = e.to_mode
            row[7] += 1
            row[8].add(e.from_mode)
            row[8].add(e.to_mode)
            continue
        rows.append([e.time_s, e.time_s, e.machine, e.from_mode, e.to_mode, e.reason, len(rows), 1,
                     {e.from_mode, e.to_mode}])
        last[e.machine] = len(rows) - 1
    out = []
    for r in rows:
        if r[7] > 1:
            out.append((r[0], r[1], r[2], r[3], r[4], f"{r[7]} changes between {'/'.join(sorted(r[8]))} "
                        f"(chatter, each < {debounce_s * 1e3:g} ms apart)"))
        else:
            out.append((r[0], r[1], r[2], r[3], r[4], r[5]))
    return out


def _draw_strips(ax, trace: Trace, machines: list[str]) -> None:
    """One horizontal strip per state machine: a coloured bar per mode with its name inside where it fits,
    chatter hatched with its count."""
    span = float(trace.time_s[-1] - trace.time_s[0]) or 1.0
    colors: dict[str, str] = {}
    for row, machine in enumerate(machines):
        y = len(machines) - 1 - row
        for seg in mode_segments(trace, machine):
            width = seg.end_s - seg.start_s
            if seg.changes > 1:
                ax.broken_barh([(seg.start_s, width)], (y + 0.1, 0.8), facecolors="0.85", edgecolors="0.3",
                               hatch="////", lw=0.4)
                text = f"{seg.changes} changes"
            else:
                color = colors.setdefault(seg.label, f"C{len(colors) % 10}")
                ax.broken_barh([(seg.start_s, width)], (y + 0.1, 0.8), facecolors=color, alpha=0.35,
                               edgecolors="0.3", lw=0.4)
                text = seg.label
            if width / span > 0.012 * max(len(text), 3):  # the name fits in the bar (fontsize 6 at 10 in)
                ax.text(seg.start_s + width / 2, y + 0.5, _plain(text), ha="center", va="center", fontsize=6,
                        clip_on=True, parse_math=False)
    ax.set_yticks([len(machines) - 1 - i + 0.5 for i in range(len(machines))], [_plain(m) for m in machines],
                  fontsize=7)
    ax.set_ylim(0, len(machines))
    ax.set_title("Modes (hatched: faster changes than %g ms, merged for display)" % (DEBOUNCE_S * 1e3), fontsize=9,
                 loc="left")


def _event_machines(trace: Trace) -> list[str]:
    t0, t1 = (float(trace.time_s[0]), float(trace.time_s[-1])) if len(trace) else (0.0, 0.0)
    return list(dict.fromkeys(e.machine for e in trace.events if t0 <= e.time_s <= t1 and e.machine != "scenario"))


def _plain(text: str) -> str:
    from vehicle_assist.scenarios.errors import plain

    return plain(text)


def _render(trace: Trace, panels: list[Panel], path: str | Path, title: str) -> Path:
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    n = max(len(panels), 1)
    machines = _event_machines(trace)
    strip_in = 0.3 * len(machines) + 0.2 if machines else 0.0
    height_in = PANEL_HEIGHT_IN * n + strip_in + 0.8
    fig = Figure(figsize=(FIGURE_WIDTH_IN, height_in), dpi=DPI)
    # fixed margins instead of a layout engine: the constrained solver cost 0.3 s per figure
    fig.subplots_adjust(left=0.13, right=0.92, top=1.0 - 0.75 / height_in, bottom=0.45 / height_in,
                        hspace=0.42 * 2.2 / PANEL_HEIGHT_IN)
    FigureCanvasAgg(fig)
    ratios = [PANEL_HEIGHT_IN] * n + ([strip_in] if machines else [])
    grid = fig.subplots(len(ratios), 1, sharex=True, squeeze=False, gridspec_kw={"height_ratios": ratios})[:, 0]
    axes = list(np.atleast_1d(grid[:n]))
    strip_ax = grid[n] if machines else None
    # user text: no mathtext ($), no control characters; left-aligned above the legends' row
    fig.text(0.01, 1.0 - 0.12 / height_in, _plain(title), fontsize=11, va="top", ha="left", parse_math=False)
    if not panels:
        axes[0].text(0.5, 0.5, "no plottable channels in this trace", ha="center", va="center",
                     transform=axes[0].transAxes)
    for ax, panel in zip(axes, panels):
        handles = _draw_lines(ax, trace, panel.lines)
        if panel.right_lines and any(l.channel in trace for l in panel.right_lines):
            right = ax.twinx()
            handles += _draw_lines(right, trace, panel.right_lines, color_offset=len(handles))
            right.set_ylabel(panel.right_ylabel)
        ax.set_title(panel.title, fontsize=9, loc="left")
        ax.set_ylabel(panel.ylabel)
        if panel.ylim is not None:
            ax.set_ylim(*panel.ylim)
        ax.grid(True, lw=0.4, alpha=0.6)
        if handles:
            # in the title row, right-aligned: never hides data
            ax.legend(handles=handles, loc="lower right", bbox_to_anchor=(1.0, 1.0), ncols=min(len(handles), 4),
                      fontsize=7, frameon=False, borderaxespad=0.1, handlelength=2.5)
    if strip_ax is not None:
        _draw_strips(strip_ax, trace, machines)
        axes.append(strip_ax)
    axes[-1].set_xlabel("time [s]")
    if len(trace):
        axes[-1].set_xlim(float(trace.time_s[0]), float(trace.time_s[-1]))
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=DPI)
    return atomic_write_bytes(path, buffer.getvalue())


def overview_png(trace: Trace, path: str | Path, title: str) -> Path:
    """Write a PNG with one shared-time panel per signal group present in ``trace``; return its path."""
    return _render(trace, [p for p in PANELS if p.present(trace)], path, title)


def force_history_png(trace: Trace, path: str | Path, title: str) -> Path:
    """Write a PNG of every longitudinal force (kN) incl. brake capacities (dotted); return its path."""
    panels = [FORCE_PANEL] if FORCE_PANEL.present(trace) else []
    return _render(trace, panels, path, title)


# Paper 000 Fig. 7 (engine speed, clutch position, park pressure, vehicle speed over time) and Fig. 4
# (drive force, grade resistance, park force): the figures of the truck hill start.
HILL_START_PANELS = (
    Panel("Engine speed (paper 000 Fig. 7)", "speed [rpm]",
          (Line("engine_speed_radps", "engine", 1.0 / RPM_TO_RADPS),
           Line("input_shaft_speed_radps", "clutch driven plate", 1.0 / RPM_TO_RADPS, "--"))),
    Panel("Clutch position", "position [0..1]",
          (Line("clutch_position_frac", "clutch position"), Line("clutch_command_frac", "command", 1.0, "--"),
           Line("valve_32_energized_flag", "3/2 valve energised", 1.0, ":")),
          ylim=(-0.05, 1.05)),
    Panel("Park-brake chamber pressure", "pressure [bar]",
          (Line("park_chamber_pressure_pa", "spring chamber", 1.0 / BAR_TO_PA),
           Line("relay_control_pressure_pa", "relay control line", 1.0 / BAR_TO_PA, "--"))),
    Panel("Vehicle speed", "speed [km/h]", (Line("speed_mps", "speed", 1.0 / KPH_TO_MPS),),
          right_ylabel="position [m]", right_lines=(Line("position_m", "position", 1.0, "--"),)),
)
PARK_FORCE_PANEL = Panel(
    "Force history (paper 000 Fig. 4)", "force [kN]",
    (Line("drive_force_n", "drive force F_t", _KN), Line("grade_resistance_n", "grade resistance F_i", _KN),
     Line("park_brake_force_n", "park-brake force F_g", _KN),
     Line("park_brake_capacity_n", "park-brake capacity", _KN, ":")),
)


def hill_start_png(trace: Trace, path: str | Path, title: str) -> Path:
    """Paper 000 style: engine speed, clutch position, park pressure, vehicle speed, and the force history."""
    panels = [p for p in HILL_START_PANELS + (PARK_FORCE_PANEL,) if p.present(trace)]
    return _render(trace, panels, path, title)


FIGURES = {"overview": overview_png, "forces": force_history_png, "hill_start": hill_start_png}


# Paper 001 Fig. 8: brake force, brake pressure, speed and jerk against time.
EHB_PANELS = (
    Panel("Brake force (paper 001 Fig. 8a)", "force [kN]",
          (Line("service_brake_force_n", "brake force on the car", _KN),
           Line("service_brake_capacity_n", "brake force capacity", _KN, ":"),
           Line("grade_force_estimate_n", "F_ang (assist)", _KN, "--"),
           Line("torque_force_estimate_n", "F_tq (assist)", _KN, "--"))),
    Panel("Brake pressure (Fig. 8b)", "pressure [bar]",
          (Line("brake_pressure_pa", "EHB pressure", 1.0 / BAR_TO_PA),
           Line("hsa_pressure_command_pa", "assist request", 1.0 / BAR_TO_PA, "--"))),
    Panel("Vehicle speed (Fig. 8c)", "speed [km/h]", (Line("speed_mps", "speed", 1.0 / KPH_TO_MPS),),
          right_ylabel="accelerator [0..1]", right_lines=(Line("accelerator_frac", "accelerator", 1.0, ":"),)),
    Panel("Jerk, 5 Hz Butterworth (Fig. 8d)", "jerk [m/s^3]", (Line("jerk_filtered_mps3", "filtered jerk"),)),
)


def hill_start_ehb_png(trace: Trace, path: str | Path, title: str) -> Path:
    """Paper 001 style (Fig. 8): brake force, brake pressure, speed and filtered jerk."""
    from vehicle_assist.metrics.common import filtered_jerk

    channels = dict(trace.channels)
    channels["jerk_filtered_mps3"] = filtered_jerk(trace)
    view = Trace(channels, trace.descriptions, trace.meta, trace.events)
    return _render(view, [p for p in EHB_PANELS if p.present(view)], path, title)


FIGURES["hill_start_ehb"] = hill_start_ehb_png
