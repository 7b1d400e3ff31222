"""Curve-shift envelope and requirements (data/envelopes/curve_shift.toml, data/requirements/curve_shift.toml).

The falsifier found (issue #11) that the upshift inhibit held 2nd gear to 4008 rpm on a 6 deg downhill curve exit
with a 1 s late preview (94.7 km/h, R = 30 m), where the normal schedule stayed below 3430 rpm; the engine-protection
release (upshift_release_speed_rpm) fixed it, and since item 1 of the review the preview plausibility check also
catches the late preview at curve entry (fallback to the normal schedule), so curve mode no longer outlasts the
curve. Reference: n_max_dn = 4000 rpm (curve_shift.md 5.2) and the no-assist twin of the same point. The defect is
restored by removing both (release above the cut-off, plausibility check off): the requirement must fail.
Criterion 1 is stated exactly (no exemption): the protection release, when it fires, violates it.
"""
from __future__ import annotations

import vehicle_assist as va
from vehicle_assist.verification.envelope import load_envelope

POINT = dict(entry_speed=94.69, sight_distance=176.7, preview_radius_noise=2.549, preview_latency=0.9552,
             driver_style=0.9161, grade=-5.86, radius="r30", preview="ok")


def _rob(sc, rid):
    return {r.id: r.robustness for r in va.simulate(sc).requirements}[rid]


def test_envelope_loads_and_base_meets_requirements():
    env = load_envelope("curve_shift")
    assert env.layout == "amt_car"
    base = va.simulate(va.load_scenario("curve_envelope_base"))
    assert base.ok and all(r.robustness >= 0 for r in base.requirements)


def test_falsifier_finding_is_fixed_and_the_defect_fails():
    env = load_envelope("curve_shift")
    sc = env.scenario(POINT)
    assert _rob(sc, "curve_shift.no_overspeed") > 0
    twin = va.simulate(env.scenario(POINT, baseline=True)).trace
    assert twin["engine_speed_radps"].max() < 418.879  # the normal schedule alone is safe here
    assert va.simulate(sc).metrics["preview_fallback_count"] == 1  # the late preview is rejected at curve entry
    no_release = sc.with_sets("vehicle.curve_shift.upshift_release_speed_rpm=9000")
    assert _rob(no_release, "curve_shift.no_overspeed") > 0  # the plausibility check alone is enough here
    defect = sc.with_sets("vehicle.curve_shift.upshift_release_speed_rpm=9000",
                          "vehicle.curve_shift.plausibility_check_flag=0")
    assert _rob(defect, "curve_shift.no_overspeed") < 0
    # with the release but without the plausibility check the protection fires in curve mode: criterion 1 fails
    released = va.simulate(sc.with_sets("vehicle.curve_shift.plausibility_check_flag=0"))
    assert released.metrics["protection_upshifts_count"] == 1
    assert {r.id: r.robustness for r in released.requirements}["curve_shift.no_upshift_in_curve_mode"] < 0
    assert released.metrics["upshifts_in_curve_mode_count"] == 1


def test_no_upshift_requirement_fails_for_the_normal_schedule():
    """Negative control of curve_shift.no_upshift_in_curve_mode (criterion 1, reason: the lift-off upshift of the
    normal schedule, P1/P13): with the strategy off the 65 and 48 km/h cases upshift inside the command window."""
    from vehicle_assist.verification.requirements import get_requirement, robustness

    req = get_requirement("curve_shift.no_upshift_in_curve_mode")
    for v in (65, 48):
        off = va.simulate(va.load_scenario(f"curve_b{v}"))
        assert robustness(req, off.trace) < 0.0, v
        assert off.metrics["upshifts_in_curve_mode_count"] >= 1
        on = va.simulate(va.load_scenario(f"curve_s{v}"))
        assert robustness(req, on.trace) >= 0.0, v


def test_rtamt_prev_on_numbers_is_not_used():
    """The requirement compares consecutive gear commands through recorded delay-line channels. Reference: a
    hand-built trace with one upshift in curve mode gives robustness -0.5 (the implication's bound), none gives 0."""
    import numpy as np

    from vehicle_assist.verification.requirements import get_requirement, robustness

    req = get_requirement("curve_shift.no_upshift_in_curve_mode")
    assert "prev(" not in req.formula
    g = np.array([2, 2, 3, 3, 3.])
    tr = {"time_s": np.arange(5) * 0.01, "gear_command_index": g, "gear_command_prev_index": np.r_[2, g[:-1]],
          "curve_mode_held_index": np.r_[0, np.ones(4)]}
    assert robustness(req, tr) == -0.5  # max(-(1 - 0.5), 2 - 3)
    tr["gear_command_index"] = np.array([3, 3, 2, 2, 2.])
    tr["gear_command_prev_index"] = np.r_[3, tr["gear_command_index"][:-1]]
    assert robustness(req, tr) == 0.0
    tr["curve_mode_held_index"] = np.zeros(5)  # never in curve mode: finite, positive
    assert robustness(req, tr) == 0.5


def test_guard_holds_after_the_torque_interruption_on_a_downhill():
    """Review finding (curve_shift.md 5.2 / 8 criterion 4: 'never engage a gear whose engine speed right after the
    shift would exceed n_guard = 3800 rpm'): the guard compared the engine speed at the *command*; on a 6 deg downhill
    the car gains speed during the 0.8 s torque interruption, and a 4->2 skip commanded at 3711 rpm engaged at
    3838 rpm (401.9 rad/s). Reference: n_guard = 397.9 rad/s of the spec; the point was found by a grid probe of the
    envelope (45 km/h, R = 30 m, 1 s preview latency, k = 1.0). The strategy must still downshift (P9 rule 2)."""
    env = load_envelope("curve_shift")
    point = dict(entry_speed=45.0, sight_distance=150.0, preview_radius_noise=0.0, preview_latency=1.0,
                 driver_style=1.0, grade=-6.0, radius="r30", preview="ok")
    r = va.simulate(env.scenario(point))
    assert r.metrics["engine_speed_after_downshift_max_radps"] <= 397.9
    assert r.metrics["kj_advance_max_frac"] == 1.0
    g = r.trace["gear_command_index"][r.trace["curve_mode_flag"] > 0.5]
    assert g.min() <= 3  # still downshifted from 4th in curve mode


CMD_BEFORE_SIGHT = dict(entry_speed=67.13, sight_distance=88.76, preview_radius_noise=3.921, preview_latency=0.0,
                        driver_style=0.7852, grade=-5.731, radius="r30", preview="radius_small")


def test_criterion_1_holds_when_the_command_precedes_the_driver_on_a_downhill():
    """Regression of the independent review's counterexample (falsify ... no_upshift_in_curve_mode -n 128 --seed 3,
    32nd evaluation): sight distance 89 m < command distance 150 m on a 5.7 deg downhill. Before the fix the kj_max
    skip 5->3 came at the command (3480 rpm, throttle 0.25), the engine climbed to the 3900 rpm release in 3rd before
    the driver braked and the protection upshifted inside curve mode (robustness -0.5). References: criterion 1 of
    curve_shift.md 8 (no upshift in curve mode), the release speed 3900 rpm of the vehicle file, n_guard = 3800 rpm
    (criterion 4), the no-assist twin (engine below 3425 rpm), P9 rule 2 (the strategy must still downshift early)
    and criterion 3 (never later than the normal line). The seeded defect (advance_horizon_flag = 0) must fail."""
    import numpy as np

    env = load_envelope("curve_shift")
    r = va.simulate(env.scenario(CMD_BEFORE_SIGHT))
    assert {q.id: q.robustness for q in r.requirements}["curve_shift.no_upshift_in_curve_mode"] >= 0
    assert r.metrics["protection_upshifts_count"] == 0 and r.metrics["upshifts_in_curve_mode_count"] == 0
    tr = r.trace
    cm = tr["curve_mode_flag"] > 0.5
    assert tr["engine_speed_radps"][cm].max() < 3800 * np.pi / 30  # below n_guard, so 100 rpm below the release
    assert r.metrics["engine_speed_after_downshift_max_radps"] <= 397.9
    g = tr["gear_command_index"]
    idx = np.nonzero(np.diff(g))[0] + 1
    shifts = [(int(g[i - 1]), int(g[i]), i) for i in idx if cm[i]]
    # skip less at the command (5->4, not 5->3): the advance horizon held 3rd (counted), then 4->3 once the driver brakes
    assert shifts[0][:2] == (5, 4) and tr["advance_hold_count"][shifts[0][2]] >= 1
    i43 = [i for a, b, i in shifts if (a, b) == (4, 3)][0]
    assert tr["brake_pedal_frac"][i43] > 0.0
    assert tr["speed_mps"][i43] >= tr["normal_downshift_speed_mps"][i43 - 1]  # criterion 3 (line below 4th)
    entry = tr["curve_distance_true_m"] <= 0.0
    assert g[np.argmax(entry)] <= 3  # still in a low gear at the curve entry (P9 rule 2)
    twin = va.simulate(env.scenario(CMD_BEFORE_SIGHT, baseline=True)).trace
    assert twin["engine_speed_radps"].max() < 3425 * np.pi / 30
    # the defect restored: the skip at the command and the protection release in curve mode come back
    bad = va.simulate(env.scenario(CMD_BEFORE_SIGHT).with_sets("vehicle.curve_shift.advance_horizon_flag=0"))
    assert {q.id: q.robustness for q in bad.requirements}["curve_shift.no_upshift_in_curve_mode"] < 0
    assert bad.metrics["protection_upshifts_count"] == 1
    assert bad.trace["advance_hold_count"].max() == 0
