"""A false TPMS alarm while braking in a CURVE with the steering held (session j, J6; tire_blowout_findings.md "J6 (session
j)"): reproduce's false-alarm campaign for ``tire_blowout.no_lane_departure_caused`` with the signed per-side lane
overshoot (main cd8736d; CMA-ES 2026, -n 48, batch 8, /tmp/lead/j/fa_cau_signed) found #26: FR named (no blowout),
119.7 km/h, mu scale 0.506, 650 m LEFT curve, fixed steering, pedal 0.319 from 1.88 s at 1.13 /s - the car with the
function ends 0.159 m beyond the RIGHT (outer) marking; the same car without the function stays 0.978 m inside it on
the right (it leaves the lane on the LEFT, 1.446 m, the GMA holding its outer front low).

Mechanism (code before, rejected_hold_limit_flag 0): TPMS-path detection 1.94 s, FR released 19 -> 2 bar while FL was
built (yaw +2.4 deg/s over the twin), rejected yaw_implausible 2.055 s; FR re-applied at once to the driver's pressure
(reject_reapply_flag) and ABS-built to 45 bar, then ONE ABS hold from 2.30 to 2.955 s while its slip crept 10 -> 20 %
(an ABS hold has no time limit: status h item 8); with FL also in ABS the front axle saturated (sum of the tire lateral
forces 5100 N in the twin vs 200-500 N), the yaw rate fell to -2.5 deg/s in a LEFT curve and the car ploughed out to the
right. Without the function the GMA (started by FL's ABS alone) held FR at 28-30 bar: no saturated front axle.

Rule (rejected_hold_limit_flag 1, shipped): after a rejected FRONT detection, while the driver steers a curve, the
platform candidate esp.abs_hold_limit (Bosch ABS control cycle: a held wheel that does not re-accelerate gets a stepwise
pressure reduction; no new threshold) acts on both fronts - the wheels whose ABS history the function made (one built,
one released and stepped back to the driver's pressure). The twin and the rear wheels keep today's ABS.

References (independent of the code's formulas): the same car without the function (the envelope's twin, same driver,
road and false alarm) and the requirement's per-side comparison (data/requirements/tire_blowout.toml
no_lane_departure_caused: a false detection may not take the car further beyond a marking than the twin, issue #10
'Faults'); the lane geometry (the right marking). The hold check is the mechanism (the rule's own window), not a reference.
Seeded defect: rejected_hold_limit_flag 0 (the code before) -> the checks marked below fail."""
from __future__ import annotations

import numpy as np
import pytest

from vehicle_assist.verification.envelope import load_envelope
from tests.support import envelope_point_run as _run

B = "vehicle.blowout_compensation."
# the code before session j: J6's rule AND J5's reject_heading_return_flag at 0 (merged together, each also rescues the
# other's counterexample: J5's alone leaves #26 0.375 m beyond the LEFT marking - the twin 1.446 m - J6's alone 0.383 m
# inside the right one; both off: 0.159 m beyond the right marking, the campaign's violation)
DEFECT = (B + "rejected_hold_limit_flag=0", B + "reject_heading_return_flag=0")
L, R = "blowout_lane_overshoot_left_m", "blowout_lane_overshoot_right_m"
# /tmp/lead/j/fa_cau_signed/falsify.json #26 (main cd8736d), as the search wrote it
FA26 = {"speed": 119.71670044351775, "mu": 0.5059564103251724, "brake.start_s": 1.8815848031644897,
        "brake.level_frac": 0.3190238908819084, "brake.rate_per_s": 1.1310613203907285, "braking": "brakes",
        "wheel": "fr", "driver": "fixed", "curve": "r650"}


@pytest.fixture(scope="module")
def runs():
    env = load_envelope("tire_blowout_false_alarm")
    return {"on": _run(env, FA26), "defect": _run(env, FA26, sets=DEFECT), "none": _run(env, FA26, baseline=True)}


def _events(res, machine, to_mode=None):
    return [x for x in res.events if x.machine == machine and (to_mode is None or x.to_mode == to_mode)]


def test_point_is_a_false_front_detection_rejected(runs):
    """The point exercises the rule: a detection of the healthy FR, rejected; the twin has no detection."""
    for k in ("on", "defect"):
        assert _events(runs[k], "blowout_compensation", "BUILD"), k
        assert _events(runs[k], "blowout_compensation", "REJECTED"), k
    assert not _events(runs["none"], "blowout_compensation")


def test_twin_stays_inside_the_right_marking(runs):
    """The premise of the counterexample: without the function the car never crosses the RIGHT (outer) marking."""
    assert runs["none"].metrics[R] < 0.0, runs["none"].metrics[R]


def test_false_alarm_causes_no_lane_departure(runs):
    """no_lane_departure_caused, per side: max(0, overshoot_twin) - overshoot_function >= 0 on the left AND the right.
    Measured (shipped 3): right -0.383 m (twin -0.978 -> 0), left -0.904 (twin +1.446); with the defect the right reads
    +0.159 m beyond the marking -> fails."""
    on, none = runs["on"].metrics, runs["none"].metrics
    for side in (L, R):
        assert max(0.0, none[side]) - on[side] >= 0.0, (side, on[side], none[side])


def test_defect_reproduces_the_counterexample(runs):
    """Negative control: with rejected_hold_limit_flag 0 the campaign's violation is back (0.159 m beyond the right
    marking, the lead's robustness -0.159) - the check above can fail."""
    d, none = runs["defect"].metrics, runs["none"].metrics
    assert max(0.0, none[R]) - d[R] < 0.0, (d[R], none[R])


def _longest_rising_hold_s(res, wheel, t0):
    """The longest ABS hold of ``wheel`` after t0 during which its slip rose (end - start > 0) [s]."""
    df = res.to_pandas()
    t = np.asarray(df["time_s"]); slip = np.asarray(df[f"wheel_slip_{wheel}_frac"])
    ev = sorted((x.time_s, x.to_mode) for x in res.events if x.machine == f"abs_{wheel}" and x.time_s >= t0)
    best = 0.0
    for (ta, ma), (tb, _) in zip(ev, ev[1:]):
        if ma == "HOLD":
            ia, ib = int(np.argmin(abs(t - ta))), int(np.argmin(abs(t - tb)))
            if slip[ib] > slip[ia]:
                best = max(best, tb - ta)
    return best


def test_rejected_front_not_held_while_its_slip_creeps(runs):
    """Mechanism: after the rejection the re-applied FR does not sit in one ABS hold while its slip rises. The defect:
    0.655 s (2.30-2.955 s, slip 10 -> 20 %); the rule ends such a hold after two 0.1-s windows (esp.abs_hold_window_s)
    plus the dump step -> at most 0.25 s."""
    for k, ok in (("on", True), ("defect", False)):
        t_rej = _events(runs[k], "blowout_compensation", "REJECTED")[0].time_s
        hold = _longest_rising_hold_s(runs[k], "fr", t_rej)
        assert (hold <= 0.25) == ok, (k, hold)


# The same campaign re-run on this branch (rejected_hold_limit_flag 1 (J6: 3 before the merge collapsed its values); CMA-ES 2026 -n 48 -b 8, /tmp/j6/camp/fa_cau_signed)
# took another path and found 2 violations in a region the lead's run did not reach (mu ~0.43, a light HBA pedal): #26
# below -0.421 m (flag 0: -0.540) and #37 (follow driver) -0.426 (flag 0: -0.556). Both cars leave on the right (twin
# +0.958 m); after the rejection the function car's rears stay at 35-41 bar while the twin's HBA pumps them to 55-68 bar,
# so it brakes less (17.2 vs 15.3 m/s at 5 s) and runs wider. Not fixed (tire_blowout_findings.md J6): open.
FA26B = {"speed": 116.79101257036126, "mu": 0.42877647546066444, "brake.start_s": 1.5617686635453025,
         "brake.level_frac": 0.059246256671671466, "brake.rate_per_s": 16.81957723218628, "braking": "brakes",
         "wheel": "fr", "driver": "fixed", "curve": "r650"}


@pytest.mark.parametrize("sets,holds", [((), True), (DEFECT, False)])
def test_light_hba_pedal_false_alarm_no_lane_departure_caused(sets, holds):
    """J6's open point (a strict xfail on its branch) is met by the merged session-j code: J5's heading return gives
    the rejection's heading back (in the lane: 0.258 m deviation vs the twin's 1.941 m, measured at the merge c5adff0); with both session-j rules at 0 it is 1.498 m beyond the right marking vs
    the twin's 0.958 (J6: 1.379 with its own rule alone)."""
    env = load_envelope("tire_blowout_false_alarm")
    on, none = _run(env, FA26B, sets=sets).metrics, _run(env, FA26B, baseline=True).metrics
    ok = all(max(0.0, none[side]) - on[side] >= 0.0 for side in (L, R))
    assert ok == holds, (sets, on[L], on[R], none[L], none[R])
