"""Review R0 (session n) of the road-edge judgement of the blowout rows: ``blowout_lateral_deviation_road_max_m`` (row
``tire_blowout.no_worse_than_no_compensation``) and ``blowout_road_departure_earliness_s`` (row
``tire_blowout.no_earlier_road_departure``), on HAND-BUILT traces whose departure times and offsets are known in closed
form. The numbers are written here, not imported from the code under test: the road edge is the lane margin
(3.75 m lane, JTG B01-2014 - 1.794 m BJ2500 width) / 2 = 0.978 m plus the 3.0 m hard shoulder the requirement states;
the earliness horizon is the 30-s run cap the requirement states. Independent references: the closed-form crossing
time of a linear drift, mirror symmetry (a departure to the left is judged as one to the right), and the twin: each
class of the two-run comparison (both on the road; one off; both off, either first; a car that leaves and comes back)
is evaluated through the shipped requirement file."""
from __future__ import annotations

import numpy as np
import pytest

import vehicle_assist.metrics.blowout  # noqa: F401  (registers the blowout metrics)
from vehicle_assist.core.trace import Trace
from vehicle_assist.metrics.common import compute_metrics
from vehicle_assist.verification.requirements import comparative_metrics, comparative_robustness, load_requirement_file

EDGE_M = (3.75 - 1.794) / 2.0 + 3.0  # 3.978 m: lane margin + hard shoulder (requirement text)
HORIZON_S = 30.0  # the braking option's run cap (requirement text)
T_B = 1.0  # the blowout instant of the hand-built traces
DT = 0.01
DEV = "blowout_lateral_deviation_road_max_m"
EARLY = "blowout_road_departure_earliness_s"


def drift(rate_mps: float, e0: float = 0.0, back_at_s: float | None = None, cap_m: float | None = None,
          t_end: float = 20.0) -> Trace:
    """Lane offset e0 until T_B, then e0 + rate*(t - T_B) (optionally held at cap_m in magnitude, optionally back to e0
    from back_at_s on: a car that leaves the road and comes back). blowout_frac rises just after T_B, so t_b = T_B."""
    t = np.round(np.arange(0.0, t_end + DT / 2, DT), 10)
    e = e0 + rate_mps * np.clip(t - T_B, 0.0, None)
    if cap_m is not None:
        e = np.clip(e, -cap_m, cap_m)
    if back_at_s is not None:
        e = np.where(t >= back_at_s, e0, e)
    phi = (t > T_B + 1e-9).astype(float)
    return Trace({"time_s": t, "lane_offset_m": e, "blowout_frac": phi, "blowout_mode_index": np.zeros_like(t)})


def departure_s(rate_mps: float, e0: float = 0.0) -> float:
    """First sample with |offset| beyond the edge, closed form of the linear drift."""
    return T_B + np.ceil(round((EDGE_M - abs(e0)) / abs(rate_mps) / DT, 6)) * DT


def metrics(tr: Trace) -> dict:
    return compute_metrics(tr, [DEV, EARLY])


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_on_the_road_the_deviation_is_the_unclipped_one_and_no_departure(sign):
    m = metrics(drift(sign * 1.0, cap_m=3.5))  # 3.5 m out: on the shoulder, still on the road
    assert m[DEV] == pytest.approx(3.5, abs=1e-9)
    assert m[EARLY] == 0.0


@pytest.mark.parametrize("sign", [1.0, -1.0])
@pytest.mark.parametrize("rate", [0.5, 1.0, 2.0])
def test_off_the_road_the_deviation_is_the_edge_and_the_earliness_the_closed_form(sign, rate):
    m = metrics(drift(sign * rate))  # drifts 9.5-38 m out by 20 s
    assert m[DEV] == pytest.approx(EDGE_M, abs=1e-9)  # clipped: how far beyond the edge does not count
    assert m[EARLY] == pytest.approx(HORIZON_S - (departure_s(rate) - T_B), abs=1e-6)


def test_a_car_that_leaves_the_road_and_comes_back_counts_as_departed_at_its_first_crossing():
    m = metrics(drift(1.0, back_at_s=8.0))  # out beyond the edge from 4.98 s, back on the lane centre at 8 s
    assert m[DEV] == pytest.approx(EDGE_M, abs=1e-9)
    assert m[EARLY] == pytest.approx(HORIZON_S - (departure_s(1.0) - T_B), abs=1e-6)


def test_the_departure_is_judged_on_the_absolute_offset_not_on_the_change_since_the_blowout():
    # a curve run that starts 0.5 m off-centre: the edge is 3.978 m from the LANE CENTRE, i.e. 3.478 m of change
    m = metrics(drift(1.0, e0=0.5))
    assert m[EARLY] == pytest.approx(HORIZON_S - (departure_s(1.0, e0=0.5) - T_B), abs=1e-6)
    m2 = metrics(drift(1.0, e0=0.5, cap_m=3.9))  # 3.4 m of change, 3.9 m from the centre: on the road
    assert m2[EARLY] == 0.0 and m2[DEV] == pytest.approx(3.4, abs=1e-9)


def rob(req_id: str, fn: Trace, tw: Trace) -> float:
    req = load_requirement_file("tire_blowout")[req_id]
    assert req.comparative
    names = comparative_metrics(req)
    return comparative_robustness(req, compute_metrics(fn, names), compute_metrics(tw, names))


ROW1 = "tire_blowout.no_worse_than_no_compensation"
ROW2 = "tire_blowout.no_earlier_road_departure"


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_requirement_classes(sign):
    """(row 1, row 2) robustness for each class; violation = negative. Mirror: the same on either side."""
    on_small, on_big = drift(sign * 1.0, cap_m=1.0), drift(sign * 1.0, cap_m=3.0)
    off_early, off_late = drift(sign * 2.0), drift(sign * 0.5)  # departures at 2.99 s and 8.96 s
    t_early, t_late = departure_s(2.0), departure_s(0.5)
    # both on the road: the smaller deviation wins, no departure row
    assert rob(ROW1, on_small, on_big) == pytest.approx(2.0, abs=1e-9)
    assert rob(ROW1, on_big, on_small) == pytest.approx(-2.0, abs=1e-9)
    assert rob(ROW2, on_big, on_small) == 0.0
    # the function's car leaves the road, the twin stays on: both rows violated
    assert rob(ROW1, off_late, on_big) == pytest.approx(3.0 - EDGE_M, abs=1e-9)
    assert rob(ROW2, off_late, on_big) == pytest.approx(-(HORIZON_S - (t_late - T_B)), abs=1e-6)
    # the twin leaves, the function's car stays on: both rows hold
    assert rob(ROW1, on_big, off_late) == pytest.approx(EDGE_M - 3.0, abs=1e-9)
    assert rob(ROW2, on_big, off_late) == pytest.approx(HORIZON_S - (t_late - T_B), abs=1e-6)
    # both leave: row 1 ties at the edge, row 2 is the function's departure minus the twin's
    assert rob(ROW1, off_late, off_early) == 0.0 and rob(ROW1, off_early, off_late) == 0.0
    assert rob(ROW2, off_late, off_early) == pytest.approx(t_late - t_early, abs=1e-6)
    assert rob(ROW2, off_early, off_late) == pytest.approx(t_early - t_late, abs=1e-6)
    # the same departure instant: a tie, not a violation
    assert rob(ROW2, off_early, drift(sign * 2.0, back_at_s=6.0)) == 0.0


def test_a_car_that_comes_back_is_not_better_than_one_that_stays_on_the_road():
    back = drift(1.0, back_at_s=8.0)
    stays = drift(1.0, cap_m=3.5)
    assert rob(ROW1, back, stays) < 0.0 and rob(ROW2, back, stays) < 0.0
