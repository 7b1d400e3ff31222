"""Review RL2 (session l): holes found in L3 (event-field ranges) and L1 (blown_side_fault_flag) as merged in 488e3a4.

References, independent of the code under test: the scenario schema's own rule (an event after run.duration_s is an
input error), the envelope file's text (the bound that is wrong is named), the function's own reason table
(LIMIT_REASONS: every code the trace can carry), and for L1 the paper's compensation (P7, eqs. 26-28: before the
driver brakes the opposite rear is built to the balance and the limit code is 0 - the rule's own statement is that
without the pedal "the paper's compensation runs as before")."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from vehicle_assist.scenarios.errors import InputError
from vehicle_assist.verification.envelope import load_envelope, shipped_envelopes

BAR = 1.0e5
ON = ("vehicle.blowout_compensation.blown_side_fault_flag=1",)
# K1's r41 #360 as in tests/verification/test_blowout_blown_side_fault.py (the lead's /tmp/lead/l/base/f_r41 #360)
P360 = {"speed": 63.136574275141896, "mu": 0.34681190240008497, "delay": 0.16104437685029044,
        "wheel_speed_noise": 0.13613312727728766, "noise_seed": 6437.0, "brake_gain": 1.0538247572128214,
        "accumulator": 62.85697243180388, "brake.start_s": 1.3099401049183217, "brake.level_frac": 0.49237410416076977,
        "brake.rate_per_s": 5.629822385267875, "braking": "brakes", "wheel": "rr", "driver": "follow",
        "curve": "straight", "fault": "inlet_stuck_fr"}


def _edited(tmp_path: Path, old: str, new: str) -> Path:
    text = shipped_envelopes()["tire_blowout_faults"].read_text(encoding="utf-8")
    assert old in text
    p = tmp_path / "faults.toml"
    p.write_text(text.replace(old, new), encoding="utf-8")
    return p


def test_a_set_that_puts_the_fault_time_after_the_run_is_a_load_error():
    """L3 open item 4: --set run.duration_s=3 with fault_time up to 4 s failed at the first late point mid-search.
    Now with_sets (the --set path of falsify/study) validates the points: one line naming the --set and fault_time.
    Session n (N1, class A): the braking option sets run.duration_s = 30 after the --set (a braking point runs to
    standstill), so the --set shortens only the points without a pedal: the envelope restricted to them (-R
    braking=none) is the case. Gap (src, for the lead): unrestricted, with_sets(["run.duration_s=3"]) loads although its
    braking=none points with fault_time > 3 s fail mid-search - validate_points varies fault_time at the centre's
    braking = brakes only."""
    env = load_envelope("tire_blowout_faults").restrict(braking=("none",))
    with pytest.raises(InputError) as exc:
        env.with_sets(["run.duration_s=3"])
    text = str(exc.value)
    assert "\n" not in text and "--set run.duration_s=3" in text and "fault_time = 4" in text, text
    env.with_sets(["run.duration_s=4.5"])  # a run that still covers the range loads


def test_the_unrestricted_envelope_checks_fault_time_under_each_run_choice():
    """N1's gap, fixed (session n): the whole envelope with --set run.duration_s=3 loaded although a fault_time of 4 s
    fails mid-search. validate_points now checks every range end under each option of a choice that writes the run
    (choices.braking): a one-line load error."""
    env = load_envelope("tire_blowout_faults")
    with pytest.raises(InputError) as exc:
        env.with_sets(["run.duration_s=3"])
    text = str(exc.value)
    assert "\n" not in text and "fault_time = 4" in text, text


def test_a_set_run_duration_stands_over_the_braking_option():
    """Session n: the braking option runs to standstill (run.duration_s = 30); a user's --set run.duration_s is not
    silently replaced on those points - every point, braking or not, runs the --set's length."""
    env = load_envelope("tire_blowout").with_sets(["run.duration_s=7"])
    for braking in ("brakes", "none"):
        point = dict(env.center(), braking=braking)
        assert env.scenario(point).model.run.duration_s == 7.0, braking
    plain = load_envelope("tire_blowout")
    assert plain.scenario(dict(plain.center(), braking="brakes")).model.run.duration_s == 30.0
    assert plain.scenario(dict(plain.center(), braking="none")).model.run.duration_s == 5.0


def test_a_bad_centre_is_reported_as_the_centre_not_as_the_first_dimension(tmp_path):
    """max = 40 s puts the centre's fault at 20 s, after the 5-s run: the message named "speed = 40" (the first
    dimension) - now the centre point with its fault_time. Session n (N1, class A): the centre brakes (braking =
    brakes), its run is 30 s since the judging window; max = 80 s puts its fault at 40 s, after it."""
    with pytest.raises(InputError) as exc:
        load_envelope(_edited(tmp_path, "max = 4.0\nwhen", "max = 80.0\nwhen"))
    text = str(exc.value)
    assert "\n" not in text and "the centre point" in text and "fault_time=40" in text and "speed = 80" not in text, text


def test_a_padded_event_path_gets_the_event_form_message(tmp_path):
    """' append_events[0].at_s' slipped past the event-path check and failed as '--set ... unknown section'."""
    with pytest.raises(InputError) as exc:
        load_envelope(_edited(tmp_path, 'path = "append_events[0].at_s"', 'path = " append_events[0].at_s"'))
    text = str(exc.value)
    assert "\n" not in text and "append_events[I].FIELD" in text, text


def test_the_report_legend_names_every_limit_code():
    """Issue #10 'Faults' ('says why'): the reproduce report's legend of blowout_limit_code listed 0-5; code 6
    (blown_side_fault_flag) was missing. It is now built from LIMIT_REASONS."""
    from vehicle_assist.functions.blowout_compensation import LIMIT_BLOWN_SIDE, LIMIT_REASONS
    from vehicle_assist.procedures.blowout_study import limit_code_legend

    legend = limit_code_legend()
    assert LIMIT_BLOWN_SIDE == len(LIMIT_REASONS) - 1
    for k, why in enumerate(LIMIT_REASONS):
        assert f"{k} {why}" in legend


def test_blown_side_rule_leaves_the_paper_compensation_before_the_pedal():
    """L1's rule acts only while the driver brakes (its source text: 'Without the pedal ... the paper's compensation
    runs as before'). K1 r41 #360 (RR blown, FR stuck, detected 1.195 s, pedal from 1.31 s): before the pedal the
    opposite rear RL is built to the balance (> 10 bar; measured 38.6 bar) and the limit code is 0. A mutant without
    the pedal gate (the rule always on) dumps RL to the blown RR (0 bar) and shows code 6 at once - the L1 tests did
    not see it (review RL2: 4 passed, 1 xfailed with that mutant)."""
    import vehicle_assist as va

    env = load_envelope("tire_blowout_faults")
    r = va.simulate(env.scenario(P360).with_sets(*ON, "run.duration_s=1.5"), requirements=False)
    t = np.asarray(r.trace["time_s"])
    pre = (t >= 1.25) & (t < P360["brake.start_s"])  # after the detection and the build, before the pedal
    assert pre.sum() >= 5
    assert np.max(np.asarray(r.trace["wheel_pressure_rl_pa"])[pre]) > 10 * BAR
    assert np.all(np.asarray(r.trace["blowout_limit_code"])[t < P360["brake.start_s"]] == 0)


def test_limit_code_6_is_taken_back_when_the_pedal_is_released():
    """#360 with the driver releasing the pedal (eased to 0 over 0.2 s, 1 s after reaching the level): the rule stands
    aside and the paper's compensation is back (RL counter-braked > 10 bar, RR released < 2 bar; measured 32.2 / 1.4
    bar) - the code must not keep saying 'no counter-brake is added' (code 6; at 488e3a4 it stayed 6 to the end)."""
    import vehicle_assist as va
    from vehicle_assist.verification.envelope import pedal_table, toml_value

    env = load_envelope("tire_blowout_faults")
    tab = pedal_table(P360["brake.start_s"], P360["brake.level_frac"], rate_per_s=P360["brake.rate_per_s"],
                      ease_after_s=1.0, ease_to_frac=0.0, ease_time_s=0.2)
    sc = env.scenario(P360).with_sets(*ON, f"{env.model.profiles['brake'].path}={toml_value(tab)}", "run.duration_s=3.5")
    r = va.simulate(sc, requirements=False)
    t = np.asarray(r.trace["time_s"])
    code = np.asarray(r.trace["blowout_limit_code"])
    on = (t > P360["brake.start_s"] + 0.1) & (t < tab["time_s"][-2])
    assert np.all(code[on] == 6)  # while braking: the rule acts and says so
    off = t > tab["time_s"][-1] + 0.2  # pedal released
    assert np.min(np.asarray(r.trace["wheel_pressure_rl_pa"])[off]) > 10 * BAR  # the paper's counter-brake is back
    assert np.max(np.asarray(r.trace["wheel_pressure_rr_pa"])[off]) < 2 * BAR  # ... and the blown wheel released
    assert np.all(code[off] == 0), np.unique(code[off])


# the lead's /tmp/lead/l/base/f_r41 #378 (fault envelope at t = 0): RR blown, FR stuck, braking from 1.51 s, r1000,
# 76 km/h, mu 0.666; with blown_side_fault_flag = 1 the spin-front rule (code 5) engages at ~4.05 s
P378 = {"speed": 76.49012023309223, "mu": 0.6661434757430691, "delay": 0.3386205492190542,
        "wheel_speed_noise": 0.06362553565972197, "noise_seed": 7841.0, "brake_gain": 0.8452214281640918,
        "accumulator": 51.65388974130821, "brake.start_s": 1.5075861347179234, "brake.level_frac": 0.2622671413265846,
        "brake.rate_per_s": 0.28711197195071575, "braking": "brakes", "wheel": "rr", "driver": "follow",
        "curve": "r1000", "fault": "inlet_stuck_fr"}


@pytest.mark.parametrize("flag", [1, pytest.param(0, marks=pytest.mark.xfail(
    strict=True, reason="flag 0: the blown rear held at the driver's 10-44 bar while code 5 says 'rear wheel released'"))])
def test_spin_front_keeps_the_blown_rear_released(flag):
    """Code 5 (spin_front_flag) states 'rear wheel released': with blown_side_spin_front_flag (candidate) the
    blown-side rule (blown_side_fault_flag 1) stands aside there, so every sample with code 5 from 0.1 s after each
    entry has RR < 5 bar (measured 1.4 bar); at 0 RR stays with the driver (10-44 bar) - the code then says something
    the brakes do not do."""
    import vehicle_assist as va

    env = load_envelope("tire_blowout_faults")
    r = va.simulate(env.scenario(P378).with_sets(*ON, f"vehicle.blowout_compensation.blown_side_spin_front_flag={flag}"),
                    requirements=False)
    t = np.asarray(r.trace["time_s"])
    code = np.asarray(r.trace["blowout_limit_code"])
    five = code == 5
    assert five.sum() >= 20, five.sum()  # the spin-front phase is reached (the test's premise)
    start = np.maximum.accumulate(np.where(five & ~np.r_[False, five[:-1]], t, -np.inf))  # each code-5 entry's time
    settled = five & (t > start + 0.1)  # 0.1 s after each entry into code 5 (the release's dump time)
    assert settled.sum() >= 10
    assert np.max(np.asarray(r.trace["wheel_pressure_rr_pa"])[settled]) < 5 * BAR


def test_blown_front_with_its_side_rear_stuck_is_left_as_before():
    """L1 measured the rule on a blown FRONT (its side's rear stuck) and found it wrong there (14 of 18 changed points
    worse, 4 new violations), so it returns for b < 2 - but no test guarded that return (review RL2: a mutant acting on
    fronts too passes L1's tests, whose only point is a blown rear). #360 mirrored to FR blown, RR stuck: flag 1 must
    give the run of flag 0 (the code before) bit for bit, and never limit code 6. (Session m M2: a blown front is now
    blown_side_front_flag's - pinned 0 here, the return this test guards; M2's value 2 is tested in
    test_blowout_blown_side_front.py.)"""
    import vehicle_assist as va

    env = load_envelope("tire_blowout_faults")
    point = dict(P360, wheel="fr", fault="inlet_stuck_rr")
    runs = [va.simulate(env.scenario(point).with_sets(f"vehicle.blowout_compensation.blown_side_fault_flag={f}",
                                                      "vehicle.blowout_compensation.blown_side_front_flag=0"),
                        requirements=False) for f in (1, 0)]
    assert np.max(np.asarray(runs[0].trace["brake_pedal_frac"])) > 0.3  # the driver brakes (the rule's condition)
    for w in ("fl", "fr", "rl", "rr"):
        assert np.array_equal(runs[0].trace[f"wheel_pressure_{w}_pa"], runs[1].trace[f"wheel_pressure_{w}_pa"]), w
    assert 6 not in np.asarray(runs[0].trace["blowout_limit_code"])


def test_blown_front_with_its_side_rear_stuck_keeps_the_paper_release_at_the_shipped_flags():
    """(Review RM2, session m) The guard above pins blown_side_front_flag = 0 (the code before, still the seeded defect
    the tests compare with). At the SHIPPED flags (blown_side_fault_flag 4, blown_side_front_flag 2) a blown front is
    the rule's, and what the guard was for still holds: L1's stand-down (blown wheel to the driver and ABS, no
    counter-brake) never reaches a blown FRONT - the paper's release stands (P7, eqs. 26-28: F_b = 0; flag 0 keeps FR
    at 0 bar) while code 6 says the rule acts. #360 mirrored (FR blown, RR stuck, straight, pedal 0.49 from 1.31 s):
    value 2 FR max 0.0 bar, code 6, 0.058 m (twin 0.677); value 1 (the stand-down, M2's measured bad candidate) FR
    15-19 bar, 0.304 m. A mutant letting value 2 fall through to the stand-down fails here."""
    import vehicle_assist as va

    env = load_envelope("tire_blowout_faults")
    point = dict(P360, wheel="fr", fault="inlet_stuck_rr")
    # the vehicle file's shipped flags but (session o, O4) blown_side_stop_flag 0: with O4's rule the counter-brake FL
    # takes its share inside the dead band and from 3.2 s the blown FR is braked (up to 56 bar, ABS-dumped); traced by
    # RO4: blown_front_hold's Q_HOLD (the driver's counter-steer is a steered reference toward FR, FL now at its ABS
    # limit) -> W_N, the driver's master pressure; with blown_front_hold_flag 0 FR stays 0 bar (test_review_ro4.py);
    # road max 0.143 m vs 0.062 at 0 (twin 0.677), both rows pass (findings O4, RO4). This test's statement (L1's
    # stand-down never reaches a blown front) is blown_side_fault's
    r = va.simulate(env.scenario(point).with_sets("vehicle.blowout_compensation.blown_side_stop_flag=0"),
                    requirements=False)
    t = np.asarray(r.trace["time_s"])
    w = (t >= 1.4) & (t <= 3.5)
    assert np.max(np.asarray(r.trace["brake_pedal_frac"])) > 0.3  # the driver brakes (the rule's condition)
    assert np.max(np.asarray(r.trace["wheel_pressure_fr_pa"])[w]) < 2.0e5  # released (esp.plausibility_pressure)
    assert np.all(np.asarray(r.trace["blowout_limit_code"])[w] == 6)
