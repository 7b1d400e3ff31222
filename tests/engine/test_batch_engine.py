"""The fast batch path (issue 13) against the reference path it replaces.

References: the numpy metrics of ``metrics/*.py`` (``compute_metrics``) and the single-run path
(``simulate``: one kernel call, numpy metrics, scenarios built with ``with_sets``). The batch path (compiled
metric twins, one compiled call per chunk, records written by ``build_variants``) must give the very same bits:
every comparison here is on ``float.hex`` / raw bytes, not a tolerance.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import vehicle_assist as va
from vehicle_assist.core.trace import Trace
from vehicle_assist.metrics import compute_metrics
from vehicle_assist.metrics.fast import compute_metrics_fast, twins
from vehicle_assist.scenarios.runner import simulate_batch
from vehicle_assist.scenarios.variants import build_variants

DATA = Path(va.__file__).parent / "data" / "scenarios"
LAYOUTS = ("truck_amt", "ev_ehb")


def _same(x, y) -> bool:
    x, y = float(x), float(y)
    return x.hex() == y.hex() or (x != x and y != y)


def _scenarios(layout: str) -> list:
    out = []
    for path in sorted(DATA.glob("*.toml")):
        sc = va.load_scenario(path.stem)
        if sc.layout == layout:
            out.append(sc)
    return out


@pytest.mark.parametrize("layout", LAYOUTS)
def test_batch_equals_single_runs_bit_for_bit(layout):
    """Every shipped scenario of the layout in one batch: metrics, every kept channel and the checks verdict are
    those of its own ``simulate`` (reference: the single-run path with numpy metrics)."""
    scs = _scenarios(layout)
    singles = [va.simulate(sc, requirements=False) for sc in scs]
    channels = [c for c in singles[0].trace.channels if c != "time_s"]
    res = simulate_batch(scs, keep_channels=channels, workers=2)
    for sc, ref, metrics, kept, ok in zip(scs, singles, res.metrics, res.channels, res.checks_ok):
        assert list(metrics) == list(ref.metrics), sc.name
        bad = [k for k in ref.metrics if not _same(ref.metrics[k], metrics[k])]
        assert not bad, (sc.name, bad)
        assert all(ref.trace.channels[c].tobytes() == kept[c].tobytes() for c in ["time_s"] + channels), sc.name
        assert ok == all(c.ok for c in ref.checks), sc.name


@pytest.mark.parametrize("layout", LAYOUTS)
def test_fast_metrics_equal_numpy_metrics(layout):
    """Compiled twins vs the numpy metrics on (runs, samples) chunks: two variants stacked (a lighter vehicle),
    all metrics of the trace, identical bits. Each twin must be exercised by at least one layout."""
    used = set()
    for sc in _scenarios(layout):
        a = va.simulate(sc, requirements=False).trace
        b = va.simulate(sc.with_sets(f"vehicle.body.mass_kg={sc.vehicle.model.body.mass_kg * 0.7}"),
                        requirements=False).trace
        if len(b) != len(a):
            continue
        ch = {k: np.vstack([a.channels[k], b.channels[k]]) for k in a.channels if k != "time_s"}
        t = a.channels["time_s"]
        ref = compute_metrics(Trace({**ch, "time_s": t}))
        fast = compute_metrics_fast(ch, t, fallback=lambda names: pytest.fail(f"no twin for {names}"))
        assert list(fast) == list(ref)
        for k in ref:
            assert all(_same(x, y) for x, y in zip(ref[k], fast[k])), (sc.name, k, ref[k], fast[k])
        used |= set(ref)
    assert used & set(twins())


def test_fast_metrics_nan_and_edge_cases():
    """Hand-made traces that reach the NaN and never-found branches (reference: the numpy metrics)."""
    rng = np.random.default_rng(3)
    t = np.arange(300) * 0.01
    runs = 6
    ch = {
        "position_m": np.cumsum(rng.standard_normal((runs, 300)), axis=1),
        "speed_mps": rng.standard_normal((runs, 300)),
        "accel_mps2": rng.standard_normal((runs, 300)),
        "engine_speed_radps": 100 + rng.standard_normal((runs, 300)),
        "gear_index": np.tile(np.repeat([3.0, 0.0, 2.0, 0.0, 1.0, 0.0], 50), (runs, 1)),
        "brake_pedal_frac": np.zeros((runs, 300)),
        "accelerator_frac": np.zeros((runs, 300)),
        "clutch_slip_power_w": rng.standard_normal((runs, 300)) ** 2,
        "vehicle_held_flag": (rng.random((runs, 300)) < 0.2).astype(float),
    }
    ch["speed_mps"][1, 7] = np.nan
    ch["engine_speed_radps"][2, 120] = np.nan
    ch["brake_pedal_frac"][3, 10:40] = 0.5
    ch["brake_pedal_frac"][4, 10:] = 0.5  # applied, never released: NaN launch time
    ch["accelerator_frac"][5, 30:] = 0.3
    ch["clutch_slip_power_w"][5, 3] = np.nan
    ref = compute_metrics(Trace({**ch, "time_s": t}))
    fast = compute_metrics_fast(ch, t)
    for k in ref:
        assert all(_same(x, y) for x, y in zip(ref[k], fast[k])), (k, ref[k], fast[k])


def test_build_variants_equals_with_sets():
    """Records written by ``build_variants`` give what ``with_sets`` per variant gives (reference), including an
    axis of the scenario record (road slope) and the overrides listed per variant."""
    sc = va.load_scenario("truck_11deg_late_release")
    axes = {"vehicle.body.mass_kg": [13000, 21000.5, 30000], "vehicle.park_brake.reservoir_pressure_bar": [6.5, 8.0],
            "road.slope_deg": [8, 11.5]}
    vs = build_variants(sc, axes)
    assert vs.fast and len(vs) == 12
    slow = [sc.with_sets(*vs.sets(k)) for k in range(len(vs))]
    a = simulate_batch(vs, keep_channels=["speed_mps"])
    b = simulate_batch(slow, keep_channels=["speed_mps"])
    assert a.overrides == b.overrides
    assert a.checks_ok == b.checks_ok
    for x, y, cx, cy in zip(a.metrics, b.metrics, a.channels, b.channels):
        assert all(_same(x[k], y[k]) for k in y)
        assert cx["speed_mps"].tobytes() == cy["speed_mps"].tobytes()
    part = vs[5:9]  # a slice (what a worker gets) runs variants 5..8
    c = simulate_batch(part)
    assert c.overrides == a.overrides[5:9]
    assert all(_same(x[k], y[k]) for x, y in zip(c.metrics, a.metrics[5:9]) for k in y)


def test_build_variants_falls_back_when_not_exact():
    """An axis the records do not hold (run duration changes the record count) is built one by one; same results."""
    sc = va.load_scenario("hsa_ev_5deg_paper")
    vs = build_variants(sc, {"run.duration_s": [4.0, 5.0], "vehicle.body.mass_kg": [1500, 1700]})
    assert not vs.fast
    a = simulate_batch(vs)
    b = simulate_batch([sc.with_sets(*vs.sets(k)) for k in range(len(vs))])
    assert all(_same(x[k], y[k]) for x, y in zip(a.metrics, b.metrics) for k in y)
    with pytest.raises(Exception):
        build_variants(sc, {"vehicle.body.mass_kg": ["heavy"]})


@pytest.mark.parametrize("axes, needle", [({}, "no axes"), ({"vehicle.body.mass_kg": []}, "no values")])
def test_build_variants_without_axes_or_values_is_a_clear_error(axes, needle):
    # (no axes used to raise numpy's "multiple indices are not supported for 0d arrays" from the record builder)
    base = va.load_scenario("truck_11deg_late_release")
    with pytest.raises(ValueError, match=needle):
        build_variants(base, axes)


def test_batch_without_metrics_and_unknown_metric():
    """``metric_names=[]`` runs the variants without metrics (the study and falsify paths ask for this); an unknown
    metric name is still the numpy path's one-line error."""
    sc = va.load_scenario("hsa_ev_5deg_paper", ["run.duration_s=0.5"])
    res = simulate_batch([sc, sc], keep_channels=["speed_mps"], metric_names=[])
    assert res.metrics == [{}, {}] and len(res.channels[0]["speed_mps"]) > 0
    with pytest.raises(ValueError, match="unknown metric"):
        simulate_batch([sc], metric_names=["no_such_metric"])


def test_fast_time_after_start_edge_cases():
    """The one twin of ``release_after_start_s`` and ``assist_idle_after_start_s`` (metrics/fast.py
    ``time_after_start_s``) against those two numpy metrics (reference) on hand-made EV traces that reach every
    branch: never started, started but never released / never idle, released or idle before the start (the search
    starts at the start), already released at the start (0 s), NaN speed and NaN pressure."""
    from vehicle_assist.functions import hill_start_ehb as HE
    from vehicle_assist.metrics import hill_start_ehb as HEM

    n, runs = 200, 8
    t = np.arange(n) * 0.01
    v = np.zeros((runs, n))
    p = np.full((runs, n), 5e5)
    mode = np.full((runs, n), float(HE.HOLD))
    v[1:, 50:] = 1.0                      # every run but the first starts at sample 50
    p[2, 120:] = 0.0                      # released 0.7 s after the start
    mode[2, 90:] = float(HE.IDLE)         # idle 0.4 s after the start
    p[3, 10:20] = 0.0                     # released (and idle) only before the start: never after it
    mode[3, 10:20] = float(HE.IDLE)
    p[4, :] = 0.0                         # released and idle all along: 0 s
    mode[4, :] = float(HE.IDLE)
    v[5, 30] = np.nan                     # NaN speed before the start
    p[5, 60] = np.nan
    p[5, 61:] = HEM.RELEASED_PA           # at the threshold, not below it: never released
    p[6, 70] = HEM.RELEASED_PA * 0.999    # just below the threshold
    mode[6, 70] = float(HE.FOLLOW)
    mode[6, 71] = float(HE.IDLE)
    v[7, 50:] = HEM.START_SPEED_MPS       # at the start speed, not above it: never started
    ch = {"speed_mps": v, "brake_pressure_pa": p, "hsa_mode_index": mode}
    names = ["release_after_start_s", "assist_idle_after_start_s"]
    ref = compute_metrics(Trace({**ch, "time_s": t}), names)
    fast = compute_metrics_fast(ch, t, names, fallback=lambda names: pytest.fail(f"no twin for {names}"))
    for k in names:
        assert all(_same(x, y) for x, y in zip(ref[k], fast[k])), (k, ref[k], fast[k])
    # the cases are the intended ones (so that the comparison above covers them)
    assert np.isnan(ref["release_after_start_s"][[0, 1, 3, 5, 7]]).all()
    assert ref["release_after_start_s"][2] == pytest.approx(0.7) and ref["release_after_start_s"][4] == 0.0
    assert ref["assist_idle_after_start_s"][2] == pytest.approx(0.4)


def test_chunk_runner_loads_from_the_cache_in_a_new_process():
    """The chunk call each layout gets from ``vehicles.common.chunk_runner`` is cached like a plain function: a
    second process loads it from the compile cache instead of compiling it again (a closure over the kernel, or the
    kernel passed as an argument, is keyed on the dispatcher object and recompiles in every process)."""
    import json
    import os
    import subprocess
    import sys

    code = (
        "import json, numpy as np, vehicle_assist as va\n"
        "from vehicle_assist.scenarios.runner import simulate_batch\n"
        "from vehicle_assist.vehicles import truck_amt, ev_ehb\n"
        "for name in ('truck_11deg_late_release', 'hsa_ev_5deg_paper'):\n"
        "    simulate_batch([va.load_scenario(name, ['run.duration_s=0.05'])] * 2, workers=1, metric_names=[])\n"
        "print(json.dumps({m.LAYOUT: [sum(m.simulate_many.stats.cache_hits.values()),\n"
        "                             sum(m.simulate_many.stats.cache_misses.values())] for m in (truck_amt, ev_ehb)}))\n"
    )
    # the package's compile cache (NUMBA_CACHE_DIR, set by ``import vehicle_assist``); the first run fills it if cold
    env = {**os.environ, "NUMBA_CACHE_DIR": os.environ["NUMBA_CACHE_DIR"]}
    runs = [subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, check=True)
            for _ in range(2)]
    stats = json.loads(runs[1].stdout.strip().splitlines()[-1])
    assert stats == {"truck_amt": [1, 0], "ev_ehb": [1, 0]}, stats


def test_stop_events_are_detected_in_the_records():
    """A chunk whose runs may end early gets full trace rows (the in-call copy assumes runs of one length): the
    detector reads the scenario records. Reference: the events each scenario was given (stop / set_input / none)."""
    from vehicle_assist.scenarios.runner import _may_stop, pack_records

    base = va.load_scenario("ev_5deg_hold_and_pull_away")
    scs = [base.with_sets("events=[]"), base.with_sets('events=[{at_s=6.0, action="stop"}]'),
           base.with_sets('events=[{at_s=1.0, action="set_input", input="accelerator", value=0.2}, '
                          '{at_s=6.0, action="stop"}]'),
           base.with_sets('events=[{at_s=1.0, action="set_input", input="accelerator", value=0.2}]')]
    s = pack_records([sc.flat for sc in scs])
    assert [_may_stop(s, np.array([i])) for i in range(4)] == [False, True, True, False]
    assert _may_stop(s, np.array([0, 3])) is False and _may_stop(s, np.array([0, 2])) is True


def test_runs_of_different_length_without_a_stop_event_are_run_again(monkeypatch):
    """If runs of one chunk end up with different lengths although no stop event was found (the detector missed
    one), the chunk is run again into full trace rows: metrics and kept channels still those of single runs."""
    from vehicle_assist.scenarios import runner

    base = va.load_scenario("ev_5deg_hold_and_pull_away")
    scs = [base, base.with_sets('events=[{at_s=6.0, action="stop"}]')]
    monkeypatch.setattr(runner, "_may_stop", lambda s, idx: False)
    res = simulate_batch(scs, keep_channels=["speed_mps"], workers=1)
    for sc, metrics, kept in zip(scs, res.metrics, res.channels):
        ref = va.simulate(sc, requirements=False)
        assert all(_same(ref.metrics[k], metrics[k]) for k in ref.metrics), sc.name
        assert kept["speed_mps"].tobytes() == ref.trace.channels["speed_mps"].tobytes(), sc.name
