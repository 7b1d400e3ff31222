"""Lane keeper (drivers/lane_keeper.py): geometry of the lane errors (closed forms) and the delay line."""
from __future__ import annotations

import math

import pytest

from vehicle_assist.drivers import lane_keeper as lk


def test_straight_and_circle_errors():
    """Straight lane: e_y = y, e_psi = psi. Circle of R (left): a point on the circle with the tangent heading
    has zero error; 1 m inside gives e_y = +1 m."""
    assert lk.lane_errors(10.0, 0.3, 0.02, 0.0) == pytest.approx((0.3, 0.02))
    r = 500.0
    th = 0.2
    x, y = r * math.sin(th), r - r * math.cos(th)
    ey, ep = lk.lane_errors(x, y, th, r)
    assert ey == pytest.approx(0.0, abs=1e-9) and ep == pytest.approx(0.0, abs=1e-9)
    ey, _ = lk.lane_errors(x + math.sin(th) * 0 - math.sin(th), y + math.cos(th), th, r)
    assert ey == pytest.approx(1.0, abs=1e-6)


def test_reaction_delay_and_rate_limit():
    """The driver answers an offset only after the delay, and no faster than the rate limit."""
    buf = lk.initial_buffer()
    dt = 0.001
    delta = 0.0
    for k in range(600):
        delta = lk.lane_keeper_step(buf, k, 500, 1.0, 0.0, 0.0, delta, 0.01, 0.3, 0.5, dt)
        if k < 500:
            assert delta == 0.0
    assert delta == pytest.approx(-min(0.01, 0.5 * dt * 100), rel=1e-6)
