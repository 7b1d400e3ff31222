"""Direction of the spin-front rule's sideslip triggers (independent review V, session 2026-11-24 e).

The spin-front rule (``spin_front_flag``) brakes the front wheel on the side away from a blown REAR wheel - the outer
front wheel of a spin TOWARD the blown side (ESP oversteer practice: braking the outer front wheel; its brake force
turns the car back). Its triggers are the mu-0.8 yaw bound, the sideslip bound |beta| > atan(0.02*mu*g) and the phase
plane |beta_dot + B1*beta| > B2 - the last two are symmetric in beta. Reference (kinematics, sign only): in a spin
toward the blown (left, CCW +) side the heading turns past the velocity, so beta = atan(v_y/v_x) and beta_dot =
a_y/u - r are negative (for a blown right wheel positive). A positive beta with a left-blown wheel is the slide of the
opposite (clockwise) rotation: the car's nose already points right of its path, and a brake on the right front adds a
clockwise moment to it. Before the fix a rear-left blowout at 60 km/h with a small CCW yaw rate (0.01 rad/s) and
a_y = +5 m/s^2 (beta growing at +0.29 rad/s) moved the counter-brake to the right front at once (code 5); the same
slide mirrored (a_y = -5 m/s^2, the spin's own direction) must still do so. Fails at 37c39cd (main before the fix): the first test.
"""
from __future__ import annotations

import numpy as np
import pytest

import vehicle_assist as va
from vehicle_assist.functions import blowout_compensation as bc
from vehicle_assist.scenarios.runner import pack_records

V = 60.0 / 3.6
FAST = V * 0.359 / 0.24  # a fully deflated wheel's reading (tire_blowout.md 7: R_out 0.359 m, R_in 0.24 m)


@pytest.fixture(scope="module")
def params():
    return pack_records([va.load_scenario("blowout_lf_60kph_paper").vehicle.flat()])[0]


def _rl_blowout(p, yaw, a_y, s):
    """Rear-left blowout confirmed by both sources (0.2 s), then ``s`` seconds at the given yaw rate / lateral
    acceleration; returns the state and whether the spin-front rule ever took the right front."""
    st = bc.initial_state()
    ev = np.zeros((64, 5))
    req = np.zeros(4, dtype=np.int64)
    n, t, dt = 0, 0.0, 0.005
    vw = np.array([V, V, FAST, V])
    took_fr = False
    for k in range(int(round((0.2 + s) / dt))):
        y, ay = (0.0, 0.0) if k * dt < 0.2 else (yaw, a_y)
        v_ref = bc.reference_step(st, vw, 0.0, 3.0, dt, p)
        n = bc.blowout_step(st, vw, v_ref, 0.0, 0.0, y, 0.0, 3.0, np.ones(4), np.zeros(4), p, dt, t, 6, ev, n, req, ay)
        took_fr = took_fr or int(st[bc.S_LIMIT_CODE]) == bc.LIMIT_SPIN_FRONT
        t += dt
    return st, took_fr


def test_slide_of_the_opposite_rotation_does_not_brake_the_front(params):
    """beta > 0 (clockwise slide) with a left-blown rear: no spin-front transfer; the sideslip bound then refuses."""
    st, took_fr = _rl_blowout(params, 0.01, 5.0, 1.0)
    assert st[bc.S_BETA_EST] > 0.0
    assert not took_fr
    assert bc.MODES[int(st[bc.S_MODE])] == "REFUSED" and int(st[bc.S_LIMIT_CODE]) == bc.LIMIT_SIDESLIP_BOUND


def test_slide_of_the_spin_toward_the_blown_side_brakes_the_front(params):
    """Mirror (beta < 0, the spin's own slide): the right front takes the counter-brake, as before."""
    st, took_fr = _rl_blowout(params, 0.01, -5.0, 1.0)
    assert st[bc.S_BETA_EST] < 0.0
    assert took_fr and int(st[bc.S_TARGET]) == 1
