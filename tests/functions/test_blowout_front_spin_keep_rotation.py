"""``front_spin_keep_flag`` (session g, G5) keeps a running FRONT compensation beyond the stable region only in the spin
TOWARD the blown side (``front_spin_keep_rotation_flag``; independent review RG2, session 2026-11-24 g).

G5's rule decided on the yaw DEVIATION from the steering reference alone. References, independent of the rule's code:
Rajamani, Vehicle Dynamics and Control (2nd ed. 2012) ch. 8 - the desired yaw rate is bounded by 0.85*mu*g/u (the bound
the refusal uses), so beyond it a reference further out than the measured rotation is no target the road carries; the
moment of the compensating front (FR braked for a blown FL: clockwise) adds to a clockwise rotation (the rule's own
text: "rotating AWAY from the blown side the compensation's moment would add to the rotation: refused as before");
the sign kinematics of a spin (heading turning past the velocity: beta points away from the rotation -
spin_front_applies, independent review V). Closed forms: beta_dot = a_y/u - r integrated from the detection."""
from __future__ import annotations

import numpy as np
import pytest

import vehicle_assist as va
from tests.support import BlowoutEcu
from vehicle_assist.functions import blowout_compensation as bc
from vehicle_assist.scenarios.runner import pack_records

V = 60.0 / 3.6
FAST = 1.5 * V
R_BOUND = 0.85 * 0.8 * 9.81 / V  # Rajamani's bound at the ECU's mu 0.8: 0.400 rad/s at 60 km/h
BETA_BOUND = np.arctan(0.02 * 0.8 * 9.81)  # 0.156 rad
BLOWN_LF = dict(vw=(FAST, V, V, V), tpms=1.0)  # both sources: no yaw-plausibility rejection


@pytest.fixture(scope="module")
def params():
    return pack_records([va.load_scenario("blowout_lf_60kph_paper").vehicle.flat()])[0]


Ecu = BlowoutEcu  # tests/support.py: the ECU loop on given measurements


def _steer_for(p, r_ref):
    """Road-wheel angle whose steady-state reference yaw rate at V is ``r_ref`` (reference_yaw_rate is linear in it)."""
    return r_ref / bc.reference_yaw_rate(1.0, V, p)


def _hold(p, flag=None):
    """HOLD after a two-source FL detection; ``flag`` None = the shipped toml value, else
    front_spin_keep_rotation_flag."""
    changes = {} if flag is None else {"blowout_compensation_front_spin_keep_rotation_flag": flag}
    e = Ecu(p, **changes).run(0.2).run(0.4, **BLOWN_LF)
    assert e.mode == "HOLD"
    return e


def test_rotating_away_beyond_the_bound_with_the_reference_further_out_is_refused(params):
    """FL blown, the driver steering right for -1.3 x the bound (-0.52 rad/s), the car rotating right at -1.1 x the
    bound (beyond it, AWAY from FL): the deviation +0.08 rad/s points toward FL, but the rotation does not - the FR's
    clockwise moment would add to it. Refused (FR back to the driver and ABS); with the defect (flag 0) kept."""
    steer = _steer_for(params, -1.3 * R_BOUND)
    assert bc.reference_yaw_rate(steer, V, params) == pytest.approx(-1.3 * R_BOUND, rel=1e-9)
    e = _hold(params).run(0.005, yaw=-1.1 * R_BOUND, steer=steer, **BLOWN_LF)
    assert e.rows[-1] == ("HOLD", "REFUSED", "beyond_stable_region") and e.req[1] == bc.Q_NONE
    d = _hold(params, 0.0).run(0.005, yaw=-1.1 * R_BOUND, steer=steer, **BLOWN_LF)
    assert d.mode == "HOLD", d.rows


def test_rotating_toward_the_blown_side_still_kept(params):
    """G5's case is kept: straight steering, the car rotating toward FL at 1.1 x the bound - no refusal."""
    e = _hold(params).run(0.005, yaw=1.1 * R_BOUND, **BLOWN_LF)
    assert e.mode == "HOLD" and e.req[1] in (bc.Q_HOLD, bc.Q_PULSE)


def test_sideslip_of_the_opposite_rotation_is_refused(params):
    """Sideslip-bound trigger: yaw +0.2 rad/s (toward FL, half the yaw bound, deviation toward FL) with a_y = u*0.4:
    beta_dot = a_y/u - r = +0.2 rad/s, beta crosses +0.156 rad (TOWARD FL: the slide of the opposite rotation) after
    0.78 s (closed form). Refused on the sideslip bound; with the defect kept."""
    t_cross = BETA_BOUND / 0.2
    e = _hold(params).run(round(t_cross + 0.03, 3), yaw=0.2, a_y=V * 0.4, **BLOWN_LF)
    assert ("HOLD", "REFUSED", "beyond_stable_region") in e.rows and e.st[bc.S_LIMIT_CODE] == bc.LIMIT_SIDESLIP_BOUND
    d = _hold(params, 0.0).run(round(t_cross + 0.03, 3), yaw=0.2, a_y=V * 0.4, **BLOWN_LF)
    assert d.mode == "HOLD", d.rows


def test_sideslip_of_the_spin_toward_the_blown_side_still_kept(params):
    """The slide of the spin toward FL (a_y = 0: beta_dot = -0.2 rad/s, beta away from FL) is G5's case: kept."""
    t_cross = BETA_BOUND / 0.2
    e = _hold(params).run(round(t_cross + 0.03, 3), yaw=0.2, **BLOWN_LF)
    assert e.mode == "HOLD", e.rows


# ---- front_spin_keep_arrest_flag: the keep only while the spin is being arrested ---------------------------------
def test_kept_while_the_rotation_turns_back(params):
    """FL blown, HOLD, the car beyond the yaw bound rotating toward FL at 1.3 x the bound and falling by 0.2 % of the
    bound per period: the outer-front brake is arresting it - kept (no refusal) for 0.5 s."""
    e = _hold(params)
    for k in range(100):
        e.run(0.005, yaw=(1.3 - 0.002 * k) * R_BOUND, **BLOWN_LF)
    assert e.mode == "HOLD", e.rows


def test_refused_when_the_rotation_keeps_growing(params):
    """The same car whose rotation toward FL keeps reaching new highs (+0.1 % of the bound per period): after the yaw
    mode's time constant (settling_time_s / 4 = 0.125 s at 60 km/h, closed form 2/a_1) the keep has not arrested it -
    refused, as before front_spin_keep_flag; with the defect (flag 0) kept to the end."""
    tau = 0.25 * bc.settling_time_s(V, params)
    assert tau == pytest.approx(0.125, abs=0.01)
    e = _hold(params)
    d = Ecu(params, blowout_compensation_front_spin_keep_arrest_flag=0.0).run(0.2).run(0.4, **BLOWN_LF)
    for k in range(60):
        e.run(0.005, yaw=(1.1 + 0.001 * k) * R_BOUND, **BLOWN_LF)
        d.run(0.005, yaw=(1.1 + 0.001 * k) * R_BOUND, **BLOWN_LF)
    assert ("HOLD", "REFUSED", "beyond_stable_region") in e.rows
    assert d.mode == "HOLD", d.rows


# random 7 b64 -R braking=brakes -R wheel=fl,fr, history #32 (tire_blowout_findings.md RG2)
P32 = {"speed": 106.80442449144316, "mu": 0.428669191692977, "delay": 0.3414353862539548,
       "wheel_speed_noise": 0.06271122235923189, "noise_seed": 5516.0, "brake_gain": 1.0845858509340665,
       "brake.start_s": 0.6306299023003397, "brake.level_frac": 0.37208577075880755,
       "brake.rate_per_s": 0.4895576316374359, "braking": "brakes", "wheel": "fl", "driver": "fixed", "curve": "r650"}
METRIC = "blowout_lateral_deviation_run_max_m"
KEEP = "vehicle.blowout_compensation.front_spin_keep_flag"


@pytest.fixture(scope="module")
def runs32():
    from tests.support import envelope_point_run
    from vehicle_assist.verification.envelope import load_envelope

    env = load_envelope("tire_blowout")
    return {"on": envelope_point_run(env, P32),
            "refused": envelope_point_run(env, P32, sets=(f"{KEEP}=0",)),
            "none": envelope_point_run(env, P32, baseline=True)}


def test_32_kept_compensation_no_worse_than_refused(runs32):
    """#32 (FL 107 km/h mu 0.43, 650 m curve toward FL, fixed steering, slow pedal): beyond the bound 0.12 s after the
    detection; kept by front_spin_keep_flag alone the yaw rose 0.267 -> 0.325 rad/s over 1 s, the spin was slowed but
    never arrested and the car slid farther: 10.098 m vs 5.431 m refused (the code before G5). With the arrest rule
    refused once the rotation still grows after the time constant: 5.407 m. Reference: the code before G5 (refused).
    Session n (N1, class B, corrected): judged to standstill (13.8 s) both cars leave the road (unclipped run max 5.489
    vs 5.431 m: a distance beyond the road edge, which the requirement no longer ranks), so the test compares what
    tire_blowout's two never-worse rows compare: road deviation 3.978 = 3.978 m (tie, the +0.05 m margin of before
    kept), the road departure 0.005 s LATER than refused (robustness +0.005 s)."""
    from tests.support import never_worse_rows

    rows = never_worse_rows(runs32["on"], runs32["refused"])
    assert rows["no_worse_than_no_compensation"] >= -0.05, rows
    assert rows["no_earlier_road_departure"] >= 0.0, rows


def test_32_no_worse_than_without_compensation(runs32):
    """Row no_worse_than_no_compensation (road deviation). Session n (N1, class D): the strict xfail of before (5.407 m vs
    none 4.414 m at 5 s, all three cars spinning) is gone under the new judgement: judged to standstill both cars leave
    the road (run max 5.489 vs 10.548 m), the road deviation ties at the road edge 3.978 m (robustness 0). Which car left
    first is the other row (next test)."""
    from tests.support import never_worse_rows

    assert never_worse_rows(runs32["on"], runs32["none"])["no_worse_than_no_compensation"] >= 0.0


@pytest.mark.xfail(strict=True, reason="N1 (session n): random 7 b64 braking FL/FR #32 to standstill: the function's car "
                   "leaves the road 0.18 s before the twin (earliness 27.025 vs 26.845 s; road deviation tie 3.978 m; "
                   "run max 5.489 vs 10.548 m): the kept-then-refused front compensation does not arrest the spin "
                   "toward FL, the car slides off the road first (all three cars spin)")
def test_32_no_earlier_road_departure_than_without_compensation(runs32):
    from tests.support import never_worse_rows

    assert never_worse_rows(runs32["on"], runs32["none"])["no_earlier_road_departure"] >= 0.0
