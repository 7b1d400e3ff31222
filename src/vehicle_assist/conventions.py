"""Axes, signs and shared constants (common.md sections 1, 2 and 13).

* ISO 8855 axes: x forward, y left, z up; yaw rate positive counter-clockwise seen from above.
* Road grade angle positive uphill in the direction of travel.
* Longitudinal speed positive forward; "rollback" is v < 0 while the driver wants to go forward uphill.
* Forces on the vehicle in traces (``*_force_n``) are positive along +x (forward / uphill);
  resistances in the driving equation (``grade_resistance_n``, ``aero_drag_n``) are positive when they
  oppose forward motion, as in F_t = F_f + F_w + F_i + F_j (common.md section 3).
* Wheel order: fl, fr, rl, rr.
* Lane radius (``lane_keeper.lane_radius_m``) signed as the yaw rate: 0 straight, R > 0 a LEFT curve (counter-clockwise,
  centre at y = +R), R < 0 a RIGHT curve (clockwise, centre at y = R < 0); lane offset left +. A right curve of -R is
  the left curve of R mirrored (session m, M4).
"""
from __future__ import annotations

G_MPS2 = 9.81  # std (common.md 13)
RHO_AIR_KGPM3 = 1.2258  # std: Chinese textbook value behind the 21.15 drag constant (common.md 3.1)
RHO_BRAKE_FLUID_KGPM3 = 1050.0  # assumed (common.md 13)
STANDSTILL_SPEED_MPS = 1.0e-3  # v_eps of the stick/slip rule, assumed (common.md 3.3)
WHEEL_ORDER = ("fl", "fr", "rl", "rr")
