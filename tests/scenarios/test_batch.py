"""A batch gives exactly the metrics of single runs (same kernel, vectorised metrics per chunk)."""
import numpy as np
import pytest

import vehicle_assist as va
from vehicle_assist.scenarios.runner import simulate_batch

TRUCK = ["hsa_truck_full_14deg_8p0bar", "hsa_truck_empty_11deg_6p5bar", "hsa_truck_full_14deg_no_assist_early_release",
         "truck_11deg_late_release"]


def _same(a: dict, b: dict) -> list:
    return [k for k in a if not np.isclose(a[k], b[k], rtol=0.0, atol=0.0, equal_nan=True)]


@pytest.mark.parametrize("workers", [1, 2])
def test_batch_metrics_equal_single_run_metrics(workers):
    """Bit-identical metrics: every metric of every variant in a batch equals the single run's (the batch
    vectorises the metrics over (runs, samples) arrays; determinism makes exact equality the right check)."""
    scs = [va.load_scenario(n) for n in TRUCK] + [va.load_scenario(TRUCK[0], ["vehicle.body.mass_kg=25000"])]
    batch = simulate_batch(scs, workers=workers)
    for sc, m in zip(scs, batch.metrics):
        single = va.simulate(sc).metrics
        assert set(m) == set(single)
        assert not _same(single, m), (sc.name, _same(single, m))


def test_batch_of_runs_with_different_lengths():
    """Variants whose runs end at different times (a stop event) fall back to per-run metrics, still exact."""
    base = va.load_scenario("ev_5deg_hold_and_pull_away")
    scs = [base, base.with_sets('events=[{at_s=6.0, action="stop"}]')]
    batch = simulate_batch(scs, keep_channels=["speed_mps"])
    for sc, m, kept in zip(scs, batch.metrics, batch.channels):
        r = va.simulate(sc)
        assert not _same(r.metrics, m)
        assert len(kept["speed_mps"]) == len(r.trace)


def test_batch_checks_flags():
    """checks_ok per variant: S1 passes; the same start in 1st gear does not launch (the assist refuses a grade
    beyond the engine), so its launch check fails."""
    scs = [va.load_scenario("hsa_truck_full_14deg_8p0bar"),
           va.load_scenario("hsa_truck_full_14deg_8p0bar", ['driver.gear_lever={time_s=[0.0], gear=["1"]}'])]
    batch = simulate_batch(scs)
    assert batch.checks_ok == [True, False]
