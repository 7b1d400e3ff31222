"""Whole-vehicle closed-form checks of the compact EV (vehicles/ev_ehb.py) through the scenario API.

Each test starts from the shipped ``ev_5deg_hold_and_pull_away`` scenario, replaces road, driver and
run settings by ``--set``-style overrides so that the driving equation (common.md 3) has a closed-form
solution, and compares the trace with it. The kernel integrates with semi-implicit Euler at 1 ms; each
docstring derives its tolerance from that step.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

import vehicle_assist as va
from vehicle_assist.conventions import G_MPS2

DT_S = 1.0e-3
SCENARIO = "ev_5deg_hold_and_pull_away"
NO_PEDALS = ['driver.accelerator={time_s=[0.0], frac=[0.0]}', 'driver.brake_pedal={time_s=[0.0], frac=[0.0]}']


def run(*sets: str):
    sc = va.load_scenario(SCENARIO, list(sets))
    return sc, va.simulate(sc)


def params(sc) -> dict:
    return sc.vehicle.flat()


def equivalent_mass(p: dict) -> float:
    """delta*m of common.md 4, written out independently of plant/longitudinal.py."""
    r = p["body_wheel_radius_m"]
    return (p["body_mass_kg"] + p["body_wheel_inertia_total_kgm2"] / r**2
            + p["motor_rotor_inertia_kgm2"] * p["motor_reduction_ratio"] ** 2 * p["motor_efficiency_frac"] / r**2)


def test_coast_down_quadratic_drag_matches_closed_form() -> None:
    """(a) Flat road, f = 0, motor torque 0: delta*m dv/dt = -0.5 rho CdA v^2 -> v(t) = v0/(1 + k v0 t),
    k = 0.5*rho*CdA/(delta*m) (1.2258 kg/m^3, CdA 0.66 m^2, delta*m 1572.7 kg), v0 = 100 km/h, 20 s.

    Tolerance: explicit Euler on v' = -k v^2 has global error e(T) ~ (dt/2)*|a(T) - a(0)| (the error
    equation e' = -2kv e + (dt/2) v'' with small -2kv); here that is ~2.5e-5 m/s, so 1e-4 m/s.
    Negative control: the same law with delta = 1 (rotating masses forgotten) differs by > 0.1 m/s.
    """
    sc, r = run("road.slope_deg=0", "vehicle.body.rolling_resistance_coeff=0", "run.initial_speed_kph=100",
                "run.duration_s=20", *NO_PEDALS)
    p = params(sc)
    t = r.trace["time_s"]
    v = r.trace["speed_mps"]
    v0 = 100.0 / 3.6
    k = 0.5 * 1.2258 * p["body_drag_area_m2"] / equivalent_mass(p)
    closed = v0 / (1.0 + k * v0 * t)
    a0, a_end = -k * v0**2, -k * closed[-1] ** 2
    bound = 2.0 * 0.5 * DT_S * abs(a_end - a0)
    assert np.max(np.abs(v - closed)) <= max(bound, 1e-4)
    assert r.trace["motor_torque_nm"].max() == 0.0
    k_wrong = 0.5 * 1.2258 * p["body_drag_area_m2"] / p["body_mass_kg"]
    assert abs(v[-1] - v0 / (1.0 + k_wrong * v0 * t[-1])) > 0.1


def test_coast_down_rolling_resistance_is_linear_and_stops_exactly() -> None:
    """(b) Flat road, CdA = 0, f = 0.05: delta*m dv/dt = -m g f -> v(t) = v0 - g f t m/(delta m) until
    t_stop = v0 delta m/(m g f); after that the car is held at exactly 0 (static rolling resistance,
    common.md 3.3) and its position stays constant.

    Tolerance: Euler is exact for a constant acceleration, so v matches to rounding (1e-9 m/s); the stop
    instant within one 1 ms step plus one record period (10 ms); the stop position
    x_stop = v0^2 delta m/(2 m g f) within v0*dt (semi-implicit Euler advances x with v_{n+1}).
    """
    v0 = 18.0 / 3.6
    f = 0.05
    sc, r = run("road.slope_deg=0", "road.rolling_resistance_coeff=0.05", "vehicle.body.drag_area_m2=0",
                "run.initial_speed_kph=18", "run.duration_s=15", *NO_PEDALS)
    p = params(sc)
    m, m_eq = p["body_mass_kg"], equivalent_mass(p)
    decel = G_MPS2 * f * m / m_eq
    t_stop = v0 / decel
    t = r.trace["time_s"]
    v = r.trace["speed_mps"]
    x = r.trace["position_m"]
    moving = t < t_stop - 0.011
    assert np.max(np.abs(v[moving] - (v0 - decel * t[moving]))) < 1e-9
    stopped = t > t_stop + 0.011
    assert stopped.sum() > 300
    assert np.all(v[stopped] == 0.0)
    assert np.all(r.trace["accel_mps2"][stopped] == 0.0)
    assert np.all(x[stopped] == x[stopped][0])
    assert np.all(r.trace["vehicle_held_flag"][stopped] == 1.0)
    assert x[-1] == pytest.approx(v0**2 / (2.0 * decel), abs=v0 * DT_S)
    held_events = [e for e in r.events if e.machine == "vehicle" and e.to_mode == "HELD"]
    assert len(held_events) == 1 and abs(held_events[0].time_s - t_stop) <= 2 * DT_S


def test_uphill_acceleration_at_constant_pedal() -> None:
    """(c1) 5 deg grade, CdA = 0, accelerator 0.4 -> pedal map 68.26 N*m (a breakpoint of the map):
    F_t = T i eta / r = 68.26*8*0.92/0.3 = 1674.6 N, F_i = m g sin 5 deg = 1282.5 N, F_f = m g f cos = 219.9 N,
    a = (F_t - F_i - F_f)/(delta m) = 0.1095 m/s^2, constant once the motor lag (tau 20 ms) has settled.

    Started at 1 km/h uphill so it is moving forward throughout (rolling resistance sign fixed).
    Tolerance: after 0.5 s = 25 tau the lag residue is e^-25 ~ 1e-11 relative; 1e-9 relative on a.
    """
    sc, r = run("road.slope_deg=5", "vehicle.body.drag_area_m2=0", "run.initial_speed_kph=1", "run.duration_s=4",
                'driver.accelerator={time_s=[0.0], frac=[0.4]}', 'driver.brake_pedal={time_s=[0.0], frac=[0.0]}')
    p = params(sc)
    m, m_eq, rw = p["body_mass_kg"], equivalent_mass(p), p["body_wheel_radius_m"]
    torque = 68.26
    alpha = math.radians(5.0)
    f = p["body_rolling_resistance_coeff"]
    f_t = torque * p["motor_reduction_ratio"] * p["motor_efficiency_frac"] / rw
    a_closed = (f_t - m * G_MPS2 * math.sin(alpha) - m * G_MPS2 * f * math.cos(alpha)) / m_eq
    assert a_closed == pytest.approx(0.1095, abs=5e-4)
    t = r.trace["time_s"]
    window = t >= 0.5
    assert np.all(r.trace["speed_mps"] > 0.0)
    np.testing.assert_allclose(r.trace["accel_mps2"][window], a_closed, rtol=1e-9)
    np.testing.assert_allclose(r.trace["drive_force_n"][window], f_t, rtol=1e-9)


def test_terminal_speed_on_grade_with_drag() -> None:
    """(c2) Terminal speed where F_t = F_i + F_f + F_w (common.md 3 with F_j = 0):
    v_T = sqrt((F_t - F_i - F_f)/(0.5 rho CdA)). CdA raised to 10 m^2 so v_T = 5.30 m/s is reached quickly.

    Started at v_T; the 20 ms motor-torque lag at t = 0 costs ~0.02 m/s, which decays with the linearised
    time constant delta m/(rho CdA v_T) = 24 s, so after 200 s it is < 1e-5 m/s. The Euler fixed point is
    the exact equilibrium, so the tolerance is 1e-4 m/s.
    """
    sc, r0 = run("road.slope_deg=5", "vehicle.body.drag_area_m2=10", "run.duration_s=1",
                 'driver.accelerator={time_s=[0.0], frac=[0.4]}', 'driver.brake_pedal={time_s=[0.0], frac=[0.0]}')
    p = params(sc)
    m, rw = p["body_mass_kg"], p["body_wheel_radius_m"]
    alpha = math.radians(5.0)
    f_t = 68.26 * p["motor_reduction_ratio"] * p["motor_efficiency_frac"] / rw
    excess = f_t - m * G_MPS2 * (math.sin(alpha) + p["body_rolling_resistance_coeff"] * math.cos(alpha))
    v_t = math.sqrt(excess / (0.5 * 1.2258 * 10.0))
    assert v_t == pytest.approx(5.30, abs=0.01)
    _, r = run("road.slope_deg=5", "vehicle.body.drag_area_m2=10", f"run.initial_speed_kph={v_t * 3.6!r}",
               "run.duration_s=200", "run.record_period_s=0.1",
               'driver.accelerator={time_s=[0.0], frac=[0.4]}', 'driver.brake_pedal={time_s=[0.0], frac=[0.0]}')
    assert r.trace["speed_mps"][-1] == pytest.approx(v_t, abs=1e-4)
    assert abs(r.trace["accel_mps2"][-1]) < 1e-5


@pytest.mark.parametrize("slope_deg", [5.0, 10.0])
def test_brake_hold_threshold_pressure(slope_deg) -> None:
    """(d) Held by brake pressure p on a slope: stays at exactly v = 0 iff
    K_b_tot p / r + m g f cos(alpha) >= m g sin(alpha) (common.md 3.3, 7.1), so the threshold is
    p* = m g (sin - f cos) r / K_b_tot, with K_b_tot = 2 K_b_f + 2 K_b_r = 53.76 N*m/bar computed here from
    the caliper data (K_b = n_f mu_b A_wc r_eff eta_b) and the pedal mapping p = pedal * 100 bar.

    Runs at p*(1 + 1e-3) must hold for the whole run (speed and position exactly 0.0); runs at
    p*(1 - 1e-3) must roll back (net force 1e-3 of the brake force, ~2 N, gives v ~ -2e-3 m/s in 2 s).
    The 0.1 % margin is far above rounding (1e-15) and shows the threshold sits where the closed form says.
    """
    sc, _ = run(f"road.slope_deg={slope_deg}", *NO_PEDALS, "run.duration_s=0.01")
    p = params(sc)
    k_f = 2 * 0.38 * math.pi * 0.054**2 / 4 * 0.110 * 1.0
    k_r = 2 * 0.38 * math.pi * 0.036**2 / 4 * 0.100 * 1.0
    k_tot = 2 * k_f + 2 * k_r
    assert p["brakes_total_gain_nm_per_pa"] == pytest.approx(k_tot, rel=1e-12)
    assert k_tot * 1e5 == pytest.approx(53.76, abs=0.01)
    m, rw, f = p["body_mass_kg"], p["body_wheel_radius_m"], p["body_rolling_resistance_coeff"]
    alpha = math.radians(slope_deg)
    p_star = m * G_MPS2 * (math.sin(alpha) - f * math.cos(alpha)) * rw / k_tot
    pedal_star = p_star / p["ehb_pedal_full_pressure_pa"]
    for factor, holds in ((1.001, True), (0.999, False)):
        pedal = pedal_star * factor
        _, r = run(f"road.slope_deg={slope_deg}", "run.duration_s=2",
                   'driver.accelerator={time_s=[0.0], frac=[0.0]}',
                   f'driver.brake_pedal={{time_s=[0.0], frac=[{pedal!r}]}}')
        v, x = r.trace["speed_mps"], r.trace["position_m"]
        assert r.trace["brake_pressure_pa"][0] == pytest.approx(pedal * 100e5, rel=1e-12)
        if holds:
            assert np.all(v == 0.0) and np.all(x == 0.0), f"pedal {pedal:.6f} should hold on {slope_deg} deg"
            assert np.all(r.trace["vehicle_held_flag"] == 1.0)
        else:
            assert v[-1] < -1e-3 and x[-1] < 0.0, f"pedal {pedal:.6f} should not hold on {slope_deg} deg"


def test_tyre_limit_on_a_low_mu_slope_sliding_deceleration() -> None:
    """(e) Tyre adhesion (issue #7, common.md 9): on 20 deg with mu = 0.3 the four locked wheels give at most
    mu*(F_zf + F_zr) = mu*m*g*cos (the grade transfer moves load between the axles but not their sum), so the car
    slides back with delta*m*a = -m*g*sin + (mu + f)*m*g*cos although the pedal asks for 100 bar (17.9 kN of brake,
    far above the grade force 5.0 kN). Closed form from these numbers; Euler is exact for a constant acceleration, so
    1e-9 relative. Control: mu = 0.5 holds ((0.5 + 0.015)*cos 20 deg = 0.484 > sin 20 deg = 0.342): v == 0."""
    common = ("road.slope_deg=20", "run.duration_s=2", "vehicle.hill_start_assist.enabled_flag=0", "vehicle.body.drag_area_m2=0",
              'driver.accelerator={time_s=[0.0], frac=[0.0]}', 'driver.brake_pedal={time_s=[0.0], frac=[1.0]}')
    sc, r = run("road.friction_mu=0.3", *common)
    p = params(sc)
    m, m_eq = p["body_mass_kg"], equivalent_mass(p)
    a20 = math.radians(20.0)
    a_closed = m * G_MPS2 * (-math.sin(a20) + (0.3 + p["body_rolling_resistance_coeff"]) * math.cos(a20)) / m_eq
    assert a_closed < -0.4
    moving = r.trace["time_s"] > 0.05
    np.testing.assert_allclose(r.trace["accel_mps2"][moving], a_closed, rtol=1e-9)
    _, held = run("road.friction_mu=0.5", *common)
    assert np.all(held.trace["speed_mps"] == 0.0)


def test_drive_force_limited_by_the_front_axle_load() -> None:
    """(f) Front-wheel drive on a level road, mu = 0.3, full accelerator (motor 6133 N >> mu*F_zf ~ 2.5 kN), no drag or
    rolling resistance: delta*m*a = mu*F_zf with F_zf = m*(g*l_r - a*h)/l (common.md 9, acceleration transfer), so
    a = mu*g*l_r*m/(m_eq*l + mu*m*h), l = 2.70 m, l_r = 1.57 m, h = 0.55 m (compact_ev chassis). The kernel uses the
    previous step's acceleration in the load transfer; its fixed point is the closed form: 1e-9 relative after 1 s."""
    sc, r = run("road.slope_deg=0", "road.friction_mu=0.3", "vehicle.body.drag_area_m2=0",
                "vehicle.body.rolling_resistance_coeff=0", "run.duration_s=3", "run.initial_speed_kph=1",
                'driver.accelerator={time_s=[0.0], frac=[1.0]}', 'driver.brake_pedal={time_s=[0.0], frac=[0.0]}')
    p = params(sc)
    m, m_eq = p["body_mass_kg"], equivalent_mass(p)
    l, l_r, h = 2.70, 2.70 - 1.13, 0.55
    a_closed = 0.3 * G_MPS2 * l_r * m / (m_eq * l + 0.3 * m * h)
    window = r.trace["time_s"] >= 1.0
    np.testing.assert_allclose(r.trace["accel_mps2"][window], a_closed, rtol=1e-9)
    assert r.trace["motor_force_n"][window].min() > 2.0 * r.trace["drive_force_n"][window].max()
