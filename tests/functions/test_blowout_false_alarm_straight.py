"""A false TPMS alarm on a braking car on a STRAIGHT road with the steering held (session i, I8; tire_blowout_findings.md
"I8 (session i)"): the lead's reproduce of paper 004's false-alarm campaign for ``tire_blowout.no_lane_departure_caused``
(procedures/blowout_study.py falsify_extra: CMA-ES 2026, -n 48, batch 8) found ONE violation, #25: FR named, straight,
96 km/h, mu scale 0.564, fixed steering, pedal 0.327 from 1.90 s at 9.6 /s - 0.991 m off the lane centre with the
function (0.013 m beyond the lane) vs 0.000 m without it.

Mechanism (shipped code): TPMS-path detection 1.955 s (the alarm alone, driver braking),
FR released 21 -> 5 bar while FL was built to 37 bar for 80 ms; the front brake-force difference yawed the car
(2.3 deg/s) until the yaw rejection (2.035 s); FR re-applied, but the braking car near its friction limit has little yaw
damping and the held steering never takes the heading error (2.1 deg at 4 s) back: 0.99 m.

References (independent of the code's formulas): the same car without the function (the envelope's twin, same driver,
road and false alarm: a symmetric braking car on a straight road keeps its heading, 0.000 m) and the requirement's own
comparison (data/requirements/tire_blowout.toml no_lane_departure_caused / no_worse_than_no_compensation, rollback floor
0). I8's candidate (the TPMS-path confirmation release made yaw-neutral: 0.991 -> 0.000 m here, but a real braking
blowout without its counter-brake for the confirmation time, 40 real-blowout points worse, bb47 #52 0.283 -> 2.084 m)
was shipped off and deleted in session j (J3) with its rows. Session j (J5): reject_heading_return_flag gives the heading
back after the rejection - no lane departure (0.294 m off centre, inside the lane); never-worse inside the lane (0.294 vs
0.000 m) stays a strict xfail (open)."""
from __future__ import annotations

import pytest

from vehicle_assist.verification.envelope import load_envelope
from tests.support import envelope_point_run as _run

B = "vehicle.blowout_compensation."
DEFECT = (B + "reject_heading_return_flag=0",)  # the code before session j (J5): the kick's heading never given back
DEV = "blowout_lateral_deviation_run_max_m"
EXC = "blowout_lane_exceedance_m"
# /tmp/lead/i/fa_caused/falsify.json #25 (main 0e7a661), as the search wrote it
FA25 = {"speed": 96.00629966134198, "mu": 0.564059797326502, "brake.start_s": 1.9022609026158666,
        "brake.level_frac": 0.32699046767000983, "brake.rate_per_s": 9.61338028039029, "braking": "brakes",
        "wheel": "fr", "driver": "fixed", "curve": "straight"}


@pytest.fixture(scope="module")
def runs():
    env = load_envelope("tire_blowout_false_alarm")
    return {"shipped": _run(env, FA25), "none": _run(env, FA25, baseline=True), "defect": _run(env, FA25, sets=DEFECT)}


def _events(res, to_mode):
    return [x for x in res.events if x.machine == "blowout_compensation" and x.to_mode == to_mode]


def test_point_is_a_false_tpms_detection_rejected(runs):
    """The point is a TPMS-path detection of the healthy FR under the driver's brake, then rejected (a false alarm);
    the twin has no detection."""
    assert _events(runs["shipped"], "BUILD") and _events(runs["shipped"], "REJECTED")
    assert not [x for x in runs["none"].events if x.machine == "blowout_compensation"]


@pytest.mark.parametrize("k,holds", [("shipped", True), ("defect", False)])
def test_false_alarm_causes_no_lane_departure(runs, k, holds):
    """no_lane_departure_caused (issue #10 'Faults'): the lane exceedance with the function is no more than the twin's,
    max(0, exc_twin) - exc >= 0. Session i: 0.013 m beyond the lane vs 0.000 (a strict xfail); since session j the
    shipped reject_heading_return_flag (J5) gives the kick's heading back: 0.000 m beyond (0.294 m off centre). The
    row at flag 0 (the code before) must still violate it, so the check can fail."""
    on, none = runs[k].metrics[EXC], runs["none"].metrics[EXC]
    assert (max(0.0, none) - on >= 0.0) == holds, (k, on, none)


@pytest.mark.xfail(strict=True, reason="shipped code: fa_caused #25 0.294 m (J5, session j; 0.991 before) vs 0.000 m without the "
                   "function, inside the lane (tire_blowout_findings.md I8 session i, J5 session j; open, status j)")
def test_false_alarm_no_worse_than_the_twin(runs):
    """no_worse_than_no_compensation (rollback floor 0): the run's largest lateral deviation no more than the twin's.
    Shipped 0.294 m (0.991 before session j's reject_heading_return) vs 0.000 m (open)."""
    on, none = runs["shipped"].metrics[DEV], runs["none"].metrics[DEV]
    assert on <= none, (on, none)
