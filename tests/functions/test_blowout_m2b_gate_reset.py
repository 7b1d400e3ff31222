"""Final read (session m): ``blown_side_front_flag`` = 3's gate (M2b, S_M2B_GATE) belongs to one pedal application and one
blown wheel. At the rule's own interface (blowout_compensation.blown_side_fault): a blown FRONT whose same-side REAR
inlet is stuck (trapped 0 bar), a two-source detection, the driver braking. The gate opens when the yaw error points away
from the blown side beyond esp.yaw_hold_rate and then caps the free rear at the trapped pressure + 1 bar (S_REAR_CAP);
inside the dead band a CLOSED gate writes no cap (value 2's and 3's own statement, independent of any run's output).
Before the final read the gate survived a pedal release and a detection of the other front, so a fresh application (or
the other wheel, whose 'away' is the opposite sign) started capped."""
from __future__ import annotations

import numpy as np

from vehicle_assist.functions import blowout_compensation as bc
from tests.support import packed_params

BAR = 1.0e5


def _params():
    return packed_params("blowout_lf_60kph_paper")


def _call(st, p, b, braking, yaw_err):
    """One period; returns S_REAR_CAP (-1 = no cap written)."""
    inlet_ok = np.ones(4)
    inlet_ok[b + 2] = 0.0  # the blown front's same-side rear is stuck
    req = np.zeros(4, dtype=np.int64)
    st[bc.S_REAR_CAP] = -1.0
    p_est = np.array([0.0, 40.0, 0.0, 40.0]) * BAR if b == 0 else np.array([40.0, 0.0, 40.0, 0.0]) * BAR
    bc.blown_side_fault(st, b, 1 - b, bc.BUILD, braking, inlet_ok, p_est, 40.0 * BAR, req, p, yaw_err)
    return float(st[bc.S_REAR_CAP])


def _state():
    st = bc.initial_state()
    st[bc.S_SOURCES] = bc.SRC_WS + bc.SRC_TPMS
    st[bc.S_L6_TRAPPED:bc.S_L6_TRAPPED + 4] = 0.0  # diagnosed stuck with nothing trapped
    return st


def test_gate_opens_beyond_the_hold_rate_and_caps_the_free_rear():
    p = _params()
    assert p.blowout_compensation_blown_side_front_flag == 3
    st = _state()
    away = -1.5 * p.esp_yaw_hold_rate_radps * bc.toward_blown_side(0, 1.0)  # FL: away from the left side
    assert _call(st, p, 0, 1.0, away) == bc.PRESSURE_MARGIN_PA
    inside = 0.5 * p.blowout_compensation_yaw_deadband_radps
    assert _call(st, p, 0, 1.0, -inside * bc.toward_blown_side(0, 1.0)) == bc.PRESSURE_MARGIN_PA  # hysteresis: still open


def test_a_new_pedal_application_starts_with_the_gate_closed():
    p = _params()
    st = _state()
    away = -1.5 * p.esp_yaw_hold_rate_radps * bc.toward_blown_side(0, 1.0)
    assert _call(st, p, 0, 1.0, away) > 0.0
    assert _call(st, p, 0, 0.0, away) < 0.0  # pedal released: the rule stands aside
    inside = -0.5 * p.blowout_compensation_yaw_deadband_radps * bc.toward_blown_side(0, 1.0)
    assert _call(st, p, 0, 1.0, inside) < 0.0  # pressed again inside the dead band: no cap


def test_the_other_front_does_not_inherit_the_gate():
    p = _params()
    st = _state()
    away_fl = -1.5 * p.esp_yaw_hold_rate_radps * bc.toward_blown_side(0, 1.0)
    assert _call(st, p, 0, 1.0, away_fl) > 0.0
    inside_fr = -0.5 * p.blowout_compensation_yaw_deadband_radps * bc.toward_blown_side(1, 1.0)
    assert _call(st, p, 1, 1.0, inside_fr) < 0.0  # FR detected next, its yaw error inside the dead band
