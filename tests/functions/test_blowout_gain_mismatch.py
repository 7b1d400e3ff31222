"""Tire-capacity rule with a plant that is NOT the ECU's nominal (issue #10 independent review, finding 2).

The estimator test in test_blowout_tire_capacity.py inverts the plant's own Dugoff with the ECU's own data. Here the
"plant" that makes the wheel's pressure has a different pad friction (brake gain) and longitudinal stiffness C_x than
the ECU believes, and the reference is independent of the ECU: the friction the road actually has.

Tolerances (sources): pad friction +-13 % = an SAE J866 friction-code band (e.g. F: 0.35-0.45 about 0.40; hot/fade and
wet friction are coded/tested separately and can be far lower), as in the SUV file's brakes.gain_scale_frac; C_x +-15 %
assumed (tire wear, inflation and temperature; the SUV file's tires.longitudinal_stiffness_scale_frac).
Cases: a wet road (mu 0.35) must be detected (latch, target lowered); a road with more friction than the ECU's nominal
0.8 (mu 1.0, dry asphalt) must not be. With the defect (tire_capacity_flag = 0) nothing latches: the wet cases fail.
"""
from __future__ import annotations

import numpy as np
import pytest

import vehicle_assist as va
from vehicle_assist.functions import blowout_compensation as bc
from vehicle_assist.plant.tires.dugoff import dugoff_forces

V = 100.0 / 3.6
FAST = V * 0.359 / 0.24  # tire_blowout.md 7: R_out/R_in
GAIN = (0.87, 1.13)  # plant pad friction / nominal (SAE J866 code band)
CX = (0.85, 1.15)  # plant C_x / nominal (assumed)


@pytest.fixture(scope="module")
def params():
    from vehicle_assist.scenarios.runner import pack_records

    return pack_records([va.load_scenario("blowout_lf_60kph_paper").vehicle.flat()])[0]


def _run(params, mu_road, s, k_gain, k_cx, flag=1):
    """LF blown at 100 km/h, no driver's brake; RF (the compensating wheel) slows into slip s over 8 periods and holds
    it 50 ms. Its pressure is what a plant with brake gain k_gain*K_b and stiffness k_cx*C_x needs for its Dugoff force
    on a road of mu_road (plus J*|omega_dot| while it slows). Returns (latched, held force / road H = 1 force)."""
    p = params.copy()
    p.blowout_compensation_tire_capacity_flag = float(flag)
    st = bc.initial_state()
    ev = np.zeros((64, 5))
    req = np.zeros(4, dtype=np.int64)
    dt = 0.005
    clock = {"n": 0, "t": 0.0}

    def step(vw, p_est):
        v_ref = bc.reference_step(st, np.array(vw, float), 0.0, 1.0, dt, p)
        clock["n"] = bc.blowout_step(st, np.array(vw, float), v_ref, 0.0, 0.0, 0.0, 0.0, 1.0, np.ones(4),
                                     np.array(p_est, float), p, dt, clock["t"], 6, ev, clock["n"], req, 0.0)
        clock["t"] += dt

    for _ in range(40):
        step((V, V, V, V), (0, 0, 0, 0))
    for _ in range(12):
        step((FAST, V, V, V), (0, 0, 0, 0))
    assert bc.MODES[int(st[bc.S_MODE])] in ("BUILD", "HOLD")
    fz = st[bc.S_FZ_TARGET]
    k_b = p.brakes_front_gain_nm_per_pa * k_gain  # the plant's actual gain
    r = p.body_wheel_radius_m

    def pressure(sk, t_extra=0.0):
        f = abs(dugoff_forces(sk, 0.0, fz, mu_road, p.tires_longitudinal_stiffness_n * k_cx,
                              p.tires_cornering_stiffness_front_n_per_rad)[0])
        return (f * r + t_extra) / k_b

    n = 8
    t_dec = p.body_wheel_inertia_kgm2 * (V * s / (n * dt)) / r
    for k in range(1, n + 1):
        step((FAST, V * (1.0 - s * k / n), V, V), (0, pressure(s * k / n, t_dec), 0, 0))
    for _ in range(10):
        step((FAST, V * (1.0 - s), V, V), (0, pressure(s), 0, 0))
    held = st[bc.S_P_REQ] * k_b / r  # the force the held target actually gives (plant gain)
    return st[bc.S_CAP_LATCHED] > 0.5, held / (0.5 * mu_road * fz)


# the cost of judging at the upper end of the pad-friction tolerance (brake_gain_tolerance_frac 0.18): a plant with
# 13 % LESS pad friction than nominal on mu 0.35 at 4 % slip reads q*1.18/0.87 = 1.36 x its true f(H), above 0.8 or with a
# capacity above the nominal mu: the rule waits for deeper slip (at 10 % it latches in all cases, below)
LATE = {(0.87, 0.85, 0.04), (0.87, 1.15, 0.04)}
WET = [pytest.param(g, c, s, marks=pytest.mark.xfail(strict=True, reason="honest FAIL, the gain tolerance's cost: -13 % "
                    "pad friction at 4 % slip on mu 0.35 is not told from +18 % pad friction in the linear region by an "
                    "absolute force; latched at 10 % slip")) if (g, c, s) in LATE else (g, c, s)
       for g in GAIN for c in CX for s in (0.04, 0.10)]


@pytest.mark.parametrize("k_gain,k_cx,s", WET)
def test_wet_road_detected_with_gain_and_stiffness_error(params, k_gain, k_cx, s):
    """mu 0.35 road (the ECU plans with 0.8): the rule latches, and the target's actual force is at most ~the road's
    H = 1 force mu*F_z/2 (the rule's own aim) inflated by the gain error it cannot see (1/0.87 = 1.15)."""
    latched, ratio = _run(params, 0.35, s, k_gain, k_cx)
    assert latched
    assert ratio <= 1.0 / min(GAIN) * 1.05


def test_wet_road_not_detected_with_the_defect(params):
    """Negative control: tire_capacity_flag = 0 never latches."""
    assert not _run(params, 0.35, 0.10, 1.13, 0.85, flag=0)[0]


DRY = [(k_gain, k_cx, s) for k_gain in GAIN for k_cx in CX for s in (0.03, 0.05)]
# measured: a plant with 13 % MORE pad friction than nominal reads as a 13 % weaker tire with the nominal gain
# (q = f(H)/1.13); with a softer tire (C_x -15 %) q = 0.85/1.13 = 0.75 < CAP_FORCE_RATIO 0.8 inside the linear region,
# and the capacity inverted from it is small at small slip, so mu_est < 0.8 too: the rule false-latched on a dry road
# until it judged the evidence at the upper end of the pad-friction tolerance (brake_gain_tolerance_frac 0.18:
# q = 0.75*1.18 = 0.89 > 0.8)
FALSE_LATCH = [(1.13, 0.85, 0.03), (1.13, 0.85, 0.05)]


@pytest.mark.parametrize("k_gain,k_cx,s", DRY)
def test_dry_road_not_limited_with_gain_and_stiffness_error(params, k_gain, k_cx, s):
    """mu 1.0 road (more than the ECU's nominal 0.8): no latch."""
    assert not _run(params, 1.0, s, k_gain, k_cx)[0]


@pytest.mark.parametrize("k_gain,k_cx,s", FALSE_LATCH)
def test_dry_road_false_latch_with_the_gain_tolerance_defect(params, k_gain, k_cx, s):
    """Negative control: brake_gain_tolerance_frac = 0 (nominal gain only, the rule before) latches on the dry road."""
    p = params.copy()
    p.blowout_compensation_brake_gain_tolerance_frac = 0.0
    assert _run(p, 1.0, s, k_gain, k_cx)[0]


@pytest.mark.parametrize("k_gain", (1.0, 1.13, 1.18))
def test_wet_road_detected_at_the_tolerance_edge(params, k_gain):
    """The tolerance's cost on a wet road (mu 0.35 and 0.5 against the nominal 0.8): still latched with the plant at the
    upper end of the pad-friction band (a stiffer tire C_x +15 % is the hardest case: it reads least saturated)."""
    for mu in (0.35, 0.5):
        assert _run(params, mu, 0.10, k_gain, 1.15)[0], mu
