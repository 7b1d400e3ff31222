"""The `vehicle-assist` command line, run as a real subprocess (so "no traceback" is what a user sees).

Requirement (issue): "Bad input gets a clear one-line error naming the file, the field, the bad value and
the allowed range ... The CLI exits non-zero with no traceback; nothing is written." Plus the positive
behaviour of list / check / show / fsm / run / sweep (outputs, units row, resumable sweeps).
"""
from __future__ import annotations

import csv
import json
import os
import subprocess
import sys
import tomllib
from pathlib import Path

import pyarrow.parquet as pq
import pytest
from pandas.testing import assert_frame_equal

from vehicle_assist.functions.amt_launch import MACHINE
from vehicle_assist.scenarios.loader import shipped

SCENARIO = shipped("scenarios")["truck_11deg_early_release"]
SWEEP_ARGS = ["truck_11deg_late_release", "--grid", "vehicle.body.mass_kg=13000,20000", "--set", "run.duration_s=3"]


def cli(*args: str, cwd: Path) -> subprocess.CompletedProcess:
    """Run `python -m vehicle_assist.cli ARGS` in cwd; wide, colourless terminal so lines are not wrapped."""
    env = {**os.environ, "COLUMNS": "250", "NO_COLOR": "1", "TERM": "dumb"}
    return subprocess.run([sys.executable, "-m", "vehicle_assist.cli", *map(str, args)], cwd=cwd, env=env,
                          capture_output=True, text=True, timeout=300)


def assert_clean_input_error(res: subprocess.CompletedProcess, *fragments: str) -> str:
    """Exit 2, stderr is exactly one `error:` line holding the fragments, and no traceback anywhere."""
    assert "Traceback" not in res.stderr + res.stdout, res.stderr
    assert res.returncode == 2, (res.returncode, res.stderr)
    lines = [line for line in res.stderr.splitlines() if line.strip()]
    assert len(lines) == 1 and lines[0].startswith("error: "), res.stderr
    missing = [f for f in fragments if f not in lines[0]]
    assert not missing, f"error line lacks {missing}: {lines[0]}"
    return lines[0]


def bad_scenario(tmp_path: Path, old: str, new: str) -> Path:
    text = SCENARIO.read_text(encoding="utf-8")
    assert old in text
    path = tmp_path / "bad.toml"
    path.write_text(text.replace(old, new, 1), encoding="utf-8")
    return path


# (replacement in the scenario text or None, --set assignments, fragments of the error line)
BAD_INPUTS = {
    "slope-95": (("slope_deg = 11", "slope_deg = 95"), [], ["road.slope_deg", "= 95", "allowed: -45 <= slope_deg <= 45"]),
    "negative-mass-set": (None, ["vehicle.body.mass_kg=-5"], ["vehicle.body.mass_kg", "= -5", "allowed: 100 <= mass_kg"]),
    "nan-set": (None, ["road.slope_deg=nan"], ["road.slope_deg", "= nan", "NaN or inf"]),
    "unknown-key": (("slope_deg = 11", "slop_deg = 11"), [], ["road.slop_deg", "did you mean 'slope_deg'"]),
    "non-monotonic": (("time_s = [0.0, 2.0, 2.5]", "time_s = [0.0, 2.5, 2.0]"), [], ["driver.accelerator.time_s", "2 follows 2.5"]),
    "invalid-toml": (("slope_deg = 11", "slope_deg = = 11"), [], ["not valid TOML"]),
    "missing-file": ("MISSING", [], ["missing.toml", "file not found"]),
}


def scenario_arg(tmp_path: Path, change) -> str:
    if change == "MISSING":
        return str(tmp_path / "missing.toml")
    if change is None:  # an unchanged copy; the --set makes it bad
        path = tmp_path / "copy.toml"
        path.write_text(SCENARIO.read_text(encoding="utf-8"), encoding="utf-8")
        return str(path)
    return str(bad_scenario(tmp_path, *change))


@pytest.mark.parametrize("case", list(BAD_INPUTS))
def test_run_bad_input_exits_2_one_line_no_traceback_nothing_written(tmp_path, case):
    """Requirement: `run` on bad input exits non-zero (2) with one `error:` line naming the file and the
    field, no traceback, and the --out directory is never created."""
    change, sets, fragments = BAD_INPUTS[case]
    scenario = scenario_arg(tmp_path, change)
    out = tmp_path / "out"
    res = cli("run", scenario, *[a for s in sets for a in ("--set", s)], "--out", out, cwd=tmp_path)
    assert_clean_input_error(res, scenario, *fragments)
    assert not out.exists()


@pytest.mark.parametrize("case", ["slope-95", "negative-mass-set", "missing-file"])
def test_sweep_bad_input_exits_2_nothing_written(tmp_path, case):
    """Requirement: `sweep` on a bad scenario or --set exits 2 with one clean line; --out is not created."""
    change, sets, fragments = BAD_INPUTS[case]
    scenario = scenario_arg(tmp_path, change)
    out = tmp_path / "out"
    res = cli("sweep", scenario, "--grid", "run.seed=1,2", *[a for s in sets for a in ("--set", s)], "--out", out, cwd=tmp_path)
    assert_clean_input_error(res, scenario, *fragments)
    assert not out.exists()


@pytest.mark.parametrize("case", ["slope-95", "unknown-key"])
def test_check_and_show_bad_input_exit_2(tmp_path, case):
    """Requirement: `check` and `show` report bad input as one clean line with exit code 2."""
    change, sets, fragments = BAD_INPUTS[case]
    scenario = scenario_arg(tmp_path, change)
    for command in ("check", "show"):
        assert_clean_input_error(cli(command, scenario, cwd=tmp_path), scenario, *fragments)


def test_bad_vehicle_file_names_the_vehicle_file(tmp_path):
    """Requirement: a bad value in a vehicle file is reported against that vehicle file (check and show)."""
    vehicle = tmp_path / "truck.toml"
    text = shipped("vehicles")["heavy_amt_truck_empty"].read_text(encoding="utf-8")
    vehicle.write_text(text.replace("mass_kg = 13000", "mass_kg = -5", 1), encoding="utf-8")
    scenario = bad_scenario(tmp_path, 'base = "heavy_amt_truck_empty"', f'base = "{vehicle}"')
    assert_clean_input_error(cli("check", scenario, cwd=tmp_path), str(vehicle), "body.mass_kg", "= -5", "allowed:")
    assert_clean_input_error(cli("show", vehicle, cwd=tmp_path), str(vehicle), "body.mass_kg", "= -5", "allowed:")


def test_sweep_bad_grid_value_writes_nothing(tmp_path):
    """Requirement ("nothing is written"): a bad --grid value exits 2 with one clean line and no --out dir."""
    out = tmp_path / "out"
    res = cli("sweep", "truck_11deg_late_release", "--grid", "vehicle.body.mass_kg=-5,13000", "--out", out, cwd=tmp_path)
    assert_clean_input_error(res, "vehicle.body.mass_kg", "= -5")
    assert not out.exists()


# ---------------------------------------------------------------------------------------------- positive
def test_list_shows_every_shipped_name(tmp_path):
    """Requirement: `list` names every shipped scenario and vehicle."""
    res = cli("list", cwd=tmp_path)
    assert res.returncode == 0, res.stderr
    for kind in ("scenarios", "vehicles"):
        for name in shipped(kind):
            assert name in res.stdout


@pytest.mark.parametrize("name", sorted(shipped("scenarios")))
def test_check_accepts_every_shipped_scenario(tmp_path, name):
    """Requirement: every shipped scenario validates (`check` exits 0 and says ok)."""
    res = cli("check", name, cwd=tmp_path)
    assert res.returncode == 0, res.stderr
    assert res.stdout.startswith(f"ok: {name}")


def test_show_vehicle_json_has_value_unit_and_source(tmp_path):
    """Requirement: `show VEHICLE --format json` is valid JSON; each number has value, unit and source."""
    res = cli("show", "heavy_amt_truck_empty", "--format", "json", cwd=tmp_path)
    assert res.returncode == 0, res.stderr
    mass = json.loads(res.stdout)["body"]["mass_kg"]
    assert mass["value"] == 13000
    assert mass["unit"] == "kg"
    assert mass["source"].strip()


def test_show_scenario_prints_parseable_toml(tmp_path):
    """Requirement: `show SCENARIO` prints the resolved scenario as TOML that tomllib parses back."""
    res = cli("show", "truck_11deg_early_release", cwd=tmp_path)
    assert res.returncode == 0, res.stderr
    doc = tomllib.loads(res.stdout)
    assert doc["name"] == "truck_11deg_early_release"
    assert doc["road"]["slope_deg"] == 11
    assert doc["vehicle"]["name"] == "heavy_amt_truck_empty"


def test_fsm_prints_mermaid_with_every_transition(tmp_path):
    """Requirement: `fsm amt_launch` prints a Mermaid stateDiagram-v2 holding every transition of the machine."""
    res = cli("fsm", "amt_launch", cwd=tmp_path)
    assert res.returncode == 0, res.stderr
    lines = [line.strip() for line in res.stdout.splitlines()]
    assert lines[0] == "stateDiagram-v2"
    for t in MACHINE.transitions:
        assert f"{t.source} --> {t.target}: {t.guard}" in lines


def test_fsm_unknown_name_is_a_clean_error(tmp_path):
    """Requirement: an unknown state machine name is one clean error line with a did-you-mean."""
    assert_clean_input_error(cli("fsm", "amt_lanch", cwd=tmp_path), "did you mean 'amt_launch'")


def test_run_writes_trace_csv_with_units_metrics_and_plot(tmp_path):
    """Requirement: `run` exits 0 on a shipped scenario whose checks come out as expected and writes
    trace.parquet, trace.csv (units in trace.units.json), metrics.json and overview.png."""
    out = tmp_path / "out"
    res = cli("run", "truck_11deg_late_release", "--out", out, cwd=tmp_path)
    assert "Traceback" not in res.stderr
    assert res.returncode == 0, res.stdout + res.stderr
    assert sorted(p.name for p in out.iterdir()) == ["metrics.json", "overview.png", "trace.csv", "trace.parquet", "trace.units.json"]

    with (out / "trace.csv").open(newline="") as f:
        names, first = next(csv.reader(f)), next(csv.reader(f))
    unit = json.loads((out / "trace.units.json").read_text())["units"]
    assert unit["time_s"] == "s" and unit["speed_mps"] == "m/s" and unit["engine_speed_radps"] == "rad/s"
    assert float(first[0]) == 0.0

    trace = pq.read_table(out / "trace.parquet")
    assert trace.column_names == names
    assert trace.column("time_s")[-1].as_py() == pytest.approx(20.0, abs=0.02)

    doc = json.loads((out / "metrics.json").read_text())
    assert {"metrics", "checks", "events", "meta"} <= set(doc)
    assert "rollback_distance_m" in doc["metrics"]
    assert (out / "overview.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_run_with_set_changes_the_run(tmp_path):
    """Requirement: `run --set run.duration_s=2` takes the override (the trace ends at 2 s). Exit 1 is allowed:
    it means a check did not come out as expected in the shortened run, not an input error (that is 2)."""
    out = tmp_path / "out"
    res = cli("run", "truck_11deg_late_release", "--set", "run.duration_s=2", "--out", out, cwd=tmp_path)
    assert "Traceback" not in res.stderr
    assert res.returncode in (0, 1), res.stderr
    assert pq.read_table(out / "trace.parquet").column("time_s")[-1].as_py() == pytest.approx(2.0, abs=0.02)


def test_sweep_writes_rows_resumes_and_refuses_a_different_grid(tmp_path):
    """Requirement: `sweep` writes sweep.parquet with one row per variant; an interrupted sweep resumes
    (finished parts are reused, the result is the same); a different grid into the same --out is refused."""
    out = tmp_path / "sweep"
    res = cli("sweep", *SWEEP_ARGS, "--chunk", "1", "--out", out, cwd=tmp_path)
    assert res.returncode == 0, res.stderr
    first = pq.read_table(out / "sweep.parquet").to_pandas()
    assert len(first) == 2
    assert first["vehicle.body.mass_kg"].tolist() == [13000, 20000]
    part0, part1 = out / "parts" / "part-00000.parquet", out / "parts" / "part-00001.parquet"
    stamp0 = part0.stat().st_mtime_ns

    # interrupted after the first part: the second part and the merged file are missing
    part1.unlink()
    (out / "sweep.parquet").unlink()
    res = cli("sweep", *SWEEP_ARGS, "--chunk", "1", "--out", out, cwd=tmp_path)
    assert res.returncode == 0, res.stderr
    assert part0.stat().st_mtime_ns == stamp0, "finished part was recomputed instead of reused"
    assert part1.exists()
    assert_frame_equal(pq.read_table(out / "sweep.parquet").to_pandas(), first)  # NaN == NaN here

    # complete sweep run again: nothing recomputed, same result
    stamp1 = part1.stat().st_mtime_ns
    res = cli("sweep", *SWEEP_ARGS, "--chunk", "1", "--out", out, cwd=tmp_path)
    assert res.returncode == 0, res.stderr
    assert (part0.stat().st_mtime_ns, part1.stat().st_mtime_ns) == (stamp0, stamp1)
    assert_frame_equal(pq.read_table(out / "sweep.parquet").to_pandas(), first)  # NaN == NaN here

    # a different grid into the same directory is refused, and the old result is untouched
    res = cli("sweep", "truck_11deg_late_release", "--grid", "vehicle.body.mass_kg=13000,25000",
              "--set", "run.duration_s=3", "--chunk", "1", "--out", out, cwd=tmp_path)
    assert_clean_input_error(res, str(out), "different sweep")
    assert_frame_equal(pq.read_table(out / "sweep.parquet").to_pandas(), first)  # NaN == NaN here


def test_yaw_rates_shown_in_deg_per_s_not_rpm():
    """Issue #10 review: a yaw rate of 0.1 rad/s is 5.73 deg/s (1 rad = 180/pi deg); engine speeds stay in rpm."""
    from vehicle_assist.cli import _external
    from vehicle_assist.report.compare import display

    assert _external("blowout_yaw_rate_peak_radps", 0.1) == "5.73 deg/s"
    assert display("yaw_rate_radps", 0.1) == (pytest.approx(5.7295779513), "deg/s")
    assert _external("engine_speed_peak_radps", 188.6).endswith("rpm")
