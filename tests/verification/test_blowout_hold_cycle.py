"""The blown inner front's hold/release decision (docs/functions/tire_blowout_sessions.md "Status at the end of session
2026-11-24 h" items 1, 3, 7; tire_blowout_findings.md G2, H8, RH2, I3).

``blown_front_hold`` (functions/blowout_compensation.py) holds the blown INNER front of a braked curve toward it
(Q_HOLD: the driver's/ABS pressure) while the yaw rate is at or below the steered reference, and releases it (dump to
~1 bar) above: switched at the reference itself, so the wheel alternates between the two extremes on every swing of the
yaw mode around the reference (the limit cycle of I3). I3's relay with the closed-loop dead band as hysteresis was a
candidate shipped off (690 braking front points: violations 35 -> 39) and was deleted in session j (J3); its
closed-loop rows (#161, #139 of the lead's CMA-ES 2026 -n 200) went with it. What stays: the shipped switching rows.

Can fail: a decision with any hysteresis or offset around the reference (e.g. I3's relay) gives other rows."""
from __future__ import annotations

import numpy as np

import vehicle_assist as va
from vehicle_assist.functions import blowout_compensation as bc
from vehicle_assist.scenarios.runner import pack_records


def _params():
    sc = va.load_scenario("blowout_lf_60kph_paper")
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


def test_switched_at_the_reference():
    """Released at every sample above the steered reference (toward the blown side), held at or below it: +0.5, +1.5,
    +0.5 deg/s released, -0.5, -1.5 held, +0.5 released again (no memory, no band)."""
    y = np.deg2rad([0.5, 1.5, 0.5, -0.5, -1.5, 0.5])
    assert _seq(_params(), y) == [R, R, R, H, H, R]


def test_switched_at_the_reference_mirrored_for_fr():
    """FR blown, FL compensating, a right curve (reference -0.03 rad/s): toward FR = negative yaw."""
    y = -np.deg2rad([0.5, 1.5, 0.5, -0.5, -1.5, 0.5])
    assert _seq(_params(), y, b=1, tg=0, r_ref=-0.03) == [R, R, R, H, H, R]
