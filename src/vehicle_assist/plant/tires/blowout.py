"""Tire blowout: deflation, load redistribution through the suspension diagonals, blown-tire properties and
the full Dugoff tire (tire_blowout.md 2.3, 3, 6; paper 004 eqs. 6-8 and 13-21).

Wheels are indexed fl, fr, rl, rr (0..3). Diagonal A = (fl, rr), diagonal B = (fr, rl).

Deflation (eq. 21, spec 3): ``phi(t)`` ramps 0 -> 1 linearly over ``t_blow`` from the blowout time; the
blown wheel's rolling radius is ``R(t) = R_out - (R_out - R_in)*phi``.

Load transfer (eqs. 13-20, generalised to any blown wheel b): with ``d_i = +1`` on diagonal A and ``-1`` on B,
the rigid-body compatibility (eq. 14: corner heights of the two diagonals sum equally, h = h0 - F'/K_s,
equal h0 per axle) is ``sum_i d_i*(R_i - F'_i/K_i) = 0``. The blown wheel's diagonal loses ``f``, the other
gains it (``F'_i = F_i - f*d_i*d_b``), so

    f = [dR + d_b * sum_i d_i*F_i/K_i] / sum_i 1/K_i ,    dR = R_out - R_blown

which for b = fl is the spec's eq. (16-20) form; straight driving gives f = dR*K_sf*K_sr/(2*(K_sf + K_sr)).
Clipped to 0 <= f <= min(F_b, F_partner). ``K_i`` may include the tire in series (spec 3 note).
"""
from __future__ import annotations

import math

import numba as nb
import numpy as np

from vehicle_assist.plant.tires.dugoff import dugoff_forces

DIAGONAL = np.array([1.0, -1.0, -1.0, 1.0])  # +1 on diagonal A (fl, rr), -1 on diagonal B (fr, rl)
PARTNER = np.array([3, 2, 1, 0], dtype=np.int64)  # diagonal partner of each wheel
OPPOSITE = np.array([1, 0, 3, 2], dtype=np.int64)  # the other wheel of the same axle
WHEEL_NAMES = ("fl", "fr", "rl", "rr")


@nb.njit(cache=True, nogil=True, error_model="numpy")
def deflation_frac(t, t_blow_start, t_blow_s):
    """phi(t) in [0, 1]: 0 before the blowout, linear over t_blow_s, then 1 (spec 3 eq. 21)."""
    if t < t_blow_start:
        return 0.0
    if t_blow_s <= 0.0:
        return 1.0
    return min((t - t_blow_start) / t_blow_s, 1.0)


@nb.njit(cache=True, nogil=True, error_model="numpy")
def blown_radius_m(phi, r_out_m, r_in_m):
    """Rolling radius of the blown wheel, R_out -> R_in as phi goes 0 -> 1."""
    return r_out_m - (r_out_m - r_in_m) * phi


@nb.njit(cache=True, nogil=True, error_model="numpy")
def transfer_n(blown, fz_fl, fz_fr, fz_rl, fz_rr, d_radius_m, k_front_npm, k_rear_npm):
    """Load transfer f [N] (eqs. 16-20 generalised); ``blown`` < 0 or dR <= 0 gives 0."""
    if blown < 0 or d_radius_m <= 0.0:
        return 0.0
    fz = (fz_fl, fz_fr, fz_rl, fz_rr)
    inv = (1.0 / k_front_npm, 1.0 / k_front_npm, 1.0 / k_rear_npm, 1.0 / k_rear_npm)
    db = DIAGONAL[blown]
    num = d_radius_m
    den = 0.0
    for i in range(4):
        num += db * DIAGONAL[i] * fz[i] * inv[i]
        den += inv[i]
    f = num / den
    return min(max(f, 0.0), min(fz[blown], fz[PARTNER[blown]]))


@nb.njit(cache=True, nogil=True, error_model="numpy")
def redistributed_loads(blown, fz_fl, fz_fr, fz_rl, fz_rr, f):
    """(F'_fl, F'_fr, F'_rl, F'_rr) (eq. 13): the blown wheel's diagonal loses f, the other gains it."""
    if blown < 0:
        return fz_fl, fz_fr, fz_rl, fz_rr
    db = DIAGONAL[blown]
    return (fz_fl - f * db * DIAGONAL[0], fz_fr - f * db * DIAGONAL[1],
            fz_rl - f * db * DIAGONAL[2], fz_rr - f * db * DIAGONAL[3])


@nb.njit(cache=True, nogil=True, error_model="numpy")
def series_rate_npm(k_suspension_npm, k_tire_npm):
    """Suspension and tire in series, 1/K = 1/K_s + 1/K_t (spec 3 note); K_t <= 0 means rigid tire."""
    if k_tire_npm <= 0.0:
        return k_suspension_npm
    return 1.0 / (1.0 / k_suspension_npm + 1.0 / k_tire_npm)


@nb.njit(cache=True, nogil=True, error_model="numpy")
def stiffness_factor(phi, k_blown_frac):
    """Stiffness scale of the blown tire: 1 -> k_blown_frac as phi goes 0 -> 1 (spec 6, k_Cy)."""
    return 1.0 - (1.0 - k_blown_frac) * phi


@nb.njit(cache=True, nogil=True, error_model="numpy")
def dugoff_full(slip, tan_alpha, fz_n, mu0, cx_n, cy_n, eps_r_s_per_m, wheel_speed_mps):
    """Dugoff with the friction reduction with slip speed (spec 2.3):
    mu = mu0*(1 - eps_r*u_w*sqrt(s^2 + tan^2 alpha)) (not below 0), then both H branches of dugoff_forces.
    Returns (F_x retarding magnitude, F_y leftward)."""
    s = min(max(slip, 0.0), 1.0)
    mu = mu0 * max(1.0 - eps_r_s_per_m * abs(wheel_speed_mps) * math.sqrt(s * s + tan_alpha * tan_alpha), 0.0)
    return dugoff_forces(s, tan_alpha, fz_n, mu, cx_n, cy_n)


@nb.njit(cache=True, nogil=True, error_model="numpy")
def blown_drag_n(phi, drag_coeff, fz_blown_n, mu_peak):
    """Retarding drag of the blown tire on its rim (spec 4/6): phi * c_drag * F'_z, c_drag = mu_blow (paper
    worst case, dragged at s = 1) or f_blow (rolling-drag alternative); never above the road's peak mu*F'_z."""
    return phi * min(drag_coeff, mu_peak) * max(fz_blown_n, 0.0)
