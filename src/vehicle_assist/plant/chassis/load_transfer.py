"""Quasi-static wheel loads with longitudinal and lateral load transfer (common.md 9; tire_blowout.md 2.1).

    F_zf_axle = m*(g*l_r - a_x*h)/l            F_zr_axle = m*(g*l_f + a_x*h)/l
    dF_zf = m*a_y*h*phi_f/B_f                  dF_zr = m*a_y*h*(1 - phi_f)/B_r
    F_z_fl = F_zf_axle/2 - dF_zf   F_z_fr = F_zf_axle/2 + dF_zf
    F_z_rl = F_zr_axle/2 - dF_zr   F_z_rr = F_zr_axle/2 + dF_zr

``phi_f`` is the front share of the roll stiffness (the lateral transfer split between the axles; roll
centres at ground level, assumed). With ``phi_f = l_r/l`` this is exactly the common.md 9 form. a_x forward
+, a_y left + (ISO 8855): braking (a_x < 0) moves load to the front, a left turn (a_y > 0) to the right
wheels. Loads are clipped at 0 (a wheel lifting off carries nothing; the sum then exceeds m*g, which
only happens beyond the rollover limit and is not the validity range of this model).
"""
from __future__ import annotations

import numba as nb


@nb.njit(cache=True, nogil=True, error_model="numpy")
def wheel_loads(m_kg, g, l_f, l_r, h, b_f, b_r, roll_split_front, a_x, a_y):
    """(F_z_fl, F_z_fr, F_z_rl, F_z_rr) [N]."""
    wheelbase = l_f + l_r
    front = m_kg * (g * l_r - a_x * h) / wheelbase
    rear = m_kg * (g * l_f + a_x * h) / wheelbase
    d_f = m_kg * a_y * h * roll_split_front / b_f
    d_r = m_kg * a_y * h * (1.0 - roll_split_front) / b_r
    return (max(0.5 * front - d_f, 0.0), max(0.5 * front + d_f, 0.0),
            max(0.5 * rear - d_r, 0.0), max(0.5 * rear + d_r, 0.0))
