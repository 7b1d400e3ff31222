"""Review RM7 (session m; tire_blowout_findings.md "RM7"): ``front_substitute_rear_flag`` = 2 (M7) at the function's
own interface, for BOTH blown fronts.

The lead's envelopes have LEFT curves only (lane_keeper: radius <= 0 is straight), so the curve gate - and with it M7's
latch - only ever decides for FL blown (a curve toward the blown side); for FR blown the gate is open through the
steered reference's sign and the latch is never read. The end-to-end tests (test_blowout_front_substitute_curve_gate.py)
therefore cannot see a latch that drops the blown side's sign (e.g. ``S_M7_ERR0 = yaw_err``): FR blown in a RIGHT curve
is the mirror image of FL blown in a left curve and must get the same decision (mirror symmetry, independent of the
model's output). The numbers below are the rule's own statement: the latch compared with esp.yaw_dump_rate (read from
the vehicle's parameters, the GMA dump threshold), the curve beyond yaw_deadband; the yaw errors are set at 0.8 and 1.25
times that rate, so a comparison that moves to another rate (yaw_hold_rate, or 1.5x the dump rate) fails one row.

Rule under test (blowout_compensation.front_substitute_rear, value 2): in LIMITED code 1 with the driver braking, the
blown side's rear is released while the yaw error toward the blown side exceeds the dump rate, unless the car is in a
curve steered toward the blown side AND the yaw error toward the blown side at the first braking period of the episode
(S_M7_ERR0) was already beyond the dump rate (a rotation under way before the rear pair braked: held at the substitute's
level, S_REAR_CAP). Value 1 = the curve gate unconditional (the code before).
"""
from __future__ import annotations

import numpy as np
import pytest

from vehicle_assist.functions import blowout_compensation as bc
from tests.support import packed_params

BAR = 1.0e5
FRONT_SUBSTITUTE = {0: 3, 1: 2}  # blown front -> substitute rear (the rear on the OTHER side)
SIGN = {0: 1.0, 1: -1.0}  # CCW + quantities toward the blown side: + for FL (left), - for FR (right)


def _params(flag):
    sets = () if flag is None else ("vehicle.blowout_compensation.front_substitute_rear_flag=%d" % flag,)
    return packed_params("blowout_lf_60kph_paper", *sets)


def _episode(flag, b, err0_frac, err1_frac, curve_toward):
    """Two braking periods of one LIMITED code-1 episode: the first with the yaw error err0_frac * dump rate toward the
    blown side, the second with err1_frac * dump rate. Curve steered toward (True) or away from (False) the blown side,
    0.1 rad/s (> yaw_deadband). Returns (request of the blown side's rear, S_REAR_CAP) after the second period."""
    p = _params(flag)
    dump = p.esp_yaw_dump_rate_radps
    assert 0.1 > p.blowout_compensation_yaw_deadband_radps
    s = SIGN[b]
    r_ref = (s if curve_toward else -s) * 0.1
    tg = FRONT_SUBSTITUTE[b]
    p_est = np.array([0.0, 0.0, 40.0, 40.0]) * BAR
    p_est[tg] = 60.0 * BAR
    st = bc.initial_state()
    for frac in (err0_frac, err1_frac):
        req = np.zeros(4, dtype=np.int64)
        st[bc.S_REAR_CAP] = -1.0
        bc.front_substitute_rear(b, tg, 1.0, s * frac * dump, r_ref, p_est, req, p, st)
    return int(req[b + 2]), float(st[bc.S_REAR_CAP])


@pytest.mark.parametrize("b", [0, 1], ids=["FL_blown", "FR_blown"])
@pytest.mark.parametrize("err0_frac, curve_toward, released", [
    (0.8, True, True),    # curve toward the blown side, no rotation when the pair began to brake: released (M7)
    (1.25, True, False),  # a rotation already under way at the first braking period: the curve gate holds (L2, f_r11 #24)
    (1.25, False, True),  # curve away from the blown side: the gate never holds
    (0.8, False, True),
])
def test_latch_decides_the_curve_gate_mirror_symmetric(b, err0_frac, curve_toward, released):
    req, cap = _episode(None, b, err0_frac, 1.6, curve_toward)
    if released:
        assert req == bc.Q_RELEASE and cap < 0.0, (req, cap)
    else:
        assert req != bc.Q_RELEASE and cap == pytest.approx(60.0 * BAR), (req, cap)


@pytest.mark.parametrize("b", [0, 1], ids=["FL_blown", "FR_blown"])
def test_value_1_holds_in_a_curve_toward_the_blown_side(b):
    """Negative control: value 1 (L2's unconditional curve gate, the code before) holds where value 2 releases."""
    req, cap = _episode(1, b, 0.8, 1.6, True)
    assert req != bc.Q_RELEASE and cap == pytest.approx(60.0 * BAR), (req, cap)


@pytest.mark.parametrize("b", [0, 1], ids=["FL_blown", "FR_blown"])
def test_below_the_dump_rate_never_released(b):
    """The yaw limitation's own threshold: under the dump rate the blown side's rear is held at the substitute's level."""
    req, cap = _episode(None, b, 0.8, 0.8, True)
    assert req != bc.Q_RELEASE and cap == pytest.approx(60.0 * BAR), (req, cap)
