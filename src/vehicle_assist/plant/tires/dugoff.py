"""Dugoff combined-slip tire model (tire_blowout.md 2.3; Dugoff, Fancher, Segel 1970 as used by paper 004).

Inputs per wheel: vertical load F_z [N], braking slip s in [0, 1] (common.md 2: 0 free rolling, 1 locked),
tan of the slip angle alpha_t (positive gives a positive, leftward lateral force), peak road friction mu,
longitudinal stiffness C_x [N per unit slip], cornering stiffness C_y [N/rad]:

    H    = mu*F_z*(1 - s) / (2*sqrt(C_x^2 s^2 + C_y^2 tan^2(alpha_t)))
    f(H) = H*(2 - H) if H < 1 else 1
    F_x  = C_x * s/(1 - s) * f(H)          (retarding magnitude; the caller gives it the sign)
    F_y  = C_y * tan(alpha_t)/(1 - s) * f(H)

At s = 1 the analytic limit is used: F_x = C_x*mu*F_z/sqrt(C_x^2 + C_y^2 tan^2), F_y likewise with C_y*tan.
F_z <= 0 gives no force. The friction reduction with slip speed (eps_r) is left out (eps_r = 0, spec 7).
"""
from __future__ import annotations

import math

import numba as nb


@nb.njit(cache=True, nogil=True, error_model="numpy")
def dugoff_forces(slip, tan_alpha, fz_n, mu, cx_n, cy_n):
    """(F_x retarding magnitude >= 0 for s >= 0, F_y leftward) of one tire."""
    if fz_n <= 0.0:
        return 0.0, 0.0
    s = min(max(slip, 0.0), 1.0)
    if s >= 1.0 - 1e-9:
        den = math.sqrt(cx_n * cx_n + cy_n * cy_n * tan_alpha * tan_alpha)
        return cx_n * mu * fz_n / den, cy_n * tan_alpha * mu * fz_n / den
    den = 2.0 * math.sqrt(cx_n * cx_n * s * s + cy_n * cy_n * tan_alpha * tan_alpha)
    if den <= 0.0:
        return 0.0, 0.0
    h = mu * fz_n * (1.0 - s) / den
    f = h * (2.0 - h) if h < 1.0 else 1.0
    return cx_n * s / (1.0 - s) * f, cy_n * tan_alpha / (1.0 - s) * f
