"""Review RJ4 (session j; tire_blowout_findings.md "J9", "RJ4"): the SHIPPED heading-return baseline on one gyro sample.

test_blowout_false_alarm_heading.py::test_baseline_is_not_one_gyro_sample compares heading_return_mean_baseline_flag
1 (quiet) with 0 (a front released) and passes with both rows as measured - so the shipped value (0: S_GB_R0 = the one
yaw-error sample at the detection) shows green although it fails the claim the test states: a car that never turned,
one gyro sample of +-0.5 deg/s at the detection instant, must not get a front released after the rejection. This file
states the claim for the shipped configuration (no flag set), as a strict xfail (an honest red, the known open defect:
J9 did not ship the mean because the shipped split-mu row needs the one sample; RJ2 item B / C). When the rule no longer
holds a one-sample set-point the xfail turns XPASS and must be removed.

Review RL1 (session l): XPASS since heading_return_own_yaw_flag 4 (the rule's releases only turn the car TOWARD the
steered reference and are sized to the rate error to it: a car at the reference gets no release whatever the baseline
holds), so the xfail is removed; the one-sample baseline itself is unchanged (J9's mean stays a candidate). The row at
value 3 (L5: the sign gate alone, 0 <= 0 lets the release through at a zero yaw error) releases - the check can fail.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

import vehicle_assist as va
from vehicle_assist.functions import blowout_compensation as bc
from vehicle_assist.scenarios.runner import pack_records


def _released_after_spike(spike_deg_s, **sets):
    from tests.support import BlowoutEcu

    sc = va.load_scenario("blowout_lf_60kph_paper")  # as test_blowout_false_alarm_heading._params
    p = pack_records([sc.vehicle.flat()])[0]
    ecu = BlowoutEcu(p, v_mps=26.7, **sets)
    kw = dict(braking=1.0, p_est=(40.0e5,) * 4)
    ecu.run(0.2, **kw)
    n = int(round(p.blowout_compensation_detection_delay_s / 0.005))
    ecu.run(n * 0.005, tpms=2.0, **kw)  # FR named, the detection window
    ecu.run(0.005, tpms=2.0, yaw=math.radians(spike_deg_s), **kw)  # the detection sample: one gyro spike
    assert ecu.mode == "BUILD", ecu.rows
    st = ecu.st
    st[bc.S_GB_ON], st[bc.S_GB_B], st[bc.S_GB_PSI] = 1.0, 1.0, 0.0  # armed, caused heading 0 (the car never turned)
    released = False
    for _ in range(600):  # 3 s at the true yaw 0
        req = np.zeros(4, dtype=np.int64)
        bc.reject_heading_return(st, bc.REJECTED, 1.0, 0.0, 26.7, np.full(4, 40.0e5), req, ecu.p, 0.005)
        released |= bool(np.any(req == bc.Q_RELEASE))
    return released


@pytest.mark.parametrize("spike_deg_s", [-0.5, 0.5])
def test_shipped_rule_quiet_on_one_gyro_sample(spike_deg_s):
    assert not _released_after_spike(spike_deg_s)


@pytest.mark.parametrize("spike_deg_s", [-0.5, 0.5])
def test_value_3_releases_on_one_gyro_sample(spike_deg_s):
    """Negative control (RL1): with L5's value 3 (and at 0) the one-sample set-point releases a front."""
    assert _released_after_spike(spike_deg_s, blowout_compensation_heading_return_own_yaw_flag=3)
    assert _released_after_spike(spike_deg_s, blowout_compensation_heading_return_own_yaw_flag=0)
