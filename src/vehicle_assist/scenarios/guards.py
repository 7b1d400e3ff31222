"""Guards against hostile or careless input: input files, output directories, text shown to the user,
resource estimates and the sweep lock (issue #14).

Stated bounds (each error message names the bound it hit):

* **Input files** (scenario, vehicle, ``base``): a shipped name, or a path to a regular file with the
  ``.toml`` suffix of at most :data:`MAX_INPUT_BYTES` (1 MiB; the largest shipped file is 9 kB). Paths
  longer than :data:`MAX_PATH_CHARS` characters, with a component longer than 255 bytes or holding a NUL
  are refused before the file system is asked. Files are opened non-blocking (a FIFO never blocks) and
  read with a bound (``/dev/zero`` never reads forever).
* **Nesting**: tables and arrays at most :data:`MAX_DEPTH` levels deep (the schema needs 4);
  ``base`` chains at most :data:`MAX_BASE_CHAIN` files long, cycles are named.
* **Resources**: a run or sweep estimated to need more than :data:`MAX_MEMORY_BYTES` of memory or to take
  more than :data:`MAX_SECONDS` of wall time is refused unless ``--yes`` is given; one that cannot fit in
  the machine's memory is refused even then.
* **Text**: user-derived text shown on a terminal, in a plot or on a page goes through :func:`plain`, which
  shows control characters (C0, DEL, C1 - so ESC, CSI and OSC sequences - and the bidirectional overrides)
  as visible escapes such as ``\\x1b`` instead of emitting them.
"""
from __future__ import annotations

import math
import os
import socket
import stat as stat_mod
from dataclasses import dataclass
from pathlib import Path

from vehicle_assist.scenarios.errors import InputError, plain

__all__ = ["plain", "check_path_text", "read_bounded", "toml_depth", "check_out_dir", "Estimate", "estimate_run",
           "estimate_sweep", "refuse_past_bounds", "OutputLock", "MAX_INPUT_BYTES", "MAX_DEPTH", "MAX_BASE_CHAIN",
           "MAX_MEMORY_BYTES", "MAX_SECONDS"]

MAX_INPUT_BYTES = 1 << 20
MAX_PATH_CHARS = 4096
MAX_NAME_BYTES = 255
MAX_DEPTH = 32
MAX_BASE_CHAIN = 16
MAX_MEMORY_BYTES = 2 << 30
MAX_SECONDS = 600.0
# Cost model of one variant, measured on the 2-core development machine (truck, 20 s at 1 ms: 4 ms):
# 0.2 us per plant step and core, 2 us per recorded row (metrics), 1 ms fixed (packing, checks).
SECONDS_PER_STEP = 0.2e-6
SECONDS_PER_RECORD = 2e-6
SECONDS_PER_VARIANT = 1e-3
# A single run holds the trace buffer, its channel copies, metric temporaries and the CSV text: ~8 copies.
RUN_MEMORY_FACTOR = 8
CSV_BYTES_PER_VALUE = 24


def check_path_text(text: str, what: str = "path") -> None:
    """Refuse a path that is empty, holds a NUL, or is longer than the OS allows, before using it."""
    if text == "":
        raise InputError(f"{what}: an empty path; give a file or directory name")
    if "\x00" in text:
        raise InputError(f"{what} {plain(text[:80])!r}: holds a NUL character; give a plain path")
    if len(text) > MAX_PATH_CHARS:
        raise InputError(f"{what} {plain(text[:60])!r}... is {len(text)} characters long; at most {MAX_PATH_CHARS} are allowed")
    for part in text.split("/"):
        if len(part.encode("utf-8", "surrogateescape")) > MAX_NAME_BYTES:
            raise InputError(f"{what} {plain(text[:60])!r}...: a path component is longer than {MAX_NAME_BYTES} bytes")


def read_bounded(path: Path, what: str = "") -> tuple[str, tuple]:
    """Text of a regular ``.toml`` file of at most MAX_INPUT_BYTES, and its identity (dev, inode, mtime, size).

    Opened with O_NONBLOCK so a FIFO cannot block; refused unless ``fstat`` says it is a regular file."""
    label = plain(str(path))
    check_path_text(str(path), what or "file")
    if path.suffix != ".toml":
        raise InputError(f"{label}: cannot read it (not a .toml file); give a shipped name or a path ending in .toml "
                         "(see 'vehicle-assist list')")
    flags = os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_NOCTTY", 0)
    try:
        fd = os.open(path, flags)
    except FileNotFoundError:
        raise InputError(f"{label}: file not found; give an existing file or a shipped name (see 'vehicle-assist list')") from None
    except OSError as exc:
        reason = exc.strerror or exc.__class__.__name__
        raise InputError(f"{label}: cannot read it ({reason}); give a readable UTF-8 TOML file") from None
    try:
        st = os.fstat(fd)
        if stat_mod.S_ISDIR(st.st_mode):
            raise InputError(f"{label}: cannot read it (it is a directory); give a readable UTF-8 TOML file")
        if not stat_mod.S_ISREG(st.st_mode):
            raise InputError(f"{label}: cannot read it (not a regular file); give a readable UTF-8 TOML file")
        if st.st_size > MAX_INPUT_BYTES:
            raise InputError(f"{label}: {st.st_size} bytes; input files are limited to {MAX_INPUT_BYTES} bytes (1 MiB)")
        chunks = []
        total = 0
        while True:
            try:
                data = os.read(fd, 65536)
            except OSError as exc:
                raise InputError(f"{label}: cannot read it ({exc.strerror}); give a readable UTF-8 TOML file") from None
            if not data:
                break
            total += len(data)
            if total > MAX_INPUT_BYTES:
                raise InputError(f"{label}: more than {MAX_INPUT_BYTES} bytes; input files are limited to 1 MiB")
            chunks.append(data)
    finally:
        os.close(fd)
    try:
        text = b"".join(chunks).decode("utf-8")
    except UnicodeDecodeError:
        raise InputError(f"{label}: cannot read it (UnicodeDecodeError); give a readable UTF-8 TOML file") from None
    return text, (st.st_dev, st.st_ino, st.st_mtime_ns, st.st_size)


def toml_depth(doc) -> int:
    """Nesting depth of parsed TOML (tables and arrays), computed without recursion."""
    deepest = 0
    stack = [(doc, 1)]
    while stack:
        node, depth = stack.pop()
        deepest = max(deepest, depth)
        if depth > MAX_DEPTH:
            return depth
        children = node.values() if isinstance(node, dict) else node
        for child in children:
            if isinstance(child, (dict, list)):
                stack.append((child, depth + 1))
    return deepest


def check_out_dir(text: str, option: str = "--out") -> Path:
    """Validate an output directory without creating anything: not empty, not '/', not a file, not under
    a file, and the nearest existing ancestor is a writable directory."""
    check_path_text(text, option)
    label = plain(text)
    path = Path(text)
    try:
        resolved = path.resolve()
    except (OSError, RuntimeError) as exc:
        raise InputError(f"{option} {label}: cannot resolve it ({getattr(exc, 'strerror', None) or exc}); give another directory") from None
    if resolved == Path(resolved.anchor):
        raise InputError(f"{option} {label}: refusing to write into the file-system root; give a directory of its own")
    probe = path
    while True:
        try:
            st = os.stat(probe)
        except FileNotFoundError:
            parent = probe.parent
            if parent == probe:
                raise InputError(f"{option} {label}: no existing parent directory; give another directory") from None
            probe = parent
            continue
        except NotADirectoryError:
            raise InputError(f"{option} {label}: a parent of it is a file, not a directory; give another directory") from None
        except OSError as exc:
            raise InputError(f"{option} {label}: cannot use it ({exc.strerror}); give another directory") from None
        break
    if not stat_mod.S_ISDIR(st.st_mode):
        what = "is a file" if probe == path else f"{plain(str(probe))} is a file"
        raise InputError(f"{option} {label}: {what}, not a directory; give a directory")
    if not os.access(probe, os.W_OK | os.X_OK) or not _can_create_in(probe):
        raise InputError(f"{option} {label}: {plain(str(probe))} is not writable; give a directory you can write to")
    return path


def _can_create_in(directory: Path) -> bool:
    """Create and remove an empty directory in ``directory`` (os.access is True for root on a read-only mount)."""
    import tempfile

    try:
        os.rmdir(tempfile.mkdtemp(prefix=".vehicle-assist-probe-", dir=directory))
        return True
    except OSError:
        return False


def free_bytes(path: Path) -> int | None:
    probe = path
    while not probe.exists() and probe.parent != probe:
        probe = probe.parent
    try:
        import shutil

        return shutil.disk_usage(probe).free
    except OSError:
        return None


def physical_memory() -> int | None:
    try:
        return os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (ValueError, OSError, AttributeError):
        return None


@dataclass(frozen=True)
class Estimate:
    what: str
    memory_bytes: float
    seconds: float
    disk_bytes: float = 0.0

    def describe(self) -> str:
        return f"{self.what}: about {_size(self.memory_bytes)} of memory, {_duration(self.seconds)} wall time" + (
            f", {_size(self.disk_bytes)} on disk" if self.disk_bytes else "")


def _size(n: float) -> str:
    for unit in ("B", "KiB", "MiB", "GiB", "TiB"):
        if n < 1024 or unit == "TiB":
            return f"{n:.0f} {unit}" if unit == "B" else f"{n:.1f} {unit}"
        n /= 1024
    return f"{n:.1f} TiB"


def _duration(s: float) -> str:
    if s < 60:
        return f"{s:.1f} s"
    if s < 3600:
        return f"{s / 60:.1f} min"
    return f"{s / 3600:.1f} h"


def _per_variant(sc) -> tuple[int, int, float]:
    """(records, bytes per record, seconds) of one variant."""
    from vehicle_assist.vehicles import layouts

    run = sc.model.run
    records = int(math.floor(run.duration_s / run.record_period_s + 1e-9)) + 1
    steps = run.duration_s / run.plant_step_s
    row = layouts.get(sc.layout).TRACE_DTYPE.itemsize
    return records, row, steps * SECONDS_PER_STEP + records * SECONDS_PER_RECORD + SECONDS_PER_VARIANT


def estimate_run(sc, write: bool = True) -> Estimate:
    records, row, seconds = _per_variant(sc)
    values = records * row / 8
    disk = values * (8 + CSV_BYTES_PER_VALUE) if write else 0.0
    if write:
        seconds += values * 1e-6  # CSV formatting (%.17g), measured ~1 us per value
    factor = RUN_MEMORY_FACTOR if write else 3  # without writing: buffer, channel copies, metric temporaries
    return Estimate(f"run {plain(sc.name)}", records * row * factor, seconds, disk)


def estimate_sweep(sc, n_variants: int, workers: int, chunk: int) -> Estimate:
    from vehicle_assist.scenarios.runner import BATCH_CHUNK

    records, row, seconds = _per_variant(sc)
    per_worker = min(BATCH_CHUNK, chunk) * records * row * 3  # buffer, channel views, metric temporaries
    kept = n_variants * 2000 + min(chunk, n_variants) * 20000  # combos and variant objects of one part
    return Estimate(f"sweep of {n_variants} variants", per_worker * workers + kept,
                    seconds * n_variants / max(workers, 1), n_variants * 400.0)


def refuse_past_bounds(est: Estimate, yes: bool, out: Path | None = None) -> None:
    """Refuse past MAX_MEMORY_BYTES / MAX_SECONDS unless ``yes``; refuse always if it cannot fit."""
    ram = physical_memory()
    if ram and est.memory_bytes > ram:
        raise InputError(f"{est.describe()}; this machine has {_size(ram)} of memory, so it cannot run; "
                         "shorten run.duration_s or raise run.record_period_s / run.plant_step_s")
    if out is not None and est.disk_bytes:
        free = free_bytes(out)
        if free is not None and est.disk_bytes > free:
            raise InputError(f"{est.describe()}; only {_size(free)} free under {plain(str(out))}; free space or give another --out")
    if yes:
        return
    if est.memory_bytes > MAX_MEMORY_BYTES:
        raise InputError(f"{est.describe()}; more than the {_size(MAX_MEMORY_BYTES)} allowed without --yes; "
                         "shorten run.duration_s, raise run.record_period_s, or add --yes")
    if est.seconds > MAX_SECONDS:
        raise InputError(f"{est.describe()}; longer than the {_duration(MAX_SECONDS)} allowed without --yes; "
                         "make the grid smaller or add --yes")


class OutputLock:
    """Exclusive lock of an output directory: ``OUT/.vehicle-assist.lock`` created with O_EXCL, holding
    ``pid host``. A lock whose process is gone (same host) is stale and taken over; a live one is an
    InputError naming the pid. The lock file is removed on exit."""

    NAME = ".vehicle-assist.lock"

    def __init__(self, directory: Path):
        self.path = Path(directory) / self.NAME
        self.held = False

    def _owner(self) -> tuple[int, str] | None:
        try:
            pid_text, host = self.path.read_text(encoding="utf-8").split()[:2]
            return int(pid_text), host
        except (OSError, ValueError):
            return None

    def acquire(self) -> "OutputLock":
        me = f"{os.getpid()} {socket.gethostname()}\n".encode()
        for _ in range(3):
            try:
                fd = os.open(self.path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o644)
            except FileExistsError:
                owner = self._owner()
                if owner is not None and owner[1] == socket.gethostname() and not _alive(owner[0]):
                    # stale: move it aside under a unique name (two breakers cannot both win), then retry
                    aside = self.path.with_name(f"{self.NAME}.stale.{os.getpid()}")
                    try:
                        os.replace(self.path, aside)
                        os.remove(aside)
                    except OSError:
                        pass
                    continue
                who = f"process {owner[0]} on {plain(owner[1])}" if owner else "another process"
                raise InputError(f"{plain(str(self.path.parent))}: {who} is writing a sweep here (lock file {self.NAME}); "
                                 "wait for it to finish or use another --out") from None
            except OSError as exc:
                raise InputError(f"{plain(str(self.path.parent))}: cannot create the lock file ({exc.strerror}); give another --out") from None
            with os.fdopen(fd, "wb") as handle:
                handle.write(me)
            self.held = True
            return self
        raise InputError(f"{plain(str(self.path.parent))}: cannot take the lock {self.NAME}; use another --out")

    def release(self) -> None:
        if self.held:
            try:
                os.remove(self.path)
            except OSError:
                pass
            self.held = False

    def __enter__(self):
        return self.acquire()

    def __exit__(self, *exc):
        self.release()


def _alive(pid: int) -> bool:
    if pid <= 0:
        return False
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True
