"""plant/sensors.py: delay, bias, seeded noise and faults of the sampled measurements.

Model (module docstring): y_k = x(t_k - d) + bias + sigma*n_k, d a whole number of controller ticks
kept in a ring buffer of depth d + 1 (as the kernels size it); faults lost (value 0, ok 0), stuck
(holds the last good output, ok 1), bias (adds the fault value).
"""
from __future__ import annotations

import numpy as np
import pytest

from vehicle_assist.plant.sensors import FAULT_BIAS, FAULT_LOST, FAULT_NONE, FAULT_STUCK, FAULTS, sample_sensors


class Bank:
    """Drives sample_sensors for ``n`` sensors the way vehicles/*.py do (one call per controller tick)."""

    def __init__(self, n=1, delay_ticks=0, noise_std=0.0, bias=0.0):
        self.delay = np.full(n, float(delay_ticks))
        self.history = np.zeros((n, int(self.delay.max()) + 1))
        self.noise_std = np.full(n, float(noise_std))
        self.bias = np.full(n, float(bias))
        self.fault = np.zeros(n)
        self.fault_value = np.zeros(n)
        self.last = np.zeros(n)
        self.value = np.zeros(n)
        self.ok = np.zeros(n)
        self.tick = 0

    def sample(self, truth, noise_row=None):
        truth = np.atleast_1d(np.asarray(truth, dtype=float))
        noise_row = np.zeros_like(truth) if noise_row is None else np.atleast_1d(noise_row)
        sample_sensors(truth, self.history, self.tick, noise_row, self.noise_std, self.bias, self.delay,
                       self.fault, self.fault_value, self.last, self.value, self.ok)
        self.tick += 1
        return self.value.copy(), self.ok.copy()


@pytest.mark.parametrize("delay_ticks", [0, 1, 3, 7])
def test_delay_by_whole_ticks(delay_ticks) -> None:
    """y_k = x_{k-N}; before N samples exist the oldest sample (x_0) is returned."""
    bank = Bank(delay_ticks=delay_ticks)
    for k in range(30):
        y, ok = bank.sample(100.0 + k)
        assert y[0] == 100.0 + max(k - delay_ticks, 0)
        assert ok[0] == 1.0


def test_bias_and_noise_add() -> None:
    """y = x + bias + sigma*n exactly (hand numbers: 10 + 0.5 + 2*(-0.25) = 10)."""
    bank = Bank(noise_std=2.0, bias=0.5)
    y, _ = bank.sample(10.0, noise_row=-0.25)
    assert y[0] == 10.0


def test_noise_std_within_statistical_bounds() -> None:
    """Seeded standard-normal rows (as the runner draws them) times sigma = 3: over n = 20000 samples the
    sample mean is within 5 sigma/sqrt(n) of 0 and the sample std within 5 sqrt(1/(2n)) (relative) of sigma
    (5-sigma bounds: a false failure has probability ~1e-6; the seed makes the test deterministic anyway)."""
    n, sigma = 20000, 3.0
    rows = np.random.default_rng(12345).standard_normal((n, 2))
    bank = Bank(n=2, noise_std=sigma)
    bank.noise_std[1] = 0.0  # a noise-free sensor next to it must stay exact
    err = np.empty(n)
    for k in range(n):
        y, _ = bank.sample([7.0, 7.0], noise_row=rows[k])
        err[k] = y[0] - 7.0
        assert y[1] == 7.0
    assert abs(err.mean()) < 5 * sigma / np.sqrt(n)
    assert abs(err.std(ddof=1) / sigma - 1.0) < 5 * np.sqrt(1.0 / (2 * n))
    np.testing.assert_allclose(err, sigma * rows[:, 0], rtol=0, atol=1e-12)


def test_lost_gives_zero_and_not_ok() -> None:
    bank = Bank(n=2)
    bank.sample([3.0, 4.0])
    bank.fault[0] = FAULT_LOST
    y, ok = bank.sample([5.0, 6.0])
    assert (y[0], ok[0]) == (0.0, 0.0)
    assert (y[1], ok[1]) == (6.0, 1.0)


def test_stuck_holds_last_good_value_and_stays_ok() -> None:
    """Stuck: the output freezes at the last value before the fault (incl. its bias/noise), flag still 1."""
    bank = Bank(bias=1.0)
    bank.sample(2.0)
    y0, _ = bank.sample(3.0)
    assert y0[0] == 4.0
    bank.fault[0] = FAULT_STUCK
    for x in (10.0, -5.0, 99.0):
        y, ok = bank.sample(x)
        assert (y[0], ok[0]) == (4.0, 1.0)


def test_bias_fault_adds_its_value() -> None:
    bank = Bank(bias=0.5)
    bank.fault[0] = FAULT_BIAS
    bank.fault_value[0] = 2.0
    y, ok = bank.sample(1.0)
    assert (y[0], ok[0]) == (3.5, 1.0)


def test_fault_codes() -> None:
    assert FAULTS == {"none": FAULT_NONE, "lost": FAULT_LOST, "stuck": FAULT_STUCK, "bias": FAULT_BIAS}
    assert len(set(FAULTS.values())) == 4
