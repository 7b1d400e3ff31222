"""vehicle-assist: design, simulate, calibrate and verify vehicle assistance functions.

Python API (everything here is typed; ``py.typed`` ships with the package)::

    import vehicle_assist as va
    sc = va.load_scenario("hsa_truck_full_14deg_8p0bar", {"vehicle.body.mass_kg": 20000, "run.duration_s": 10})
    result = va.simulate(sc)                 # Result: trace, metrics, events, checks, requirements
    df = result.to_pandas()                  # the trace as a DataFrame (units in df.attrs["units"])
    batch = va.simulate_batch([sc.with_sets(f"road.slope_deg={a}") for a in (8, 10, 12)])
    batch.to_pandas()                        # one row per variant: its overrides, metrics and checks_ok
    trace = va.read_run("out/run")           # a run directory, trace.parquet, trace.csv or trace.mf4

Importing the package has no process-wide effect besides pointing numba's compile cache at the package's
own directory (``NUMBA_CACHE_DIR``, only if the caller has not set a writable one; see ``_cache.py``).
Old cache versions are pruned when the first run starts. ``OPENBLAS_NUM_THREADS=1`` (idle BLAS threads
slow batches on small machines) is set by the command line only; API users who run big batches may set
it themselves before importing numpy.
"""
from __future__ import annotations

import json as _json
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable

from vehicle_assist import _cache

_cache.configure()

if TYPE_CHECKING:  # pragma: no cover
    from vehicle_assist.core.trace import Event, Trace
    from vehicle_assist.scenarios.loader import LoadedScenario, Vehicle
    from vehicle_assist.scenarios.runner import BatchResult, Result

__version__ = "0.1.0"

Overrides = Mapping[str, Any] | Sequence[str]


def _flatten(prefix: str, value: Any, out: list[str]) -> None:
    if isinstance(value, Mapping):
        for k, v in value.items():
            _flatten(f"{prefix}.{k}" if prefix else str(k), v, out)
        return
    if isinstance(value, tuple):
        value = list(value)
    if hasattr(value, "item") and not isinstance(value, (list, str)):  # numpy scalar
        value = value.item()
    out.append(f"{prefix}={_json.dumps(value)}")


def as_sets(overrides: Overrides | None) -> list[str]:
    """Overrides as ``dotted.path=value`` strings: a dict ``{"vehicle.body.mass_kg": 20000}`` (values as
    numbers, strings, booleans or lists; nested dicts are flattened), or already a list of such strings."""
    if overrides is None:
        return []
    if isinstance(overrides, str):
        return [overrides]
    if isinstance(overrides, Mapping):
        out: list[str] = []
        _flatten("", overrides, out)
        return out
    return [str(s) for s in overrides]


def load_scenario(name_or_path: str | Path, overrides: Overrides | None = None, *,
                  sets: Overrides | None = None) -> LoadedScenario:
    """Load a shipped scenario (by name) or a scenario TOML file, with optional overrides.

    ``overrides`` (or the keyword ``sets``): ``{"road.slope_deg": 12, "driver.gear_lever.gear": ["1"]}`` or
    ``["road.slope_deg=12", 'driver.gear_lever.gear=["1"]']``. Bad input raises ``InputError`` (one line)."""
    from vehicle_assist.scenarios import loader

    return loader.load_scenario(name_or_path, as_sets(overrides) + as_sets(sets))


def load_vehicle(name_or_path: str | Path, overrides: dict | None = None) -> Vehicle:
    """Load a shipped vehicle (by name) or a vehicle TOML file."""
    from vehicle_assist.scenarios import loader

    return loader.load_vehicle(name_or_path, overrides)


def simulate(scenario: LoadedScenario, requirements: bool = True) -> Result:
    """Run one scenario: full trace, metrics, events, checks and requirement robustness."""
    from vehicle_assist.scenarios import runner

    _cache.prune_stale()
    return runner.simulate(scenario, requirements=requirements)


def simulate_batch(scenarios: Sequence[LoadedScenario], keep_channels: Iterable[str] = (), keep_every: int = 1,
                   metric_names: Iterable[str] | None = None, workers: int | None = None,
                   progress: Callable[[int], None] | None = None) -> BatchResult:
    """Run many variants of one layout on all cores; per-variant metrics (and kept channels)."""
    from vehicle_assist.scenarios import runner

    _cache.prune_stale()
    return runner.simulate_batch(scenarios, keep_channels, keep_every, metric_names, workers, progress)


def read_run(path: str | Path) -> Trace:
    """A run's trace from a run directory, ``.parquet``, ``.csv`` (with its sidecar) or ``.mf4`` file."""
    from vehicle_assist.io.results import read_run as _read_run

    return _read_run(path)


def __getattr__(name: str) -> Any:
    # classes on demand: importing the package stays cheap (no numba compile until a run is asked for)
    if name in ("Result", "BatchResult"):
        from vehicle_assist.scenarios import runner

        return getattr(runner, name)
    if name in ("Trace", "Event"):
        from vehicle_assist.core import trace

        return getattr(trace, name)
    if name in ("LoadedScenario", "Vehicle"):
        from vehicle_assist.scenarios import loader

        return getattr(loader, name)
    raise AttributeError(f"module 'vehicle_assist' has no attribute {name!r}")


__all__ = ["load_scenario", "load_vehicle", "simulate", "simulate_batch", "read_run", "as_sets", "Result",
           "BatchResult", "Trace", "Event", "LoadedScenario", "Vehicle", "__version__"]
