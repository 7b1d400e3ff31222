"""The dask backend (issue #13) on a real LocalCluster of processes (2 workers x 1 thread).

References: the thread path of the same code (``--scheduler threads``) is the reference for every value,
compared bit for bit (the float64 bit patterns, so NaN == NaN only when the payloads are equal); the
resume tests use the part files' inodes and the number of parts on disk to tell a skipped part from a
recomputed one. A worker is killed by a worker plugin at the start of one task (deterministic: the task is
lost mid-run, the scheduler must rerun it elsewhere); the client is killed with SIGKILL mid-sweep.
"""
from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pyarrow.parquet as pq
import pytest

distributed = pytest.importorskip("distributed", reason="the [dist] extra (dask.distributed) is not installed")

import vehicle_assist as va  # noqa: E402
from vehicle_assist import distributed as va_dist  # noqa: E402
from vehicle_assist.scenarios.errors import InputError  # noqa: E402
from vehicle_assist.scenarios.sweep import run_sweep  # noqa: E402

SCENARIO = "truck_11deg_late_release"
SETS = ["run.duration_s=4"]
# 300 variants in 15 parts of 20
GRID = ["vehicle.body.mass_kg=" + ",".join(str(13000 + 1500 * i) for i in range(15)),
        "road.slope_deg=" + ",".join(str(4 + 0.5 * i) for i in range(20))]
CHUNK = 20
N_PARTS = 15


def assert_bitwise_equal(a_path: Path, b_path: Path) -> None:
    a, b = pq.read_table(a_path), pq.read_table(b_path)
    assert a.schema.names == b.schema.names
    assert a.num_rows == b.num_rows
    for name in a.schema.names:
        x, y = a.column(name).to_numpy(zero_copy_only=False), b.column(name).to_numpy(zero_copy_only=False)
        if x.dtype.kind == "f":
            assert np.array_equal(x.view(np.uint64), y.view(np.uint64)), f"column {name} differs"
        else:
            assert list(x) == list(y), f"column {name} differs"


@pytest.fixture(scope="module")
def cluster():
    # compile (or load) the kernel here first: the workers then only load it from the shared disk cache
    va.simulate(va.load_scenario(SCENARIO, SETS + ["run.duration_s=0.1"]), requirements=False)
    lc = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0",
                                  env={"OPENBLAS_NUM_THREADS": "1", "NUMBA_CACHE_DIR": os.environ.get("NUMBA_CACHE_DIR", "")})
    try:
        yield lc
    finally:
        lc.close()


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    """The same sweep on this process's threads."""
    out = tmp_path_factory.mktemp("threads") / "sweep"
    path, n = run_sweep(va.load_scenario(SCENARIO, SETS), GRID, out, chunk=CHUNK, scheduler="threads")
    assert n == 300
    return path


class KillOnce(distributed.WorkerPlugin):
    """Kill the worker process (SIGKILL) when it starts the task whose key ends with ``suffix``, once."""

    def __init__(self, marker: str, suffix: str, delay_s: float = 0.0):
        self.marker, self.suffix, self.delay_s = marker, suffix, delay_s

    def transition(self, key, start, finish, **kwargs):
        if finish != "executing" or not str(key).startswith("sweep-part"):
            return
        if self.delay_s:
            time.sleep(self.delay_s)
        if self.suffix and str(key).endswith(self.suffix):
            try:
                fd = os.open(self.marker, os.O_CREAT | os.O_EXCL | os.O_WRONLY)
            except FileExistsError:
                return
            os.close(fd)
            os.kill(os.getpid(), signal.SIGKILL)


def test_sweep_on_cluster_equals_threads_bitwise_and_survives_a_killed_worker(cluster, reference, tmp_path):
    """Requirement (issue #13): the sweep on a dask cluster gives the thread path's values bit for bit, and a
    worker killed while it runs a part costs only a rerun of that part."""
    import cloudpickle

    cloudpickle.register_pickle_by_value(sys.modules[__name__])
    marker = tmp_path / "killed"
    client = distributed.Client(cluster)
    try:
        pids_before = set(client.run(os.getpid).values())
        client.register_plugin(KillOnce(str(marker), "-3"), name="kill-once")
        out = tmp_path / "dist"
        path, n = run_sweep(va.load_scenario(SCENARIO, SETS), GRID, out, chunk=CHUNK, scheduler=cluster.scheduler_address)
        assert marker.exists(), "the plugin did not kill a worker: the test did not test a lost worker"
        client.wait_for_workers(2, timeout=60)
        assert set(client.run(os.getpid).values()) != pids_before, "the killed worker was not replaced"
        client.unregister_worker_plugin("kill-once")
    finally:
        client.close()
    assert n == 300
    assert len(list((out / "parts").glob("part-*.parquet"))) == N_PARTS
    assert_bitwise_equal(path, reference)
    for k in range(N_PARTS):  # every part file too, not only the merged table
        assert_bitwise_equal(out / "parts" / f"part-{k:05d}.parquet", reference.parent / "parts" / f"part-{k:05d}.parquet")


def test_killed_client_resumes_skipping_finished_parts(cluster, reference, tmp_path):
    """Requirement (issue #13): a sweep whose client process is killed (SIGKILL) resumes when run again: the
    parts written before the kill are kept (same inode: not rewritten), the rest computed, the result the
    thread path's bit for bit. Tasks are slowed to ~0.4 s each so the kill lands mid-sweep."""
    import cloudpickle

    cloudpickle.register_pickle_by_value(sys.modules[__name__])
    client = distributed.Client(cluster)
    client.register_plugin(KillOnce("", "", delay_s=0.4), name="slow")
    out = tmp_path / "dist"
    args = [sys.executable, "-m", "vehicle_assist.cli", "sweep", SCENARIO, *[a for s in SETS for a in ("--set", s)],
            *[a for g in GRID for a in ("--grid", g)], "--chunk", str(CHUNK), "--out", str(out),
            "--scheduler", cluster.scheduler_address]
    env = {**os.environ, "COLUMNS": "200", "NO_COLOR": "1", "TERM": "dumb"}
    try:
        proc = subprocess.Popen(args, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, start_new_session=True)
        deadline = time.monotonic() + 300  # a loaded machine may compile first
        parts = out / "parts"
        while time.monotonic() < deadline and len(list(parts.glob("part-*.parquet"))) < 3 and proc.poll() is None:
            time.sleep(0.05)
        os.kill(proc.pid, signal.SIGKILL)
        proc.communicate(timeout=30)
        before = {p.name: p.stat().st_ino for p in parts.glob("part-*.parquet")}
        assert 3 <= len(before) < N_PARTS, f"the kill did not land mid-sweep ({len(before)} parts)"
        assert not (out / "sweep.parquet").exists()
        res = subprocess.run(args, env=env, capture_output=True, text=True, timeout=300)
        assert res.returncode == 0, res.stderr
        assert "Traceback" not in res.stderr + res.stdout
    finally:
        client.unregister_worker_plugin("slow")
        client.close()
    after = {p.name: p.stat().st_ino for p in parts.glob("part-*.parquet")}
    assert len(after) == N_PARTS
    assert all(after[name] == ino for name, ino in before.items()), "a finished part was recomputed"
    assert_bitwise_equal(out / "sweep.parquet", reference)


def test_falsify_and_envelope_points_on_cluster_equal_threads(cluster):
    """Requirement (issue #13): falsification's batch evaluation and the envelope study's chunks give the same
    values on the cluster as on threads (bitwise)."""
    from vehicle_assist.verification.envelope import load_envelope
    from vehicle_assist.verification.falsify import evaluate_points
    from vehicle_assist.verification.requirements import get_requirement
    from vehicle_assist.verification.study import run_points

    env = load_envelope("hill_start_ehb").with_sets(["run.duration_s=4"])
    rng = np.random.default_rng(1)
    points = [env.unit_to_point(u) for u in rng.random((12, len(env.dims)))]
    req = get_requirement("hill_start_ehb.no_worse_than_no_assist")
    local = evaluate_points(env, req, points)
    local_runs = run_points(env, points[:6], chunk=4)
    with va_dist.Backend(cluster.scheduler_address) as backend:
        assert va_dist.active() is backend
        remote = evaluate_points(env, req, points)
        remote_runs = run_points(env, points[:6], chunk=4)
    assert va_dist.active() is None
    assert np.array_equal(np.array(local[0]).view(np.uint64), np.array(remote[0]).view(np.uint64))
    for a, b in zip(local[1] + local[2], remote[1] + remote[2]):
        assert a.keys() == b.keys()
        assert np.array_equal(np.array(list(a.values())).view(np.uint64), np.array(list(b.values())).view(np.uint64))
    for a, b in zip(local_runs[0] + local_runs[1], remote_runs[0] + remote_runs[1]):
        assert a.keys() == b.keys()
        assert np.array_equal(np.array(list(a.values())).view(np.uint64), np.array(list(b.values())).view(np.uint64))


# ------------------------------------------------------------------------------------- bad input, no cluster
def _cli(*args, env_extra=None, pre=""):
    env = {**os.environ, "COLUMNS": "250", "NO_COLOR": "1", "TERM": "dumb", **(env_extra or {})}
    code = f"{pre}import sys; from vehicle_assist.cli import main; sys.argv = ['vehicle-assist', *{list(args)!r}]; main()"
    return subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=120)


def _one_error_line(res) -> str:
    assert "Traceback" not in res.stderr + res.stdout, res.stderr
    assert res.returncode == 2, (res.returncode, res.stderr)
    lines = [line for line in res.stderr.splitlines() if line.strip()]
    assert len(lines) == 1 and lines[0].startswith("error: "), res.stderr
    return lines[0]


SWEEP = ["sweep", SCENARIO, "--set", "run.duration_s=1", "--grid", "vehicle.body.mass_kg=13000,20000"]


def test_unreachable_scheduler_is_one_line_exit_2_after_the_timeout(tmp_path):
    """Requirement: an address nobody listens on -> one line, exit 2, within the connect timeout; nothing written."""
    import socket

    with socket.socket() as s:  # a port that was free a moment ago (nothing listens on it)
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    t0 = time.monotonic()
    res = _cli(*SWEEP, "--out", str(tmp_path / "o"), "--scheduler", f"tcp://127.0.0.1:{port}",
               env_extra={"VEHICLE_ASSIST_CONNECT_TIMEOUT_S": "2"})
    line = _one_error_line(res)
    assert "cannot connect to the dask scheduler" in line and "within 2 s" in line
    assert time.monotonic() - t0 < 60
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize("value,fragment", [("nonsense", "give a dask scheduler address"),
                                            ("weird://host:1", "unknown address scheme")])
def test_malformed_scheduler_is_one_line_exit_2(tmp_path, value, fragment):
    res = _cli(*SWEEP, "--out", str(tmp_path / "o"), env_extra={"VEHICLE_ASSIST_SCHEDULER": value,
                                                                 "VEHICLE_ASSIST_CONNECT_TIMEOUT_S": "2"})
    assert fragment in _one_error_line(res)
    assert not (tmp_path / "o").exists()


def test_without_dask_scheduler_names_the_extra(tmp_path):
    """Requirement: without dask installed, --scheduler says which extra to install (one line, exit 2)."""
    block = "import sys; sys.modules['distributed'] = None; sys.modules['dask'] = None; "
    res = _cli(*SWEEP, "--out", str(tmp_path / "o"), "--scheduler", "tcp://127.0.0.1:8786", pre=block)
    line = _one_error_line(res)
    assert "vehicle-assist[dist]" in line
    res = _cli("falsify", "hill_start_ehb", "-r", "hill_start_ehb.no_rollback", "-n", "2", "--out", str(tmp_path / "f"),
               "--scheduler", "local", pre=block)
    assert "vehicle-assist[dist]" in _one_error_line(res)


def test_large_jobs_choose_a_local_cluster_small_ones_threads(monkeypatch):
    """The automatic choice (module doc of vehicle_assist.distributed): threads below LARGE_RUNS, a local
    cluster from there on; 'threads' and an address override it; the env var is read when no option is given."""
    monkeypatch.delenv(va_dist.ENV_VAR, raising=False)
    monkeypatch.setattr(os, "cpu_count", lambda: 2)
    assert va_dist.choose(None, va_dist.LARGE_RUNS - 1) is None
    assert va_dist.choose(None, va_dist.LARGE_RUNS) == "local"
    assert va_dist.choose("threads", 10**6) is None
    assert va_dist.choose("tcp://10.0.0.1:8786", 1) == "tcp://10.0.0.1:8786"
    monkeypatch.setenv(va_dist.ENV_VAR, "threads")
    assert va_dist.choose(None, 10**6) is None
    monkeypatch.setattr(os, "cpu_count", lambda: 1)
    monkeypatch.delenv(va_dist.ENV_VAR)
    assert va_dist.choose(None, 10**6) is None  # one core: nothing to gain from processes


class _FakeClient:
    def __init__(self, versions_error=None, ident=None):
        self.versions_error, self.ident = versions_error, ident

    def wait_for_workers(self, n, timeout):
        pass

    def get_versions(self, check):
        if self.versions_error:
            raise ValueError(self.versions_error)

    def run(self, fn):
        return {"tcp://w1:1": self.ident if self.ident is not None else fn()}

    def nthreads(self):
        return {"tcp://w1:1": 1}


def test_wrong_version_cluster_is_refused():
    """Requirement: a scheduler/worker of other dask versions, or workers with another vehicle-assist (version or
    source), are refused with one line before anything runs (results would not be bitwise the local ones)."""
    b = va_dist.Backend("tcp://sched:8786")
    b.client = _FakeClient(versions_error="Mismatched versions found\n+---+")
    with pytest.raises(InputError, match="runs other versions than this client: Mismatched versions found$"):
        b._check_workers()
    other = {**va_dist.identity(), "vehicle_assist": "0.0.1"}
    b.client = _FakeClient(ident=other)
    with pytest.raises(InputError, match=r"worker tcp://w1:1 runs another vehicle-assist .*vehicle_assist 0\.0\.1 != "):
        b._check_workers()
    b.client = _FakeClient()
    b._check_workers()
    assert b.n_threads == 1
