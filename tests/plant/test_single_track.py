"""Single-track mode of the car platform (plant/chassis/single_track.py, issue #11).

References: closed forms of curve_shift.md 2 (understeer gradient eq. 8, steady yaw-rate gain, a_y = u^2/R),
the spec's worked number K = 3.793e-3 rad/(m/s^2) (criterion 9) and a_y_neutral = 5.5 +/- 0.1 (criterion 10);
and an independent published implementation of the same equations, the CommonRoad single-track model
(``vehiclemodels.vehicle_dynamics_st``, TUM; a test-only dependency) integrated by scipy's solve_ivp on a
step steer with the CommonRoad vehicle 2 parameters: yaw rate within 1 % (issue #11).
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from vehicle_assist.plant.chassis import single_track as st

# curve_shift.md 6 (assumed axle data of the paper-003 car)
M, LF, LR, KF, KR = 2124.0, 1.35, 1.65, 110e3, 140e3


def test_understeer_gradient_spec_value_and_sign():
    k = st.understeer_gradient(M, LF, LR, KF, KR)
    assert k == pytest.approx(3.793e-3, abs=2e-6)  # curve_shift.md 8 criterion 9
    assert math.degrees(k) * 9.81 == pytest.approx(2.13, abs=0.01)  # "2.1 deg/g" (sec. 3)
    # sign: K > 0 exactly when l_r/K_f > l_f/K_r (understeer), < 0 when reversed, 0 when equal
    assert st.understeer_gradient(M, LF, LR, 140e3, 110e3) < 0 and 1.65 / 140e3 < 1.35 / 110e3
    assert st.understeer_gradient(M, 1.5, 1.5, 1e5, 1e5) == 0.0


@pytest.mark.parametrize("u_kph,delta_deg", [(30, 4.0), (65, 1.5), (100, 1.0), (130, -0.5)])
def test_step_steer_reaches_closed_form_steady_state(u_kph, delta_deg):
    u = u_kph / 3.6
    delta = math.radians(delta_deg)
    beta = r = a_y = 0.0
    for _ in range(8000):  # 8 s at 1 ms
        beta, r, a_y = st.step(beta, r, u, delta, M, 3600.0, LF, LR, KF, KR, 1e-3)
    k = st.understeer_gradient(M, LF, LR, KF, KR)
    r_ref = u * delta / (LF + LR + k * u * u)  # yaw-rate gain (curve_shift.md 2)
    assert r == pytest.approx(r_ref, rel=1e-6)
    assert a_y == pytest.approx(u * r_ref, rel=1e-6)  # steady turning: a_y = u*r = u^2/R
    radius = u / r_ref
    # eq. 5: delta = l/R + K*a_y
    assert delta == pytest.approx((LF + LR) / radius + k * u * u / radius, rel=1e-9)
    # the kinematic-driver feedforward gives the same steer angle
    assert st.steer_for_curvature_rad(1.0 / radius, u, LF + LR, k) == pytest.approx(delta, rel=1e-9)


def test_positive_steer_gives_positive_yaw_rate():
    """ISO 8855 (conventions.py): a left (positive) steer turns left (positive yaw rate and a_y)."""
    beta, r, a_y = st.step(0.0, 0.0, 20.0, 0.02, M, 3600.0, LF, LR, KF, KR, 0.01)
    assert r > 0 and a_y > 0
    beta2, r2, a_y2 = st.step(0.0, 0.0, 20.0, -0.02, M, 3600.0, LF, LR, KF, KR, 0.01)
    assert (beta2, r2, a_y2) == pytest.approx((-beta, -r, -a_y))


def test_handling_diagram_neutral_steer_threshold():
    """curve_shift.md 3 and criterion 10: a_y_neutral = 5.5 +/- 0.1 m/s^2; a_y_stab 6.17/6.33/6.58 at 80/65/48."""
    a_ys, neutral, _ = st.safety_threshold(80 / 3.6, M, LF, LR, KF, KR, 0.95, 0.74, 1.3)
    assert neutral == pytest.approx(5.5, abs=0.1)
    assert a_ys == pytest.approx(min(neutral, 0.9 * 0.74 * 9.81))
    for u_kph, ref in ((80, 6.17), (65, 6.33), (48, 6.58)):
        assert st.safety_threshold(u_kph / 3.6, M, LF, LR, KF, KR, 0.95, 0.74, 1.3)[2] == pytest.approx(ref, abs=0.05)
    # the handling curve starts with the linear gradient K
    grad0 = st.handling_curve(0.01, M, LF, LR, KF, KR, 0.95, 0.74, 1.3) / 0.01
    assert grad0 == pytest.approx(st.understeer_gradient(M, LF, LR, KF, KR), rel=1e-3)


@pytest.mark.parametrize("u_mps,delta_rad", [(15.0, 0.03), (25.0, 0.02), (35.0, 0.01)])
def test_step_steer_against_commonroad(u_mps, delta_rad):
    """Independent reference: CommonRoad's single-track model (same linear-tire equations, its own code and its
    vehicle 2 parameters), integrated with solve_ivp (rtol 1e-10); our backward-Euler mode at 1 ms."""
    import vehiclemodels as vm  # the dev extra (pyproject): a missing reference fails, never skips
    from scipy.integrate import solve_ivp
    from vehiclemodels.parameters_vehicle2 import parameters_vehicle2
    from vehiclemodels.vehicle_dynamics_st import vehicle_dynamics_st

    assert vm is not None
    p = parameters_vehicle2()
    mu = p.tire.p_dy1
    c_s = -p.tire.p_ky1 / p.tire.p_dy1
    m, lf, lr, iz = p.m, p.a, p.b, p.I_z
    l = lf + lr
    k_f = mu * c_s * m * 9.81 * lr / l  # per-axle cornering stiffness of CommonRoad's tire model at a_x = 0
    k_r = mu * c_s * m * 9.81 * lf / l
    t_end = 3.0
    times = np.linspace(0.0, t_end, 301)
    x0 = [0.0, 0.0, delta_rad, u_mps, 0.0, 0.0, 0.0]
    ref = solve_ivp(lambda t, x: vehicle_dynamics_st(x, [0.0, 0.0], p), (0.0, t_end), x0, t_eval=times,
                    rtol=1e-10, atol=1e-12, method="LSODA")
    r_ref = ref.y[5]
    dt = 1e-3
    beta = r = 0.0
    ours = [0.0]
    for k in range(1, int(round(t_end / dt)) + 1):
        beta, r, _ = st.step(beta, r, u_mps, delta_rad, m, iz, lf, lr, k_f, k_r, dt)
        if k % 10 == 0:
            ours.append(r)
    ours = np.array(ours)
    peak = np.max(np.abs(r_ref))
    assert np.max(np.abs(ours - r_ref)) <= 0.01 * peak
    assert ours[-1] == pytest.approx(r_ref[-1], rel=1e-3)
    # and the reference agrees with the closed-form steady state
    assert r_ref[-1] == pytest.approx(u_mps * delta_rad / (l + st.understeer_gradient(m, lf, lr, k_f, k_r) * u_mps ** 2), rel=1e-3)
