"""MDF4 export/import (issue #12). Reference: asammdf itself, opening the file independently of our reader
(units, comments, value-to-text tables, event blocks), and the float64 samples of the simulated trace."""
from __future__ import annotations

import json

import numpy as np
import pytest

asammdf = pytest.importorskip("asammdf")

import vehicle_assist as va  # noqa: E402
from vehicle_assist.io.mdf import read_trace_mdf4, write_trace_mdf4  # noqa: E402
from vehicle_assist.io.results import read_run  # noqa: E402


@pytest.fixture(scope="module")
def run():
    return va.simulate(va.load_scenario("hsa_truck_full_14deg_8p0bar", {"run.duration_s": 6.0}))


def test_asammdf_opens_the_file_with_units_descriptions_modes_and_events(run, tmp_path):
    path = write_trace_mdf4(run.trace, tmp_path / "trace.mf4")
    with asammdf.MDF(str(path)) as mdf:
        speed = mdf.get("speed_mps")
        assert speed.unit == "m/s" and speed.comment == run.trace.descriptions["speed_mps"]
        np.testing.assert_array_equal(speed.samples, run.trace["speed_mps"])
        assert mdf.get("engine_speed_radps").unit == "rad/s"
        # value-to-text: the physical value of the mode channel is the mode name
        modes = json.loads(run.trace.meta["mode_names"])["hsa_mode_index"]
        shown = mdf.get("hsa_mode_index").samples
        raw = run.trace["hsa_mode_index"].astype(int)
        assert [s.decode() for s in shown[::100]] == [modes[i] for i in raw[::100]]
        # every transition is an MDF event block, at its time, named machine FROM->TO, guard as comment
        assert len(mdf.events) == len(run.trace.events) > 0
        first, ev = mdf.events[0], run.trace.events[0]
        assert first.name == f"{ev.machine} {ev.from_mode}->{ev.to_mode}" and first.comment == ev.reason
        assert first.sync_base * first.sync_factor == pytest.approx(ev.time_s, abs=1e-9)
        assert len(mdf.get("events").samples) == len(run.trace.events)


def test_mdf4_round_trip_is_exact(run, tmp_path):
    path = write_trace_mdf4(run.trace, tmp_path / "trace.mf4")
    back = read_run(path)
    assert back.names == run.trace.names
    for name in run.trace.names:
        np.testing.assert_array_equal(back[name], run.trace[name], err_msg=name)
    assert back.meta == run.trace.meta and back.events == run.trace.events
    assert back.descriptions == {k: v for k, v in run.trace.descriptions.items() if k != "time_s" and v}


def test_a_foreign_mdf_file_is_read_onto_one_time_base(tmp_path):
    """A file not written by us (two channels at different rates, no header meta) comes back resampled."""
    t_fast, t_slow = np.linspace(0, 1, 11), np.linspace(0, 1, 3)
    mdf = asammdf.MDF(version="4.10")
    mdf.append([asammdf.Signal(2 * t_fast, t_fast, name="a_m", unit="m")])
    mdf.append([asammdf.Signal(t_slow * 10, t_slow, name="b_s", unit="s")])
    mdf.save(tmp_path / "x.mf4")
    mdf.close()
    trace = read_trace_mdf4(tmp_path / "x.mf4")
    np.testing.assert_allclose(trace["b_s"], 10 * t_fast)  # linear: interpolation is exact
    np.testing.assert_array_equal(trace["a_m"], 2 * t_fast)
