"""The public Python API of issue #12: dict overrides, read_run, to_pandas with parameters, short reprs,
_repr_html_, py.typed, no process-wide side effects at import. References: the overrides as strings (the
documented form before) must give the same scenario hash; the import is checked in a fresh interpreter."""
from __future__ import annotations

import json
import os
import subprocess
import sys
import time
from pathlib import Path

import vehicle_assist as va


def test_dict_overrides_equal_string_overrides():
    a = va.load_scenario("hsa_truck_full_14deg_8p0bar", {"vehicle.body.mass_kg": 20000, "road.slope_deg": 12,
                                                           "driver.gear_lever.gear": ["1"]})
    b = va.load_scenario("hsa_truck_full_14deg_8p0bar", ["vehicle.body.mass_kg=20000", "road.slope_deg=12",
                                                         'driver.gear_lever.gear=["1"]'])
    c = va.load_scenario("hsa_truck_full_14deg_8p0bar", sets={"vehicle": {"body": {"mass_kg": 20000}},
                                                              "road.slope_deg": 12, "driver.gear_lever.gear": ["1"]})
    assert a.parameter_hash() == b.parameter_hash() == c.parameter_hash()
    assert a.scenario_hash() == b.scenario_hash()


def test_result_repr_is_short_and_has_html_and_pandas(tmp_path):
    r = va.simulate(va.load_scenario("hsa_truck_full_14deg_8p0bar", {"run.duration_s": 2}))
    assert len(repr(r)) < 200 and "hsa_truck_full_14deg_8p0bar" in repr(r)
    assert len(repr(r.trace)) < 200
    assert len(repr(r.scenario)) < 200 and len(repr(r.scenario.vehicle)) < 200
    html = r._repr_html_()
    assert "<table>" in html and "rollback_distance_m" in html
    df = r.to_pandas()
    assert list(df.columns) == r.trace.names and df.attrs["units"]["speed_mps"] == "m/s"


def test_batch_to_pandas_has_the_variant_parameters():
    base = va.load_scenario("hsa_truck_full_14deg_8p0bar", {"run.duration_s": 2})
    batch = va.simulate_batch([base.with_sets(f"road.slope_deg={a}") for a in (8, 12)])
    df = batch.to_pandas()
    assert list(df["road.slope_deg"]) == [8, 12] and list(df["run.duration_s"]) == [2, 2]
    assert "rollback_distance_m" in df.columns and "checks_ok" in df.columns
    assert len(repr(batch)) < 100


def test_read_run_reads_a_run_directory(tmp_path):
    from vehicle_assist.io.results import write_run_outputs

    r = va.simulate(va.load_scenario("hsa_truck_full_14deg_8p0bar", {"run.duration_s": 1}))
    write_run_outputs(r.trace, r.metrics, tmp_path, "t", plot=False)
    back = va.read_run(tmp_path)
    assert back.names == r.trace.names and back.events == r.trace.events
    assert json.loads(back.meta["mode_names"])["hsa_mode_index"][0] == "STANDBY"


def test_py_typed_ships():
    assert (Path(va.__file__).parent / "py.typed").exists()


def test_import_sets_no_openblas_and_prunes_nothing(tmp_path):
    """A fresh interpreter: importing the package leaves OPENBLAS_NUM_THREADS alone and does not delete old
    cache directories (pruning happens when a run starts)."""
    cache = tmp_path / "cache"
    old = cache / "vehicle-assist" / "numba"
    for k in range(8):
        (old / f"old{k}").mkdir(parents=True)
    env = {k: v for k, v in os.environ.items() if k not in ("OPENBLAS_NUM_THREADS", "NUMBA_CACHE_DIR")}
    env["XDG_CACHE_HOME"] = str(cache)
    code = "import os, vehicle_assist; print(os.environ.get('OPENBLAS_NUM_THREADS'))"
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=60)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "None"
    assert all((old / f"old{k}").is_dir() for k in range(8))
    from vehicle_assist import _cache

    assert _cache.KEEP == 4


def test_prune_keeps_versions_other_checkouts_use(tmp_path):
    """Two checkouts (git worktrees) run from different source versions at once: a run's prune must not delete a
    version another process used recently (it crashed that process mid-compile), only long-idle ones beyond KEEP."""
    cache = tmp_path / "cache"
    parent = cache / "vehicle-assist" / "numba"
    now = time.time()
    recent = [parent / f"recent{k}" for k in range(6)]  # more than KEEP, all in use within the last minutes
    idle = [parent / f"idle{k}" for k in range(3)]  # last used two days ago
    for k, d in enumerate(recent):
        d.mkdir(parents=True)
        os.utime(d, (now - 60 * (k + 1), now - 60 * (k + 1)))
    for k, d in enumerate(idle):
        d.mkdir(parents=True)
        os.utime(d, (now - 2 * 86400 - k, now - 2 * 86400 - k))
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"}
    env["XDG_CACHE_HOME"] = str(cache)
    code = "import vehicle_assist; from vehicle_assist import _cache; _cache.prune_stale()"
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=60)
    assert out.returncode == 0, out.stderr
    assert all(d.is_dir() for d in recent), [d.name for d in recent if not d.is_dir()]
    assert not any(d.is_dir() for d in idle)
