"""rejected_hold_limit_flag's hold-limit window state after its curve gate drops mid-hold (functions/esp.py: the window
state A_HOLD_S / A_HOLD_SUM / A_HOLD_PREV of abs_hold_limit; blowout_compensation.rejected_hold_reset_flag, 0 = the
code before) - review RJ3, session j (tire_blowout_findings.md "RJ3", "J10").

The rule's statement (esp.abs_hold_limit; Bosch Automotive Handbook, ABS control cycle): during a hold with the slip
above L_HOLD, each window's mean slip is compared with the PREVIOUS window's of the same hold - so a hold the limit
applies to can be stepped down at the earliest after two windows (2 x abs_hold_window_s). With 0 the state was reset only
inside abs_hold_limit: a hold the rejected-front gate (driver steering a curve) stopped covering froze it, and when the
gate came back the hold continued the stale partial window and compared it with the old mean - a dump step after less
than one window.

Reference: the rule's two-window statement (not the code's formula). ECU alone (tests.support.esp_ecu): FR rejected (mode
REJECTED forced each period), FR held at a constant slip above L_HOLD, the steering toggles the gate: on for 1.5 windows
at 12 % slip, off for 2 windows while the slip rises to 14 %, on again at 14 %: a constant slip, so with the fix no window's mean rises
and no step may come before two windows of the new gated hold.

Positive control (review RJ4, session j): the shipped row above also passes if the hold limit never acts again (first
dump None), e.g. a reset that also wiped the window state while the gate is on. So the same loop also continues with the
slip RISING in the second window of the new gated hold: window 1 at a constant 14 %, window 2 ramping 14 -> 16 % (mean
15 %, +1 point > abs_hold_slip_rise_frac 0.5 point): by the rule's statement the first dump comes at the END of window 2,
period 2*win, exactly. Flag 0 steps half a window after the return; a reset that also runs while the gate is on never steps.
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
STEER_RAD = 0.02  # road-wheel angle: at 80 km/h a steered reference yaw rate of several deg/s, beyond the dead band
FLAG0 = ("vehicle.blowout_compensation.rejected_hold_reset_flag=0",)


def _run(sets=(), rising=False):
    """Returns (gate per phase, periods of the second gated hold until FR's first dump or None, periods per window,
    params). ``rising``: the second gated hold's window 1 at a constant 14 %, window 2 ramping 14 -> 16 %, then 16 %
    (the positive control); else 3 windows at a constant 14 %."""
    p = pack_records([va.load_scenario("blowout_panic_stop_80kph", ["vehicle.brake_assist.enabled_flag=0", *sets]).vehicle.flat()])[0]
    v = 80.0 / 3.6
    win = int(round(p.esp_abs_hold_window_s / p.esp_period_s))
    e = esp_ecu(p, v, 60.0 * BAR)
    w, b, m = e["wheels"], e["bst"], e["meas"]
    gates = []

    def period(slip, steer):
        b[bc.S_MODE], b[bc.S_REJECTED], b[bc.S_TARGET] = bc.REJECTED, 1.0, -1.0
        w[1, esp.A_MODE] = abs_fn.HOLD  # FR in an ABS hold
        m.steering_angle_rad = steer
        m.wheel_speed_fr_radps = (1.0 - slip) * v / p.body_wheel_radius_m
        gates.append(abs(bc.reference_yaw_rate(steer, v, p)) > p.blowout_compensation_yaw_deadband_radps)
        esp_ecu_step(e, p)
        return int(w[1, esp.A_MODE]) == abs_fn.DUMP

    for _ in range(2 * win):  # settle the held wheel's speed (deceleration filter), gate off
        period(0.12, 0.0)
    for _ in range(3 * win // 2):  # gate on: one full window (mean 12 %) and half a window
        assert not period(0.12, STEER_RAD)
    for _ in range(2 * win):  # gate off mid-hold; the slip 2 points higher (the deceleration filter settles again)
        period(0.14, 0.0)
    slips = ([0.14] * win + [0.14 + 0.02 * (k + 1) / win for k in range(win)] + [0.16] * win if rising
             else [0.14] * (3 * win))
    first = None
    for k, s in enumerate(slips):  # gate on again
        if period(s, STEER_RAD) and first is None:
            first = k + 1
    return gates, first, win, p


def test_premise_gate_toggles():
    """Premise: the steering switches the gate (reference yaw rate beyond the dead band) on and off."""
    gates, _, win, _ = _run()
    assert not gates[0] and gates[2 * win] and not gates[2 * win + 3 * win // 2] and gates[-1]


@pytest.mark.parametrize("sets", [(), pytest.param(FLAG0, marks=pytest.mark.xfail(
    strict=True, reason="flag 0 = the code before: the frozen half window and the old hold's mean give a dump step "
    "half a window after the gate returns"))], ids=["shipped", "flag0"])
def test_no_step_before_two_windows_of_the_new_gated_hold(sets):
    """No hold-limit dump on FR within two windows of the gated hold that starts when the gate comes back."""
    _, first, win, _ = _run(sets)
    assert first is None or first >= 2 * win, (first, win)


def test_premise_rise_exceeds_the_rule_threshold():
    """Premise of the positive control: window 2's mean (15 %) exceeds window 1's (14 %) by more than
    abs_hold_slip_rise_frac."""
    _, _, win, p = _run(rising=True)
    mean2 = sum(0.14 + 0.02 * (k + 1) / win for k in range(win)) / win
    assert mean2 - 0.14 > p.esp_abs_hold_slip_rise_frac


@pytest.mark.parametrize("sets", [(), pytest.param(FLAG0, marks=pytest.mark.xfail(
    strict=True, reason="flag 0 = the code before: the stale half window steps half a window after the gate returns"))],
    ids=["shipped", "flag0"])
def test_hold_limit_steps_at_the_end_of_the_second_fresh_window(sets):
    """Positive control (RJ4): the hold limit still acts on the new gated hold, at the end of its second window."""
    _, first, win, _ = _run(sets, rising=True)
    assert first == 2 * win, (first, win)
