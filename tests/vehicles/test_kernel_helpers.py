"""Helpers the vehicle kernels share (vehicles/common.py), against independent references."""
from __future__ import annotations

import numpy as np
import pytest

from vehicle_assist.vehicles.common import countdown


@pytest.mark.parametrize("every", [1, 2, 3, 7, 10])
def test_countdown_fires_at_the_multiples_of_its_period(every):
    """The sampling tick / trace row countdown fires at step k exactly when k % every == 0 (reference: the modulo
    it replaced in the kernels), first at step 0."""
    left = np.int64(0)
    fired = []
    for k in range(53):
        now, left = countdown(left, every)
        fired.append(bool(now))
    assert fired == [k % every == 0 for k in range(53)]
