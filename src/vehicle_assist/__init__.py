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
