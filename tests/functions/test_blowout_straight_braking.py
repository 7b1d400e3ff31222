"""Front blowouts under a braking driver left worse than the no-compensation twin after session g's G1 (tire_blowout_findings.md
"G1 (session g)", "G5 (session g)"; tire_blowout_sessions.md "Session g, G5"): falsify tire_blowout -r
tire_blowout.no_worse_than_no_compensation --optimizer random --seed 47 -n 128 --keep-going -R braking=brakes (the
same at main 2ff4871 and 399b878).

* #69 FL 111.9 km/h mu 0.658 STRAIGHT, follower, pedal 0.39 at 25.9 /s from 0.84 s (HBA, master 159 bar): 13.58 m vs
  none 11.29 m. The yaw rate toward FL crosses Rajamani's stable bound 0.85*mu*g/u before the detection in both cars
  (twin 1.295 s, compensated 1.330 s; detection 1.345 s); the compensation was REFUSED beyond_stable_region at 1.425 s
  (0.249 rad/s against the ECU's mu-0.8 bound) and both cars spun (188 / 220 deg by 5 s). The refusal took the only
  counter-moment off a car spinning toward the flat: the compensating FR is the outer front of that rotation, the
  wheel an ESP brakes against oversteer. Fixed (``front_spin_keep_flag``, 0 = the code before): a running
  compensation (BUILD/HOLD) is not refused while the yaw exceeds the steering reference toward the blown side
  (at the detection the refusal stands: kept there, braking 5 #1 went 6.81 -> 14.08 m vs none 6.94) - 1.53 m, peak yaw
  0.25 rad/s, heading -6.6 deg at 5 s; its 10 neighbours (noise
  seed 1/2/3, speed -/+2 km/h, mu -/+0.02, noise 0.05 rad/s, delay +0.05 s, gain -0.05) 1.23-4.56 m vs none 10.85-13.94
  m (with the refusal: 5 of 11 spun, 2 of 11 worse than the twin).
* #106 FL 91.2 km/h mu 0.411 r650 (toward FL), follower, slow pedal (0.10 at 0.78 /s from 1.08 s), detection delay
  0.43 s: 0.463 m vs none 0.234 m, robust (+0.21 to +0.34 m over the same 10 neighbours). Open (strict xfail). The same
  point with detection delays 0.05/0.15/0.25/0.35 s: 0.917/0.873/0.700/0.577 m vs 0.234 m - the clean mechanism is the
  paper's balance planned at the ECU's nominal mu 0.8 (43.6 bar) on the OUTER front of a wet curve under a braking
  driver: FR at its ABS limit (8-10 % slip, F_y 513 -> 78 N), the yaw rate 2-4 deg/s below the steering reference for
  1.5 s (inside the 5 deg/s over-compensation dump of the feed-forward mode), the car runs wide (strict xfail below).

References, independent of the function's code: the requirement (the twin is the same point without the function,
paper 004 Fig. 4 curve 2); the heading the plant turned through (truth); Rajamani, Vehicle Dynamics and Control (2nd
ed. 2012) ch. 8, |r| <= 0.85*mu*g/u, evaluated
with the point's road friction and the plant's speed (truth)."""
from __future__ import annotations

import numpy as np
import pytest

import vehicle_assist as va
from tests.support import envelope_point_run
from vehicle_assist.functions import blowout_compensation as bc
from vehicle_assist.verification.envelope import load_envelope

METRIC = "blowout_lateral_deviation_run_max_m"
G = 9.81
DEFECT = ("vehicle.blowout_compensation.front_spin_keep_flag=0",)
# random seed 47, -R braking=brakes, budget 128 (falsify.json history)
P69 = {"speed": 111.94339873434541, "mu": 0.6580005889911276, "delay": 0.31166759271573674,
       "wheel_speed_noise": 0.10941344775895263, "noise_seed": 3066, "brake_gain": 1.014013288586125,
       "brake.start_s": 0.8393458782535852, "brake.level_frac": 0.3949211370939334,
       "brake.rate_per_s": 25.92692455162539, "braking": "brakes", "wheel": "fl", "driver": "follow",
       "curve": "straight"}
P106 = {"speed": 91.15521889669442, "mu": 0.4112364072728184, "delay": 0.4340173385577509,
        "wheel_speed_noise": 0.03195797429234702, "noise_seed": 9546, "brake_gain": 0.8223837040543704,
        "brake.start_s": 1.0770834680225498, "brake.level_frac": 0.10267027576138826,
        "brake.rate_per_s": 0.7803338965120385, "braking": "brakes", "wheel": "fl", "driver": "follow", "curve": "r650"}
P106_EARLY = {**P106, "delay": 0.05}


@pytest.fixture(scope="module")
def env():
    return load_envelope("tire_blowout")


@pytest.fixture(scope="module")
def runs69(env):
    # "on"/"defect" at the code before esp.named_front_gma_flag (session i, I4), where G5's situation exists; shipped:
    # 0.495 m (none 11.29) - with it the detection no longer comes beyond the stable region
    named0 = ("vehicle.esp.named_front_gma_flag=0",)
    return {k: envelope_point_run(env, P69, baseline=(k == "none"), sets=(DEFECT if k == "defect" else ()) + named0)
            for k in ("on", "none", "defect")}


def _first_beyond_bound_s(r, mu):
    """First time the plant's yaw rate exceeds Rajamani's stable bound 0.85*mu*g/u (road friction, plant speed)."""
    t = np.asarray(r.trace["time_s"])
    yaw = np.abs(np.asarray(r.trace["yaw_rate_radps"]))
    u = np.maximum(np.asarray(r.trace["speed_mps"]), 1.0)
    beyond = yaw > 0.85 * mu * G / u
    assert beyond.any()
    return float(t[np.argmax(beyond)])


def _events(r):
    return [(e.time_s, e.to_mode, e.reason) for e in r.events if e.machine == "blowout_compensation"]


def _turned_rad(r):
    h = np.asarray(r.trace["heading_rad"])
    return float(np.max(np.abs(h - h[0])))


def test_69_no_worse_than_without_compensation(runs69):
    """Measured: 1.529 m vs none 11.286 m (the code before, flag 0: 13.579 m)."""
    on, none = runs69["on"].metrics[METRIC], runs69["none"].metrics[METRIC]
    assert on <= none, (on, none)


@pytest.mark.xfail(strict=True, reason=(
    "N5 (session n, class C): judged to standstill by both rows of the requirement the defect (front_spin_keep_flag = "
    "0, named_front_gma_flag = 0 in both) is no longer worse than the twin: both spin off the road (road deviation tie "
    "3.978 m), the defect 0.135 s AFTER the twin (earliness 28.010 vs 28.145 s; unclipped 13.800 vs 12.740 m beyond the "
    "road edge); the rule keeps the car on the road (1.516 m)"))
def test_69_defect_is_worse_than_without_compensation(runs69):
    """The seeded defect (refused whatever the rotation) reproduces the counterexample: the check above can fail.
    N5 (session n): judged as the requirement judges (tests/support.never_worse_rows, both rows): a strict xfail with
    the numbers (reason)."""
    from tests.support import never_worse_rows

    rows = never_worse_rows(runs69["defect"], runs69["none"])
    assert min(rows.values()) < 0.0, rows


def test_69_beyond_the_stable_region_at_the_detection(runs69):
    """The point is the rule's case: both cars are beyond Rajamani's bound (road friction) at or before the detection,
    rotating toward FL (CCW +), and the twin spins (turns more than 90 deg; 220 deg measured)."""
    det = [t for t, m, why in _events(runs69["on"]) if why == "blowout_detected"]
    assert det
    for k in ("on", "none"):
        assert _first_beyond_bound_s(runs69[k], P69["mu"]) <= det[0], k
    assert _turned_rad(runs69["none"]) > np.pi / 2


def test_69_not_refused_and_no_spin(runs69):
    """Mechanism: with the rule no refusal and the car does not spin (turns less than 20 deg, 6.6 deg at 5 s measured);
    the defect refuses within 0.1 s of the detection (1.425 s) and spins (more than 90 deg)."""
    assert not [e for e in _events(runs69["on"]) if e[1] == "REFUSED"], _events(runs69["on"])
    assert _turned_rad(runs69["on"]) < np.radians(20.0)
    ev = _events(runs69["defect"])
    det = [t for t, m, why in ev if why == "blowout_detected"]
    ref = [t for t, m, why in ev if m == "REFUSED" and why == "beyond_stable_region"]
    assert det and ref and ref[0] - det[0] <= 0.1, ev
    assert _turned_rad(runs69["defect"]) > np.pi / 2


# ---- the rule on hand-made values ---------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def params():
    from vehicle_assist.scenarios.runner import pack_records

    return pack_records([va.load_scenario("blowout_lf_60kph_paper").vehicle.flat()])[0]


def _with_flag(p, flag):
    q = p.copy()
    q.blowout_compensation_front_spin_keep_flag = flag
    return q


@pytest.mark.parametrize("blown, yaw, keep", [
    (0, +0.3, True),    # FL blown, CCW rotation = toward FL: kept (FR is the outer front of the rotation)
    (0, -0.3, False),   # FL blown, rotating away (CW): refused as before
    (1, -0.3, True),    # FR blown, CW = toward FR: kept
    (1, +0.3, False),
    (2, +0.3, False),   # rear blowouts: the spin-front rule's domain, not this one
    (3, -0.3, False),
])
def test_row_rotation_sign_decides(params, blown, yaw, keep):
    tg = bc.OPPOSITE[blown]
    # (the measured rotation = the deviation here: a straight steering reference; front_spin_keep_rotation_flag)
    assert bc.front_spin_keep(blown, tg, yaw, _with_flag(params, 1), yaw, bc.LIMIT_YAW_BOUND, 0.0) == keep
    assert not bc.front_spin_keep(blown, tg, yaw, _with_flag(params, 0), yaw, bc.LIMIT_YAW_BOUND, 0.0)


def test_row_only_with_the_opposite_front_compensating(params):
    """A front blowout whose target is not the other front (the substitute rear of a stuck inlet): refused as before."""
    assert not bc.front_spin_keep(0, 3, +0.3, _with_flag(params, 1), +0.3, bc.LIMIT_YAW_BOUND, 0.0)
    assert not bc.front_spin_keep(0, -1, +0.3, _with_flag(params, 1), +0.3, bc.LIMIT_YAW_BOUND, 0.0)


def test_106_no_worse_than_without_compensation(env):
    """Was a strict xfail (G5: 0.463 vs none 0.234 m; 0.419 at main cc64ff5): fixed by esp.named_front_gma_flag
    (session i, I4: the named FL's ABS no longer starts the GMA on FR) - 0.058 m."""
    on = envelope_point_run(env, P106).metrics[METRIC]
    none = envelope_point_run(env, P106, baseline=True).metrics[METRIC]
    assert on <= none, (on, none)


@pytest.mark.xfail(strict=True, reason="#106 with a 0.05 s detection delay (the mechanism without the 0.4 s TPMS-named "
                   "window): FR held at the nominal-mu balance 43.6 bar at its ABS limit, yaw 2-4 deg/s below the "
                   "reference for 1.5 s: 0.917 vs none 0.234 m. A braking variant of the understeer rule gave 0.051 m "
                   "here but 5 points worse by 0.3-1.5 m (fixed-steering: the over-compensation had taken back the "
                   "pre-detection heading error); tire_blowout_sessions.md 'Session g, G5'")
def test_106_early_detection_no_worse_than_without_compensation(env):
    on = envelope_point_run(env, P106_EARLY).metrics[METRIC]
    none = envelope_point_run(env, P106_EARLY, baseline=True).metrics[METRIC]
    assert on <= none, (on, none)


def test_69_shipped_no_worse_than_without_compensation(env, runs69):
    """Review RI1 (session i): the rows above run at named_front_gma_flag = 0 since I4; this row keeps #69 checked at
    the SHIPPED code (I4 measured 0.495 m vs none 11.29 m): a later rule that brings #69 back beyond the twin fails here."""
    on = envelope_point_run(env, P69).metrics[METRIC]
    assert on <= runs69["none"].metrics[METRIC], (on, runs69["none"].metrics[METRIC])
