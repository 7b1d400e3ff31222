"""The numba compile cache of this package: one directory per version of the package source.

numba keys a cached function on its own file only: a kernel that calls a controller in another file keeps
running the old controller from the cache after the controller is edited. Keying the whole cache on a hash
of every source file of the package makes any edit recompile everything (hashing ~50 files takes ~2 ms).

``import vehicle_assist`` only points numba at that directory (``NUMBA_CACHE_DIR``, unless the caller set a
writable one); deleting old cache versions (:func:`prune_stale`) happens when a run starts, not at import.
"""
from __future__ import annotations

import hashlib
import os
import shutil
import sys
import tempfile
import time
from pathlib import Path

KEEP = 4  # older source versions kept besides the current one
# a version used (its directory touched) within this time is never deleted, whatever KEEP says: other checkouts of the
# package (git worktrees, a second venv) run from their own versions at the same time, and deleting a directory numba is
# compiling into or loading from crashes that process. Assumed: one day; a run starts by touching its own version.
MIN_IDLE_S = 86400.0


def source_digest() -> str:
    root = Path(__file__).resolve().parent
    digest = hashlib.sha256()
    for path in sorted(root.rglob("*.py")):
        digest.update(path.relative_to(root).as_posix().encode())
        digest.update(path.read_bytes())
    return digest.hexdigest()[:16]


def cache_parent() -> Path:
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "vehicle-assist" / "numba"


def writable(directory) -> bool:
    """True if ``directory`` exists or can be created and a file can be created in it."""
    try:
        os.makedirs(directory, exist_ok=True)
        with tempfile.TemporaryFile(dir=directory):
            pass
        return True
    except OSError:
        return False


def cache_dir() -> str:
    """The compile-cache directory for this source version (created; a temporary one if home is read-only)."""
    digest = source_digest()
    target = cache_parent() / digest
    if writable(target):
        return str(target)
    uid = getattr(os, "getuid", lambda: "user")()
    fallback = Path(tempfile.gettempdir()) / f"vehicle-assist-numba-{uid}" / digest
    if writable(fallback):
        print(f"warning: compile cache {target} is not writable; using {fallback}", file=sys.stderr)
        return str(fallback)
    fallback = Path(tempfile.mkdtemp(prefix="vehicle-assist-numba-"))
    print(f"warning: compile cache {target} is not writable; using {fallback} (compiled code is not kept)", file=sys.stderr)
    return str(fallback)


_pruned = False


def prune_stale() -> None:
    """Delete all but the ``KEEP`` newest older source versions of the cache that have not been used for
    ``MIN_IDLE_S`` (once per process; called when a run or batch starts, never at import). Only under the package's own
    cache parent directory."""
    global _pruned
    if _pruned:
        return
    _pruned = True
    parent = cache_parent()
    current = os.environ.get("NUMBA_CACHE_DIR", "")
    try:
        if not parent.is_dir():
            return
        if current and os.path.isdir(current):
            os.utime(current)  # this version is in use: other processes' prune must leave it alone
        now = time.time()
        old = sorted((d for d in parent.iterdir() if d.is_dir() and str(d) != current),
                     key=lambda d: d.stat().st_mtime, reverse=True)
        for stale in old[KEEP:]:
            if now - stale.stat().st_mtime >= MIN_IDLE_S:
                shutil.rmtree(stale, ignore_errors=True)
    except OSError:
        pass


def configure() -> None:
    """Point numba at the package's cache unless the caller set a writable ``NUMBA_CACHE_DIR``."""
    if "NUMBA_CACHE_DIR" in os.environ and writable(os.environ["NUMBA_CACHE_DIR"]):
        return
    os.environ["NUMBA_CACHE_DIR"] = cache_dir()
    if "numba" in sys.modules:  # numba already imported by the caller: set its config directly
        sys.modules["numba"].config.CACHE_DIR = os.environ["NUMBA_CACHE_DIR"]


# one scenario per shipped layout: a 0.1 s run of each compiles (or loads) its kernel, the numpy metrics' filter
# and, with a two-variant batch, the chunk call and the compiled metric twins
WARM_SCENARIOS = ("hsa_truck_full_14deg_8p0bar", "hsa_ev_5deg_paper", "hba_paper_110kph_dry", "curve_s80")


def warm(batch: bool = True) -> None:
    """Fill the compile cache for every shipped layout (``make setup`` / ``make warm``), so that a user's first
    ``vehicle-assist run`` loads compiled code instead of compiling it (~10 s)."""
    import vehicle_assist as va
    from vehicle_assist.scenarios.runner import simulate_batch

    for name in WARM_SCENARIOS:
        sc = va.load_scenario(name, ["run.duration_s=0.1"])
        va.simulate(sc)
        if batch:
            simulate_batch([sc, sc], workers=1)


if __name__ == "__main__":
    warm()
