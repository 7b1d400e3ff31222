"""Issue #12 on the command line: run --format, export, compare, sweep --plot, --version, events, check on vehicle
files, show units, bounds in display units, 80-column output. In-process (typer's CliRunner) to stay fast.

References: asammdf reads the MDF4 file independently; unit conversions are the definitions (1 km/h = 1/3.6 m/s,
1 bar = 1e5 Pa, 1 rpm = pi/30 rad/s); the names a user copies are the shipped names and metric names."""
from __future__ import annotations

import json
import re

import numpy as np
import pyarrow.parquet as pq
import pytest
from typer.testing import CliRunner

from vehicle_assist.cli import app
from vehicle_assist.metrics import METRICS
from vehicle_assist.scenarios.loader import shipped

WIDE = {"COLUMNS": "250", "NO_COLOR": "1", "TERM": "dumb"}
NARROW = {"COLUMNS": "80", "NO_COLOR": "1", "TERM": "dumb"}
SHORT = ["--set", "run.duration_s=3"]


def invoke(*args, env=WIDE):
    return CliRunner(env=env).invoke(app, [str(a) for a in args])


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    base = tmp_path_factory.mktemp("runs")
    a, b = base / "a", base / "b"
    ra = invoke("run", "hsa_truck_full_14deg_8p0bar", *SHORT, "--out", a, "--format", "mdf4,parquet", "--no-plot")
    rb = invoke("run", "hsa_truck_full_14deg_no_assist_early_release", *SHORT, "--out", b, "--no-plot")
    return a, b, ra, rb


def test_run_format_mdf4_writes_a_file_asammdf_opens_with_units_and_events(runs):
    asammdf = pytest.importorskip("asammdf")
    a, _, ra, _ = runs
    assert ra.exit_code in (0, 1), ra.output
    assert sorted(p.name for p in a.iterdir()) == ["metrics.json", "trace.mf4", "trace.parquet"]
    doc = json.loads((a / "metrics.json").read_text())
    with asammdf.MDF(str(a / "trace.mf4")) as mdf:
        assert mdf.get("speed_mps").unit == "m/s"
        assert len(mdf.events) == len(doc["events"]) > 0


def test_run_prints_events_with_chatter_merged(runs):
    _, _, _, rb = runs
    assert "events" in rb.output and "kiss_point_reached" in rb.output
    # the stick/slip chatter of the no-assist start is one row that counts its changes, not 100+ rows
    assert re.search(r"\d{2,} changes between", rb.output), rb.output  # (the table may wrap the rest)
    assert rb.output.count("static_friction_holds") < 5


def test_export_converts_a_run_and_errors_are_one_line(runs, tmp_path):
    _, b, _, _ = runs
    res = invoke("export", b, "--format", "mdf4,csv", "--out", tmp_path / "x")
    assert res.exit_code == 0, res.output
    assert {"trace.mf4", "trace.csv", "trace.units.json"} <= {p.name for p in (tmp_path / "x").iterdir()}
    assert invoke("export", b, "--format", "xlsx").exit_code == 2
    assert invoke("export", tmp_path / "nope").exit_code == 2


def test_compare_prints_deltas_and_writes_the_overlay(runs, tmp_path):
    a, b, _, _ = runs
    res = invoke("compare", a, b, "--out", tmp_path / "cmp")
    assert res.exit_code == 0, res.output
    assert "rollback_distance_m" in res.output and "delta" in res.output
    assert (tmp_path / "cmp" / "compare.png").read_bytes()[:4] == b"\x89PNG"
    # the delta printed is the difference of the two runs' metrics as written by run
    ma = json.loads((a / "metrics.json").read_text())["metrics"]["rollback_distance_m"]
    mb = json.loads((b / "metrics.json").read_text())["metrics"]["rollback_distance_m"]
    assert mb > ma  # the no-assist start rolls back (spec: the negative control)
    assert invoke("compare", a).exit_code == 2


def test_sweep_plot_writes_a_heat_map_and_a_report_with_provenance(tmp_path):
    out = tmp_path / "sw"
    res = invoke("sweep", "hsa_truck_full_14deg_8p0bar", "--grid", "road.slope_deg=10,14",
                 "--grid", "vehicle.body.mass_kg=20000,30000", *SHORT, "--out", out,
                 "--plot", "road.slope_deg vehicle.body.mass_kg engine_speed_peak_radps")
    assert res.exit_code == 0, res.output
    assert (out / "sweep.png").read_bytes()[:4] == b"\x89PNG"
    html = (out / "sweep.html").read_text()
    assert "Provenance" in html and "parameter_hash" in html and "package_version" in html
    table = pq.read_table(out / "sweep.parquet")
    assert table.schema.field("engine_speed_peak_radps").metadata[b"unit"] == b"rad/s"
    assert table.schema.field("road.slope_deg").metadata[b"unit"] == b"deg"
    record = json.loads(table.schema.metadata[b"vehicle_assist.sweep"])
    assert record["scenario"] == "hsa_truck_full_14deg_8p0bar" and record["package_version"]
    bad = invoke("sweep", "hsa_truck_full_14deg_8p0bar", "--grid", "road.slope_deg=10,14", *SHORT,
                 "--out", out, "--plot", "road.slope_deg - no_such_metric")
    assert bad.exit_code == 2


def test_grid_sweeps_a_list_valued_parameter(tmp_path):
    res = invoke("sweep", "hsa_truck_full_14deg_8p0bar", "--grid", "driver.accelerator.frac=[0,0,0.5],[0,0,0.7]",
                 *SHORT, "--out", tmp_path / "sw")
    assert res.exit_code == 0, res.output
    df = pq.read_table(tmp_path / "sw" / "sweep.parquet").to_pandas()
    assert [json.loads(v) for v in df["driver.accelerator.frac"]] == [[0, 0, 0.5], [0, 0, 0.7]]


def test_version():
    import vehicle_assist

    res = invoke("--version")
    assert res.exit_code == 0 and res.output.strip() == f"vehicle-assist {vehicle_assist.__version__}"


def test_check_accepts_vehicle_files():
    res = invoke("check", shipped("vehicles")["heavy_amt_truck_empty"])
    assert res.exit_code == 0 and "ok: vehicle heavy_amt_truck_empty" in res.output
    assert invoke("check", "heavy_amt_truck_empty").exit_code == 0


def test_show_gives_nm_per_rpm_its_unit():
    res = invoke("show", "heavy_amt_truck_empty", "--format", "json")
    doc = json.loads(res.output)
    assert doc["engine"]["governor_gain_nm_per_rpm"]["unit"] == "N*m/rpm"


def test_check_bounds_are_also_shown_in_display_units():
    """engine_speed_peak_radps bounds in rad/s also in rpm (x 30/pi); m/s also in km/h (x 3.6)."""
    import vehicle_assist as va
    from vehicle_assist.cli import _bound_display

    r = va.simulate(va.load_scenario("hsa_truck_full_14deg_8p0bar", {"run.duration_s": 1}))
    c = next(c for c in r.checks if c.metric == "engine_speed_peak_radps")
    text = _bound_display(c.metric, c)
    assert text.startswith(c.bound) and f"{c.min * 30 / np.pi:.4g} rpm" in text and f"{c.max * 30 / np.pi:.4g} rpm" in text
    c = next(c for c in r.checks if c.metric == "rollback_speed_mps")
    assert f"<= {c.max * 3.6:.4g} km/h" in _bound_display(c.metric, c)


def _names_whole(output: str, names) -> list[str]:
    words = set(re.findall(r"[A-Za-z0-9_.]+", output))
    return [n for n in names if n not in words]


def test_list_and_metrics_at_80_columns_keep_every_name_whole():
    res = invoke("list", env=NARROW)
    assert res.exit_code == 0
    assert not _names_whole(res.output, list(shipped("scenarios")) + list(shipped("vehicles")))
    res = invoke("metrics", env=NARROW)
    assert res.exit_code == 0
    assert not _names_whole(res.output, list(METRICS))
    needed = {c for m in METRICS.values() for c in m.requires}
    assert not _names_whole(res.output, needed)


def test_reproduce_output_at_80_columns_keeps_every_scenario_name_whole():
    """`reproduce` prints each scenario name on its own line: at 80 columns no name is cut or wrapped (names
    from the registered reproductions, longer ones than fit in a table column included)."""
    import io

    from rich.console import Console

    from vehicle_assist.procedures.reproduce import REPRODUCTIONS
    from vehicle_assist.procedures.run import print_entries

    entries = [{"paper": rep.paper, "scenario": name, "criterion": "rollback_distance_m", "value": 0.0, "unit": "m",
                "bound": "<= 0.01", "pass": True, "negative_control": "no_assist" in name}
               for rep in REPRODUCTIONS for name in rep.scenarios]
    buffer = io.StringIO()
    print_entries(Console(file=buffer, width=80, no_color=True), REPRODUCTIONS, entries)
    lines = buffer.getvalue().splitlines()
    for e in entries:
        assert f"  {e['scenario']}" in lines, e["scenario"]
    assert any("fails as required" in line for line in lines)
