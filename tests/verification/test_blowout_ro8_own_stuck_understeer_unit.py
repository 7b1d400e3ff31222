"""RO8 (session 2026-11-25 o, review of O8): the gates of ``own_stuck_understeer_flag`` one call at a time.

O8's point tests (test_blowout_o8_own_stuck_understeer.py) let three of four mutants of the rule pass (RO8 in
tire_blowout_findings.md): dropping the curve-direction gate, dropping the dead band on the shortfall, and releasing
the INNER (blown, stuck) front instead of the outer one. These call ``own_stuck_front`` directly with a hand-made state
(FL blown with its own inlet stuck, FR = the outer front compensating at 40 bar, the driver's master 60 bar, so the
L8 floor at the driver's pressure releases nothing) and judge the requests against the rule's text: the references are
the TOML dead band and the detection speed, not the function's output. Value set explicitly per test.
"""
from __future__ import annotations

import numpy as np
import pytest

from vehicle_assist.functions import blowout_compensation as bc
from vehicle_assist.scenarios.runner import pack_records
from vehicle_assist.verification.envelope import load_envelope

KEY = "vehicle.blowout_compensation.own_stuck_understeer_flag"
BAR = 1.0e5
U_DET = 25.0
PT = {"speed": 92.0, "mu": 0.5, "braking": "brakes", "wheel": "fl", "driver": "fixed", "curve": "r1000",
      "fault": "inlet_stuck_fl"}


def _p(value):
    env = load_envelope("tire_blowout_faults")
    sc = env.scenario(PT).with_sets(f"{KEY}={value}")
    return pack_records([sc.vehicle.flat()])[0]


def _call(value, yaw_err, r_curve, v_ref=U_DET):
    """FL (0) blown, own inlet stuck, 1 bar; FR (1) the outer front compensating at 40 bar; driver 60 bar."""
    p = _p(value)
    st = bc.initial_state()
    st[bc.S_GB_U0] = U_DET
    p_est = np.array([1.0, 40.0, 20.0, 20.0]) * BAR
    requests = np.full(4, bc.Q_NONE, dtype=np.int64)
    bc.own_stuck_front(st, 0, 1, yaw_err, p_est, 60.0 * BAR, requests, p, r_curve, v_ref)
    return [int(q) for q in requests], p.blowout_compensation_yaw_deadband_radps


@pytest.mark.parametrize("value", [1, 2])
def test_understeer_in_curve_toward_blown_releases_outer_front_only(value):
    """Curve toward FL (+0.04 rad/s at u_det), yaw short of it by the band + 0.005: the OUTER front (FR) released, the
    inner (blown, stuck) front untouched. Value 0 keeps the driver's 60-bar floor: FR not released (FAILS at 0)."""
    db = _p(value).blowout_compensation_yaw_deadband_radps
    req, _ = _call(value, -(db + 0.005), +0.04)
    assert req[1] == bc.Q_RELEASE, req
    assert req[0] == bc.Q_NONE, req


@pytest.mark.parametrize("value", [1, 2])
def test_shortfall_inside_dead_band_does_nothing(value):
    """At the detection speed a shortfall inside the dead band (band - 0.005) releases nothing."""
    db = _p(value).blowout_compensation_yaw_deadband_radps
    req, _ = _call(value, -(db - 0.005), +0.04)
    assert req == [bc.Q_NONE] * 4, req


@pytest.mark.parametrize("value", [1, 2])
def test_curve_away_from_blown_side_does_nothing(value):
    """The same shortfall sign in a curve AWAY from the blown front (-0.04 rad/s): not the rule's premise."""
    db = _p(value).blowout_compensation_yaw_deadband_radps
    req, _ = _call(value, -(db + 0.005), -0.04)
    assert req == [bc.Q_NONE] * 4, req


def test_value2_scales_the_shortfall_by_detection_speed():
    """Value 2 judges yaw_err * u_det / u: at half the detection speed 0.6 x band counts as 1.2 x band (released);
    value 1 judges the plain yaw rate (not released)."""
    db = _p(2).blowout_compensation_yaw_deadband_radps
    assert _call(2, -0.6 * db, +0.04, v_ref=U_DET / 2)[0][1] == bc.Q_RELEASE
    assert _call(1, -0.6 * db, +0.04, v_ref=U_DET / 2)[0][1] == bc.Q_NONE
