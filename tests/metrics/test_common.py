"""Tests of vehicle_assist.metrics.common against closed-form cases.

The jerk filter under test is the causal 2nd-order Butterworth at 5 Hz of common.md section 10
(cut-off assumed by the spec), started in steady state on the first sample.
"""
from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from vehicle_assist.core.trace import Trace
from vehicle_assist.metrics import common
from vehicle_assist.metrics.common import (
    METRICS,
    Metric,
    compute_metrics,
    filtered_jerk,
    launch_time_s,
    register,
)

DT_S = 1.0e-3


def rollback_trace(decel_mps2: float = 0.4, duration_s: float = 2.0) -> Trace:
    """Rolls back from rest with constant acceleration -a: v = -a t, x = -a t^2 / 2."""
    time_s = np.arange(0.0, duration_s + DT_S / 2, DT_S)
    return Trace({
        "time_s": time_s,
        "speed_mps": -decel_mps2 * time_s,
        "position_m": -0.5 * decel_mps2 * time_s**2,
        "accel_mps2": np.full_like(time_s, -decel_mps2),
    })


def test_rollback_of_constant_backward_acceleration() -> None:
    """Closed form: distance a T^2 / 2, speed a T (T = 2 s, a = 0.4 m/s^2 -> 0.8 m, 0.8 m/s)."""
    trace = rollback_trace()
    assert common.rollback_distance_m(trace) == pytest.approx(0.8, rel=1e-12)
    assert common.rollback_speed_mps(trace) == pytest.approx(0.8, rel=1e-12)
    assert common.peak_speed_mps(trace) == 0.0
    assert common.final_speed_mps(trace) == pytest.approx(-0.8, rel=1e-12)


def test_brake_energy_of_constant_deceleration_is_kinetic_energy() -> None:
    """Closed form: braking m at constant d from v0 to rest dissipates P = m d v(t), integral m v0^2 / 2.

    P is linear in t, so the trapezoid rule is exact up to rounding.
    """
    mass_kg, v0_mps, decel_mps2 = 1500.0, 10.0, 2.0
    time_s = np.arange(0.0, v0_mps / decel_mps2 + DT_S / 2, DT_S)
    speed_mps = v0_mps - decel_mps2 * time_s
    trace = Trace({"time_s": time_s, "speed_mps": speed_mps, "brake_power_w": mass_kg * decel_mps2 * speed_mps})
    assert common.brake_drag_energy_j(trace) == pytest.approx(0.5 * mass_kg * v0_mps**2, rel=1e-12)


def test_clutch_energy_of_quadratic_power_matches_trapezoid_error() -> None:
    """Closed form: P = k t^2 on [0, T] integrates to k T^3 / 3; the trapezoid rule overshoots by k T h^2 / 6."""
    k, duration_s, h = 3.0e3, 1.5, 0.01
    time_s = np.linspace(0.0, duration_s, round(duration_s / h) + 1)
    trace = Trace({"time_s": time_s, "clutch_slip_power_w": k * time_s**2})
    expected_j = k * duration_s**3 / 3.0 + k * duration_s * h**2 / 6.0
    assert common.clutch_slip_energy_j(trace) == pytest.approx(expected_j, rel=1e-12)


def test_engine_metrics() -> None:
    time_s = np.arange(5) * 0.1
    trace = Trace({
        "time_s": time_s,
        "engine_speed_radps": np.array([80.0, 60.0, 0.0, 0.0, 0.0]),
        "engine_stalled_flag": np.array([0.0, 0.0, 1.0, 1.0, 1.0]),
    })
    assert common.engine_speed_min_radps(trace) == 0.0
    assert common.engine_speed_peak_radps(trace) == 80.0
    assert common.engine_stalled_flag(trace) == 1.0
    running = Trace({"time_s": time_s, "engine_stalled_flag": np.zeros(5)})
    assert common.engine_stalled_flag(running) == 0.0


# -- jerk ------------------------------------------------------------------------------------------
def test_constant_acceleration_has_zero_jerk_from_the_first_sample() -> None:
    """Closed form: a = const -> j = 0 everywhere (the filter starts in steady state, no start transient)."""
    trace = rollback_trace()
    np.testing.assert_allclose(filtered_jerk(trace), 0.0, atol=1e-9)


def test_linear_acceleration_ramp_gives_jerk_settling_at_the_slope() -> None:
    """Closed form: a = r t -> j -> r once the filter has settled (unit DC gain, constant lag on a ramp).

    The 5 Hz 2nd-order Butterworth settles within ~0.3 s; its step-response overshoot is ~4 %, so the
    jerk never exceeds 1.05 r.
    """
    ramp_mps3 = 2.0
    time_s = np.arange(0.0, 2.0 + DT_S / 2, DT_S)
    trace = Trace({"time_s": time_s, "accel_mps2": ramp_mps3 * time_s})
    jerk = filtered_jerk(trace)
    settled = time_s > 1.0
    np.testing.assert_allclose(jerk[settled], ramp_mps3, rtol=1e-6)
    assert jerk[0] == pytest.approx(0.0, abs=0.01 * ramp_mps3)  # causal: the filter has not seen the ramp yet
    assert np.max(jerk) <= 1.05 * ramp_mps3
    assert common.jerk_filtered_peak_mps3(trace) == pytest.approx(np.max(np.abs(jerk)))
    assert common.jerk_filtered_min_mps3(trace) >= -1e-9


def test_jerk_is_zero_while_held_and_a_step_gives_the_butterworth_peak_slope() -> None:
    """Held at rest (flag 1) contributes j = 0; after release, a step of 1 m/s^2 in a gives peak jerk
    w_n * exp(-pi/4) (w_n = 2 pi 5 Hz): the peak of the impulse response of a 2nd-order Butterworth
    (zeta = 1/sqrt 2), 14.32 m/s^3, where the raw sample difference would give 1 / dt = 1000 m/s^3.
    Tolerance 0.1 %: the discrete (bilinear, 1 kHz) filter and the central difference.
    """
    time_s = np.arange(0.0, 2.0 + DT_S / 2, DT_S)
    held = time_s < 1.0
    accel_mps2 = np.where(held, 0.0, 1.0)
    trace = Trace({"time_s": time_s, "accel_mps2": accel_mps2, "vehicle_held_flag": held.astype(float)})
    jerk = filtered_jerk(trace)
    assert np.all(jerk[held] == 0.0)
    omega_n = 2.0 * np.pi * common.JERK_FILTER_CUTOFF_HZ
    assert common.jerk_filtered_max_mps3(trace) == pytest.approx(omega_n * np.exp(-np.pi / 4.0), rel=1e-3)
    assert common.jerk_filtered_min_mps3(trace) > -0.1 * omega_n  # only the small undershoot of the overshoot


def test_held_samples_are_zeroed_even_with_nonzero_acceleration() -> None:
    """Held flag wins over the acceleration channel: a held trace with a ramp in a has j = 0 everywhere."""
    time_s = np.arange(0.0, 1.0 + DT_S / 2, DT_S)
    trace = Trace({"time_s": time_s, "accel_mps2": 5.0 * time_s, "vehicle_held_flag": np.ones_like(time_s)})
    assert np.all(filtered_jerk(trace) == 0.0)
    assert common.jerk_filtered_peak_mps3(trace) == 0.0


def test_jerk_with_coarse_sampling_uses_unfiltered_acceleration() -> None:
    """At 10 Hz sampling the 5 Hz cut-off is the Nyquist frequency: j = gradient of a (a = r t -> r)."""
    time_s = np.arange(0.0, 1.01, 0.1)
    trace = Trace({"time_s": time_s, "accel_mps2": 3.0 * time_s})
    np.testing.assert_allclose(filtered_jerk(trace), 3.0, rtol=1e-9)


# -- launch ----------------------------------------------------------------------------------------
def launch_trace(**extra: np.ndarray) -> Trace:
    time_s = np.arange(0.0, 3.0 + 0.005, 0.01)
    speed_mps = np.clip(time_s - 1.2, 0.0, None)  # moves from t = 1.2 s at 1 m/s^2: 0.5 m/s at t = 1.7 s
    return Trace({"time_s": time_s, "speed_mps": speed_mps, **{k: v(time_s) for k, v in extra.items()}})


def test_launch_time_from_brake_release() -> None:
    """Brake applied from 0.2 s, released at 1.0 s; speed reaches 0.5 m/s at 1.7 s -> 0.7 s."""
    trace = launch_trace(
        brake_pedal_frac=lambda t: np.where((t >= 0.2) & (t < 1.0 - 1e-9), 0.6, 0.0),
        accelerator_frac=lambda t: np.where(t > 0.5, 0.3, 0.0),
    )
    assert launch_time_s(trace) == pytest.approx(0.7, abs=1e-9)
    assert launch_time_s(trace, speed_threshold_mps=1.0) == pytest.approx(1.2, abs=1e-9)


def test_launch_time_without_brake_starts_at_accelerator() -> None:
    """Brake never applied, accelerator from 0.5 s; speed 0.5 m/s at 1.7 s -> 1.2 s."""
    trace = launch_trace(
        brake_pedal_frac=lambda t: np.zeros_like(t),
        accelerator_frac=lambda t: np.where(t > 0.5 - 1e-9, 0.3, 0.0),
    )
    assert launch_time_s(trace) == pytest.approx(1.2, abs=1e-9)


def test_launch_time_without_pedals_starts_at_time_zero_and_nan_if_never() -> None:
    assert launch_time_s(launch_trace()) == pytest.approx(1.7, abs=1e-9)
    assert np.isnan(launch_time_s(launch_trace(), speed_threshold_mps=5.0))
    held_brake = launch_trace(brake_pedal_frac=lambda t: np.ones_like(t))
    assert np.isnan(launch_time_s(held_brake))


# -- registry --------------------------------------------------------------------------------------
def test_compute_metrics_uses_only_available_channels() -> None:
    """An EV-like trace has no engine or clutch channels: those metrics are skipped, not NaN."""
    trace = rollback_trace()
    result = compute_metrics(trace)
    assert "engine_speed_min_radps" not in result and "clutch_slip_energy_j" not in result
    assert {"rollback_distance_m", "rollback_speed_mps", "jerk_filtered_peak_mps3", "launch_time_s"} <= set(result)
    assert all(isinstance(v, float) for v in result.values())


def test_compute_metrics_by_name() -> None:
    trace = rollback_trace()
    assert list(compute_metrics(trace, ["rollback_speed_mps", "rollback_distance_m"])) == [
        "rollback_speed_mps", "rollback_distance_m"]
    with pytest.raises(ValueError, match="engine_speed_radps"):
        compute_metrics(trace, ["engine_speed_min_radps"])


def test_unknown_metric_name_suggests_the_closest() -> None:
    with pytest.raises(ValueError, match=r"did you mean 'rollback_distance_m'\?") as info:
        compute_metrics(rollback_trace(), ["rollback_distance"])
    assert "known metrics:" in str(info.value) and "launch_time_s" in str(info.value)


def test_register_adds_a_metric_and_refuses_duplicates(monkeypatch) -> None:
    monkeypatch.setattr(common, "METRICS", dict(METRICS))
    metric = Metric("duration_s", lambda t: float(t.time_s[-1] - t.time_s[0]), ("time_s",), "run length")
    register(metric)
    assert compute_metrics(rollback_trace(), ["duration_s"]) == {"duration_s": pytest.approx(2.0)}
    with pytest.raises(ValueError, match="already registered"):
        register(metric)
    register(metric, replace=True)
    assert "duration_s" not in METRICS  # the module registry was swapped out for this test only


def test_metric_names_carry_a_unit_suffix() -> None:
    from vehicle_assist.units import unit_of

    for name, metric in METRICS.items():
        assert metric.name == name
        assert unit_of(name), f"{name} has no unit suffix"


@settings(max_examples=60, deadline=None)
@given(arrays(np.float64, st.integers(2, 40), elements=st.floats(-1e3, 1e3)))
def test_rollback_is_non_negative_and_zero_for_forward_motion(values: np.ndarray) -> None:
    """Property: rollback >= 0; a non-decreasing position / non-negative speed gives exactly 0."""
    time_s = np.arange(len(values)) * 0.1
    trace = Trace({"time_s": time_s, "position_m": values, "speed_mps": values})
    assert common.rollback_distance_m(trace) >= 0.0
    assert common.rollback_speed_mps(trace) >= 0.0
    forward = Trace({"time_s": time_s, "position_m": np.cumsum(np.abs(values)), "speed_mps": np.abs(values)})
    assert common.rollback_distance_m(forward) == 0.0
    assert common.rollback_speed_mps(forward) == 0.0


def test_row_metric_gives_each_run_its_own_rows() -> None:
    """metrics/common.py row_metric (the row loop of the blowout and brake-assist metrics): fn sees one run's rows
    and the shared time base. Reference, closed form: x_i = a_i t crosses 1 m at t = 1/a_i (a_i = 1, 2, 4 m/s ->
    1, 0.5, 0.25 s on the 1 ms grid); a single run gives a float, and -0.0 shows as 0.0."""
    time_s = np.arange(0.0, 2.0 + DT_S / 2, DT_S)
    rates = np.array([1.0, 2.0, 4.0])
    x = rates[:, None] * time_s[None, :]

    def crossing(t, xr):
        return float(t[np.argmax(xr >= 1.0 - 1e-12)])

    metric = common.row_metric(crossing, ("position_m",))
    out = metric(Trace({"time_s": time_s, "position_m": x}))
    assert isinstance(out, np.ndarray)
    np.testing.assert_allclose(out, 1.0 / rates, rtol=0, atol=DT_S / 2)
    single = metric(Trace({"time_s": time_s, "position_m": x[1]}))
    assert isinstance(single, float) and single == pytest.approx(0.5, abs=DT_S / 2)
    negative_zero = common.row_metric(lambda t, xr: -0.0, ("position_m",))(Trace({"time_s": time_s, "position_m": x[0]}))
    assert np.copysign(1.0, negative_zero) == 1.0
