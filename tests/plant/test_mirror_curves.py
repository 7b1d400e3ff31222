"""Right-hand curves (signed lane radius, session m, M4) against an independent reference: mirror symmetry.

The plant, the ESP and the blowout function have no preferred side: a run with wheel w blown in a LEFT curve of
radius R and the run with the mirrored wheel (FL <-> FR, RL <-> RR; the X-split circuits FL+RR <-> FR+RL map onto
each other) blown in a RIGHT curve of -R must be mirror images: lateral offset, heading error and yaw rate negated,
wheel pressures swapped left/right. No sensor noise (the noise streams are drawn per sensor and are not mirrored).
Measured (M4): pressures and lane offsets bitwise, yaw rate within 1e-16 rad/s, forces within 1e-10 N (the sums
over the four wheels round in a different order). Were the right curve ignored (R <= 0 read as straight, the code
before) the mirrored run would drive a straight lane: its offset from the right curve's lane grows by metres.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

import vehicle_assist as va
from vehicle_assist.drivers import lane_keeper as lk
from vehicle_assist.scenarios.errors import InputError

MIRROR_WHEEL = {0: 1, 1: 0, 2: 3, 3: 2}
SWAP = {"fl": "fr", "fr": "fl", "rl": "rr", "rr": "rl"}


def _run(base, wheel, radius, sets):
    sc = va.load_scenario(base, sets=list(sets) + [f"vehicle.blowout.wheel_index={wheel}",
                                                  f"vehicle.lane_keeper.lane_radius_m={radius}"])
    return va.simulate(sc).trace


def test_right_circle_errors_closed_form():
    """Circle of R = -500 m (right turn, centre (0, -500)): a point on it with the tangent heading (clockwise) has zero
    error; 1 m to the LEFT of it (outside the right circle) reads e_y = +1 m; the right lane is the left one mirrored
    (e_y, e_psi negated exactly) and the feed-forward is negated."""
    r = 500.0
    th = 0.2
    x, y = r * math.sin(th), -(r - r * math.cos(th))
    ey, ep = lk.lane_errors(x, y, -th, -r)
    assert ey == pytest.approx(0.0, abs=1e-9) and ep == pytest.approx(0.0, abs=1e-9)
    ey, _ = lk.lane_errors(x + math.sin(th), y + math.cos(th), -th, -r)  # left normal (-sin psi, cos psi), psi = -th
    assert ey == pytest.approx(1.0, abs=1e-6)
    for gx, gy, psi in ((30.0, 1.2, 0.05), (120.0, -3.0, -0.2), (400.0, 90.0, 0.9)):
        el, pl = lk.lane_errors(gx, gy, psi, r)
        er, pr = lk.lane_errors(gx, -gy, -psi, -r)
        assert (er, pr) == (-el, -pl)
    k = lk.understeer_gradient(1700.0, 1.159, 1.417, 1.0e5, 1.1e5)
    assert lk.curve_steer_rad(-650.0, 30.0, 2.576, k) == -lk.curve_steer_rad(650.0, 30.0, 2.576, k) < 0.0


CASES = [  # (base scenario, blown wheel in the left curve, R, extra sets): fixed / follow driver, with / without the
    # function, braking driver, front and rear wheels
    ("blowout_lf_60kph_paper", 0, 650.0, []),
    ("blowout_lf_60kph_off", 0, 650.0, []),
    ("blowout_braking_60kph", 0, 1000.0, ['vehicle.lane_keeper.steering_mode="follow"']),
    ("blowout_braking_60kph_off", 0, 1000.0, ['vehicle.lane_keeper.steering_mode="follow"']),
    ("blowout_lf_60kph_paper", 2, 650.0, ['vehicle.lane_keeper.steering_mode="follow"', "run.initial_speed_kph=110"]),
    ("blowout_panic_stop_80kph", 3, 650.0, ["road.friction_mu=0.4"]),
]


@pytest.mark.parametrize("base,wheel,radius,sets", CASES)
def test_left_and_right_curves_are_mirror_images(base, wheel, radius, sets):
    a = _run(base, wheel, radius, sets)
    b = _run(base, MIRROR_WHEEL[wheel], -radius, sets)
    ya = np.asarray(a["lane_offset_m"])
    assert np.max(np.abs(ya)) > 0.02  # the run does something to compare
    for ch in ("lane_offset_m", "lane_heading_error_rad", "y_m"):
        np.testing.assert_allclose(np.asarray(b[ch]), -np.asarray(a[ch]), rtol=0, atol=1e-9, err_msg=ch)
    np.testing.assert_allclose(np.asarray(b["yaw_rate_radps"]), -np.asarray(a["yaw_rate_radps"]), rtol=0, atol=1e-12)
    np.testing.assert_allclose(np.asarray(b["x_m"]), np.asarray(a["x_m"]), rtol=0, atol=1e-9)
    for w, m in SWAP.items():
        np.testing.assert_allclose(np.asarray(b[f"wheel_pressure_{m}_pa"]), np.asarray(a[f"wheel_pressure_{w}_pa"]),
                                   rtol=0, atol=1e-3, err_msg=w)
    det_a = np.asarray(a["blowout_detected_wheel_index"])
    det_b = np.asarray(b["blowout_detected_wheel_index"])
    assert np.array_equal(det_b, np.where(det_a >= 0, np.vectorize(lambda v: MIRROR_WHEEL.get(int(v), v))(det_a), det_a))


def test_right_curve_starts_in_steady_cornering():
    """No blowout, 120 km/h on a 650 m RIGHT curve, lane-following driver: starts at yaw rate -u/R and stays within
    5 cm of the lane's circle (as the left-curve test in test_lane_keeper.py)."""
    sc = va.load_scenario("blowout_lf_60kph_off", sets=["vehicle.blowout.wheel_index=-1", "run.initial_speed_kph=120",
                                                        "vehicle.lane_keeper.lane_radius_m=-650",
                                                        'vehicle.lane_keeper.steering_mode="follow"'])
    tr = va.simulate(sc).trace
    assert np.max(np.abs(np.asarray(tr["lane_offset_m"]))) < 0.05
    assert float(np.asarray(tr["yaw_rate_radps"])[0]) == pytest.approx(-120 / 3.6 / 650, rel=1e-9)


@pytest.mark.parametrize("radius", [5.0, -5.0, 14.9, -14.9])
def test_radius_below_the_minimum_is_a_clear_error(radius):
    with pytest.raises((InputError, ValueError), match="lane_radius_m"):
        va.load_scenario("blowout_lf_60kph_paper", sets=[f"vehicle.lane_keeper.lane_radius_m={radius}"])


def test_shipped_right_curve_scenario_mirrors_the_left_one():
    """blowout_rf_80kph_right_curve (FR blown, R = -500 m) is the shipped blowout_lf_80kph_curve mirrored: its metrics
    are the left run's (per-side lane margins swapped, wheel index and moment estimate mirrored), and its checks are
    the left run's verdicts; the no-compensation twin leaves the lane (the negative control), the function keeps it."""
    left = va.simulate(va.load_scenario("blowout_lf_80kph_curve"))
    right = va.simulate(va.load_scenario("blowout_rf_80kph_right_curve"))
    off = va.simulate(va.load_scenario("blowout_rf_80kph_right_curve_off"))
    ml, mr = left.metrics, right.metrics
    swapped = {"blowout_lane_overshoot_left_m": "blowout_lane_overshoot_right_m",
               "blowout_lane_overshoot_right_m": "blowout_lane_overshoot_left_m",
               "blowout_lane_exceedance_left_m": "blowout_lane_exceedance_right_m",
               "blowout_lane_exceedance_right_m": "blowout_lane_exceedance_left_m"}
    for k in ("blowout_lateral_deviation_max_m", "blowout_lateral_deviation_3s_m", "blowout_yaw_rate_peak_radps",
              "blowout_opposite_pressure_max_pa", "blowout_balance_ratio_frac", *swapped):
        assert mr[swapped.get(k, k)] == pytest.approx(ml[k], rel=1e-9, abs=1e-9), k
    assert mr["blowout_detected_wheel_index"] == 1.0 and ml["blowout_detected_wheel_index"] == 0.0
    assert mr["blowout_moment_est_nm"] == pytest.approx(-ml["blowout_moment_est_nm"], rel=1e-9)
    assert [c.ok for c in right.checks] == [c.ok for c in left.checks]
    assert off.metrics["blowout_lane_departure_flag"] == 1.0 and mr["blowout_lane_departure_flag"] == 0.0
    # the twin drifts toward the blown (right, inner) side: beyond the RIGHT marking
    assert off.metrics["blowout_lane_overshoot_right_m"] > 1.0
