"""Driver steering for the blowout tests (paper 004; issue #10): hold the wheel or follow the lane.

* ``fixed`` (the paper's test, tire_blowout.md 6): the driver holds the steering wheel where the script puts
  it (straight: delta = 0); the scripted steering input is used unchanged.
* ``follow``: a compensatory lane keeper with a reaction delay tau (the driver acts on what was seen tau
  ago): delta = delta_script - (k_y*e_y(t - tau) + k_psi*e_psi(t - tau)) / i_s ... written at the road wheels:

      delta = delta_script - k_y*e_y(t - tau) - k_psi*e_psi(t - tau)

  e_y = lateral offset of the CG from the lane centre (left +), e_psi = heading minus the lane heading; the
  change of delta is limited to the driver's steering-wheel rate / steering ratio. The lane is a straight
  line (y = 0, R = 0) or a circle of SIGNED radius R starting tangent to +x at the origin: R > 0 a left turn
  (centre (0, R), counter-clockwise), R < 0 a right turn (centre (0, R) below the start, clockwise); the sign is
  ISO 8855's (y left +, yaw left +; session m, M4: before it, R <= 0 was a straight lane and the schema refused R < 0).
  A right curve of -R is the left curve of R mirrored in the x axis: e_y, e_psi and delta_ff are negated exactly
  (IEEE negation), so the plant's mirror symmetry carries over to the lane (tests/plant/test_mirror_curves.py).
* Curves (both modes): the driver adds the circle's steady-state angle delta_ff = l/R + K*u^2/R (single-track
  steady state, K the linear understeer gradient from the vehicle's axle stiffnesses) to the scripted angle:
  ``fixed`` holds it for the entry speed (the wheel held at the curve's angle), ``follow`` at the present speed.
* Gains (vehicle file): a single-point preview driver that steers onto the constant-curvature arc closing the
  lateral error at the preview time T_p, y(T_p) = e_y + u*T_p*e_psi + c*(u*T_p)^2/2 = 0, delta = l*c, gives
  k_y = 2*l/(u*T_p)^2 and k_psi = 2*l/(u*T_p) (optimal-curvature preview model class, Guo Konghui; MacAdam,
  IEEE SMC-11(6) 1981). The vehicle file gives them at the paper's 60 km/h (``GAIN_REFERENCE_SPEED_MPS``);
  ``preview_gains`` scales them with the speed as the law does (k_y ~ 1/u^2, k_psi ~ 1/u), so the driver does
  not over-steer at 120 km/h (fixed 60 km/h gains made a rear blowout at 120 km/h diverge).
  Structure: compensatory (feedback) driver with a dead time, McRuer-Krendel crossover model class
  (McRuer & Krendel 1974, NATO AGARDograph 188; cite, not read here). Numbers in the vehicle file are
  assumed (sources there).
"""
from __future__ import annotations

import math

import numba as nb
import numpy as np

FIXED, FOLLOW = 0, 1
BUFFER = 4096  # delay line length (samples at the plant step; 2 s at 0.5 ms)


def initial_buffer() -> np.ndarray:
    return np.zeros((BUFFER, 2))


@nb.njit(cache=True, nogil=True, error_model="numpy")
def lane_errors(gx, gy, psi, lane_radius_m):
    """(e_y left +, e_psi) of the CG relative to the lane: straight if lane_radius_m == 0, a left circle for
    lane_radius_m > 0, a right circle for lane_radius_m < 0 (signed radius, centre (0, lane_radius_m))."""
    if lane_radius_m == 0.0:
        return gy, math.atan2(math.sin(psi), math.cos(psi))
    cx, cy = 0.0, lane_radius_m  # centre: left of the start for a left curve, right of it for a right curve
    dx = gx - cx
    dy = gy - cy
    dist = math.sqrt(dx * dx + dy * dy)
    if lane_radius_m > 0.0:
        e_y = lane_radius_m - dist  # inside the left circle (left of the lane) +
        lane_heading = math.atan2(dy, dx) + 0.5 * math.pi  # counter-clockwise
    else:
        e_y = dist + lane_radius_m  # outside the right circle (left of the lane) +: dist - |R|
        lane_heading = math.atan2(dy, dx) - 0.5 * math.pi  # clockwise
    e = psi - lane_heading
    return e_y, math.atan2(math.sin(e), math.cos(e))


GAIN_REFERENCE_SPEED_MPS = 60.0 / 3.6  # paper 004 test speed: the vehicle file's gains are the preview law's there


@nb.njit(cache=True, nogil=True, error_model="numpy")
def preview_gains(k_y_ref, k_psi_ref, speed_mps):
    """(k_y, k_psi) at ``speed_mps`` from the gains at GAIN_REFERENCE_SPEED_MPS (k_y ~ 1/u^2, k_psi ~ 1/u)."""
    q = GAIN_REFERENCE_SPEED_MPS / max(speed_mps, 5.0)
    return k_y_ref * q * q, k_psi_ref * q


@nb.njit(cache=True, nogil=True, error_model="numpy")
def understeer_gradient(mass_kg, l_f_m, l_r_m, c_front_axle_n_per_rad, c_rear_axle_n_per_rad):
    """Linear single-track understeer gradient K [rad per m/s^2] = m/l*(l_r/C_f - l_f/C_r) (axle stiffnesses)."""
    return mass_kg / (l_f_m + l_r_m) * (l_r_m / c_front_axle_n_per_rad - l_f_m / c_rear_axle_n_per_rad)


@nb.njit(cache=True, nogil=True, error_model="numpy")
def curve_steer_rad(lane_radius_m, speed_mps, wheelbase_m, understeer_rad_per_mps2):
    """Steady-state road-wheel angle of the lane's circle, delta = l/R + K*u^2/R (single-track steady state;
    0 on a straight lane, negative for a right curve R < 0): the driver's feed-forward for a curve."""
    if lane_radius_m == 0.0:
        return 0.0
    return wheelbase_m / lane_radius_m + understeer_rad_per_mps2 * speed_mps * speed_mps / lane_radius_m


@nb.njit(cache=True, nogil=True, error_model="numpy")
def lane_keeper_step(buf, k, delay_steps, e_y, e_psi, delta_script, delta_prev, k_y, k_psi, max_rate_radps, dt):
    """Road-wheel steer angle of the follow driver at step k (buf: delay line of (e_y, e_psi))."""
    n = buf.shape[0]
    buf[k % n, 0] = e_y
    buf[k % n, 1] = e_psi
    d = min(delay_steps, n - 1)
    j = k - d
    if j < 0:
        ey_seen, ep_seen = 0.0, 0.0
    else:
        ey_seen, ep_seen = buf[j % n, 0], buf[j % n, 1]
    target = delta_script - k_y * ey_seen - k_psi * ep_seen
    step = max_rate_radps * dt
    return min(max(target, delta_prev - step), delta_prev + step)
