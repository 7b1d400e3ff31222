"""The distributed backend: sweeps, envelope studies and falsification on dask.distributed.

Where the runs go (``--scheduler`` on ``sweep``, ``falsify`` and ``study``, else ``$VEHICLE_ASSIST_SCHEDULER``):

* ``tcp://host:8786`` (any dask scheduler address): connect to that cluster (timeout ``CONNECT_TIMEOUT_S``);
  its workers must run the same vehicle-assist (version and source digest are checked before anything runs,
  so the results are the local path's, bitwise) and see the scenario's and vehicle's files;
* ``local``: a ``LocalCluster`` of one single-threaded worker process per core (``--workers`` processes);
* ``threads``: this process's thread pool (the path of ``simulate_batch``), whatever the size;
* nothing: ``local`` for a large job (at least ``LARGE_RUNS`` simulations, dask installed, more than one
  core), the thread pool otherwise. Why 20,000: a local cluster costs ~3-5 s before the first result (two
  worker processes spawned, the package and the cached kernels loaded in each) and gains what the thread
  pool loses to the GIL (variant building, metrics and Python glue hold it: ~25-30 % of a batch's CPU,
  see docs/engine.md), i.e. ~0.4 ms of wall time per variant on 2 cores; it pays from ~10,000 variants on.
  Below, the threads are as fast and start at once.

The client never holds the whole job: work is cut into tasks (a sweep part of ``chunk`` variants, a block
of points) that are submitted lazily with at most ``window`` in flight; a worker builds its variants
from the base scenario (sent once) and the grid indices, simulates them with ``simulate_batch`` and sends
back one small table. The sweep writes each part (atomically) as it arrives, so a killed client resumes;
a killed worker's tasks are rerun by the scheduler (up to ``distributed.scheduler.allowed-failures``).

dask is optional (``pip install 'vehicle-assist[dist]'``); without it, asking for a scheduler is a one-line
error and the automatic choice stays on threads.
"""
from __future__ import annotations

import contextlib
import os
import time
import warnings
from typing import Any, Callable, Iterable, Iterator

from vehicle_assist.scenarios.errors import InputError, plain

ENV_VAR = "VEHICLE_ASSIST_SCHEDULER"
LARGE_RUNS = 20_000
CONNECT_TIMEOUT_S = 10.0  # connecting to a scheduler and waiting for its first worker; $VEHICLE_ASSIST_CONNECT_TIMEOUT_S
EXTRA_HINT = "pip install 'vehicle-assist[dist]' (or: make setup)"

_active: "Backend | None" = None


def connect_timeout_s() -> float:
    text = os.environ.get("VEHICLE_ASSIST_CONNECT_TIMEOUT_S", "")
    try:
        value = float(text) if text.strip() else CONNECT_TIMEOUT_S
    except ValueError:
        raise InputError(f"$VEHICLE_ASSIST_CONNECT_TIMEOUT_S={plain(text)}: give seconds, e.g. 10") from None
    if not 0 < value <= 3600:
        raise InputError(f"$VEHICLE_ASSIST_CONNECT_TIMEOUT_S={plain(text)}: give 0 < seconds <= 3600")
    return value


def active() -> "Backend | None":
    """The backend of the running command (None: run in this process). Always None inside a worker."""
    return _active


def available() -> bool:
    try:
        import distributed  # noqa: F401
    except ImportError:
        return False
    return True


def requested(scheduler: str | None) -> tuple[str, str]:
    """(value, where it came from): the option if given, else the environment variable, else ''."""
    if scheduler is not None and scheduler.strip():
        return scheduler.strip(), "--scheduler"
    env = os.environ.get(ENV_VAR, "").strip()
    return (env, f"${ENV_VAR}") if env else ("", "")


def choose(scheduler: str | None, n_runs: int) -> str | None:
    """'local', a scheduler address, or None (this process's threads); see the module doc."""
    value, where = requested(scheduler)
    if value.lower() == "threads":
        return None
    if value:
        if not available():
            raise InputError(f"{where} {plain(value)}: the distributed backend needs dask.distributed, which is not "
                             f"installed: {EXTRA_HINT}")
        if value.lower() == "local":
            return "local"
        if "://" not in value and ":" not in value:
            raise InputError(f"{where} {plain(value)}: give a dask scheduler address such as tcp://host:8786, "
                             "'local' (a cluster of processes on this machine) or 'threads'")
        return value
    if n_runs >= LARGE_RUNS and (os.cpu_count() or 1) > 1 and available():
        return "local"
    return None


# ------------------------------------------------------------------------------------------ identity
def identity() -> dict:
    """What must match between the client and every worker for bitwise-identical results."""
    import numba
    import numpy

    import vehicle_assist
    from vehicle_assist.scenarios.sweep import _package_source_digest

    return {"vehicle_assist": vehicle_assist.__version__, "source": _package_source_digest(),
            "numpy": numpy.__version__, "numba": numba.__version__}


def _warm(base) -> None:
    """Compile (or load) the base layout's kernel in this process, so the cache on disk is written once
    before worker processes start and each of them only loads it."""
    from vehicle_assist.scenarios.runner import simulate, simulate_batch

    short = base.with_sets("run.duration_s=0.1")
    simulate(short, requirements=False)
    simulate_batch([short, short], workers=1)  # the batch path compiles its own specialisations (2-D metrics)


class Backend:
    """A dask client (and, for ``local``, its LocalCluster) for the duration of a ``with`` block."""

    def __init__(self, target: str, workers: int | None = None, say: Callable[[str], None] | None = None):
        self.target = target
        self.workers = workers
        self.say = say
        self.client = None
        self.cluster = None
        self.n_threads = 1

    def describe(self) -> str:
        where = "a local cluster" if self.cluster is not None else f"the dask scheduler at {self.target}"
        return f"{where} ({self.n_threads} worker thread{'s' if self.n_threads != 1 else ''})"

    def __enter__(self) -> "Backend":
        global _active
        import logging

        from distributed import Client, LocalCluster

        # a lost worker or a closed connection is logged by distributed at WARNING/ERROR with tracebacks:
        # the command reports what matters itself
        for name in ("distributed", "distributed.nanny", "distributed.scheduler", "distributed.worker",
                     "distributed.core", "distributed.client", "tornado"):
            logging.getLogger(name).setLevel(logging.CRITICAL)
        timeout = connect_timeout_s()
        try:
            if self.target == "local":
                n = self.workers or (os.cpu_count() or 1)
                env = {"OPENBLAS_NUM_THREADS": "1", "NUMBA_CACHE_DIR": os.environ.get("NUMBA_CACHE_DIR", "")}
                with warnings.catch_warnings():  # "port 8787 in use, dashboard elsewhere": not for the user
                    warnings.simplefilter("ignore")
                    self.cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=":0",
                                                silence_logs=logging.CRITICAL, env={k: v for k, v in env.items() if v})
                self.client = Client(self.cluster, timeout=timeout)
            else:
                self.client = Client(self.target, timeout=timeout)
        except InputError:
            self.close()
            raise
        except Exception as exc:  # OSError (unreachable, timeout), ValueError (bad address), a protocol error
            self.close()
            what = str(exc).splitlines()[0] if str(exc) else exc.__class__.__name__
            if self.target == "local":
                raise InputError(f"cannot start a local dask cluster: {plain(what)[:200]} (a script that uses it "
                                 "needs an 'if __name__ == \"__main__\":' guard: its workers are spawned)") from None
            raise InputError(f"cannot connect to the dask scheduler at {plain(self.target)} within "
                             f"{timeout:g} s: {plain(what)[:200]}") from None
        try:
            self._check_workers()
        except BaseException:
            self.close()
            raise
        _active = self
        return self

    def _check_workers(self) -> None:
        timeout = connect_timeout_s()
        try:
            self.client.wait_for_workers(1, timeout=max(timeout, 30.0))  # a loaded machine starts workers slowly
        except Exception:
            raise InputError(f"the dask scheduler at {plain(self.target)} has no worker (none joined within "
                             f"{max(timeout, 30.0):g} s); start some with: dask worker {plain(self.target)}") from None
        try:
            self.client.get_versions(check=True)
        except Exception as exc:
            raise InputError(f"the dask cluster at {plain(self.target)} runs other versions than this client: "
                             f"{plain(str(exc).splitlines()[0] if str(exc) else exc.__class__.__name__)[:200]}") from None
        mine = identity()
        try:
            theirs = self.client.run(identity)
        except Exception as exc:
            raise InputError(f"the workers at {plain(self.target)} cannot run vehicle-assist "
                             f"({exc.__class__.__name__}: {plain(str(exc))[:120]}); install vehicle-assist "
                             f"{mine['vehicle_assist']} with the [dist] extra on them") from None
        if self.cluster is not None:  # processes spawned from this install: the same files (edits while it runs aside)
            mine.pop("source")
            theirs = {a: {k: v for k, v in i.items() if k != "source"} for a, i in theirs.items()}
        for addr, ident in theirs.items():
            if ident != mine:
                diff = ", ".join(f"{k} {ident.get(k)} != {v}" for k, v in mine.items() if ident.get(k) != v)
                raise InputError(f"worker {plain(addr)} runs another vehicle-assist than this client ({diff}); "
                                 "results would not be the local ones; install the same version there")
        self.n_threads = max(1, sum(self.client.nthreads().values()))

    def close(self) -> None:
        with contextlib.suppress(Exception):
            if self.client is not None:
                self.client.close(timeout=5)
        with contextlib.suppress(Exception):
            if self.cluster is not None:
                self.cluster.close(timeout=10)
        self.client = self.cluster = None

    def __exit__(self, *exc) -> None:
        global _active
        _active = None
        self.close()

    # -------------------------------------------------------------------------------------- running
    def scatter(self, obj: Any):
        return self.client.scatter(obj, broadcast=True, hash=False)

    def imap_unordered(self, fn: Callable, args: Iterable[tuple], window: int | None = None,
                       key_prefix: str = "vehicle-assist") -> Iterator[Any]:
        """``fn(*a)`` for each ``a`` of ``args`` on the cluster, results in completion order; ``args`` is
        consumed lazily and at most ``window`` tasks (default: 2 per worker thread) are in flight."""
        from distributed import as_completed

        window = window or 2 * self.n_threads
        it = iter(args)
        pending = as_completed()
        stamp = f"{key_prefix}-{os.getpid()}-{time.monotonic_ns()}"

        def submit(i: int) -> bool:
            try:
                a = next(it)
            except StopIteration:
                return False
            pending.add(self.client.submit(fn, *a, key=f"{stamp}-{i}", pure=False, retries=0))
            return True

        n = 0
        while n < window and submit(n):
            n += 1
        for fut in pending:
            try:
                result = fut.result()
            except Exception as exc:
                if exc.__class__.__name__ == "KilledWorker":
                    raise InputError(f"a task was lost with its worker repeatedly (distributed.scheduler.allowed-failures) ({plain(str(exc))[:160]}); "
                                     "the cluster is unstable or out of memory; run again to resume") from None
                raise
            finally:
                fut.release()
            yield result
            if submit(n):
                n += 1

    def run_blocks(self, fn: Callable, blocks: list, *shared) -> list:
        """``[fn(*shared, block) for block in blocks]`` on the cluster, in order (``shared`` sent once)."""
        shared_f = [self.scatter(s) for s in shared]
        out: dict[int, Any] = {}
        for i, r in self.imap_unordered(_indexed, ((fn, i, *shared_f, b) for i, b in enumerate(blocks))):
            out[i] = r
        return [out[i] for i in range(len(blocks))]

    # ------------------------------------------------------------------------- verification hooks
    def evaluate_points(self, env, req, points: list[dict]) -> tuple[list, list, list]:
        """``falsify.evaluate_points`` with the points split into one block per worker thread."""
        if not points:
            return [], [], []
        k = max(1, -(-len(points) // self.n_threads))
        blocks = [points[i:i + k] for i in range(0, len(points), k)]
        robs, mets, bases = [], [], []
        for r, m, b in self.run_blocks(_evaluate_block, blocks, env, req):
            robs += r
            mets += m
            bases += b
        return robs, mets, bases

    def run_points(self, env, points: list[dict], baseline: bool, chunk: int, progress=None) -> tuple[list, list]:
        """``study.run_points``: each chunk of points (with its twins) one task, the same chunks as locally."""
        blocks = [points[i:i + chunk] for i in range(0, len(points), chunk)]
        env_f = self.scatter(env)
        out: dict[int, tuple] = {}
        args = ((_run_points_block, i, env_f, baseline, chunk, b) for i, b in enumerate(blocks))
        for i, r in self.imap_unordered(_indexed, args):
            out[i] = r
            if progress is not None:
                progress(len(blocks[i]))
        assisted, base = [], []
        for i in range(len(blocks)):
            assisted += out[i][0]
            base += out[i][1]
        return assisted, base


def _indexed(fn, i, *args):
    return i, fn(*args)


def _evaluate_block(env, req, points):
    from vehicle_assist.verification.falsify import evaluate_points

    return evaluate_points(env, req, points, workers=1)


def _run_points_block(env, baseline, chunk, points):
    from vehicle_assist.verification.study import run_points

    return run_points(env, points, baseline=baseline, chunk=chunk)


@contextlib.contextmanager
def session(scheduler: str | None, n_runs: int, workers: int | None = None, say: Callable[[str], None] | None = None,
            warm=None):
    """Run the ``with`` block on the backend ``choose(scheduler, n_runs)`` picks (yields it, or None for
    this process's threads). ``warm``: a scenario whose kernel is compiled here first (local cluster)."""
    target = choose(scheduler, n_runs)
    if target is None:
        yield None
        return
    if target == "local" and warm is not None:
        _warm(warm)
    backend = Backend(target, workers=workers, say=say)
    with backend:
        if say is not None:
            auto = "" if requested(scheduler)[0] else f" (a job of {n_runs} runs >= {LARGE_RUNS}; --scheduler threads keeps it here)"
            say(f"running on {backend.describe()}{auto}")
        yield backend
