"""HBA threshold calibration study (procedures/hba_calibration.py).

References: the controller itself (functions/brake_assist.py run in the kernel) for the offline entry test at
the paper's 30 bar / 3500 bar/s; monotonicity (a higher threshold can only detect fewer drivers).
"""
from __future__ import annotations

import numpy as np

from vehicle_assist.procedures import hba_calibration as C


def test_offline_entry_test_agrees_with_the_controller_and_maps_are_monotone() -> None:
    drivers, det, far, kernel, batch = C.study(n_per_kind=10, seed=7)
    offline = C.detections(batch.channels, *C.PAPER_POINT)
    assert np.array_equal(offline, kernel)
    assert kernel.any() and not kernel.all()  # the population straddles the thresholds
    for m in (det, far):
        assert np.all(np.diff(m, axis=0) <= 1e-12) and np.all(np.diff(m, axis=1) <= 1e-12)
    assert det.max() == 1.0  # low thresholds catch every panic driver
