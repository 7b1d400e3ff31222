"""Two-track (four-wheel) vehicle body in the road plane with four spinning wheels (tire_blowout.md 2.4-2.5,
common.md 8). States: body-fixed speeds u (forward), v (left), yaw rate r (ISO 8855, CCW +); global x, y,
heading psi; wheel speeds omega_i (fl, fr, rl, rr). Front steer delta (both front wheels alike).

Wheel-centre velocity of wheel i at (x_i, y_i) from the CG (front x = l_f, rear x = -l_r; left y = +b):
    v_xi = u - r*y_i,   v_yi = v + r*x_i;  in wheel axes (front rotated by delta):
    v_long = v_xi*cos(delta) + v_yi*sin(delta),   alpha_t = delta - atan2(v_yi, v_xi)
Forces in wheel axes (F_x fwd +, F_y left +) rotated to the body: X = F_x cos d - F_y sin d,
Y = F_x sin d + F_y cos d, and
    m*(du/dt - v*r) = sum X - F_drag - F_roll      m*(dv/dt + u*r) = sum Y
    I_z*dr/dt = b_f*(X_fr - X_fl) + b_r*(X_rr - X_rl) + l_f*(Y_fl + Y_fr) - l_r*(Y_rl + Y_rr)
Wheel:  J*d(omega)/dt = -F_x*r_w - T_b (brake a capacity; locked wheel held at omega = 0, plant/wheel.py).

Integration (semi-implicit Euler): the tire force is stiff in omega at low speed (d F_x/d omega ~
C_x*r/v), so the wheel step is linearly implicit in the tire term: omega+ = omega + dt*T/(J + dt*k),
k = r^2*max(0, -dF_x/ds)/max(v_long, v_eps) >= 0 (exact for a linear tire, unconditionally stable).
Low speed (issue #10, the stop freeze): the slip angle is the SAE J670 / ISO 8855 one, tan(alpha_t) =
-v_lat/|v_long| in wheel axes (Pacejka, Tire and Vehicle Dynamics, 3rd ed. 2012, sec. 1.2, with |V_cx|), with
the singular denominator bounded below by ``SLIP_SPEED_EPS_MPS`` as the braking slip already is (brake_assist.md
4.3; the same minimum-denominator regularisation as e.g. PhysX vehicle2's minLatSlipDenominator). Below that
speed a sideways sliding tire acts as a stiff damper (F_y = C_y*v_lat/v_eps until it saturates at mu*F_z): a car
sliding sideways with u ~ 0 decelerates at ~mu*g and comes to rest, the force always opposes the slip velocity
(no energy is created). At and above v_eps the slip angle is computed exactly as before.
Standstill: the car is held (u = v = r = 0) once every contact point is slow: the planar speed sqrt(u^2 + v^2)
and |r| times the largest wheel lever are both below ``STOP_SPEED_MPS`` (:func:`at_rest`). (Before: u alone,
which froze a car still sliding or spinning sideways.)
"""
from __future__ import annotations

import math

import numba as nb

STOP_SPEED_MPS = 0.05  # assumed: below this the braked car is taken as stopped (regularisation, tested)
SLIP_SPEED_EPS_MPS = 1.0  # v_eps of the slip denominator (brake_assist.md 4.3 uses max(v, 1 m/s))


@nb.njit(cache=True, nogil=True, error_model="numpy")
def wheel_kinematics(u, v, r, delta, x_i, y_i):
    """(v_long along the wheel heading, tan(alpha_t)) of the wheel at (x_i, y_i) from the CG."""
    vx = u - r * y_i
    vy = v + r * x_i
    c = math.cos(delta)
    s = math.sin(delta)
    v_long = vx * c + vy * s
    if vx > 1e-3 and v_long >= SLIP_SPEED_EPS_MPS:
        return v_long, math.tan(delta - math.atan2(vy, vx))  # = -v_lat/v_long (unchanged form above v_eps)
    v_lat = vy * c - vx * s
    return v_long, (0.0 - v_lat) / max(abs(v_long), SLIP_SPEED_EPS_MPS)  # 0.0 - x: no negative zero


@nb.njit(cache=True, nogil=True, error_model="numpy")
def at_rest(u, v, r, lever_m):
    """True when every contact point moves slower than STOP_SPEED_MPS: planar CG speed and yaw rate x lever."""
    return math.sqrt(u * u + v * v) <= STOP_SPEED_MPS and abs(r) * lever_m <= STOP_SPEED_MPS


@nb.njit(cache=True, nogil=True, error_model="numpy")
def braking_slip(v_long, omega, radius_m):
    """s = (v - omega*R)/max(v, v_eps) clipped to [0, 1] (common.md 2)."""
    s = (v_long - omega * radius_m) / max(v_long, SLIP_SPEED_EPS_MPS)
    return min(max(s, 0.0), 1.0)


@nb.njit(cache=True, nogil=True, error_model="numpy")
def body_forces(fx, fy, delta):
    """(X, Y) body-axis force of a wheel from its wheel-axis forces and steer angle."""
    c = math.cos(delta)
    s = math.sin(delta)
    return fx * c - fy * s, fx * s + fy * c


@nb.njit(cache=True, nogil=True, error_model="numpy")
def yaw_moment(x_fl, x_fr, x_rl, x_rr, y_fl, y_fr, y_rl, y_rr, l_f, l_r, b_f, b_r):
    """M_z = b_f*(X_fr - X_fl) + b_r*(X_rr - X_rl) + l_f*(Y_fl + Y_fr) - l_r*(Y_rl + Y_rr) (eqs. 9-10)."""
    return b_f * (x_fr - x_fl) + b_r * (x_rr - x_rl) + l_f * (y_fl + y_fr) - l_r * (y_rl + y_rr)


@nb.njit(cache=True, nogil=True, error_model="numpy")
def wheel_spin_step(omega, brake_capacity_nm, fx_n, damping_nms, radius_m, inertia_kgm2, dt):
    """(omega_new, locked): J*domega/dt = -F_x*r - T_b with the linearly implicit tire term."""
    spin = -fx_n * radius_m
    if omega <= 0.0 and -brake_capacity_nm <= spin <= brake_capacity_nm:
        return 0.0, True
    new = omega + dt * (spin - brake_capacity_nm) / (inertia_kgm2 + dt * damping_nms)
    if new <= 0.0:
        return 0.0, True
    return new, False
