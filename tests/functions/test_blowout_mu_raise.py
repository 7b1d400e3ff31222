"""The braking rule's measured friction raised from the compensating front's readings while the driver brakes
(functions/blowout_compensation.py ``measured_mu_raise``; docs/functions/tire_blowout.md status g item 10, findings_F.md
H1). A friction OVER-estimate is the unsafe direction: the rear pair is capped at the raised friction.

Independent reference: a FORWARD Dugoff tire (spec 2.3, combined slip) written here - F_x = C_x*s/(1 - s)*f(H),
H = mu*F_z*(1 - s)/(2*sqrt((C_x*s)^2 + (C_a*tan(alpha))^2)), f = H*(2 - H) below 1 - on a plant that differs from the
ECU's data within the envelope: pad friction 0.7-1.2 x nominal (data/envelopes/tire_blowout.toml brake_gain), C_x
+-15 %, slip angle 0-4 deg, the wheel load with the braking load transfer m*|a_x|*h/(2*l) (rigid-body statics) and a
blowout transfer of 0-400 N onto it. The wheel decelerates with the car (its spin balance J*omega_dot = F_x*R - T_b
sets the brake torque, hence the pressure the ECU reads). Assertion: whatever the reading, the raised friction never
exceeds the true mu. G7's rule (``measured_mu_bound_flag`` = 0: brake force at the cold band's lower edge 0.82, q
against the nominal C_x, capacity over the plan-time load) fails it (up to ~1.6 x the true mu)."""
from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

FL, FR = 0, 1
DT = 0.005
G = 9.81


def _params(*sets):
    import vehicle_assist as va
    from vehicle_assist.scenarios.runner import pack_records

    sc = va.load_scenario("blowout_lf_60kph_paper")
    return pack_records([(sc.with_sets(*sets) if sets else sc).vehicle.flat()])[0]


BOUND0 = "vehicle.blowout_compensation.measured_mu_bound_flag=0"
LOWER0 = "vehicle.blowout_compensation.measured_mu_lower_flag=0"
ABSLIM0 = "vehicle.blowout_compensation.front_abs_limit_flag=0"
REARLIM0 = "vehicle.blowout_compensation.rear_abs_limit_flag=0"


@pytest.fixture(scope="module")
def params():
    return _params()


def dugoff_fx(mu, fz, s, alpha, cx, ca):
    """Forward Dugoff longitudinal force [N] (spec 2.3, combined slip)."""
    res = math.hypot(cx * s, ca * math.tan(alpha))
    h = mu * fz * (1.0 - s) / (2.0 * res)
    f = 1.0 if h >= 1.0 else h * (2.0 - h)
    return cx * s / (1.0 - s) * f


def true_front_load(p, a_x, blow_n):
    """Front wheel load: static share m*g*l_r/(2*l) + braking transfer m*|a_x|*h/(2*l) + the blowout transfer."""
    l = p.chassis_wheelbase_m
    l_r = l - p.chassis_cg_to_front_axle_m
    m = p.body_mass_kg
    return m * G * l_r / (2.0 * l) + m * abs(a_x) * p.chassis_cg_height_m / (2.0 * l) + blow_n


def ecu_state(p, mu_meas, p_fr, v, s, a_x, abs_active=False, predump=-1.0):
    """FL blown, FR compensating (HOLD), the driver braking; the ECU's window: FR rolling at slip s, decelerating with
    the car at a_x, its pressure p_fr; the other wheels at the car's speed."""
    from vehicle_assist.functions import blowout_compensation as bc

    st = bc.initial_state()
    st[bc.S_BLOWN], st[bc.S_TARGET], st[bc.S_MODE] = FL, FR, bc.HOLD
    st[bc.S_SOURCES] = bc.SRC_WS + bc.SRC_TPMS
    st[bc.S_P_REQ] = st[bc.S_P_ADD] = 2.0e5
    l = p.chassis_wheelbase_m
    st[bc.S_FZ_TARGET] = p.body_mass_kg * G * (l - p.chassis_cg_to_front_axle_m) / (2.0 * l)  # the plan's (no a_x)
    st[bc.S_CAP_LATCHED] = 1.0
    st[bc.S_MU_MEAS] = mu_meas
    st[bc.S_F_CAP] = mu_meas * st[bc.S_FZ_TARGET]
    st[bc.S_ABS_ACTIVE + FR] = 1.0 if abs_active else 0.0
    st[bc.S_P_PREDUMP] = predump
    n = bc.WS_WINDOW_N
    for k in range(n):
        vk = v + a_x * DT * (k - (n - 1))  # older samples faster (decelerating car)
        speeds = (1.3 * vk, (1.0 - s) * vk, vk, vk)
        for i in range(4):
            st[bc.S_VW_BUF + i * n + k] = speeds[i]
            st[bc.S_P_BUF + i * n + k] = p_fr if i == FR else 0.0
    st[bc.S_BUF_LAST] = n - 1
    st[bc.S_BUF_FILL] = n
    vw = np.array((1.3 * v, (1.0 - s) * v, v, v))
    return st, np.array((0.0, p_fr, 0.0, 0.0)), vw


def run_rule(p, st, p_est, vw, v, a_x, braking=1.0, n=6):
    from vehicle_assist.functions import blowout_compensation as bc

    for _ in range(n):  # > CAP_PERSIST_S / 5 ms
        bc.tire_capacity_rule(st, FR, vw, v, 0.0, braking, p_est, np.zeros(4), p, DT, a_x)
    return st[bc.S_MU_MEAS]


def plant_pressure(p, fx, s, a_x, gain_scale):
    """Pressure [Pa] that holds the wheel at force fx while it decelerates with the car (J*omega_dot = F_x*R - T_b)."""
    r = p.body_wheel_radius_m
    omega_dot = a_x * (1.0 - s) / r
    t_b = fx * r - p.body_wheel_inertia_kgm2 * omega_dot
    return t_b / (p.brakes_front_gain_nm_per_pa * gain_scale)


GRID = list(itertools.product(
    (0.3, 0.45, 0.7, 0.95),          # true road friction
    (0.7, 0.82, 1.0, 1.2),           # plant pad friction / nominal (envelope brake_gain 0.7-1.2)
    (0.85, 1.0, 1.15),               # plant C_x / nominal
    (0.0, math.radians(2.0), math.radians(4.0)),  # slip angle
    (0.015, 0.03, 0.06, 0.12),       # slip
    (0.0, 400.0),                    # blowout transfer onto the wheel [N]
))


def scan(p, abs_case=False):
    """(worst raised/true ratio, its case) over GRID at 25 m/s; the car decelerates at 0.8*mu*g (inside the road)."""
    worst, arg = 0.0, None
    v = 25.0
    ca = p.tires_cornering_stiffness_front_n_per_rad / 2.0  # per tire
    for mu, gs, kc, alpha, s, blow in GRID:
        a_x = -0.8 * mu * G
        fz = true_front_load(p, a_x, blow)
        fx = dugoff_fx(mu, fz, s, alpha, p.tires_longitudinal_stiffness_n * kc, ca)
        pr = plant_pressure(p, fx, s, a_x, gs)
        if abs_case:
            st, p_est, vw = ecu_state(p, 0.01, pr, v, s, a_x, abs_active=True, predump=pr)
        else:
            st, p_est, vw = ecu_state(p, 0.01, pr, v, s, a_x)
        r = run_rule(p, st, p_est, vw, v, a_x) / mu
        if r > worst:
            worst, arg = r, (mu, gs, kc, round(math.degrees(alpha), 1), s, blow)
    return worst, arg


def test_raised_friction_never_exceeds_the_true_mu(params):
    """Forward Dugoff scan (1152 cases): the raised friction <= the true mu."""
    worst, arg = scan(params)
    assert worst <= 1.0 + 1e-9, f"raised {worst:.3f} x the true mu at (mu, gain, C_x, alpha, s, blow) = {arg}"


def test_raised_friction_over_states_with_g7_reading():
    """Negative control: G7's reading (measured_mu_bound_flag = 0) over-states the friction on this scan."""
    worst, arg = scan(_params(BOUND0))
    assert worst > 1.2, (worst, arg)


def test_abs_dump_raise_never_exceeds_the_true_mu(params):
    """front_abs_limit_flag: an ABS dump on the compensating front under the pedal raises the measured friction to the
    force at the dump's start (fade gain, most load): the same forward scan with the wheel ABS-active at that
    pressure - never above the true mu."""
    worst, arg = scan(params, abs_case=True)
    assert worst <= 1.0 + 1e-9, f"raised {worst:.3f} x the true mu at {arg}"


def test_raise_still_acts_on_a_linear_nominal_wheel(params):
    """The bound is not vacuous: a nominal tire (gain 1, C_x nominal, alpha 0) at 3 % slip on mu 0.95 raises the
    measured friction from 0.01 to at least a quarter of the true mu (the worst case allowed for: fade 0.66, C_x
    +15 %: 0.66 x ~F_x with f_lo = 0.57 -> mu*F_z >= 0.66*F_x*2/(1 + sqrt(0.43)) ~ 0.8*F_x)."""
    p = params
    mu, s, a_x, v = 0.95, 0.03, -3.0, 25.0
    fz = true_front_load(p, a_x, 0.0)
    fx = dugoff_fx(mu, fz, s, 0.0, p.tires_longitudinal_stiffness_n, 1.0)
    st, p_est, vw = ecu_state(p, 0.01, plant_pressure(p, fx, s, a_x, 1.0), v, s, a_x)
    got = run_rule(p, st, p_est, vw, v, a_x)
    assert 0.25 * mu < got <= mu
    # 0.80 x the force's own friction use by the derivation, over the ECU's load (which adds its blowout transfer)
    assert got >= 0.6 * fx / fz


def test_no_raise_without_the_pedal_or_with_abs_active(params):
    p = params
    mu, s, a_x, v = 0.95, 0.03, -3.0, 25.0
    fx = dugoff_fx(mu, true_front_load(p, a_x, 0.0), s, 0.0, p.tires_longitudinal_stiffness_n, 1.0)
    pr = plant_pressure(p, fx, s, a_x, 1.0)
    st, p_est, vw = ecu_state(p, 0.01, pr, v, s, a_x)
    assert run_rule(p, st, p_est, vw, v, a_x, braking=0.0) == pytest.approx(0.01)
    st, p_est, vw = ecu_state(p, 0.01, pr, v, s, a_x, abs_active=True)  # active, no dump level: no evidence
    assert run_rule(p, st, p_est, vw, v, a_x) == pytest.approx(0.01)


def _raised_then_dump(p, dump_fraction):
    """Raise on a linear reading (mu 0.95), then an ABS dump at a pressure whose upper-gain force is
    ``dump_fraction`` x the raised friction's force: the value after the dump."""
    from vehicle_assist.functions import blowout_compensation as bc

    mu, s, a_x, v = 0.95, 0.03, -3.0, 25.0
    fx = dugoff_fx(mu, true_front_load(p, a_x, 0.0), s, 0.0, p.tires_longitudinal_stiffness_n, 1.0)
    pr = plant_pressure(p, fx, s, a_x, 1.0)
    st, p_est, vw = ecu_state(p, 0.1, pr, v, s, a_x)
    raised = run_rule(p, st, p_est, vw, v, a_x)
    assert raised > 0.1
    fz_lo = bc.mu_raise_loads_n(st, FR, a_x, 0.0, p)[1]
    g_hi = 1.0 + p.blowout_compensation_brake_gain_tolerance_frac
    p_dump = dump_fraction * raised * fz_lo * p.body_wheel_radius_m / (g_hi * p.brakes_front_gain_nm_per_pa)
    st[bc.S_ABS_ACTIVE + FR] = 1.0
    st[bc.S_P_PREDUMP] = p_dump
    return raised, run_rule(p, st, p_est, vw, v, a_x, n=1)


def test_abs_dump_below_the_raise_lowers_it(params):
    """Item 10 (e): ABS found the wheel's limit at 60 % of the raised friction's force (upper gain, least load): the
    raise is taken back to that force, not below the value before the raise (0.1)."""
    raised, after = _raised_then_dump(params, 0.6)
    assert after == pytest.approx(max(0.1, 0.6 * raised), rel=1e-6)


def test_abs_dump_lowering_fails_with_the_defect():
    """Negative control: measured_mu_lower_flag = 0 keeps the raise after the dump."""
    raised, after = _raised_then_dump(_params(LOWER0), 0.6)
    assert after == pytest.approx(raised)


def test_plan_resets_the_linear_reading_time(params):
    """Item 10 (d): a new plan (new compensating wheel) starts its linear-reading time from zero; with
    measured_mu_bound_flag = 0 the time carried over."""
    from vehicle_assist.functions import blowout_compensation as bc

    for p, want in ((params, 0.0), (_params(BOUND0), 0.015)):
        st = bc.initial_state()
        st[bc.S_LIN_S] = 0.015
        bc._plan(st, FL, FR, False, 0.0, 0.0, 0.0, np.zeros(4), p)
        assert st[bc.S_LIN_S] == pytest.approx(want)


def test_front_cap_lifted_under_the_pedal(params):
    """front_abs_limit_flag: with a measured friction the compensating front under a braking driver gets the balance
    plus the driver's share (ABS limits it), not min(that, mu_meas*F_z); with the flag 0 it is capped at mu_meas*F_z."""
    from vehicle_assist.functions import blowout_compensation as bc

    out = []
    for p in (params, _params(ABSLIM0)):
        st = bc.initial_state()
        st[bc.S_BLOWN], st[bc.S_TARGET], st[bc.S_MODE] = FL, FR, bc.HOLD
        st[bc.S_P_REQ] = 5.0e5
        st[bc.S_MU_MEAS] = 0.15
        p_mc = 100.0e5
        bc.braking_rule(st, FL, FR, bc.HOLD, 1.0, -3.0, 0.0, 0.0, p_mc, np.array((0.0, 5.0e5, 0.0, 0.0)), p)
        out.append(st[bc.S_P_BRAKE])
    assert out[0] == pytest.approx(5.0e5 + params.blowout_compensation_braking_share_frac * 100.0e5)
    assert out[1] < 0.5 * out[0]


def test_rear_pair_left_to_abs_while_the_front_is_at_its_abs_limit(params):
    """rear_abs_limit_flag: with a measured friction (0.15) and ABS active on the compensating front the rear pair has no
    friction cap (S_REAR_CAP -1: ABS limits it); without ABS activity it is capped; with the flag 0 capped either way."""
    from vehicle_assist.functions import blowout_compensation as bc

    def rear_cap(p, abs_front):
        st = bc.initial_state()
        st[bc.S_BLOWN], st[bc.S_TARGET], st[bc.S_MODE] = FL, FR, bc.HOLD
        st[bc.S_P_REQ] = 5.0e5
        st[bc.S_MU_MEAS] = 0.15
        st[bc.S_ABS_ACTIVE + FR] = 1.0 if abs_front else 0.0
        bc.braking_rule(st, FL, FR, bc.HOLD, 1.0, -3.0, 0.0, 0.0, 100.0e5, np.array((0.0, 5.0e5, 0.0, 0.0)), params
                        if p is None else p)
        return st[bc.S_REAR_CAP]

    assert rear_cap(None, True) == -1.0
    assert rear_cap(None, False) > 0.0
    assert rear_cap(_params(REARLIM0), True) > 0.0


# --- review RH1 (session h): the dump reading with the lock's deceleration and a later window -------------------------
DUMP0 = "vehicle.blowout_compensation.abs_dump_bound_flag=0"
DUMP_GRID = list(itertools.product(
    (0.3, 0.45, 0.7, 0.95),          # true road friction
    (0.7, 1.0, 1.2),                 # plant pad friction / nominal (envelope brake_gain 0.7-1.2)
    (0.85, 1.0, 1.15),               # plant C_x / nominal
    (0.06, 0.1, 0.2),                # slip at the dump's start
    (0.015, 0.03, 0.06),             # slip in the window while ABS holds / re-builds (the wheel recovered)
    (30.0, 60.0),                    # wheel deceleration at the dump's start [m/s^2] (ABS dump threshold 30)
))


def dump_scan(p):
    """(worst raised/true ratio, its case): ABS dumped the compensating front while it locked - at the dump's start
    the wheel slips s_d and spins down at a_w (J*omega_dot = F_x*R - T_b: the pressure held the force F_x(s_d) AND
    the spin-down), the ECU stored that pressure and a_w; the window now shows the wheel recovered to s_now at a
    third of the pressure. Whatever the window reads, F_x(s_d) <= mu*F_z is all the dump proves."""
    from vehicle_assist.functions import blowout_compensation as bc

    worst, arg = 0.0, None
    v = 25.0
    ca = p.tires_cornering_stiffness_front_n_per_rad / 2.0
    r, j, k = p.body_wheel_radius_m, p.body_wheel_inertia_kgm2, p.brakes_front_gain_nm_per_pa
    for mu, gs, kc, s_d, s_now, a_w in DUMP_GRID:
        a_x = -0.8 * mu * G
        fz = true_front_load(p, a_x, 0.0)
        fx = dugoff_fx(mu, fz, s_d, 0.0, p.tires_longitudinal_stiffness_n * kc, ca)
        pr = (fx * r + j * a_w / r) / (k * gs)
        st, p_est, vw = ecu_state(p, 0.01, 0.3 * pr, v, s_now, a_x, abs_active=True, predump=pr)
        st[bc.S_AW_PREDUMP] = a_w
        ratio = run_rule(p, st, p_est, vw, v, a_x, n=1) / mu
        if ratio > worst:
            worst, arg = ratio, (mu, gs, kc, s_d, s_now, a_w)
    return worst, arg


def test_abs_dump_raise_at_the_lock_never_exceeds_the_true_mu(params):
    """abs_dump_bound_flag: the raise from an ABS dump (front_abs_limit_flag) with the lock's spin-down and a later,
    recovered window - never above the true mu (648 cases)."""
    worst, arg = dump_scan(params)
    assert worst <= 1.0 + 1e-9, f"raised {worst:.3f} x the true mu at (mu, gain, C_x, s_d, s_now, a_w) = {arg}"


def test_abs_dump_raise_over_states_with_h1_reading():
    """Negative control: H1's dump reading (abs_dump_bound_flag = 0: Dugoff factor from the present window's slip,
    the present wheel acceleration) over-states the friction on this scan (measured 1.57 x)."""
    worst, arg = dump_scan(_params(DUMP0))
    assert worst > 1.2, (worst, arg)
