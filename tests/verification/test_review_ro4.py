"""RO4 (session 2026-11-25 o): review of O4's ``blowout_compensation.blown_side_stop_flag`` = 1
(tire_blowout_findings.md O4, RO4).

O4's tests (test_blowout_o4_blown_side_stop.py) judge the rule by its benefit at #474 and its mirror. Three mutants of
the rule passed all of them (RO4): dropping the code-6 premise (the share taken inside the dead band for ANY braked
front blowout), braking the blown front under the rule (caught only through the road metric), and taking ABS away as
the limiter of the counter-brake front (no dump, no pre-dump ceiling while code 6). The tests below pin the rule's
statement where the benefit tests cannot see it:

* the premise: without limit code 6 the flag changes nothing (bit for bit) - a diagonal fault (FL blown, RR stuck) and
  the same point without a fault, both of which the premise-free mutant changes (3.668 -> 2.014 m, 3.366 -> 1.818 m);
* ABS stays the limiter (the rule's source text: "ABS the limiter"): while code 6 above 15 km/h the counter-brake front
  is never held locked for longer than 0.1 s (assumed: shorter than one ABS dump/re-build cycle; ABS's purpose is that
  a wheel it guards does not stay locked, Bosch Automotive Handbook ABS). Shipped: 0.0 s at #474 and its mirror;
  mutant (no ABS limit): 1.2 s / 0.885 s;
* the paper's release of the blown front (paper 004 eqs. 22-28: the blown wheel is not braked) holds under the rule:
  with blown_front_hold_flag 0 (the one documented rule that re-applies a blown front: X2, a curve steered toward
  the blown side with the other front at its ABS limit) the blown front stays below 1 bar while code 6;
* the RL2 point #360 mirrored (FR blown, RR stuck, straight, driver follows): the blown FR braked from 3.2 s at the
  shipped flags is blown_front_hold's re-apply (Q_HOLD -> W_N: the driver's 167 bar master pressure through the
  opened inlet, then ABS-dumped), which O4's rule uncovers by bringing the counter-brake FL to its ABS limit; the
  steered reference of the driver's counter-steer on the straight road reads as a curve toward FR. With
  blown_front_hold_flag 0 FR stays at 0 bar. (RO4 traced it per 5 ms sample: FR wheel mode HI -> N at 3.215 s, the
  moment FL's ABS dumps.)

These are invariants of the rule's statement, not of its benefit: at blown_side_stop_flag 0 they pass as well (the
flag-0 failures are O4's benefit tests); each is shown to FAIL on its mutant (findings RO4).
"""
from __future__ import annotations

import numpy as np
import pytest

from vehicle_assist.verification.envelope import load_envelope
from tests.support import envelope_point_run
from tests.verification.test_blowout_o4_blown_side_stop import P474, P474M
from tests.verification.test_review_rl2 import P360

ON = ("vehicle.blowout_compensation.blown_side_stop_flag=1",)
OFF = ("vehicle.blowout_compensation.blown_side_stop_flag=0",)
HOLD0 = ("vehicle.blowout_compensation.blown_front_hold_flag=0",)
W = ("fl", "fr", "rl", "rr")
BAR = 1.0e5
V_ABS_MPS = 15.0 / 3.6  # ABS's low-speed end of the no-lock requirement (UN R13-H Annex 6: 15 km/h)
LOCK_MAX_S = 0.1  # assumed: shorter than one ABS dump/re-build cycle


def _pressures(r):
    return np.concatenate([np.asarray(r.trace[f"wheel_pressure_{w}_pa"]) for w in W])


@pytest.mark.parametrize("case", ["diagonal_rr", "no_fault"])
def test_no_code_6_no_change(case):
    """The premise (limit code 6: the blown FRONT's same-side REAR inlet stuck, under the pedal): #474 with the
    fault on the diagonal rear (FL blown, RR stuck) and without a fault never write code 6, so flag 1 must equal
    flag 0 bit for bit. The premise-free mutant changes both (RO4)."""
    if case == "diagonal_rr":
        env, pt = load_envelope("tire_blowout_faults"), dict(P474, fault="inlet_stuck_rr")
    else:
        env = load_envelope("tire_blowout")
        pt = {k: v for k, v in P474.items() if k not in ("fault", "fault_time", "accumulator")}
    on, off = envelope_point_run(env, pt, sets=ON), envelope_point_run(env, pt, sets=OFF)
    assert np.all(np.asarray(on.trace["blowout_limit_code"]) != 6)  # the premise is false here
    assert np.max(np.asarray(on.trace["brake_pedal_frac"])) > 0.05  # and the rule's other condition true
    assert np.array_equal(_pressures(on), _pressures(off))


def _longest(mask, t):
    dt = float(t[1] - t[0])
    best = cur = 0.0
    for x in mask:
        cur = cur + dt if x else 0.0
        best = max(best, cur)
    return best


@pytest.mark.parametrize("side", ["474", "474m"])
def test_counter_brake_front_stays_abs_limited(side):
    """ABS stays the limiter of the share the rule gives: while code 6 and above 15 km/h the counter-brake front is
    never held locked for more than 0.1 s. Shipped 0.0 s on both; the no-ABS-limit mutant 1.2 / 0.885 s."""
    env_name, pt, tg = (("tire_blowout_faults", P474, "fr") if side == "474"
                        else ("tire_blowout_faults_right", P474M, "fl"))
    r = envelope_point_run(load_envelope(env_name), pt)
    t = np.asarray(r.trace["time_s"])
    c6 = np.asarray(r.trace["blowout_limit_code"]) == 6
    assert c6.sum() > 1000  # the premise holds over the stop (5 ms samples)
    m = (c6 & (np.asarray(r.trace[f"wheel_locked_{tg}_flag"]) > 0.5)
         & (np.asarray(r.trace["speed_mps"]) > V_ABS_MPS))
    assert _longest(m, t) <= LOCK_MAX_S, _longest(m, t)


@pytest.mark.parametrize("side", ["474", "474m"])
def test_blown_front_released_under_the_rule(side):
    """Paper 004 eqs. 22-28: the blown wheel is not braked. With blown_front_hold_flag 0 (X2's documented re-apply in
    a curve toward the blown side taken out) the blown front stays below 1 bar while code 6, the rule on. A rule that
    braked the blown front instead of (or with) the counter-brake front fails this."""
    env_name, pt, b = (("tire_blowout_faults", P474, "fl") if side == "474"
                       else ("tire_blowout_faults_right", P474M, "fr"))
    r = envelope_point_run(load_envelope(env_name), pt, sets=ON + HOLD0)
    c6 = np.asarray(r.trace["blowout_limit_code"]) == 6
    assert c6.sum() > 1000
    assert float(np.max(np.asarray(r.trace[f"wheel_pressure_{b}_pa"])[c6])) < 1.0 * BAR


def test_360_mirror_blown_fr_braked_only_by_blown_front_hold():
    """O4's untraced effect, traced: at RL2's #360 mirrored (FR blown, RR stuck, straight, driver follows) the blown FR
    is braked at the shipped flags (> 5 bar after the detection; measured up to 56 bar, ABS-dumped) and NOT with
    blown_front_hold_flag 0 (<= 1 bar, measured 0): the request is blown_front_hold's Q_HOLD, not O4's rule nor the
    driver's pressure around the function. At blown_side_stop_flag 0 the first assertion fails (FR 0 bar): the
    effect is uncovered by O4's rule, which brings the counter-brake FL to the ABS limit blown_front_hold waits for."""
    env = load_envelope("tire_blowout_faults")
    pt = dict(P360, wheel="fr", fault="inlet_stuck_rr")
    on = envelope_point_run(env, pt)
    hold0 = envelope_point_run(env, pt, sets=HOLD0)
    for r, lo, hi in ((on, 5.0 * BAR, None), (hold0, None, 1.0 * BAR)):
        t = np.asarray(r.trace["time_s"])
        fr = float(np.max(np.asarray(r.trace["wheel_pressure_fr_pa"])[t >= 1.4]))
        if lo is not None:
            assert fr > lo, fr / BAR
        if hi is not None:
            assert fr <= hi, fr / BAR
