"""Tests of vehicle_assist.io.results: exact round trips, units in files, atomic writes, strict JSON."""
from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np
import pyarrow.parquet as pq
import pytest

from vehicle_assist.core.trace import Event, Trace
from vehicle_assist.io import results
from vehicle_assist.io.results import (
    atomic_write_bytes,
    atomic_write_text,
    read_trace_parquet,
    write_json,
    write_run_outputs,
    write_trace_csv,
    write_trace_parquet,
)


def awkward_trace() -> Trace:
    """A trace whose floats are hard to keep exact: thirds, subnormals, -0.0, huge, NaN, inf."""
    time_s = np.arange(6) * 1.0e-3
    speed_mps = np.array([1.0 / 3.0, -0.0, 5e-324, 1.0e308, np.nan, -np.inf])
    rng = np.random.default_rng(7)
    return Trace(
        {
            "time_s": time_s,
            "speed_mps": speed_mps,
            "engine_speed_radps": rng.normal(100.0, 30.0, 6),
            "park_chamber_pressure_pa": rng.uniform(0.0, 8.0e5, 6),
            "vehicle_held_flag": np.array([1.0, 1.0, 0.0, 0.0, 0.0, 0.0]),
        },
        descriptions={"speed_mps": "longitudinal speed, + forward", "time_s": "simulation time"},
        meta={"package_version": "0.1.0", "scenario_sha256": "abc123"},
        events=[
            Event(0.002, "hsa", "HOLD", "RELEASE", "torque_sufficient"),
            Event(1.0 / 3.0, "clutch", "OPEN", "SLIP", "pedal_released"),
        ],
    )


def bits(values: np.ndarray) -> np.ndarray:
    return np.asarray(values, dtype=np.float64).view(np.uint64)


def dir_listing(path: Path) -> list[str]:
    return sorted(p.name for p in path.iterdir())


# -- parquet ---------------------------------------------------------------------------------------
def test_parquet_round_trip_is_bit_identical_and_keeps_metadata(tmp_path: Path) -> None:
    trace = awkward_trace()
    path = write_trace_parquet(trace, tmp_path / "sub" / "trace.parquet")
    back = read_trace_parquet(path)

    assert back.names == trace.names
    for name in trace:
        np.testing.assert_array_equal(bits(back[name]), bits(trace[name]), err_msg=name)
    assert back.descriptions == trace.descriptions
    assert back.meta == trace.meta
    assert back.events == trace.events
    assert dir_listing(tmp_path / "sub") == ["trace.parquet"]


def test_parquet_fields_carry_units(tmp_path: Path) -> None:
    write_trace_parquet(awkward_trace(), tmp_path / "t.parquet")
    schema = pq.read_schema(tmp_path / "t.parquet")
    units = {f.name: f.metadata[b"unit"].decode() for f in schema}
    assert units == {
        "time_s": "s",
        "speed_mps": "m/s",
        "engine_speed_radps": "rad/s",
        "park_chamber_pressure_pa": "Pa",
        "vehicle_held_flag": "1",
    }


def test_parquet_failure_midway_leaves_old_file_and_no_temp(tmp_path: Path, monkeypatch) -> None:
    target = tmp_path / "trace.parquet"
    target.write_bytes(b"old contents")

    def half_write(table, where, **kwargs):
        Path(where).write_bytes(b"PAR1 half a file")
        raise OSError("disk full")

    monkeypatch.setattr(pq, "write_table", half_write)
    with pytest.raises(OSError, match="disk full"):
        write_trace_parquet(awkward_trace(), target)
    assert target.read_bytes() == b"old contents"
    assert dir_listing(tmp_path) == ["trace.parquet"]


# -- csv -------------------------------------------------------------------------------------------
def test_csv_has_names_then_exact_values_and_units_in_a_sidecar(tmp_path: Path) -> None:
    """Issue #12: pandas.read_csv must give numeric columns, so the units live in trace.units.json."""
    import pandas as pd

    trace = awkward_trace()
    path = write_trace_csv(trace, tmp_path / "trace.csv")
    lines = path.read_text().splitlines()
    assert lines[0].split(",") == trace.names
    side = json.loads((tmp_path / "trace.units.json").read_text())
    assert list(side["units"].values()) == ["s", "m/s", "rad/s", "Pa", "1"]
    assert side["events"] == [e.as_dict() for e in trace.events]
    df = pd.read_csv(path)
    assert all(dtype.kind in "fi" for dtype in df.dtypes), df.dtypes  # numbers, never object (strings)
    back = results.read_trace_csv(path)
    assert back.events == trace.events and back.meta == trace.meta
    data = np.array([[float(x) for x in line.split(",")] for line in lines[1:]])
    assert data.shape == (len(trace), len(trace.names))
    for j, name in enumerate(trace.names):
        np.testing.assert_array_equal(bits(data[:, j]), bits(trace[name]), err_msg=name)


# -- atomic writes ---------------------------------------------------------------------------------
def test_atomic_write_creates_parents_and_replaces(tmp_path: Path) -> None:
    target = tmp_path / "a" / "b" / "out.txt"
    atomic_write_text(target, "first")
    atomic_write_text(target, "second ünïcode")
    assert target.read_text(encoding="utf-8") == "second ünïcode"
    assert dir_listing(target.parent) == ["out.txt"]


def test_atomic_write_gives_the_mode_open_would_give(tmp_path: Path) -> None:
    reference = tmp_path / "reference.txt"
    reference.write_text("x")
    new = atomic_write_bytes(tmp_path / "new.bin", b"x")
    assert new.stat().st_mode & 0o777 == reference.stat().st_mode & 0o777


def test_atomic_write_keeps_an_existing_files_mode(tmp_path: Path) -> None:
    target = tmp_path / "kept.txt"
    target.write_text("old")
    os.chmod(target, 0o640)
    atomic_write_text(target, "new")
    assert target.stat().st_mode & 0o777 == 0o640


@pytest.mark.parametrize("existing", [False, True])
def test_exception_midway_leaves_no_file_and_no_temp(tmp_path: Path, monkeypatch, existing: bool) -> None:
    """fsync fails after the data went to the temp file: the target is unchanged, the temp file is gone."""
    target = tmp_path / "metrics.json"
    if existing:
        target.write_text("old")

    def failing_fsync(fd: int) -> None:
        raise OSError("I/O error")

    monkeypatch.setattr(results.os, "fsync", failing_fsync)
    with pytest.raises(OSError, match="I/O error"):
        write_json({"a": 1}, target)
    if existing:
        assert target.read_text() == "old"
        assert dir_listing(tmp_path) == ["metrics.json"]
    else:
        assert dir_listing(tmp_path) == []


def test_exception_in_replace_leaves_no_temp(tmp_path: Path, monkeypatch) -> None:
    target = tmp_path / "trace.csv"
    target.write_text("old")

    def failing_replace(src, dst) -> None:
        raise PermissionError("locked")

    monkeypatch.setattr(results.os, "replace", failing_replace)
    with pytest.raises(PermissionError):
        write_trace_csv(awkward_trace(), target)
    assert target.read_text() == "old"
    assert dir_listing(tmp_path) == ["trace.csv"]


# -- json ------------------------------------------------------------------------------------------
def test_json_writes_nan_and_inf_as_null_and_keeps_order(tmp_path: Path) -> None:
    obj = {
        "z_first": float("nan"),
        "a_second": [1.5, float("inf"), -float("inf"), np.float64("nan")],
        "nested": {"value": np.float32(0.25), "count": np.int64(3), "ok": np.bool_(True), "none": None},
        "array": np.array([1.0, np.nan]),
        "path": Path("x") / "y.csv",
        "event": Event(1.0, "hsa", "HOLD", "RELEASE", "why"),
    }
    path = write_json(obj, tmp_path / "m.json")

    def no_constants(name: str) -> None:
        raise AssertionError(f"non-standard JSON constant {name}")

    back = json.loads(path.read_text(), parse_constant=no_constants)
    assert list(back) == list(obj)
    assert back["z_first"] is None
    assert back["a_second"] == [1.5, None, None, None]
    assert back["nested"] == {"value": 0.25, "count": 3, "ok": True, "none": None}
    assert back["array"] == [1.0, None]
    assert back["path"] == str(Path("x") / "y.csv")
    assert back["event"]["to_mode"] == "RELEASE"
    assert path.read_text().startswith('{\n  "z_first"')


def test_json_rejects_unknown_types(tmp_path: Path) -> None:
    with pytest.raises(TypeError):
        write_json({"x": object()}, tmp_path / "bad.json")
    assert dir_listing(tmp_path) == []


# -- one run ---------------------------------------------------------------------------------------
def test_write_run_outputs_writes_the_bundle(tmp_path: Path) -> None:
    trace = awkward_trace()
    checks = [{"criterion": "rollback_distance_m", "value": 0.0, "bound": 0.01, "pass": True}]
    paths = write_run_outputs(trace, {"rollback_distance_m": 0.0, "launch_time_s": float("nan")},
                              tmp_path / "run", "test run", checks)
    assert set(paths) == {"parquet", "csv", "metrics", "overview"}
    assert dir_listing(tmp_path / "run") == ["metrics.json", "overview.png", "trace.csv", "trace.parquet",
                                             "trace.units.json"]
    doc = json.loads(paths["metrics"].read_text())
    assert list(doc) == ["metrics", "checks", "requirements", "events", "meta"]
    assert doc["metrics"] == {"rollback_distance_m": 0.0, "launch_time_s": None}
    assert doc["checks"] == checks
    assert doc["events"] == [e.as_dict() for e in trace.events]
    assert doc["meta"] == trace.meta
    assert paths["overview"].read_bytes().startswith(b"\x89PNG\r\n\x1a\n")
