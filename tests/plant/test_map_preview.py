"""Map preview (electronic horizon, plant/map_preview.py) and what the sensor layer adds to it (issue #11).

References, independent of the code under test:
* the road's own geometry: curve_r65.xodr is a 400 m straight, a 100 m arc of R = 65 m, a straight (the file), so
  the true preview at position x is distance 400 - x, radius 65, length 100 (hand geometry);
* a hand-built two-curve map for ``next_curve`` (positions before, inside, between and after the curves);
* a pure delay: the measured value at t equals the true value at t - tau;
* noise: the sample mean and standard deviation of the radius error against the configured N(0, sigma^2)
  (bounds from the sampling distributions, > 5 sigma of the estimators, so the test fails for a wrong sigma but
  not by chance);
* faults: a map that is missing, scaled (1.5 x radius), offset (position error), and a lost channel.
"""
from __future__ import annotations

import numpy as np
import pytest

import vehicle_assist as va
from vehicle_assist.plant.map_preview import next_curve

CURVE_START_M, CURVE_LENGTH_M, RADIUS_M = 400.0, 100.0, 65.0  # curve_r65.xodr (file header)


def _run(*sets):
    base = ["vehicle.curve_shift.enabled_flag=0", "run.duration_s=30"]
    return va.simulate(va.load_scenario("curve_s80", base + list(sets))).trace


def _hand_map():
    dt = np.dtype([("road_curve_count", "f8"), ("road_curve_start_m", "f8", (2,)), ("road_curve_length_m", "f8", (2,)),
                   ("road_curve_radius_m", "f8", (2,))])
    rec = np.zeros(1, dtype=dt).view(np.recarray)
    rec.road_curve_count[0] = 2
    rec.road_curve_start_m[0] = (100.0, 300.0)
    rec.road_curve_length_m[0] = (50.0, 80.0)
    rec.road_curve_radius_m[0] = (40.0, 250.0)
    return rec[0]


@pytest.mark.parametrize("x, ref", [
    (0.0, (100.0, 40.0, 50.0, 0)), (120.0, (-20.0, 40.0, 50.0, 0)), (149.9, (-49.9, 40.0, 50.0, 0)),
    (150.0, (150.0, 250.0, 80.0, 1)), (379.0, (-79.0, 250.0, 80.0, 1)), (380.0, (0.0, 0.0, 0.0, -1))])
def test_next_curve_on_a_hand_built_map(x, ref):
    """The first curve whose end lies ahead: negative distance inside it, the next one once its end is passed."""
    d, r, length, idx = next_curve(_hand_map(), x)
    assert (d, r, length, idx) == pytest.approx(ref)


def test_true_preview_follows_the_road_geometry():
    """Distance 400 - x, radius 65, length 100 while the curve is within the 300 m range; invalid beyond the range
    and after the last curve."""
    tr = _run()
    x = tr["position_m"]
    valid = tr["preview_valid_flag"] > 0.5
    ahead = (CURVE_START_M - x <= 299.0) & (x < CURVE_START_M + CURVE_LENGTH_M - 1.0)
    assert np.all(valid[ahead])  # (1 m margins: one 10 ms sample)
    assert not np.any(valid[x > CURVE_START_M + CURVE_LENGTH_M + 1.0])
    d_meas = tr["preview_distance_m"][valid]
    assert np.max(np.abs(d_meas - (CURVE_START_M - x[valid]))) < 0.3  # one 10 ms sample at <= 30 m/s
    assert np.all(tr["preview_radius_m"][valid] == pytest.approx(RADIUS_M, abs=0.05))
    far = _run("run.initial_position_m=50")
    first = far["position_m"][np.argmax(far["preview_valid_flag"] > 0.5)]
    assert first == pytest.approx(CURVE_START_M - 300.0, abs=0.5)  # range_m = 300


def test_map_faults_missing_scaled_offset():
    """available_flag = 0: never valid; radius_scale_frac = 1.5: radius 97.5 m; distance_offset_m = 20: the map
    believes the car 20 m further on, so the distance reads 20 m short."""
    assert np.max(_run("vehicle.map_preview.available_flag=0")["preview_valid_flag"]) == 0.0
    tr = _run("vehicle.map_preview.radius_scale_frac=1.5")
    valid = tr["preview_valid_flag"] > 0.5
    assert np.all(tr["preview_radius_m"][valid] == pytest.approx(1.5 * RADIUS_M, abs=0.05))
    tr = _run("vehicle.map_preview.distance_offset_m=20")
    valid = (tr["preview_valid_flag"] > 0.5) & (tr["position_m"] < CURVE_START_M - 30.0)
    err = tr["preview_distance_m"][valid] - (CURVE_START_M - tr["position_m"][valid])
    assert np.median(err) == pytest.approx(-20.0, abs=0.3)


def test_latency_is_a_pure_delay():
    """sensors.curve_distance.delay_s = 0.5: the measured distance at t is the true distance at t - 0.5 s."""
    tau = 0.5
    tr = _run("sensors.curve_distance.delay_s=0.5")
    t = tr["time_s"]
    true_d = tr["curve_distance_true_m"]
    sel = (t > tau + 0.1) & (t < 20.0) & (tr["preview_valid_flag"] > 0.5)
    k = int(round(tau / 0.01))
    idx = np.nonzero(sel)[0]
    idx = idx[np.isfinite(true_d[idx - k])]
    assert len(idx) > 500
    assert np.max(np.abs(tr["preview_distance_m"][idx] - true_d[idx - k])) < 0.3  # one sample
    # and it is not the undelayed value: at ~20 m/s the half-second is ~10 m
    assert np.median(tr["preview_distance_m"][idx] - true_d[idx]) > 5.0


def test_radius_noise_has_the_configured_statistics():
    """sensors.curve_radius.noise_std_m = 5: radius error ~ N(0, 25). With n ~ 2000 samples the sample mean has a
    standard error 5/sqrt(n) ~ 0.11 m and the sample sd ~ 5/sqrt(2n) ~ 0.08 m: bounds 0.6 m and 0.5 m (> 5 sigma)."""
    tr = _run("sensors.curve_radius.noise_std_m=5")
    valid = tr["preview_valid_flag"] > 0.5
    err = tr["preview_radius_m"][valid] - RADIUS_M
    assert len(err) > 1500
    assert abs(np.mean(err)) < 0.6
    assert np.std(err) == pytest.approx(5.0, abs=0.5)
    # a different seed gives different noise with the same statistics
    tr2 = _run("sensors.curve_radius.noise_std_m=5", "run.seed=7")
    err2 = tr2["preview_radius_m"][tr2["preview_valid_flag"] > 0.5] - RADIUS_M
    assert np.std(err2) == pytest.approx(5.0, abs=0.5) and not np.allclose(err[:100], err2[:100])


def test_dropout_invalidates_the_preview_and_the_tcu_ignores_it():
    """A lost curve_valid channel (CAN timeout) from 4 s: the measured flag is 0 from then on, and with the strategy
    on the TCU leaves curve mode (preview_lost) and does not re-enter it."""
    ev = ["events=[{at_s = 4.0, action = \"sensor_fault\", sensor = \"curve_valid\", fault = \"lost\"}]"]
    tr = _run(*ev)
    t = tr["time_s"]
    assert np.max(tr["preview_valid_flag"][t > 4.01]) == 0.0
    assert np.max(tr["preview_valid_flag"][t < 3.9]) == 1.0
    r = va.simulate(va.load_scenario("curve_s80", ev))
    assert [e.reason for e in r.events if e.machine == "curve_shift"] == ["curve_command", "preview_lost"]
