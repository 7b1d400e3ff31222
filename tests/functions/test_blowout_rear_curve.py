"""Rear blowouts at 100-120 km/h in low-friction curves with a braking driver (``rear_braking_flag``, functions/
blowout_compensation.py ``rear_braking_rule``; session 2026-11-24 g, task G4, tire_blowout_findings.md R2 update / G4).

Reviewer R2's targeted search (falsify tire_blowout -r tire_blowout.no_worse_than_no_compensation --optimizer random
--keep-going --seed 29 -n 64 -b 32 -R wheel=rl,rr -R curve=r650,r1000 -R speed=100..120 -R mu=0.3..0.45) at main
2ff4871 found three points worse than the no-compensation twin:

* #38 RR 112 km/h mu 0.343 r650, lane follower, pedal 0.30 (HBA, master 150 bar) 0.28 s after the detection: the
  plan for the compensating RL was 0 bar (the moment already pointed away from the blown side), the driver's pressure
  reached RL through the line (47.6 bar at 2 % slip), and each ABS dump of it (0.28 rad/s wheel-speed noise, no slip
  evidence) was re-built only to the plan: RL 47.6 -> 1.4 bar in 1.8 s while the twin's rear pair carried 22-27 bar;
  the car braked less, kept speed and ran wide (4.454 m vs 4.248 m). Fixed: the rear compensating wheel is re-built to
  the driver's level it had reached (a dump with slip evidence still caps it at the dump's start, as a front wheel).
* #31 RL 109 km/h mu 0.36 r650, steering held, pedal from t_b - 0.42 s (HBA): the blown wheel is on the inside of the
  curve of a car already understeering at the friction limit; the compensated car's outer rear RR carries 30.7 bar
  (the twin's rear pair cycles at 10-27 bar under ABS's select-low with the flat wheel) and the yaw rate falls 1-3.5
  deg/s short of the steering reference: 2.207 m vs 0.572 m. Not fixed (strict xfail below; the front braking rule's yaw
  feedback on the driver's share gave 1.42 m but turned TPMS-path detections elsewhere into yaw-implausible rejections;
  tire_blowout_sessions.md "Session g, G4").
* #0 RR 101 km/h mu 0.376 r1000, follower, no pedal: not a braking point (the rule does not act). Both cars are in a
  growing driver-induced lane oscillation at the end of the 5-s run (compensated -1.78 m at 5.0 s, twin +1.27 m and
  rising); over 6 / 8 / 10 s: 2.27 / 3.94 / 4.40 m vs 2.18 / 7.13 / 17.97 m - the verdict at 5 s is the oscillation's
  phase, documented, not tested here.

References, independent of the rule's code: requirement tire_blowout.no_worse_than_no_compensation (the twin is the same
point without the function, paper 004 Fig. 4 curve 2); the twin's own rear pressures (plant truth of the same run);
the proportioning valve's closed form p_r = p_knee + s*(p_mc - p_knee) from the vehicle file (35 bar, 0.35) for the
hand-made rows."""
from __future__ import annotations

import numpy as np
import pytest

import vehicle_assist as va
from tests.support import envelope_point_run
from vehicle_assist.functions import blowout_compensation as bc
from vehicle_assist.verification.envelope import load_envelope

METRIC = "blowout_lateral_deviation_run_max_m"
DEFECT = ("vehicle.blowout_compensation.rear_braking_flag=0",)
BAR = 1.0e5
# R2's targeted random seed 29, budget 64 (restricted as above), points #38 and #31 (falsify.json history)
P38 = {"speed": 112.46379388330504, "mu": 0.3433073688268372, "delay": 0.022215802278078733,
       "wheel_speed_noise": 0.27590449608977174, "noise_seed": 1365, "brake_gain": 1.0107744981659572,
       "brake.start_s": 1.3407824494164937, "brake.level_frac": 0.2958553358299938,
       "brake.rate_per_s": 27.033359227788612, "braking": "brakes", "wheel": "rr", "driver": "follow", "curve": "r650"}
P31 = {"speed": 109.03584288737832, "mu": 0.3601469790700983, "delay": 0.24597113406978155,
       "wheel_speed_noise": 0.06390270190823151, "noise_seed": 8804, "brake_gain": 1.0938604197539732,
       "brake.start_s": 0.583378645653009, "brake.level_frac": 0.2976158625024744,
       "brake.rate_per_s": 14.167289432559762, "braking": "brakes", "wheel": "rl", "driver": "fixed", "curve": "r650"}


@pytest.fixture(scope="module")
def env():
    return load_envelope("tire_blowout")


@pytest.fixture(scope="module")
def runs38(env):
    return {k: envelope_point_run(env, P38, baseline=(k == "none"), sets=DEFECT if k == "defect" else ())
            for k in ("on", "none", "defect")}


def _mean_bar(r, ch, t0, t1):
    t = np.asarray(r.trace["time_s"])
    x = np.asarray(r.trace[ch])
    return float(np.mean(x[(t >= t0) & (t <= t1)])) / BAR


def test_38_no_worse_than_without_compensation(runs38):
    """Measured: 2.315 m vs none 4.248 m (defect 4.454 m)."""
    on, none = runs38["on"].metrics[METRIC], runs38["none"].metrics[METRIC]
    assert on <= none, (on, none)


# Session o (O3): the strict xfail test_38_defect_is_worse_than_without_compensation (N5 class C: judged to standstill
# the defect and the twin both leave the road, the defect 0.080 s AFTER the twin, earliness 26.455 vs 26.535 s) is
# replaced by the negative controls at O3's targeted #97 / right #122 below (tests test_control_*), where the defect is worse than the
# twin by the requirement's row 1 with all three cars on the road.


def test_38_compensating_rear_keeps_the_drivers_pressure(runs38):
    """Mechanism: over t = 2.5-4.5 s (pedal on, HOLD) the compensating RL is not emptied by the ABS dumps - it carries at
    least half of the twin's intact-rear pressure (the twin: ABS with the driver's pressure, 22-27 bar); defect: 1.4 bar."""
    twin = _mean_bar(runs38["none"], "wheel_pressure_rl_pa", 2.5, 4.5)
    assert _mean_bar(runs38["on"], "wheel_pressure_rl_pa", 2.5, 4.5) >= 0.5 * twin, twin
    assert _mean_bar(runs38["defect"], "wheel_pressure_rl_pa", 2.5, 4.5) < 0.2 * twin


def test_31_no_worse_than_without_compensation(env):
    """Session n (N1, class D): the strict xfail of before (R2 targeted r29 #31, blown rear on the INSIDE of a curve the
    braking car understeers in: 2.21 m vs none 0.57 m at 5 s; tire_blowout.md 'Session g, G4') is gone when both cars
    are judged to standstill: road deviation 2.548 m (stopped 9.7 s) vs the twin's 3.085 m (stopped 9.8 s; its flat
    inner rear's turn-in goes on after 5 s), both on the road (departure row 0 = 0). Both rows of the requirement."""
    from tests.support import never_worse_rows

    rows = never_worse_rows(envelope_point_run(env, P31), envelope_point_run(env, P31, baseline=True))
    assert min(rows.values()) >= 0.0, rows


# ---- Session o (O3): the negative control under both rows, judged to standstill (tire_blowout_findings.md O3) ------
# O3's targeted search at main 8594568 on the rule's premise (R2's, a rear blowout with a braking driver at low friction
# and speed): falsify tire_blowout -r tire_blowout.no_worse_than_no_compensation --optimizer random --seed 613 -n 128
# -b 64 -R wheel=rl,rr -R braking=brakes -R mu=0.3..0.45 -R speed=90..120, #97: RR 95 km/h mu 0.336 LEFT curve r650
# (the blown rear outside), lane follower, pedal 0.14 from 1.59 s, 0.30 rad/s wheel-speed noise. Measured (pt.py):
#   defect (rear_braking_flag 0): the compensating RL 1.2 bar from 2.5 s to 9.5 s (each ABS dump re-built only to the
#     plan) while the twin's rear pair carries 13-26 bar; the car brakes less (15.3 vs 13.5 m/s at 5 s) and runs wide:
#     2.771 m (lane offset -2.75 m at 5 s, stopped 10.4 s),
#   shipped: RL re-built to 20-49 bar, 1.661 m (stopped 9.1 s); twin: 2.415 m (stopped 9.3 s). All on the road.
# Rows (twin - car): defect row 1 -0.355 m, row 2 0; shipped row 1 +0.755 m, row 2 0.
P97 = {"speed": 94.80522331282222, "mu": 0.33567299831483244, "delay": 0.22320211924930414,
       "wheel_speed_noise": 0.29987550122035467, "noise_seed": 3123.0, "brake_gain": 1.143635024637663,
       "brake.start_s": 1.5942297171921198, "brake.level_frac": 0.13623610908541955,
       "brake.rate_per_s": 27.12365547029375, "braking": "brakes", "wheel": "rr", "driver": "follow", "curve": "r650"}


# The same search on the right-hand-curve envelope (tire_blowout_right, same command, seed 613), #122: RL 114 km/h
# mu 0.361 RIGHT curve rr650 (the blown rear outside: #97 mirrored), lane follower, pedal 0.19 from 1.54 s, 0.30 rad/s
# noise. Defect: the compensating RR 1.5 bar from 3 s to 10 s against the twin's rear pair 16-30 bar, 3.745 m; shipped:
# RR re-built to 24-60 bar, 2.322 m; twin 3.353 m. All on the road. Rows: defect row 1 -0.392 m, row 2 0; shipped
# row 1 +1.031 m, row 2 0. (Also defect-only row-1 violations of that search: left #58 -0.102 m, right #124 -0.297 m,
# #84 -0.068 m; tire_blowout_findings.md O3.)
P122R = {"speed": 114.01462641416182, "mu": 0.36143668495075065, "delay": 0.4148926188132933,
         "wheel_speed_noise": 0.2964638212007317, "noise_seed": 6788.0, "brake_gain": 0.7808141777595199,
         "brake.start_s": 1.541213512525794, "brake.level_frac": 0.18846559244074232,
         "brake.rate_per_s": 17.36194037698757, "braking": "brakes", "wheel": "rl", "driver": "follow",
         "curve": "rr650"}
# (envelope, point, the compensating rear's pressure channel)
CONTROLS = {"left_97": ("tire_blowout", P97, "wheel_pressure_rl_pa"),
            "right_122": ("tire_blowout_right", P122R, "wheel_pressure_rr_pa")}


@pytest.fixture(scope="module", params=sorted(CONTROLS))
def control_runs(request):
    name, point, ch = CONTROLS[request.param]
    e = load_envelope(name)
    runs = {k: envelope_point_run(e, point, baseline=(k == "none"), sets=DEFECT if k == "defect" else ())
            for k in ("on", "none", "defect")}
    return runs, ch


def test_control_defect_is_worse_than_without_compensation(control_runs):
    """Negative control (replaces N5's strict xfail at #38): the seeded defect (the code before) fails the requirement's
    row no_worse_than_no_compensation with all cars on the road - #97 2.771 m vs the twin's 2.415 m (-0.355 m), right
    #122 3.745 vs 3.353 m (-0.392 m). Both rows (tests/support.never_worse_rows)."""
    from tests.support import never_worse_rows

    runs, _ = control_runs
    rows = never_worse_rows(runs["defect"], runs["none"])
    assert min(rows.values()) < 0.0, rows


def test_control_no_worse_than_without_compensation(control_runs):
    """The rule passes both rows where its defect fails: #97 1.661 vs 2.415 m, #122 2.322 vs 3.353 m, no road
    departure (flag 0: row 1 -0.355 / -0.392 m, so this assertion fails at the defect value)."""
    from tests.support import never_worse_rows

    runs, _ = control_runs
    rows = never_worse_rows(runs["on"], runs["none"])
    assert min(rows.values()) >= 0.0, rows


def test_control_compensating_rear_keeps_the_drivers_pressure(control_runs):
    """Mechanism (the rule's reason, as test_38's): over t = 2.5-7.5 s (pedal on, HOLD) the compensating rear carries
    at least half of the twin's pressure on the same wheel (the twin: ABS with the driver's pressure, mean 18.9 / 23.5
    bar at #97 / #122; shipped 33.2 / 46.5 bar); the defect empties it (mean 1.9 / 2.1 bar: < 0.2 of the twin's)."""
    runs, ch = control_runs
    twin = _mean_bar(runs["none"], ch, 2.5, 7.5)
    assert _mean_bar(runs["on"], ch, 2.5, 7.5) >= 0.5 * twin, twin
    assert _mean_bar(runs["defect"], ch, 2.5, 7.5) < 0.2 * twin


# ---- the rule on hand-made values (bc.braking_rule dispatches a rear blowout to rear_braking_rule) -------------------
@pytest.fixture(scope="module")
def params():
    from vehicle_assist.scenarios.runner import pack_records

    return pack_records([va.load_scenario("blowout_lf_60kph_paper").vehicle.flat()])[0]


def _state(blown, p_req_pa):
    st = bc.initial_state()
    st[bc.S_BLOWN] = blown
    st[bc.S_TARGET] = bc.OPPOSITE[blown]
    st[bc.S_MODE] = bc.HOLD
    st[bc.S_P_REQ] = p_req_pa
    return st


def _step(st, p, yaw, p_est_tg, p_mc_bar=100.0, braking=1.0, flag=1):
    """One call of bc.braking_rule (yaw: measured minus reference, rad/s); the target S_P_BRAKE in bar or None."""
    q = p.copy()
    q.blowout_compensation_rear_braking_flag = flag
    b, tg = int(st[bc.S_BLOWN]), int(st[bc.S_TARGET])
    p_est = np.zeros(4)
    p_est[tg] = p_est_tg * BAR
    bc.braking_rule(st, b, tg, bc.HOLD, braking, -3.0, 0.0, yaw, p_mc_bar * BAR, p_est, q)
    return st[bc.S_P_BRAKE] / BAR if st[bc.S_P_BRAKE] >= 0.0 else None


P_DRV_100 = 35.0 + 0.35 * (100.0 - 35.0)  # proportioning valve at 100 bar master pressure (vehicle file: 35 bar, 0.35)


@pytest.mark.parametrize("flag", [1, 0])
def test_row_rebuilt_to_the_drivers_level_after_a_dump(params, flag):
    """RL blown, plan 0 bar, driver 100 bar (57.75 bar at the rear): the wheel reaches 40 bar through the line (no target:
    the ESP's usual arbitration), an ABS dump takes it to 10 bar -> re-build target 40 bar (not the plan's 0).
    With the flag at 0 (the code before) no target is set: the ESP re-built to the plan."""
    st = _state(2, 0.0)
    assert _step(st, params, 0.0, 40.0, flag=flag) is None
    got = _step(st, params, 0.0, 10.0, flag=flag)
    if flag:
        assert got == pytest.approx(40.0)
    else:
        assert got is None


def test_row_rebuild_never_above_the_drivers_pressure(params):
    """A wheel above the driver's rear pressure (a plan of 70 bar held) re-builds to max(plan, driver) = 70 bar, and with
    a plan of 0 the level counts only up to the driver's 57.75 bar."""
    st = _state(2, 70.0 * BAR)
    _step(st, params, 0.0, 75.0)
    assert _step(st, params, 0.0, 30.0) == pytest.approx(70.0)
    st = _state(2, 0.0)
    _step(st, params, 0.0, 75.0)
    assert _step(st, params, 0.0, 30.0) == pytest.approx(P_DRV_100)


def test_row_mirror_rr_blown(params):
    """RR blown, compensating RL: the same re-build (the rule does not depend on the side)."""
    st = _state(3, 5.0 * BAR)
    _step(st, params, 0.0, 30.0)
    assert _step(st, params, 0.0, 12.0) == pytest.approx(30.0)


def test_row_below_the_level_by_less_than_1_bar_no_target(params):
    """Within 1 bar of the level reached (the estimate's resolution) the ESP's usual arbitration stays."""
    st = _state(2, 0.0)
    _step(st, params, 0.0, 40.0)
    assert _step(st, params, 0.0, 39.5) is None


def test_row_not_without_the_pedal_nor_for_front_blowouts(params):
    st = _state(2, 0.0)
    _step(st, params, 0.0, 40.0, braking=0.0)
    assert _step(st, params, 0.0, 10.0, braking=0.0) is None
    st = _state(0, 0.0)  # a FRONT blowout: the front braking rule (always sets its own target), not this one
    st[bc.S_P_REQ] = 20.0 * BAR
    got = _step(st, params, 0.0, 10.0)
    assert got is not None and got >= 20.0
