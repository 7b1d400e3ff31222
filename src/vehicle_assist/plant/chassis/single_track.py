"""Linear single-track (bicycle) model: the passenger-car platform's single-track mode (curve_shift.md 2; paper
003 P3 Fig. 1; Yu Zhisheng ch. 5, Wong ch. 5, std).

Why a single-track mode next to the two-track body (two_track.py): paper 003 estimates the lateral
acceleration with the linear single-track model (P3); its shift strategy needs only a_y and yaw rate along a
road of known curvature, with no wheel spin, combined slip or load transfer. The two-track body needs four
wheel-speed states, a nonlinear combined-slip tire and a 0.5-1 ms step for stability; this mode runs the
lateral dynamics in two states beside any longitudinal model.

States: sideslip angle beta [rad] at the CG, yaw rate r [rad/s] (ISO 8855, CCW +). Inputs: forward speed
u [m/s] (from the longitudinal model), front steer angle delta [rad]. Axle cornering stiffnesses K_f, K_r
[N/rad] > 0 per axle (both tires together; curve_shift.md 2 convention). Linear tires:

    alpha_f = delta - beta - l_f*r/u          alpha_r = -beta + l_r*r/u
    F_yf = K_f*alpha_f                        F_yr = K_r*alpha_r
    m*u*(dbeta/dt + r) = F_yf + F_yr          I_z*dr/dt = l_f*F_yf - l_r*F_yr
    a_y = u*(dbeta/dt + r)                    (lateral acceleration of the CG, small angles)

Steady state (closed forms, curve_shift.md 2 eqs. 5-8):
    K = (m/l)*(l_r/K_f - l_f/K_r)   [rad/(m/s^2)], understeer gradient (K > 0 understeer)
    delta = l/R + K*a_y,   r/delta = u/(l + K*u^2),   a_y = u*r = u^2/R

Validity: u >= U_MIN_MPS (below, the lateral states follow the kinematic steady state r = u*delta/l),
small slip angles (linear tires: a_y well below mu*g). Integration: backward (implicit) Euler of the
2x2 linear system, unconditionally stable at any speed and step.

The handling diagram (curve_shift.md 3) with magic-formula axle characteristics F_y = D*sin(C*atan(B*alpha))
gives the safety threshold a_ys; it is evaluated once per vehicle (plain numpy, not in the kernel).
"""
from __future__ import annotations

import math

import numba as nb
import numpy as np

from vehicle_assist.conventions import G_MPS2

U_MIN_MPS = 1.0  # assumed: below this speed the kinematic steady state replaces the (singular) dynamics


def understeer_gradient(mass_kg, l_f_m, l_r_m, k_f_n_per_rad, k_r_n_per_rad) -> float:
    """K = (m/l)*(l_r/K_f - l_f/K_r) [rad/(m/s^2)] (curve_shift.md 2 eq. 8, ISO 4138)."""
    l = l_f_m + l_r_m
    return mass_kg / l * (l_r_m / k_f_n_per_rad - l_f_m / k_r_n_per_rad)


def steady_yaw_rate_radps(u_mps, delta_rad, wheelbase_m, understeer_rad_per_mps2) -> float:
    """r = u*delta/(l + K*u^2) (steady-state yaw-rate gain)."""
    return u_mps * delta_rad / (wheelbase_m + understeer_rad_per_mps2 * u_mps * u_mps)


@nb.njit(cache=True, nogil=True, error_model="numpy")
def steer_for_curvature_rad(curvature_per_m, u_mps, wheelbase_m, understeer_rad_per_mps2):
    """Steady-state steer angle on a path of curvature 1/R: delta = l/R + K*u^2/R (eq. 5 with a_y = u^2/R)."""
    return (wheelbase_m + understeer_rad_per_mps2 * u_mps * u_mps) * curvature_per_m


@nb.njit(cache=True, nogil=True, error_model="numpy")
def axle_forces_n(beta, r, u, delta, l_f, l_r, k_f, k_r):
    """(F_yf, F_yr) of the linear axles."""
    alpha_f = delta - beta - l_f * r / u
    alpha_r = -beta + l_r * r / u
    return k_f * alpha_f, k_r * alpha_r


@nb.njit(cache=True, nogil=True, error_model="numpy")
def derivatives(beta, r, u, delta, m, i_z, l_f, l_r, k_f, k_r):
    """(dbeta/dt, dr/dt, a_y) of the linear single-track model at forward speed u >= U_MIN_MPS."""
    f_yf, f_yr = axle_forces_n(beta, r, u, delta, l_f, l_r, k_f, k_r)
    dbeta = (f_yf + f_yr) / (m * u) - r
    dr = (l_f * f_yf - l_r * f_yr) / i_z
    return dbeta, dr, (f_yf + f_yr) / m


@nb.njit(cache=True, nogil=True, error_model="numpy")
def step(beta, r, u, delta, m, i_z, l_f, l_r, k_f, k_r, dt):
    """Backward-Euler step: returns (beta, r, a_y) at t + dt. x' = A x + B delta, (I - dt A) x+ = x + dt B delta."""
    l = l_f + l_r
    if u < U_MIN_MPS:
        return l_r / l * delta, u * delta / l, u * u * delta / l
    a11 = -(k_f + k_r) / (m * u)
    a12 = (k_r * l_r - k_f * l_f) / (m * u * u) - 1.0
    a21 = (k_r * l_r - k_f * l_f) / i_z
    a22 = -(k_f * l_f * l_f + k_r * l_r * l_r) / (i_z * u)
    b1 = k_f / (m * u)
    b2 = k_f * l_f / i_z
    m11 = 1.0 - dt * a11
    m12 = -dt * a12
    m21 = -dt * a21
    m22 = 1.0 - dt * a22
    rhs1 = beta + dt * b1 * delta
    rhs2 = r + dt * b2 * delta
    det = m11 * m22 - m12 * m21
    beta_new = (m22 * rhs1 - m12 * rhs2) / det
    r_new = (m11 * rhs2 - m21 * rhs1) / det
    _, _, a_y = derivatives(beta_new, r_new, u, delta, m, i_z, l_f, l_r, k_f, k_r)
    return beta_new, r_new, a_y


# ------------------------------------------------------------------------------- handling diagram (sec. 3)
def magic_formula_axle(k_n_per_rad: float, mu: float, load_n: float, shape_c: float) -> tuple[float, float]:
    """(B, D) of an axle F_y = D*sin(C*atan(B*alpha)) with peak D = mu*F_z and cornering stiffness B*C*D = K."""
    d = mu * load_n
    return k_n_per_rad / (shape_c * d), d


def axle_slip_rad(force_n, b, c, d):
    """Inverse of the magic formula on its rising branch: alpha = tan(asin(F/D)/C)/B (|F| < D)."""
    return np.tan(np.arcsin(np.clip(np.asarray(force_n) / d, -1.0, 1.0)) / c) / b


def handling_curve(a_y, mass_kg, l_f, l_r, k_f, k_r, mu_f, mu_r, shape_c):
    """Delta(a_y) = alpha_f - alpha_r = delta - l/R [rad] for steady turning at lateral acceleration a_y."""
    l = l_f + l_r
    load_f = mass_kg * G_MPS2 * l_r / l
    load_r = mass_kg * G_MPS2 * l_f / l
    b_f, d_f = magic_formula_axle(k_f, mu_f, load_f, shape_c)
    b_r, d_r = magic_formula_axle(k_r, mu_r, load_r, shape_c)
    a_y = np.asarray(a_y, dtype=float)
    return axle_slip_rad(load_f * a_y / G_MPS2, b_f, shape_c, d_f) - axle_slip_rad(load_r * a_y / G_MPS2, b_r, shape_c, d_r)


def safety_threshold(u_mps, mass_kg, l_f, l_r, k_f, k_r, mu_f, mu_r, shape_c) -> tuple[float, float, float]:
    """(a_ys, a_y_neutral, a_y_stab(u)) [m/s^2] from the handling diagram (curve_shift.md 3):
    a_y_neutral: smallest a_y with dDelta/da_y = 0 (the neutral-steer line at constant radius);
    a_y_stab(u): smallest a_y with l/u^2 + dDelta/da_y = 0 (constant-speed stability limit);
    a_ys = min(a_y_neutral, a_y_stab, 0.9*min(mu_f, mu_r)*g)."""
    l = l_f + l_r
    top = min(mu_f, mu_r) * G_MPS2 * 0.9999
    a = np.linspace(0.0, top, 20001)
    delta_curve = handling_curve(a, mass_kg, l_f, l_r, k_f, k_r, mu_f, mu_r, shape_c)
    grad = np.gradient(delta_curve, a)

    def first_zero(values):
        idx = np.nonzero(values <= 0.0)[0]
        if len(idx) == 0:
            return math.inf
        i = int(idx[0])
        if i == 0:
            return 0.0
        return float(a[i - 1] + (a[i] - a[i - 1]) * values[i - 1] / (values[i - 1] - values[i]))

    neutral = first_zero(grad)
    stab = first_zero(l / max(u_mps, 0.1) ** 2 + grad)
    return min(neutral, stab, 0.9 * min(mu_f, mu_r) * G_MPS2), neutral, stab
