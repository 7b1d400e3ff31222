"""The closed-form 2nd-order Butterworth used for jerk equals scipy's design and filter
(independent reference: scipy.signal.butter + lfilter with steady-state initial conditions)."""
import numpy as np
import pytest
from scipy import signal

from vehicle_assist.metrics.common import _biquad, butter2_lowpass


@pytest.mark.parametrize("fs_hz", [100.0, 1000.0, 50.0])
def test_design_matches_scipy(fs_hz):
    """Coefficients agree with scipy.signal.butter(2, 5 Hz) to rounding (1e-12)."""
    b, a = butter2_lowpass(5.0, fs_hz)
    b_ref, a_ref = signal.butter(2, 5.0, btype="low", fs=fs_hz)
    np.testing.assert_allclose(b, b_ref, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(a, a_ref, rtol=1e-12, atol=1e-15)


def test_filter_matches_scipy_lfilter_with_steady_state_start():
    """Filtered output equals lfilter(..., zi=lfilter_zi*x0) on random data, rows filtered independently."""
    rng = np.random.default_rng(1)
    x = rng.standard_normal((3, 700)) + 2.0
    b, a = butter2_lowpass(5.0, 100.0)
    y = _biquad(b, a, x)
    for row in range(3):
        ref, _ = signal.lfilter(b, a, x[row], zi=signal.lfilter_zi(b, a) * x[row, 0])
        np.testing.assert_allclose(y[row], ref, rtol=1e-12, atol=1e-12)


def test_constant_input_passes_unchanged():
    """DC gain 1 and steady-state start: a constant acceleration gives exactly that constant (closed form)."""
    b, a = butter2_lowpass(5.0, 100.0)
    y = _biquad(b, a, np.full(300, 1.7))
    np.testing.assert_allclose(y, 1.7, rtol=0, atol=1e-12)
