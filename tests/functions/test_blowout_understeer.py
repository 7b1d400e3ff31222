"""The understeer rule's restore (``understeer_flag``, functions/blowout_compensation.py ``understeer_rule``) against the
tire-capacity rule's latch (``tire_capacity_rule``, ``understeer_cap_freeze_flag``) - session 2026-11-24 g, task G3;
review R1 (tire_blowout_findings.md R1; tire_blowout_sessions.md "Status at the end of session 2026-11-24 f").

References (independent of the code's own formulas):
* Dugoff's tire (spec 2.3): in the linear region F_x = C_x*s/(1 - s); a measured brake force of a quarter of that at the
  same slip is a saturated reading (f = 0.25), whose pure-longitudinal inversion gives a capacity far below the cap.
  In combined slip that reading is mu*C_x*s/sqrt((C_x*s)^2 + (C_a*tan(alpha))^2): it falls with the slip, i.e. with
  the pressure the understeer rule dumped - the held wheel's friction direction, not its capacity.
* The capacity rule's contract (its docstring, tire_blowout.md): the lowest capacity measured at the plan's own pressure
  is kept (latched); the understeer rule's restore brings back the target it stored before lowering (which the latch
  had already capped).

Unit level: one period of each rule on a hand-built state whose filtered window (WS_WINDOW_N samples) holds a steady
wheel: the free rear wheels at the car's speed, the compensating front FR at slip s and pressure p.

Can fail: ``understeer_cap_freeze_flag = 0`` lowers the latched cap from the held wheel's reading (the freeze test and
the no-stale-window check fail; the negative control below shows it)."""
from __future__ import annotations

import numpy as np
import pytest

import vehicle_assist as va
from vehicle_assist.functions import blowout_compensation as bc
from vehicle_assist.scenarios.runner import pack_records
from tests.support import fill_ecu_window

BAR = 1.0e5
FL, FR = 0, 1
V_MPS = 25.0
SLIP = 0.03  # well above CAP_MIN_SLIP (1 %)
FREEZE0 = "vehicle.blowout_compensation.understeer_cap_freeze_flag=0"


def _params(*sets):
    sc = va.load_scenario("blowout_lf_60kph_paper")
    if sets:
        sc = sc.with_sets(*sets)
    return pack_records([sc.vehicle.flat()])[0]


@pytest.fixture(scope="module")
def params():
    return _params()


def _linear_pressure_pa(p):
    """Pressure whose brake force K_b*p/R is Dugoff's linear force C_x*s/(1 - s) at SLIP (steady wheel, no spin-up)."""
    f_lin = p.tires_longitudinal_stiffness_n * SLIP / (1.0 - SLIP)
    return f_lin * p.body_wheel_radius_m / p.brakes_front_gain_nm_per_pa


def _state(p_fr_pa):
    """HOLD after an FL blowout, FR compensating, capacity latched (a friction below the nominal was measured); the
    filtered window: FL fast (flat), FR at SLIP with pressure p_fr_pa, the rears rolling free at V_MPS."""
    st = bc.initial_state()
    st[bc.S_BLOWN], st[bc.S_TARGET], st[bc.S_MODE] = FL, FR, bc.HOLD
    st[bc.S_SOURCES] = bc.SRC_WS + bc.SRC_TPMS
    st[bc.S_P_START] = 0.0
    st[bc.S_P_REQ] = 40.0 * BAR  # the plan (balance, eq. 28)
    st[bc.S_P_ADD] = 40.0 * BAR
    st[bc.S_FZ_TARGET] = 6000.0
    st[bc.S_CAP_LATCHED] = 1.0
    speeds = (1.3 * V_MPS, (1.0 - SLIP) * V_MPS, V_MPS, V_MPS)
    press = (0.0, p_fr_pa, 0.0, 0.0)
    fill_ecu_window(st, speeds, press)
    return st, np.array(press)


def _capacity_period(p, st, p_est):
    requests = np.zeros(4)
    vw = np.array([1.3 * V_MPS, (1.0 - SLIP) * V_MPS, V_MPS, V_MPS])
    bc.tire_capacity_rule(st, FR, vw, V_MPS, 0.0, 0.0, p_est, requests, p, 0.005)
    return requests


def _held_state(p):
    """The understeer rule holds FR at a lowered pressure (a quarter of the linear force at SLIP: the saturated
    reading of a wheel carrying the curve), its stored plan 25 bar (below the 30 bar cap latched at the plan's
    pressure, as the capacity rule leaves it); the capacity evidence has persisted (S_LOW_S)."""
    p_held = 0.25 * _linear_pressure_pa(p)
    st, p_est = _state(p_held)
    st[bc.S_US_LIMITED] = 1.0
    st[bc.S_US_PLAN] = 25.0 * BAR
    st[bc.S_P_REQ] = p_held
    st[bc.S_F_CAP] = 30.0 * BAR * p.brakes_front_gain_nm_per_pa / p.body_wheel_radius_m
    st[bc.S_LOW_S] = bc.CAP_PERSIST_S
    return st, p_est


def test_cap_not_lowered_while_the_understeer_rule_holds(params):
    """While held below the plan the wheel's reading falls with the pressure the rule dumped: the latched cap stays at
    the 30 bar measured at the plan's pressure; the restore brings back the stored plan (25 bar), and the held
    wheel's samples still in the filter window do not lower it in the next period (a fresh window first)."""
    st, p_est = _held_state(params)
    f_cap = st[bc.S_F_CAP]
    _capacity_period(params, st, p_est)
    assert st[bc.S_F_CAP] == f_cap
    # restore: the car turns toward the blown side beyond the reference by 0.1 rad/s
    requests = np.zeros(4)
    bc.understeer_rule(st, FL, FR, bc.HOLD, 0.0, 0.2, 0.3, p_est, requests, params, 0.005)
    assert st[bc.S_US_LIMITED] == 0.0
    assert st[bc.S_P_REQ] == pytest.approx(25.0 * BAR)
    _capacity_period(params, st, p_est)  # same (held) window
    assert st[bc.S_F_CAP] == f_cap
    assert st[bc.S_P_REQ] == pytest.approx(25.0 * BAR)


def test_cap_lowered_when_not_held(params):
    """Control: the same evidence without the understeer hold (the wheel at its plan) lowers the cap (lowest kept)."""
    st, p_est = _held_state(params)
    st[bc.S_US_LIMITED] = 0.0
    f_cap = st[bc.S_F_CAP]
    _capacity_period(params, st, p_est)
    assert st[bc.S_F_CAP] < f_cap


def test_cap_lowered_while_held_with_the_defect():
    """Negative control: understeer_cap_freeze_flag = 0 lowers the cap from the held wheel's reading."""
    p = _params(FREEZE0)
    st, p_est = _held_state(p)
    f_cap = st[bc.S_F_CAP]
    _capacity_period(p, st, p_est)
    assert st[bc.S_F_CAP] < f_cap
