"""vehicle-assist: design, simulate, calibrate and verify vehicle assistance functions.

Python API::

    import vehicle_assist as va
    sc = va.load_scenario("truck_11deg_early_release", sets=["vehicle.body.mass_kg=30000"])
    result = va.simulate(sc)
    result.trace.to_pandas(); result.metrics; result.events
"""
import os as _os

# The compiled kernels use no BLAS; OpenBLAS's idle worker threads spin and steal the cores that batch
# runs need (measured: ~15 % slower batches on 2 cores). Only effective if numpy is not imported yet.
_os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")


def _numba_cache_dir() -> str:
    """A compile-cache directory per version of this package's source.

    numba keys a cached function on its own file only: a kernel that calls a controller in another file
    keeps running the old controller from the cache after the controller is edited. Keying the whole
    cache on a hash of every source file of the package makes any edit recompile everything (measured:
    hashing the ~50 files takes ~2 ms)."""
    import hashlib
    from pathlib import Path

    root = Path(__file__).resolve().parent
    digest = hashlib.sha256()
    for path in sorted(root.rglob("*.py")):
        digest.update(path.relative_to(root).as_posix().encode())
        digest.update(path.read_bytes())
    base = _os.environ.get("XDG_CACHE_HOME") or _os.path.join(_os.path.expanduser("~"), ".cache")
    parent = Path(base) / "vehicle-assist" / "numba"
    target = parent / digest.hexdigest()[:16]
    try:
        if not target.exists() and parent.is_dir():  # a new source version: keep the 4 newest older caches
            import shutil

            old = sorted((d for d in parent.iterdir() if d.is_dir()), key=lambda d: d.stat().st_mtime, reverse=True)
            for stale in old[4:]:
                shutil.rmtree(stale, ignore_errors=True)
    except OSError:
        pass
    if _writable(target):
        return str(target)
    # a read-only home or install (container, shared site-packages): a private temporary cache instead
    import sys
    import tempfile

    uid = getattr(_os, "getuid", lambda: "user")()
    fallback = Path(tempfile.gettempdir()) / f"vehicle-assist-numba-{uid}" / digest.hexdigest()[:16]
    if _writable(fallback):
        print(f"warning: compile cache {target} is not writable; using {fallback}", file=sys.stderr)
        return str(fallback)
    fallback = Path(tempfile.mkdtemp(prefix="vehicle-assist-numba-"))
    print(f"warning: compile cache {target} is not writable; using {fallback} (compiled code is not kept)", file=sys.stderr)
    return str(fallback)


def _writable(directory) -> bool:
    """True if ``directory`` exists or can be created and a file can be created in it."""
    import tempfile

    try:
        _os.makedirs(directory, exist_ok=True)
        with tempfile.TemporaryFile(dir=directory):
            pass
        return True
    except OSError:
        return False


if "NUMBA_CACHE_DIR" not in _os.environ or not _writable(_os.environ["NUMBA_CACHE_DIR"]):
    # an explicit, writable setting (benchmarks, CI) wins; an unwritable one would crash numba's cache
    _os.environ["NUMBA_CACHE_DIR"] = _numba_cache_dir()
    import sys as _sys

    if "numba" in _sys.modules:  # numba already imported by the caller: set its config directly
        _sys.modules["numba"].config.CACHE_DIR = _os.environ["NUMBA_CACHE_DIR"]

__version__ = "0.1.0"


def __getattr__(name):
    # lazy API: importing the package stays cheap (no numba compile until a run is asked for)
    if name in ("load_scenario", "load_vehicle"):
        from vehicle_assist.scenarios import loader

        return getattr(loader, name)
    if name in ("simulate", "simulate_batch"):
        from vehicle_assist.scenarios import runner

        return getattr(runner, name)
    raise AttributeError(name)


__all__ = ["load_scenario", "load_vehicle", "simulate", "simulate_batch", "__version__"]
