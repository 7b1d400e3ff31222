"""The blown inner front's hold/release limit cycle (docs/functions/tire_blowout_sessions.md "Status at the end of session
2026-11-24 h" items 1, 3, 7; tire_blowout_findings.md G2, H8, RH2, I3).

``blown_front_hold`` (functions/blowout_compensation.py) holds the blown INNER front of a braked curve toward it
(Q_HOLD: the driver's/ABS pressure) while the yaw rate is at or below the steered reference, and releases it (dump to
~1 bar) above. Switched at the reference itself the wheel alternates between the two extremes on every swing of the
yaw mode around the reference. ``blown_front_hold_band_flag`` (candidate, shipped 0 = that code) makes the decision a
relay with the function's closed-loop yaw dead band (yaw_deadband_deg_per_s = 1 deg/s) as its hysteresis on both sides
of the reference: released once the yaw exceeds the reference by more than the band, held once it falls short of it by
more than the band, the last decision kept inside.

Point: lead's CMA-ES 2026 -n 200 (the 4718b3b search path, /tmp/lead/g7/c2026_200) #161: FL, 115.8 km/h, mu scale
0.32, 650 m curve toward FL, lane-following driver, pedal from t_b - 0.5 s. At cc64ff5 (flag 0): FL under ABS at
14.8 bar; at 1.22-1.35 s the yaw swings +0.07..+0.41 deg/s above the reference (inside the dead band), FL is released
14.8 -> 1.2 bar, the yaw then goes 1-2 deg/s below the reference and the (single-source) detection is rejected
yaw_implausible at 1.84 s: 0.973 m vs 0.839 m without compensation. With the rule FL stays at the ABS's 12.6-14.8 bar,
0.864 m - still worse than none (rejected 1.87 s while the low-mu car understeers as its twin does: strict xfail).
#139 (same search): 1.636 -> 0.422 m (none 3.307).

Can fail: the unit rows and both closed-loop checks fail with the flag at 0 (the code before)."""
from __future__ import annotations

import numpy as np
import pytest

import vehicle_assist as va
from tests.support import envelope_point_run
from vehicle_assist.functions import blowout_compensation as bc
from vehicle_assist.scenarios.runner import pack_records
from vehicle_assist.verification.envelope import load_envelope

METRIC = "blowout_lateral_deviation_run_max_m"
FLAG = "vehicle.blowout_compensation.blown_front_hold_band_flag"
ON, OFF = FLAG + "=1", FLAG + "=0"
BAR = 1.0e5
DB = np.deg2rad(1.0)  # yaw_deadband_deg_per_s of data/vehicles/suv_bj2500.toml (assumed there: closed-loop dead band)

P161 = {"speed": 115.7784984930548, "mu": 0.3217146868606445, "delay": 0.020004975682029268,
        "wheel_speed_noise": 0.29104182270417833, "noise_seed": 3242.0, "brake_gain": 0.9713873362437861,
        "brake.start_s": 0.5014370372440895, "brake.level_frac": 0.14607932509121924,
        "brake.rate_per_s": 22.264975094601247, "braking": "brakes", "wheel": "fl", "driver": "follow", "curve": "r650"}
P139 = {"speed": 119.84403735928768, "mu": 0.36299618936160044, "delay": 0.023499768671344616,
        "wheel_speed_noise": 0.16909668999260571, "noise_seed": 4732.0, "brake_gain": 1.1061434563499706,
        "brake.start_s": 0.5677318958568539, "brake.level_frac": 0.12008820887471472,
        "brake.rate_per_s": 10.777638740934636, "braking": "brakes", "wheel": "fl", "driver": "follow", "curve": "r650"}


def _params(flag):
    sc = va.load_scenario("blowout_lf_60kph_paper").with_sets(FLAG + "=%d" % flag)
    return pack_records([sc.vehicle.flat()])[0]


def _seq(p, yaws_rel, b=0, tg=1, r_ref=0.03):
    """Requests on the blown front for a sequence of yaw deviations [rad/s] (toward FL = +), the same state: FL blown,
    FR compensating and ABS-active, braking, HOLD, a curve toward FL (reference 0.03 rad/s = 1.7 deg/s)."""
    st = bc.initial_state()
    st[bc.S_ABS_ACTIVE + tg] = 1.0
    out = []
    for y in yaws_rel:
        requests = np.full(4, bc.Q_NONE, dtype=np.int64)
        requests[b] = bc.Q_RELEASE
        bc.blown_front_hold(st, b, tg, bc.HOLD, 1.0, y, r_ref, requests, p)
        out.append(int(requests[b]))
    return out


H, R = bc.Q_HOLD, bc.Q_RELEASE


def test_relay_rows():
    """Relay with the dead band as hysteresis: held inside the band above the reference (+0.5 deg/s), released beyond
    it (+1.5), still released back inside (+0.5, -0.5), held again only beyond the band below (-1.5), then held inside
    (+0.5). The code before (flag 0) releases at every sample above the reference."""
    y = np.deg2rad([0.5, 1.5, 0.5, -0.5, -1.5, 0.5])
    assert _seq(_params(1), y) == [H, R, R, R, H, H]
    assert _seq(_params(0), y) == [R, R, R, H, H, R]


def test_relay_rows_mirrored_for_fr():
    """FR blown, FL compensating, a right curve (reference -0.03 rad/s): toward FR = negative yaw."""
    y = -np.deg2rad([0.5, 1.5, 0.5, -0.5, -1.5, 0.5])
    assert _seq(_params(1), y, b=1, tg=0, r_ref=-0.03) == [H, R, R, R, H, H]


def test_band_is_the_dead_band():
    """The switching levels are the dead band itself (no constant of the rule's own): just inside -> no switch, just
    beyond -> switch."""
    p = _params(1)
    assert _seq(p, [0.99 * DB]) == [H]
    assert _seq(p, [1.01 * DB]) == [R]
    assert _seq(p, [1.01 * DB, -0.99 * DB]) == [R, R]
    assert _seq(p, [1.01 * DB, -1.01 * DB]) == [R, H]


@pytest.fixture(scope="module")
def runs():
    env = load_envelope("tire_blowout")
    out = {}
    for name, pt in (("p161", P161), ("p139", P139)):
        out[name] = {"on": envelope_point_run(env, pt, sets=[ON]), "off": envelope_point_run(env, pt, sets=[OFF]),
                     "none": envelope_point_run(env, pt, baseline=True)}
    return out


def _fl_min_bar(run, t0, t1):
    tr = run.trace.channels
    t = np.asarray(tr["time_s"])
    k = (t >= t0) & (t <= t1)
    return float(np.min(np.asarray(tr["wheel_pressure_fl_pa"])[k])) / BAR


def test_161_abs_held_flat_front_not_dumped_on_a_swing_inside_the_band(runs):
    """#161, 1.20-1.36 s: the plant's yaw exceeds the reference by at most 0.41 deg/s (inside the 1 deg/s band); with
    the rule FL keeps the ABS's pressure (>= 12 bar, measured 12.6), with the flag at 0 it is dumped (1.2 bar)."""
    assert _fl_min_bar(runs["p161"]["on"], 1.20, 1.36) > 8.0
    assert _fl_min_bar(runs["p161"]["off"], 1.20, 1.36) < 2.0


@pytest.mark.parametrize("name", ["p161", "p139"])
def test_better_than_the_code_before(runs, name):
    """#161 0.864 vs 0.973 m, #139 0.422 vs 1.636 m (flag 1 vs 0)."""
    r = runs[name]
    assert r["on"].metrics[METRIC] < r["off"].metrics[METRIC] - 0.05


@pytest.mark.xfail(strict=True, reason="tire_blowout_findings.md I3: #161 with the rule 0.864 m vs none 0.839 m - the real blowout "
                   "is still rejected yaw_implausible (1.87 s) while the low-mu car understeers 2-4 deg/s below the "
                   "reference as its twin does; not fixed")
def test_161_no_worse_than_no_compensation(runs):
    r = runs["p161"]
    assert r["on"].metrics[METRIC] <= r["none"].metrics[METRIC]
