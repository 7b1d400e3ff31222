"""The spin-front rule's friction-free trigger (``phase_plane_flag``, functions/blowout_compensation.py
``phase_plane_unstable``; session 2026-11-24 e, R2): the sideslip phase plane |beta_dot + B1*beta| > B2 (Inagaki,
Kushiro, Yamamoto, AVEC 1994 / JSAE Review 1995, dry-road boundary B1 = 2.49 1/s, B2 = 9.55 deg/s) on the measured
beta_dot = a_y/u - r and its integral. References: the published boundary (corners in degrees), the steady-curve
kinematics u*r = a_y (no sideslip growth on any friction), and the falsifier's counterexample (F2 random 7 #7) against
its no-compensation twin. Each check fails with the seeded defect phase_plane_flag = 0 (the mu-0.8 bounds alone)."""
from __future__ import annotations

import math

import numpy as np
import pytest

import vehicle_assist as va
from vehicle_assist.functions import blowout_compensation as bc
from vehicle_assist.scenarios.runner import pack_records

PP0 = "vehicle.blowout_compensation.phase_plane_flag=0"
METRIC = "blowout_lateral_deviation_run_max_m"
DEG = math.pi / 180.0


@pytest.fixture(scope="module")
def params():
    return pack_records([va.load_scenario("blowout_lf_60kph_paper").vehicle.flat()])[0]


@pytest.mark.parametrize("beta_deg, beta_dot_deg_s, outside", [
    (0.0, 9.4, False), (0.0, 9.7, True), (0.0, -9.7, True),  # intercept 9.55 deg/s
    (3.78, 0.0, False), (3.89, 0.0, True), (-3.89, 0.0, True),  # beta axis: 9.55/2.49 = 3.835 deg
    (2.0, -4.9, False), (2.0, 4.6, True),  # 4.98 - 4.9 = 0.08; 4.98 + 4.6 = 9.58 deg/s
])
def test_boundary_of_the_published_region(params, beta_deg, beta_dot_deg_s, outside):
    """The region |beta_dot + 2.49*beta| <= 9.55 deg/s in the ECU's SI units (rad, rad/s): the degree corners of the
    published boundary land on the right side (a unit slip, e.g. B2 left in deg/s, moves them by 57x)."""
    assert bc.phase_plane_unstable(beta_deg * DEG, beta_dot_deg_s * DEG, params) is outside


def test_flag_zero_never_fires(params):
    p = params.copy()
    p.blowout_compensation_phase_plane_flag = 0.0
    assert not bc.phase_plane_unstable(0.2, 1.0, p)


V = 60.0 / 3.6
FAST = V * 0.359 / 0.24  # a fully deflated wheel's reading (tire_blowout.md 7)


def _rl_blowout(p, yaw, a_y, s=0.1):
    """Rear-left blowout confirmed by both sources, then ``s`` seconds at the given yaw rate / lateral acceleration."""
    st = bc.initial_state()
    ev = np.zeros((64, 5))
    req = np.zeros(4, dtype=np.int64)
    n, t, dt = 0, 0.0, 0.005
    vw = np.array([V, V, FAST, V])
    for k in range(int(round((0.2 + s) / dt))):
        y, ay = (0.0, 0.0) if k * dt < 0.2 else (yaw, a_y)
        v_ref = bc.reference_step(st, vw, 0.0, 3.0, dt, p)
        n = bc.blowout_step(st, vw, v_ref, 0.0, 0.0, y, 0.0, 3.0, np.ones(4), np.zeros(4), p, dt, t, 6, ev, n, req, ay)
        t += dt
    return st


def test_sliding_rear_triggers_the_spin_front_rule_below_the_yaw_bound(params):
    """Yaw 0.25 rad/s toward the blown (left) side at 60 km/h, below the mu-0.8 bound 0.85*0.8*g/u = 0.40 rad/s, with a
    lateral acceleration of only 0.3*u*r: the sideslip grows at a_y/u - r = -0.175 rad/s = -10.0 deg/s, outside the
    region: the front-right wheel takes the counter-brake (LIMITED, code 5). With the defect: still the rear (RR)."""
    st = _rl_blowout(params, 0.25, 0.3 * V * 0.25)
    assert bc.MODES[int(st[bc.S_MODE])] == "LIMITED" and int(st[bc.S_LIMIT_CODE]) == bc.LIMIT_SPIN_FRONT
    assert int(st[bc.S_TARGET]) == 1  # FR
    p0 = params.copy()
    p0.blowout_compensation_phase_plane_flag = 0.0
    st0 = _rl_blowout(p0, 0.25, 0.3 * V * 0.25)
    assert int(st0[bc.S_LIMIT_CODE]) != bc.LIMIT_SPIN_FRONT and int(st0[bc.S_TARGET]) == 3  # RR


def test_steady_curve_does_not_trigger(params):
    """A steady curve (a_y = u*r: no sideslip growth) at 0.35 rad/s toward the blown side, 5.8 m/s^2 - above what a
    wet road carries: the friction-free criterion stays quiet (only a growing sideslip is a spin)."""
    st = _rl_blowout(params, 0.35, V * 0.35, s=0.4)
    assert int(st[bc.S_LIMIT_CODE]) != bc.LIMIT_SPIN_FRONT and int(st[bc.S_TARGET]) == 3


# F2 (session 2026-11-24 e) random seed 7 b32 #7 (envelope data/envelopes/tire_blowout.toml): RL 110.1 km/h, friction
# scale 0.48, light pedal (44 N) from t_b + 0.24 s, 1000 m, pads at 71 %, wheel-speed noise 0.097 rad/s. With the mu-0.8
# bounds alone the rule moved the counter-brake to FR only at 3.385 s: 17.33 m vs none 15.94 m.
F_R7_RANDOM7_7 = {"speed": 110.09750464874168, "mu": 0.4796084032566129, "delay": 0.2828648956225929,
                  "wheel_speed_noise": 0.09664899293406753, "noise_seed": 7512.0, "brake_gain": 0.7125984354008801,
                  "brake.start_s": 1.244370545130408, "brake.level_frac": 0.04426463836053247,
                  "brake.rate_per_s": 3.7104449793907452, "braking": "brakes", "wheel": "rl", "driver": "fixed",
                  "curve": "r1000"}  # as in test_blowout_never_worse.py (/tmp/F2/random_7/falsify.json history #7)


@pytest.fixture(scope="module")
def r7_7():
    from vehicle_assist.verification.envelope import load_envelope

    env = load_envelope("tire_blowout")
    on = env.scenario(F_R7_RANDOM7_7)
    return {"on": va.simulate(on), "off": va.simulate(env.scenario(F_R7_RANDOM7_7, baseline=True)),
            "defect": va.simulate(on.with_sets(PP0))}


def _transfer_s(r):
    ev = [e.time_s for e in r.events if e.machine == "blowout_compensation" and e.to_mode == "LIMITED"]
    return ev[0] if ev else math.inf


def test_random7_7_no_worse_than_no_compensation(r7_7):
    """Requirement tire_blowout.no_worse_than_no_compensation (run max lateral deviation, data/requirements/
    tire_blowout.toml): the compensated car no farther off than the same blowout without compensation.
    Session n (N1, class B, corrected): judged to standstill both cars leave the road (unclipped run max 24.737 vs
    18.600 m, distances beyond the road edge that the requirement no longer ranks); the test compares what the
    requirement compares: road deviation tie 3.978 m, the function's car leaves the road 0.070 s after the twin."""
    from tests.support import never_worse_rows

    assert r7_7["on"].metrics["blowout_limit_code"] == 5
    rows = never_worse_rows(r7_7["on"], r7_7["off"])
    assert min(rows.values()) >= 0.0, rows
    assert _transfer_s(r7_7["on"]) < _transfer_s(r7_7["defect"]) - 0.5  # the slide seen, not the late yaw bound


@pytest.mark.xfail(strict=True, reason=(
    "N5 (session n, class C): judged to standstill by both rows of the requirement phase_plane_flag = 0 is no longer "
    "worse than the twin: all three cars leave the road (road deviation tie 3.978 m), the defect 0.060 s AFTER the twin "
    "(earliness 27.925 vs 27.985 s; unclipped 59.733 vs 18.600 m beyond the road edge); the shipped trigger leaves it "
    "0.010 s after the defect (27.915 s)"))
def test_random7_7_worse_with_the_mu08_bounds_alone(r7_7):
    """Negative control: phase_plane_flag = 0 (the trigger before) is the falsifier's counterexample again. N5 (session
    n): judged as the requirement judges (tests/support.never_worse_rows, both rows): a strict xfail (reason)."""
    from tests.support import never_worse_rows

    rows = never_worse_rows(r7_7["defect"], r7_7["off"])
    assert min(rows.values()) < 0.0, rows
