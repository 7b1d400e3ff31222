"""Front-left blowouts on a wet curve with a braking driver (issue #10; docs/functions/tire_blowout_sessions.md, "Open at the end
of session 2026-11-23 d" item 2): the falsifier's counterexamples #15/#16 of tire_blowout.no_worse_than_no_compensation
(random seed 7, budget 32, --keep-going, over data/envelopes/tire_blowout.toml; findings F round 7 and F6).

Requirement: data/requirements/tire_blowout.toml ``no_worse_than_no_compensation`` (tire_blowout.md 9.5; conventions.md
'Evidence'): the largest lateral deviation from t_b to the end of the run with compensation is no larger than the same
blowout without compensation (paper 004 Fig. 4 curve 2; the envelope's baseline enabled_flag = 0).

Can fail: with the seeded defect braking_rule_flag = 0 (the rules before the braking rule) both points are worse than
no compensation (2.53 / 0.96 m vs 1.37 / 0.23 m at 7fc28cc); checked below as negative controls."""
from __future__ import annotations

import pytest

import vehicle_assist as va
from tests.support import envelope_point_metric
from vehicle_assist.verification.envelope import load_envelope

METRIC = "blowout_lateral_deviation_run_max_m"
DEFECT = "vehicle.blowout_compensation.braking_rule_flag=0"
# random seed 7 #15: FL 94.2 km/h, mu scale 0.308, 0.28 rad/s wheel-speed noise (a noise-triggered ABS dump on the
# compensating wheel), pads 11 % above nominal, 317 N from t_b + 0.82 s, following driver, 650 m curve
P15 = {"speed": 94.22989668538476, "mu": 0.30809293610645416, "delay": 0.16907369458553353,
       "wheel_speed_noise": 0.28150238605938416, "noise_seed": 5383, "brake_gain": 1.1057937013733754,
       "brake.start_s": 1.8160521632234516, "brake.level_frac": 0.3170528692383573, "brake.rate_per_s": 5.759416580184629,
       "braking": "brakes", "wheel": "fl", "driver": "follow", "curve": "r650"}
# random seed 7 #16 (F6): FL 108.3 km/h, mu scale 0.319, 0.095 rad/s noise, 177 N from t_b + 1.09 s
P16 = {"speed": 108.32072570734762, "mu": 0.3194725040509675, "delay": 0.18255684002250486,
       "wheel_speed_noise": 0.09540095935868467, "noise_seed": 1127, "brake_gain": 1.0133059096640604,
       "brake.start_s": 2.0949163507326665, "brake.level_frac": 0.17744909184105462, "brake.rate_per_s": 25.887981198219236,
       "braking": "brakes", "wheel": "fl", "driver": "follow", "curve": "r650"}


@pytest.fixture(scope="module")
def env():
    return load_envelope("tire_blowout")


def _dev(env, point, baseline=False, sets=()):
    return envelope_point_metric(env, point, METRIC, baseline, sets)


@pytest.fixture(scope="module")
def p15(env):
    return {"on": _dev(env, P15), "off": _dev(env, P15, baseline=True), "defect": _dev(env, P15, sets=[DEFECT])}


@pytest.fixture(scope="module")
def p16(env):
    return {"on": _dev(env, P16), "off": _dev(env, P16, baseline=True), "defect": _dev(env, P16, sets=[DEFECT]),
            "no_pedal_on": _dev(env, dict(P16, braking="none")),
            "no_pedal_off": _dev(env, dict(P16, braking="none"), baseline=True)}


def test_noisy_dump_point_no_worse(p15):
    """#15: after a noise-triggered ABS dump the compensating front wheel re-builds to its pre-dump pressure and takes
    its driver share while the car does not yaw away; the rear pair is held in its linear region at the measured
    friction (it had run 5-10 % slip at 30-40 bar and the car spun toward the blown side)."""
    assert p15["on"] <= p15["off"]


def test_noisy_dump_point_worse_with_the_defect(env, p15):
    """Negative control: braking_rule_flag = 0 (the old re-build to the lowered no-brake target) is worse than none
    (2.52 vs 1.37 m) - with the code before, i.e. also without gma_blown_front_flag (f57f9a5): that later ESP fix
    (the blown front no longer arms the GMA on the compensating wheel) alone takes this point to 0.78 m, so it is
    switched off here to show what the braking rule fixed."""
    before = _dev(env, P15, sets=[DEFECT, "vehicle.blowout_compensation.gma_blown_front_flag=0"])
    assert before > p15["off"]


def test_knife_edge_point_no_worse(p16):
    """#16 (F6): with the pedal the compensating front was capped at its friction circle at the MEASURED friction
    (12.5 bar; mu_meas 0.213 on a 0.319 road, lateral share 825 N) while the uncompensated twin's front carried 31 bar
    under ABS: ~2 vs 4.4 m/s^2, 0.312 vs 0.225 m. The measured friction is the pure-longitudinal Dugoff inversion on a
    wheel that carries its lateral share (combined slip), i.e. already the friction left for F_x next to F_y; the cap
    is that measured longitudinal capacity (front_circle_measured_flag; tire_blowout_findings.md X2). History: braking rule 0.96 ->
    0.54 m, rear circle 0.47 m, understeer rule 0.312 m."""
    assert p16["on"] <= p16["off"]


def test_knife_edge_point_worse_with_the_lateral_demand_counted_twice(env, p16):
    """Negative control: front_circle_measured_flag = 0 (the circle sqrt((mu_meas*F_z)^2 - F_y^2)) - 0.312 m vs none
    0.225 m at the commit of the flag. Session h (H1): front_abs_limit_flag lifts that cap under the pedal altogether,
    so the control isolates the circle with it at 0 (with it on: 0.185 m, the circle not reached). NOT SHIPPED CODE
    (session i, I2): with front_abs_limit_flag = 1 front_circle_measured_flag is unreachable (it acts only under the
    pedal with a measured friction, exactly where front_abs_limit lifts the cap); this control tests the
    front_abs_limit_flag = 0 configuration only - tests/functions/test_blowout_rear_circle_cap.py
    test_front_circle_measured_flag_is_dead_with_front_abs_limit checks that the flag is dead as shipped."""
    assert _dev(env, P16, sets=["vehicle.blowout_compensation.front_circle_measured_flag=0",
                                "vehicle.blowout_compensation.front_abs_limit_flag=0"]) > p16["off"]


def test_knife_edge_point_braking_no_worse_than_not_braking(p16):
    """What the braking rule does guarantee at #16: the compensated car that brakes goes no farther off than the same
    compensated car without the pedal (+5 % of it: assumed margin for the different speeds over the run). With the
    defect the compensating wheel ran at 13-15 % ABS slip on the wet curve and the braking car went 0.96 m off."""
    assert p16["on"] <= 1.05 * p16["no_pedal_on"]


def test_knife_edge_point_braking_worse_than_not_braking_with_the_defect(p16):
    """Negative control of the test above: braking_rule_flag = 0."""
    assert p16["defect"] > 1.05 * p16["no_pedal_on"]


# random seed 43 b32 #24 (session e, lead's falsifier at 0d1f516): FL 117.5 km/h, mu scale 0.433, 0.19 rad/s noise
# (seed 5529), pads nominal, 0.078 pedal (46 bar) from t_b + 1.08 s, following driver, 650 m curve
P43 = {"speed": 117.52309728149241, "mu": 0.43265407028814795, "delay": 0.04551680285283055,
       "wheel_speed_noise": 0.19145182515509998, "noise_seed": 5529, "brake_gain": 1.0033424001466735,
       "brake.start_s": 2.077024603994354, "brake.level_frac": 0.07773666364520873, "brake.rate_per_s": 27.310839118668028,
       "braking": "brakes", "wheel": "fl", "driver": "follow", "curve": "r650"}
# the code before the rear friction-circle cap, also without the later understeer rule (understeer_flag, session f: it
# lowers the compensating front before the pedal and with it this point is no longer worse than none even with the
# linear-region rear cap; the negative control shows what the rear cap fixed)
CIRCLE_DEFECT = ("vehicle.blowout_compensation.rear_circle_flag=0", "vehicle.blowout_compensation.understeer_flag=0")


def _rear_pressure_bar(env, point, baseline=False, sets=()):
    """Mean rear wheel-cylinder pressure [bar] from 0.3 s after the pedal to 2.0 s after it."""
    import numpy as np
    sc = env.scenario(point, baseline=baseline)
    tr = va.simulate(sc.with_sets(*sets) if sets else sc, requirements=False).trace
    t = np.asarray(tr["time_s"])
    w = (t >= point["brake.start_s"] + 0.3) & (t <= point["brake.start_s"] + 2.0)
    rear = 0.5 * (np.asarray(tr["wheel_pressure_rl_pa"]) + np.asarray(tr["wheel_pressure_rr_pa"]))
    return float(rear[w].mean()) / 1e5


@pytest.fixture(scope="module")
def p43(env):
    return {"on": _dev(env, P43), "off": _dev(env, P43, baseline=True),
            "defect": _dev(env, P43, sets=list(CIRCLE_DEFECT)),
            "rear_on": _rear_pressure_bar(env, P43), "rear_off": _rear_pressure_bar(env, P43, baseline=True),
            "rear_defect": _rear_pressure_bar(env, P43, sets=list(CIRCLE_DEFECT))}


def test_curve_braking_point_no_worse(p43):
    """#24 of random seed 43: the rear pair capped at its friction circle (with its lateral share, measured friction)
    keeps the driver's braking on the intact rear axle; the car slows and stays nearer the lane than without
    compensation (0.65 vs 0.84 m). Knife edge in the noise seed (tire_blowout_findings.md Q3): seeds 1-6 give
    -0.08..+0.35 m margins, the defect -0.32..+0.11 m; this is the falsifier's own point."""
    assert p43["on"] <= p43["off"]


@pytest.mark.xfail(strict=True, reason=(
    "N1 (session n, class C): judged to standstill the defect (rear_circle_flag = 0) is no longer worse than no "
    "compensation: 0.889 m (stopped 11.6 s) vs the twin's 0.949 m (stopped 8.8 s; both on the road): the twin, 0.84 m "
    "at 5 s, drifts on; the defect's 5-s loss was the window. The rule still beats the defect (0.121 vs 0.889 m)"))
def test_curve_braking_point_worse_with_the_defect(p43):
    """Negative control: rear_circle_flag = 0 (the linear-region cap) is worse than none (0.89 vs 0.84 m). Session n
    (N1, class C): a 5-s-window control, xfail(strict) with the numbers; the rule-vs-defect control at standstill is the
    next test."""
    assert p43["defect"] > p43["off"]


def test_curve_braking_point_rule_beats_the_defect_to_standstill(p43):
    """Session n (N1, class C, the replacement control): judged to standstill the rule is better than its defect at the
    same point: run max 0.121 m vs 0.889 m (both on the road, where it equals the requirement's road deviation)."""
    assert p43["on"] < p43["defect"]


def test_curve_braking_rear_axle_keeps_the_drivers_pressure(p43):
    """Independent reference = the uncompensated twin: its rear tires run at 1-4 % slip (linear region) under the
    driver's 46 bar (39 bar behind the proportioning valve), so a rear cap that is physically needed cannot be far
    below it. The compensated car's rear pressure is at least 80 % of the twin's (assumed margin for the different
    speed and load transfer); the defect's linear-region cap held the rears at ~1 bar."""
    assert p43["rear_on"] >= 0.8 * p43["rear_off"]


def test_curve_braking_rear_axle_with_the_defect(p43):
    """Negative control of the test above: rear_circle_flag = 0."""
    assert p43["rear_defect"] < 0.8 * p43["rear_off"]
