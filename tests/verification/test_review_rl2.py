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
    Now with_sets (the --set path of falsify/study) validates the points: one line naming the --set and fault_time."""
    env = load_envelope("tire_blowout_faults")
    with pytest.raises(InputError) as exc:
        env.with_sets(["run.duration_s=3"])
    text = str(exc.value)
    assert "\n" not in text and "--set run.duration_s=3" in text and "fault_time = 4" in text, text
    env.with_sets(["run.duration_s=4.5"])  # a run that still covers the range loads


def test_a_bad_centre_is_reported_as_the_centre_not_as_the_first_dimension(tmp_path):
    """max = 40 s puts the centre's fault at 20 s, after the 5-s run: the message named "speed = 40" (the first
    dimension) - now the centre point with its fault_time."""
    with pytest.raises(InputError) as exc:
        load_envelope(_edited(tmp_path, "max = 4.0\nwhen", "max = 40.0\nwhen"))
    text = str(exc.value)
    assert "\n" not in text and "the centre point" in text and "fault_time=20" in text and "speed = 40" not in text, text


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
