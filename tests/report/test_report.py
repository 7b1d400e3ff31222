"""Tests of vehicle_assist.report: overview PNGs for truck and EV traces, and the reproduce page."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from vehicle_assist.core.trace import Event, Trace
from vehicle_assist.report.html import write_reproduce_page
from vehicle_assist.report.plots import DPI, PANEL_HEIGHT_IN, force_history_png, overview_png

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
TIME_S = np.arange(0.0, 4.0 + 0.005, 0.01)


def truck_trace() -> Trace:
    t = TIME_S
    speed = np.clip(0.8 * (t - 1.5), -0.05, None)
    return Trace(
        {
            "time_s": t,
            "speed_mps": speed,
            "position_m": np.cumsum(speed) * 0.01,
            "engine_speed_radps": 80.0 + 20.0 * np.sin(t),
            "input_shaft_speed_radps": np.clip(60.0 * (t - 1.0), 0.0, None),
            "accelerator_frac": np.clip(t - 1.0, 0.0, 0.4),
            "clutch_position_frac": np.clip(1.0 - (t - 1.0), 0.0, 1.0),
            "drive_force_n": 4.0e4 * np.clip(t - 1.0, 0.0, 1.0),
            "grade_resistance_n": np.full_like(t, 3.0e4),
            "park_brake_force_n": 3.0e4 * np.clip(1.0 - (t - 1.0), 0.0, 1.0),
            "park_brake_capacity_n": np.full_like(t, 6.0e4),
            "park_chamber_pressure_pa": 7.0e5 * np.clip(t - 1.0, 0.0, 1.0),
            "engine_stalled_flag": np.zeros_like(t),
        },
        events=[Event(1.0, "hsa", "HOLD", "RELEASE", "torque_sufficient"),
                Event(2.0, "clutch", "SLIP", "LOCKED", "speed_matched")],
    )


def ev_trace() -> Trace:
    t = TIME_S
    return Trace({
        "time_s": t,
        "speed_mps": np.clip(t - 2.0, 0.0, None),
        "motor_speed_radps": 30.0 * np.clip(t - 2.0, 0.0, None),
        "motor_torque_nm": np.full_like(t, 150.0),
        "accelerator_frac": np.clip(t - 1.0, 0.0, 0.5),
        "brake_pedal_frac": np.where(t < 1.0, 0.5, 0.0),
        "brake_pressure_pa": 3.0e6 * np.clip(2.0 - t, 0.0, 1.0),
        "brake_pressure_command_pa": 3.0e6 * np.clip(1.9 - t, 0.0, 1.0),
    })


def png_size(path: Path) -> tuple[int, int]:
    """(width, height) in pixels from the PNG IHDR chunk."""
    data = path.read_bytes()
    assert data.startswith(PNG_SIGNATURE)
    return int.from_bytes(data[16:20], "big"), int.from_bytes(data[20:24], "big")


def expected_height(panels: int, machines: int = 0) -> int:
    """Panels, a mode strip of 0.3 in per state machine with events (+0.2 in), title and axis margins."""
    strip = 0.3 * machines + 0.2 if machines else 0.0
    return round(DPI * (PANEL_HEIGHT_IN * panels + strip + 0.8))


@pytest.mark.parametrize(
    "make, panels",
    [(truck_trace, 5),  # motion, rotational speeds, pedals+clutch, forces, pressures
     (ev_trace, 4)],  # motion, motor speed, pedals, pressures (no force channels)
)
def test_overview_png_has_one_panel_per_present_group(tmp_path: Path, make, panels: int) -> None:
    path = overview_png(make(), tmp_path / "out" / "overview.png", "Hill start <test>")
    assert path.stat().st_size > 10_000
    width, height = png_size(path)
    assert width == round(DPI * 10.0)
    assert abs(height - expected_height(panels, len({e.machine for e in make().events}))) <= 1
    assert sorted(p.name for p in path.parent.iterdir()) == ["overview.png"]


def test_overview_png_of_a_trace_without_key_channels(tmp_path: Path) -> None:
    trace = Trace({"time_s": TIME_S, "gear_index": np.ones_like(TIME_S)})
    width, height = png_size(overview_png(trace, tmp_path / "o.png", "empty"))
    assert abs(height - expected_height(1)) <= 1


def test_force_history_png(tmp_path: Path) -> None:
    path = force_history_png(truck_trace(), tmp_path / "forces.png", "forces")
    assert png_size(path)[0] == round(DPI * 10.0)


# -- html ------------------------------------------------------------------------------------------
ENTRIES = [
    {"paper": "000", "scenario": "truck_14deg", "criterion": "rollback_distance_m", "value": 0.0,
     "unit": "m", "bound": "<= 0.01", "pass": True},
    {"paper": "001", "scenario": "ev <script>alert(1)</script>", "criterion": "jerk & co",
     "value": 12.345678, "unit": "m/s^3", "bound": 10.0, "pass": False},
    {"paper": "002", "scenario": "x", "criterion": "launch_time_s", "value": float("nan"),
     "unit": "s", "bound": 3.0, "pass": None},
]


def test_reproduce_page_table_escaping_and_relative_figures(tmp_path: Path) -> None:
    figure = tmp_path / "site" / "figures" / "truck 14deg.png"
    figure.parent.mkdir(parents=True)
    figure.write_bytes(PNG_SIGNATURE)
    page = write_reproduce_page(ENTRIES, [("Truck <14 deg>", figure)], tmp_path / "site" / "index.html",
                                "Reproduction & checks")
    text = page.read_text(encoding="utf-8")
    assert text.startswith("<!DOCTYPE html>")
    assert "<title>Reproduction &amp; checks</title>" in text
    assert "<script>" not in text and "&lt;script&gt;" in text
    assert "jerk &amp; co" in text
    assert text.count('class="pass">PASS') == 1 and text.count('class="fail">FAIL') == 1
    assert 'class="unknown"' in text
    assert ">12.35<" in text and ">NaN<" in text and "&lt;= 0.01" in text
    assert 'src="figures/truck%2014deg.png"' in text
    assert "<figcaption>Truck &lt;14 deg&gt;</figcaption>" in text
    assert "1 as expected, 1 failed, 3 criteria" in text
    assert "http" not in text  # self-contained: no external resources


def test_negative_controls_say_fails_as_required_with_their_reason_and_sections(tmp_path: Path) -> None:
    """Issue #12: a negative control that breaks its bound (as the spec requires) is never a green PASS next to
    that bound; one that meets it is a FAIL. Sections per paper and study, extra keys shown, provenance."""
    entries = [
        {"paper": "000", "scenario": "no_assist", "criterion": "rollback_distance_m", "value": 0.2332, "unit": "m",
         "bound": "<= 0.01", "pass": True, "negative_control": True, "why": "hill_start_amt.md 9.2: must roll back"},
        {"paper": "000", "scenario": "bad_control", "criterion": "rollback_distance_m", "value": 0.0, "unit": "m",
         "bound": "<= 0.01", "pass": False, "negative_control": True, "why": "spec 9.2"},
        {"paper": "000", "scenario": "grid", "criterion": "9.7", "value": 1.0, "unit": "1", "bound": "> 0",
         "pass": True, "section": "study: load adaptation", "robustness": 0.25},
    ]
    page = write_reproduce_page(entries, [], tmp_path / "index.html", "t", papers={"000": "Truck AMT"},
                                scenario_hashes={"no_assist": {"scenario_hash": "abc", "parameter_hash": "def"}},
                                info={"package_version": "9.9", "git_commit": "cafe", "date_utc": "2026-01-01"})
    text = page.read_text(encoding="utf-8")
    assert 'class="pass">PASS' not in text.split("study: load adaptation")[0]
    assert text.count("fails as required</td>") == 1 and "FAIL (should fail)" in text
    assert text.count("must fail:</span>") == 2 and "hill_start_amt.md 9.2: must roll back" in text
    assert 'id="paper-000"' in text and "<h2>Paper 000: Truck AMT</h2>" in text
    assert "<h3>study: load adaptation</h3>" in text and "robustness = 0.25" in text
    assert "Provenance" in text and "cafe" in text and "<code>abc</code>" in text


def test_mode_strips_merge_chatter_for_display_only() -> None:
    """Reference: a hand-made event list (3 changes 1 ms apart inside a 10 s run) -> HELD, one chatter segment
    counting them, MOVING; the trace keeps all events."""
    from vehicle_assist.report.plots import debounced_events, mode_segments

    t = np.linspace(0.0, 10.0, 1001)
    ev = [Event(2.0, "vehicle", "HELD", "MOVING", "a"), Event(2.001, "vehicle", "MOVING", "HELD", "b"),
          Event(2.002, "vehicle", "HELD", "MOVING", "a"), Event(5.0, "clutch", "SLIP", "LOCK", "c")]
    trace = Trace({"time_s": t}, events=ev)
    segs = mode_segments(trace, "vehicle")
    assert [(s.label, s.changes) for s in segs] == [("HELD", 1), ("MOVING<->HELD", 3), ("MOVING", 1)]
    assert segs[1].start_s == 2.0 and segs[1].end_s == 2.002
    rows = debounced_events(ev)
    assert len(rows) == 2 and rows[0][:2] == (2.0, 2.002) and "3 changes" in rows[0][5]
    assert len(trace.events) == 4


def test_reproduce_page_rejects_incomplete_entries(tmp_path: Path) -> None:
    with pytest.raises(ValueError, match="pass"):
        write_reproduce_page([{k: v for k, v in ENTRIES[0].items() if k != "pass"}], [],
                             tmp_path / "p.html", "t")
    assert not (tmp_path / "p.html").exists()
