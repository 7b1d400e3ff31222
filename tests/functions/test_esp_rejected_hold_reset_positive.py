"""Positive control for rejected_hold_reset_flag (review RJ4, session j; tire_blowout_findings.md "J10", "RJ4").

test_esp_rejected_hold_reset.py checks that no hold-limit dump comes BEFORE two windows of the gated hold that starts
when the rejected-front gate returns; its shipped row also passes if the hold limit never acts again (first dump None),
e.g. a reset that also wiped the window state while the gate is on. Here the same ECU loop (FR rejected, FR held above
L_HOLD, the gate on / off / on) continues with the slip RISING in the second window of the new gated hold. The rule's
statement (esp.abs_hold_limit; Bosch Automotive Handbook, ABS control cycle: hold, then a stepwise reduction while the
wheel does not re-accelerate): each window's mean slip is compared with the previous window's of the same hold; risen by
more than abs_hold_slip_rise_frac -> a dump step. Fresh windows from the gate's return: window 1 at a constant 14 %,
window 2 ramping 14 -> 16 % (mean 15 %, +1 point > 0.5 point): the first dump is at the END of window 2, period 2*win,
exactly. Flag 0 (the code before) steps half a window after the return (the stale half window and the old mean);
a reset that also runs while the gate is on never steps.
"""
from __future__ import annotations

import pytest

import vehicle_assist as va
from tests.support import esp_ecu, esp_ecu_step
from vehicle_assist.functions import abs as abs_fn
from vehicle_assist.functions import blowout_compensation as bc
from vehicle_assist.functions import esp
from vehicle_assist.scenarios.runner import pack_records

BAR = 1.0e5
STEER_RAD = 0.02  # as test_esp_rejected_hold_reset.py: the steered reference beyond the dead band at 80 km/h
FLAG0 = ("vehicle.blowout_compensation.rejected_hold_reset_flag=0",)


def _first_dump(sets=()):
    p = pack_records([va.load_scenario("blowout_panic_stop_80kph", ["vehicle.brake_assist.enabled_flag=0", *sets]).vehicle.flat()])[0]
    v = 80.0 / 3.6
    win = int(round(p.esp_abs_hold_window_s / p.esp_period_s))
    e = esp_ecu(p, v, 60.0 * BAR)
    w, b, m = e["wheels"], e["bst"], e["meas"]

    def period(slip, steer):
        b[bc.S_MODE], b[bc.S_REJECTED], b[bc.S_TARGET] = bc.REJECTED, 1.0, -1.0
        w[1, esp.A_MODE] = abs_fn.HOLD  # FR in an ABS hold
        m.steering_angle_rad = steer
        m.wheel_speed_fr_radps = (1.0 - slip) * v / p.body_wheel_radius_m
        esp_ecu_step(e, p)
        return int(w[1, esp.A_MODE]) == abs_fn.DUMP

    for _ in range(2 * win):  # settle, gate off
        period(0.12, 0.0)
    for _ in range(3 * win // 2):  # gate on: 1.5 windows at 12 %
        assert not period(0.12, STEER_RAD)
    for _ in range(2 * win):  # gate off mid-hold, slip 14 %
        period(0.14, 0.0)
    slips = [0.14] * win + [0.14 + 0.02 * (k + 1) / win for k in range(win)] + [0.16] * win
    for k, s in enumerate(slips):  # gate on again: window 1 constant, window 2 rising
        if period(s, STEER_RAD):
            return k + 1, win, p
    return None, win, p


def test_premise_rise_exceeds_the_rule_threshold():
    """Premise: window 2's mean (15 %) exceeds window 1's (14 %) by more than abs_hold_slip_rise_frac."""
    _, win, p = _first_dump()
    mean2 = sum(0.14 + 0.02 * (k + 1) / win for k in range(win)) / win
    assert mean2 - 0.14 > p.esp_abs_hold_slip_rise_frac


@pytest.mark.parametrize("sets", [(), pytest.param(FLAG0, marks=pytest.mark.xfail(
    strict=True, reason="flag 0 = the code before: the stale half window steps half a window after the gate returns"))],
    ids=["shipped", "flag0"])
def test_hold_limit_steps_at_the_end_of_the_second_fresh_window(sets):
    first, win, _ = _first_dump(sets)
    assert first == 2 * win, (first, win)
