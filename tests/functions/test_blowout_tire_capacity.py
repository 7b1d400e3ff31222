"""Compensating wheel limited by what its tire measurably gives (issue #10 round 3; functions/blowout_compensation.py
``tire_capacity_check`` / ``tire_capacity_rule``, flag ``tire_capacity_flag``, 0 = seeded defect).

References: the plant's Dugoff tire (plant/tires/dugoff.py, spec 2.3) gives the force a wheel at slip s carries on a
road of friction mu; the estimator, fed with the brake pressure that balances that force (steady wheel) and the slip,
must return that force, q = f(H) and the capacity mu*F_z; and the wheel spin balance J*omega_dot = F_x*R - T_b."""
from __future__ import annotations

import numpy as np
import pytest

import vehicle_assist as va
from vehicle_assist.functions import blowout_compensation as bc
from vehicle_assist.plant.tires.dugoff import dugoff_forces

V = 100.0 / 3.6
R_OUT, R_IN = 0.359, 0.24  # tire_blowout.md 7
FAST = V * R_OUT / R_IN


@pytest.fixture(scope="module")
def params():
    from vehicle_assist.scenarios.runner import pack_records

    return pack_records([va.load_scenario("blowout_lf_60kph_paper").vehicle.flat()])[0]


def _steady(params, mu, fz, s):
    """Plant Dugoff brake force at slip s (alpha = 0) and the front pressure that balances it on a steady wheel."""
    f = abs(dugoff_forces(s, 0.0, fz, mu, params.tires_longitudinal_stiffness_n,
                          params.tires_cornering_stiffness_front_n_per_rad)[0])
    return f, f * params.body_wheel_radius_m / params.brakes_front_gain_nm_per_pa


@pytest.mark.parametrize("mu,s", [(0.35, 0.10), (0.35, 0.04), (0.8, 0.08)])
def test_check_recovers_the_tire_force_and_its_friction_out_of_the_linear_region(params, mu, s):
    fz = 6000.0
    f, p = _steady(params, mu, fz, s)
    vw = V * (1.0 - s)
    fx, s_m, q, cap = bc.tire_capacity_check(p, vw, vw, V, 0.005, params.brakes_front_gain_nm_per_pa, params)
    lin = params.tires_longitudinal_stiffness_n * s / (1.0 - s)
    assert f < 0.999 * lin  # the point is out of the linear region (H < 1)
    assert fx == pytest.approx(f, rel=1e-9) and s_m == pytest.approx(s, rel=1e-9)
    assert q == pytest.approx(f / lin, rel=1e-9)
    assert cap == pytest.approx(mu * fz, rel=1e-6)  # the road's friction times the load, from measurements only


def test_check_reads_one_in_the_linear_region(params):
    f, p = _steady(params, 0.8, 6000.0, 0.01)
    vw = V * 0.99
    _, _, q, _ = bc.tire_capacity_check(p, vw, vw, V, 0.005, params.brakes_front_gain_nm_per_pa, params)
    assert q == pytest.approx(1.0, abs=1e-9)


def test_check_takes_the_wheel_deceleration_off_the_brake_torque(params):
    """J*omega_dot = F_x*R - T_b: a wheel spinning down at 100 rad/s^2 carries J*100/R less than T_b/R."""
    p = 30e5
    r = params.body_wheel_radius_m
    dt = 0.005
    fx, _, _, _ = bc.tire_capacity_check(p, V - 100.0 * r * dt, V, V, dt, params.brakes_front_gain_nm_per_pa, params)
    assert fx == pytest.approx((params.brakes_front_gain_nm_per_pa * p - params.body_wheel_inertia_kgm2 * 100.0) / r,
                               rel=1e-6)


def _ecu_run(params, flag, braking=0.0, mu_road=0.35, s=0.10):
    """LF blown at 100 km/h, RF (the compensating wheel) then shows slip s with the pressure that balances the plant
    Dugoff force on a road of mu_road. Returns (state, RF request, pressure shown)."""
    p = params.copy()
    p.blowout_compensation_tire_capacity_flag = float(flag)
    st = bc.initial_state()
    ev = np.zeros((64, 5))
    req = np.zeros(4, dtype=np.int64)
    n, t, dt = 0, 0.0, 0.005

    def step(vw, tpms, p_est):
        nonlocal n, t
        v_ref = bc.reference_step(st, np.array(vw, float), 0.0, tpms, dt, p)
        n = bc.blowout_step(st, np.array(vw, float), v_ref, braking, 0.0, 0.0, 0.0, tpms, np.ones(4),
                            np.array(p_est, float), p, dt, t, 6, ev, n, req, 0.0)
        t += dt

    for _ in range(40):
        step((V, V, V, V), 0.0, (0, 0, 0, 0))
    for _ in range(12):  # detection (0.05 s) and the plan at p_0 = 0
        step((FAST, V, V, V), 1.0, (0, 0, 0, 0))
    assert bc.MODES[int(st[bc.S_MODE])] in ("BUILD", "HOLD")
    fz = st[bc.S_FZ_TARGET]
    _, p_rf = _steady(p, mu_road, fz, s)
    # the wheel slows into its slip over 8 periods (a wheel cannot step: the filtered deceleration, signal_filter_flag,
    # would read a step as 8 periods of infinite deceleration), its pressure the plant balance of the Dugoff force at
    # each slip plus the torque that decelerates the wheel, J*|omega_dot| (spin balance J*omega_dot = F_x*R - T_b)
    n_ramp = 8
    t_dec = p.body_wheel_inertia_kgm2 * (V * s / (n_ramp * dt)) / p.body_wheel_radius_m  # J*|omega_dot| [N*m]
    for k in range(1, n_ramp + 1):
        _, p_k = _steady(p, mu_road, fz, s * k / n_ramp)
        step((FAST, V * (1.0 - s * k / n_ramp), V, V), 1.0, (0, p_k + t_dec / p.brakes_front_gain_nm_per_pa, 0, 0))
    for _ in range(10):  # 50 ms out of the linear region
        step((FAST, V * (1.0 - s), V, V), 1.0, (0, p_rf, 0, 0))
    return st, int(req[1]), p_rf


def test_rule_lowers_the_target_below_the_measured_force_and_dumps(params):
    """mu 0.35 road, RF at 10 % slip: latched; target <= the Dugoff H = 1 force of the measured capacity
    (mu*F_z/2, as pressure) and <= the plan re-scaled to the measured friction; the added pressure is dumped."""
    st, rq, p_rf = _ecu_run(params, 1)
    assert st[bc.S_CAP_LATCHED] == 1.0
    h1 = 0.5 * 0.35 * st[bc.S_FZ_TARGET] * params.body_wheel_radius_m / params.brakes_front_gain_nm_per_pa
    assert st[bc.S_P_REQ] <= h1 * 1.001
    assert st[bc.S_P_REQ] <= st[bc.S_P_ADD] * 0.35 / params.blowout_compensation_mu_estimate_frac * 1.001
    assert st[bc.S_P_REQ] >= st[bc.S_P_START]
    assert rq == bc.Q_RELEASE


def test_rule_off_with_the_defect(params):
    """Negative control: tire_capacity_flag = 0 keeps the nominal plan (target unchanged, no dump)."""
    st, rq, _ = _ecu_run(params, 0)
    assert st[bc.S_CAP_LATCHED] == 0.0 and rq != bc.Q_RELEASE
    assert st[bc.S_P_REQ] == pytest.approx(st[bc.S_P_START] + st[bc.S_P_ADD])


def test_rule_does_not_act_when_the_tire_gives_the_nominal_friction(params):
    """mu 0.85 road (above the ECU's nominal 0.8), RF past its linear region (f(H) ~ 0.75) as the paper's plan puts it: no limit."""
    st, rq, _ = _ecu_run(params, 1, mu_road=0.85, s=0.08)
    assert st[bc.S_CAP_LATCHED] == 0.0 and rq != bc.Q_RELEASE


def test_rule_does_not_act_while_the_driver_brakes(params):
    """Brake light on: the wheel's pressure is partly the driver's (unknown to the function): no latch, no dump."""
    st, rq, _ = _ecu_run(params, 1, braking=1.0)
    assert st[bc.S_CAP_LATCHED] == 0.0 and rq != bc.Q_RELEASE
