"""The command line under hostile or careless input (issue #14), one test (or table) per class of the issue.

Reference: the issue's list of failures, each reproduced on main before the fix, and the project rule
"bad input -> one-line clear error (exit 2), never a traceback; nothing is written". Most cases run the
typer app in-process (fast); the few that need a fresh interpreter (environment, numba cache) run it as a
subprocess. Every error case asserts: exit code 2, exactly one `error:` line on stderr, no traceback, no raw
control character, the expected fragments, and that --out was not created.
"""
from __future__ import annotations

import errno
import json
import os
import subprocess
import sys
from pathlib import Path

import pyarrow.parquet as pq
import pytest
from typer.testing import CliRunner

import vehicle_assist.report.plots  # noqa: F401  (imported before any test patches io.results)
from vehicle_assist.cli import app
from vehicle_assist.scenarios.guards import OutputLock
from vehicle_assist.scenarios.loader import shipped

SCENARIO = shipped("scenarios")["truck_11deg_late_release"]
SHORT = ["--set", "run.duration_s=2"]
ENV = {"COLUMNS": "250", "NO_COLOR": "1", "TERM": "dumb"}


def invoke(*args):
    return CliRunner(env=ENV).invoke(app, [str(a) for a in args])


def _control(text: str) -> list[str]:
    return [c for c in text if (ord(c) < 32 and c not in "\n\t") or 0x7f <= ord(c) <= 0x9f]


def one_line(res, *fragments: str) -> str:
    assert res.exception is None or isinstance(res.exception, SystemExit), repr(res.exception)
    assert "Traceback" not in res.stdout + res.stderr
    assert res.exit_code == 2, (res.exit_code, res.stdout, res.stderr)
    lines = [line for line in res.stderr.splitlines() if line.strip()]
    assert len(lines) == 1 and lines[0].startswith("error: "), res.stderr
    assert not _control(res.stderr + res.stdout), repr(res.stderr)
    missing = [f for f in fragments if f not in lines[0]]
    assert not missing, f"error line lacks {missing}: {lines[0]}"
    return lines[0]


def scenario_copy(tmp_path: Path, old: str = "", new: str = "", name: str = "s.toml") -> Path:
    text = SCENARIO.read_text(encoding="utf-8")
    if old:
        assert old in text
        text = text.replace(old, new, 1)
    path = tmp_path / name
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text, encoding="utf-8")
    return path


# ------------------------------------------------------------------------------------------ --out problems
@pytest.mark.parametrize("kind", ["file", "under-file", "root", "empty", "unwritable", "nul", "long", "symlink-loop"])
def test_bad_out_is_refused_before_simulating(tmp_path, kind, monkeypatch):
    """Issue #14: --out that is a file, under a file, '/', '', not writable or holds a NUL is one line and
    exit 2 before the simulation runs (the simulator is replaced by a trap)."""
    import vehicle_assist.scenarios.runner as runner

    monkeypatch.setattr(runner, "simulate", lambda sc: pytest.fail("simulated before --out was checked"))
    (tmp_path / "afile").write_text("x")
    (tmp_path / "l1").symlink_to(tmp_path / "l2")
    (tmp_path / "l2").symlink_to(tmp_path / "l1")
    out = {"long": "o" * 5000, "symlink-loop": tmp_path / "l1" / "out","file": tmp_path / "afile", "under-file": tmp_path / "afile" / "sub", "root": "/", "empty": "",
           "unwritable": "/proc/vehicle-assist-out", "nul": "a\x00b"}[kind]
    fragment = {"file": "is a file", "under-file": "a parent of it is a file", "root": "file-system root",
                "empty": "empty path", "unwritable": "not writable", "nul": "NUL", "long": "at most 4096",
                "symlink-loop": "--out"}[kind]
    for command in (["run", "truck_11deg_late_release"], ["sweep", "truck_11deg_late_release", "--grid", "run.seed=1,2"]):
        one_line(invoke(*command, "--out", out), "--out", fragment)
    assert (tmp_path / "afile").read_text() == "x"


def test_unwritable_directory_by_mode(tmp_path):
    """Issue #14: a read-only directory (mode 0555) is refused before simulating (skipped where the
    test runs as root, for whom modes do not apply; /proc covers that case above)."""
    ro = tmp_path / "ro"
    ro.mkdir()
    ro.chmod(0o555)
    try:
        if os.access(ro, os.W_OK):
            pytest.skip("running as root: directory modes do not stop writes")
        one_line(invoke("run", "truck_11deg_late_release", "--out", ro / "out"), "not writable")
    finally:
        ro.chmod(0o755)


@pytest.mark.parametrize("code", [errno.ENOSPC, errno.EACCES])
def test_write_failure_is_one_line(tmp_path, monkeypatch, code):
    """Issue #14: a full disk (ENOSPC) or a permission error while writing the run's files is one line."""
    import vehicle_assist.io.results as results

    def fail(path, data):
        raise OSError(code, os.strerror(code), str(path))

    monkeypatch.setattr(results, "atomic_write_bytes", fail)
    out = tmp_path / "out"
    one_line(invoke("run", "truck_11deg_late_release", *SHORT, "--out", out), "cannot write results", os.strerror(code))


def test_full_disk_during_a_sweep_keeps_finished_parts(tmp_path, monkeypatch):
    """Issue #14: ENOSPC in the second part of a sweep is one line; the first part stays intact and a
    later resume (disk freed) reuses it."""
    import vehicle_assist.scenarios.sweep as sweep_mod

    real = sweep_mod.pq.write_table
    calls = []

    def write(table, where, *a, **k):
        calls.append(where)
        if len(calls) == 2:
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(where))
        return real(table, where, *a, **k)

    monkeypatch.setattr(sweep_mod.pq, "write_table", write)
    out = tmp_path / "sw"
    args = ["sweep", "truck_11deg_late_release", "--grid", "run.seed=1,2", *SHORT, "--chunk", "1", "--out", out]
    one_line(invoke(*args), "No space left on device")
    part0 = out / "parts" / "part-00000.parquet"
    stamp = part0.stat().st_mtime_ns
    assert pq.read_table(part0).num_rows == 1 and not (out / "parts" / "part-00001.parquet").exists()
    monkeypatch.setattr(sweep_mod.pq, "write_table", real)
    res = invoke(*args)
    assert res.exit_code == 0, res.stderr
    assert part0.stat().st_mtime_ns == stamp
    assert pq.read_table(out / "sweep.parquet").num_rows == 2


# ------------------------------------------------------------------------------------------ resume and lock
SWEEP = ["--grid", "vehicle.body.mass_kg=13000,20000", *SHORT, "--chunk", "1"]


def test_resume_after_the_scenario_file_was_edited_is_refused(tmp_path):
    """Issue #14 (2,000 of 6,000 rows were stale): a resume after the scenario file changed is refused,
    naming the scenario file and the hashes; the old result is untouched."""
    path = scenario_copy(tmp_path)
    out = tmp_path / "sw"
    assert invoke("sweep", path, *SWEEP, "--out", out).exit_code == 0
    before = (out / "sweep.parquet").read_bytes()
    path.write_text(path.read_text().replace("slope_deg = 11", "slope_deg = 12", 1))
    one_line(invoke("sweep", path, *SWEEP, "--out", out), "the scenario file", "scenario_hash", "stale")
    assert (out / "sweep.parquet").read_bytes() == before


def test_resume_after_the_vehicle_file_was_edited_is_refused(tmp_path):
    """Issue #14: the parameter hash of the resolved vehicle is part of the resume check."""
    vehicle = tmp_path / "truck.toml"
    vehicle.write_text(shipped("vehicles")["heavy_amt_truck_empty"].read_text(encoding="utf-8"))
    path = scenario_copy(tmp_path, 'base = "heavy_amt_truck_empty"', 'base = "truck.toml"')
    out = tmp_path / "sw"
    assert invoke("sweep", path, "--grid", "run.seed=1,2", *SHORT, "--out", out).exit_code == 0
    vehicle.write_text(vehicle.read_text().replace("drag_area_m2 = ", "drag_area_m2 = 1", 1))
    one_line(invoke("sweep", path, "--grid", "run.seed=1,2", *SHORT, "--out", out), "vehicle parameters", "parameter_hash")


def test_sweep_record_holds_hashes_and_version(tmp_path):
    """Issue #14: sweep.json records scenario hash, parameter hash and package version (and source digest)."""
    out = tmp_path / "sw"
    assert invoke("sweep", "truck_11deg_late_release", *SWEEP, "--out", out).exit_code == 0
    record = json.loads((out / "sweep.json").read_text())
    assert {"scenario_hash", "parameter_hash", "package_version", "package_source"} <= set(record)
    assert not (out / OutputLock.NAME).exists(), "lock left behind after a finished sweep"


def test_a_second_sweep_into_a_locked_directory_is_refused(tmp_path):
    """Issue #14: while a live process holds OUT's lock, another sweep gets one line naming it."""
    out = tmp_path / "sw"
    out.mkdir()
    (out / OutputLock.NAME).write_text(f"{os.getpid()} {os.uname().nodename}\n")
    one_line(invoke("sweep", "truck_11deg_late_release", *SWEEP, "--out", out), f"process {os.getpid()}", "use another --out")
    assert not (out / "sweep.json").exists()


def test_a_stale_lock_of_a_dead_process_is_taken_over(tmp_path):
    """Issue #14: a lock left by a process that no longer exists does not block the sweep."""
    dead = subprocess.Popen([sys.executable, "-c", "pass"])
    dead.wait()
    out = tmp_path / "sw"
    out.mkdir()
    (out / OutputLock.NAME).write_text(f"{dead.pid} {os.uname().nodename}\n")
    res = invoke("sweep", "truck_11deg_late_release", *SWEEP, "--out", out)
    assert res.exit_code == 0, res.stderr
    assert pq.read_table(out / "sweep.parquet").num_rows == 2 and not (out / OutputLock.NAME).exists()


def test_corrupt_sweep_record_is_one_line(tmp_path):
    """Issue #14: a corrupt sweep.json crashes no more: one line telling to delete it or use another --out."""
    out = tmp_path / "sw"
    out.mkdir()
    (out / "sweep.json").write_text("{not json")
    one_line(invoke("sweep", "truck_11deg_late_release", *SWEEP, "--out", out), "sweep.json", "corrupt")


def test_corrupt_part_is_recomputed(tmp_path):
    """Issue #14: a damaged part file is reported and recomputed; the merged result equals a clean run."""
    out = tmp_path / "sw"
    assert invoke("sweep", "truck_11deg_late_release", *SWEEP, "--out", out).exit_code == 0
    clean = pq.read_table(out / "sweep.parquet").to_pandas()
    (out / "parts" / "part-00001.parquet").write_bytes(b"PAR1 garbage")
    res = invoke("sweep", "truck_11deg_late_release", *SWEEP, "--out", out)
    assert res.exit_code == 0, res.stderr
    assert "part-00001.parquet: unreadable" in res.stdout and "recomputing" in res.stdout
    assert pq.read_table(out / "sweep.parquet").to_pandas().equals(clean)


# ------------------------------------------------------------------------------------------ sweep options
@pytest.mark.parametrize(("option", "fragment"), [
    (["--workers", "-1"], "--workers -1"), (["--workers", "100000"], "--workers 100000"),
    (["--chunk", "0"], "--chunk 0"), (["--chunk", "-3"], "--chunk -3"),
    (["--grid", "vehicle.base=heavy_amt_truck_full,compact_ev"], "a sweep runs one layout"),
    (["--grid", "run.seed=3,4"], "given twice"),
])
def test_bad_sweep_options_leave_nothing_behind(tmp_path, option, fragment):
    """Issue #14: bad --workers/--chunk, a grid over vehicle.base across layouts and a duplicate axis are one
    line; neither sweep.json nor parts/ is left behind (OUT is not even created)."""
    out = tmp_path / "sw"
    one_line(invoke("sweep", "truck_11deg_late_release", "--grid", "run.seed=1,2", *option, "--out", out), fragment)
    assert not out.exists()


# ------------------------------------------------------------------------------------------ resources
def test_huge_grid_is_refused_with_an_estimate_unless_yes(tmp_path):
    """Issue #14 (a 1000x1000 grid started a 50-minute job): the estimate is shown and the sweep refused
    past 10 minutes without --yes; nothing is written."""
    values = ",".join(str(13000 + i) for i in range(1000))
    out = tmp_path / "sw"
    line = one_line(invoke("sweep", "truck_11deg_late_release", "--grid", f"vehicle.body.mass_kg={values}",
                           "--grid", f"vehicle.body.drag_area_m2={','.join(str(5 + i / 1000) for i in range(1000))}", "--out", out),
                    "sweep of 1000000 variants", "wall time", "--yes")
    assert " min" in line or " h" in line
    assert not out.exists()


@pytest.mark.parametrize(("sets", "fragment"), [
    (["run.duration_s=3600", "run.plant_step_s=1e-5", "run.record_period_s=1e-5", "run.controller_period_s=1e-4"], "memory"),
    (["run.duration_s=3600", "run.record_period_s=1e-3"], "memory"),
])
def test_huge_run_is_refused_before_it_starts(tmp_path, sets, fragment):
    """Issue #14 (duration x step combinations asked for 102 GiB): estimated and refused, nothing written."""
    out = tmp_path / "out"
    one_line(invoke("run", "truck_11deg_late_release", *[a for s in sets for a in ("--set", s)], "--out", out), fragment)
    assert not out.exists()


# ------------------------------------------------------------------------------------------ markup and escapes
@pytest.mark.parametrize("name", ["[/]x", "[bold red]boom[/]", "a\x1b[2Jb", "t\x1b]0;pwned\x07", "c\x1b]52;c;aGk=\x07", "\u202eevil"])
def test_user_text_is_printed_plain(tmp_path, name):
    """Issue #14: a scenario name with Rich markup or ESC/OSC sequences is printed as plain, visible text by
    `check` (no MarkupError, no markup rendered, no raw control character)."""
    path = scenario_copy(tmp_path, 'name = "truck_11deg_late_release"', f"name = {json.dumps(name)}")
    res = invoke("check", path)
    assert res.exit_code == 0, (res.stdout, res.stderr, res.exception)
    assert not _control(res.stdout) and "\u202e" not in res.stdout, repr(res.stdout)
    if name.startswith("["):
        assert name in res.stdout


@pytest.mark.parametrize("path_text", ["[/]x.toml", "[bold]y[/bold].toml", "z\x1b[2J.toml"])
def test_markup_or_escapes_in_a_file_name_are_plain_in_the_error(tmp_path, path_text):
    """Issue #14: a (missing) file whose name holds markup or an ESC sequence gives one plain error line."""
    line = one_line(invoke("check", tmp_path / path_text), "file not found")
    assert "\\x1b" in line or "[" in line


def test_markup_in_an_existing_file_path(tmp_path):
    """Issue #14: an existing scenario under a directory named '[' (path '[/]x.toml') loads and prints plainly."""
    path = scenario_copy(tmp_path, name="[/]x.toml")
    res = invoke("check", path)
    assert res.exit_code == 0, (res.stderr, res.exception)
    bad = scenario_copy(tmp_path, "slope_deg = 11", "slope_deg = 95", name="[/]bad.toml")
    one_line(invoke("check", bad), str(bad), "road.slope_deg")


def test_escape_in_an_unknown_key_is_visible_not_emitted(tmp_path):
    """Issue #14: a key holding an ESC sequence appears escaped in the error line."""
    path = scenario_copy(tmp_path, "slope_deg = 11", '"slope\\u001b[2J" = 11')
    one_line(invoke("check", path), "slope\\x1b[2J")


def test_mathtext_and_escapes_in_the_name_do_not_break_the_plot(tmp_path):
    """Issue #14 (`cost $x^$` crashed the plot after trace and metrics were written): the run writes all four
    files and the title is drawn as plain text."""
    path = scenario_copy(tmp_path, 'name = "truck_11deg_late_release"', 'name = "cost $x^$ \\u001b[2J"')
    out = tmp_path / "out"
    res = invoke("run", path, *SHORT, "--out", out)
    assert res.exit_code in (0, 1), (res.stderr, res.exception)
    assert sorted(p.name for p in out.iterdir()) == ["metrics.json", "overview.png", "trace.csv", "trace.parquet", "trace.units.json"]


def test_plot_titles_take_any_text(tmp_path):
    """Issue #14: every figure function accepts titles with mathtext, markup and control characters."""
    import numpy as np

    from vehicle_assist.core.trace import Trace
    from vehicle_assist.report.plots import FIGURES

    trace = Trace({"time_s": np.linspace(0, 1, 11), "speed_mps": np.zeros(11)})
    for title in ["$x^$", "$\\frac{", "a\x1b]0;t\x07b", "[/]"]:
        for name, figure in [(k, FIGURES[k]) for k in ("overview", "forces", "hill_start")]:
            assert figure(trace, tmp_path / f"{name}.png", title).read_bytes()[:4] == b"\x89PNG"


def test_html_page_escapes_control_characters(tmp_path):
    """Issue #14: text on the reproduce page is HTML-escaped and control characters are visible escapes."""
    from vehicle_assist.report.html import write_reproduce_page

    entry = {"paper": "0<script>", "scenario": "a\x1b[2Jb", "criterion": "c", "value": 1.0, "unit": "m", "bound": "<= 1", "pass": True}
    page = write_reproduce_page([entry], [], tmp_path / "index.html", "t\x07").read_text()
    assert "<script>" not in page and "\x1b" not in page and "\x07" not in page and "a\\x1b[2Jb" in page


# ------------------------------------------------------------------------------------------ show and paths
@pytest.mark.parametrize("arg", ["/etc/shadow", "/proc/self/environ", "a" * 5000 + ".toml", "/dev/zero", "x\x00.toml"])
def test_show_and_check_refuse_non_toml_and_bad_paths(arg):
    """Issue #14: show/check on system files, /dev/zero, an over-long path or a NUL give one line, read nothing."""
    for command in ("check", "show"):
        one_line(invoke(command, arg))


# ------------------------------------------------------------------------------------------ read-only install
def test_unwritable_compile_cache_falls_back_with_a_warning(tmp_path):
    """Issue #14: with the cache home not writable, the package picks a writable temporary cache and says so
    (one warning line); `check` succeeds. (/proc cannot be written even by root.)"""
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"}
    env.update(ENV, XDG_CACHE_HOME="/proc/vehicle-assist-cache")
    res = subprocess.run([sys.executable, "-c", "import os, vehicle_assist, numba; print(numba.config.CACHE_DIR); "
                          "from vehicle_assist.cli import main; import sys; sys.argv=['va', 'check', 'truck_11deg_late_release']; main()"],
                         env=env, capture_output=True, text=True, timeout=300, cwd=tmp_path)
    assert res.returncode == 0, res.stderr
    cache_dir, ok = res.stdout.splitlines()[:2]
    assert not cache_dir.startswith("/proc") and os.access(cache_dir, os.W_OK)
    assert ok.startswith("ok: ")
    assert "warning: compile cache" in res.stderr and "not writable" in res.stderr


def test_api_simulate_refuses_a_run_that_cannot_fit_in_memory():
    """Issue #14 (102 GiB runs): the Python API refuses too, before allocating, when the estimate exceeds the
    machine's memory (reference: 3.6e8 trace rows of >= 200 bytes are > 60 GiB on any machine here)."""
    import vehicle_assist as va
    from vehicle_assist.scenarios.errors import InputError
    from vehicle_assist.scenarios.guards import physical_memory

    sc = va.load_scenario("truck_11deg_late_release", ["run.duration_s=3600", "run.plant_step_s=1e-5",
                                                       "run.record_period_s=1e-5", "run.controller_period_s=1e-4"])
    if (physical_memory() or 0) > 1 << 40:
        pytest.skip("machine with more than 1 TiB of memory")
    with pytest.raises(InputError, match="cannot run"):
        va.simulate(sc)


# --- reviewer (issue #14 follow-up): commands added since (falsify, study, r139) and user envelope files ---
@pytest.mark.parametrize("cmd", [
    ["falsify", "hill_start_amt", "-r", "hill_start_amt.no_rollback", "--budget", "2"],
    ["study", "hill_start_amt", "-r", "hill_start_amt.no_rollback", "--samples", "2"],
    ["r139"],
])
@pytest.mark.parametrize("bad", ["/", "file", "file/sub"])
def test_verification_commands_check_out_first(tmp_path, monkeypatch, cmd, bad):
    """Before: `falsify/study/r139 --out /` ran the whole search and wrote falsify.json, coverage_*.png and
    r139.json into the file-system root (as root). Reference: the --out rule of docs/scenarios.md."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "file").write_text("x")
    res = invoke(*cmd, "--out", bad)
    one_line(res, "--out")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["file"]


def test_envelope_file_fifo_refused(tmp_path):
    """Before: `falsify FIFO.toml` blocked forever (and /dev/zero read without bound)."""
    fifo = tmp_path / "env.toml"
    os.mkfifo(fifo)
    res = invoke("falsify", fifo, "-r", "hill_start_amt.no_rollback", "--budget", "2", "--out", tmp_path / "o")
    one_line(res, "not a regular file")
    res = invoke("envelope", "/dev/zero")
    assert res.exit_code == 2 and "Traceback" not in res.stdout + res.stderr
    assert not (tmp_path / "o").exists()


def test_study_output_checked_before_coverage(tmp_path):
    """Before: `study --sensitivity 2 --output foo` ran and wrote the whole coverage study, then failed."""
    res = invoke("study", "hill_start_amt", "-r", "hill_start_amt.no_rollback", "--samples", "2",
                 "--sensitivity", "2", "--output", "foo", "--out", tmp_path / "st")
    one_line(res, "--output", "foo")
    assert not (tmp_path / "st").exists()


def test_falsify_refuses_a_batch_that_cannot_fit(tmp_path):
    """Before: `falsify --set run.plant_step_s=1e-5 --set run.record_period_s=1e-5` started a batch of 8 runs of
    up to the envelope's 120 s (about 180 GiB of trace buffers). Reference: the size rule of docs/scenarios.md."""
    res = invoke("falsify", "hill_start_amt", "-r", "hill_start_amt.no_rollback", "--budget", "2",
                 "--set", "run.plant_step_s=1e-5", "--set", "run.record_period_s=1e-5", "--out", tmp_path / "o")
    one_line(res, "memory")
    assert not (tmp_path / "o").exists()


def test_study_refuses_runs_that_cannot_fit(tmp_path):
    res = invoke("study", "hill_start_amt", "-r", "hill_start_amt.no_rollback", "--samples", "2",
                 "--set", "run.plant_step_s=1e-5", "--set", "run.record_period_s=1e-5", "--out", tmp_path / "o")
    one_line(res, "memory")
    assert not (tmp_path / "o").exists()
