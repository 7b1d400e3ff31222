"""One tire interface for every fidelity level: ``tire_forces(model, ...) -> (F_x, F_y)`` in wheel axes.

``F_x`` is the longitudinal force on the wheel centre, forward positive (negative while braking), ``F_y``
the lateral force, leftward positive (ISO 8855, conventions.py). Models (``tires.model`` in a vehicle file):

* ``MODEL_BURCKHARDT`` (0): Burckhardt curve mu(s_res) = c1*(1 - exp(-c2*s_res)) - c3*s_res on the
  resultant slip s_res = sqrt(s^2 + tan^2(alpha_t)), shared between the directions in proportion to the
  slip components (the combined form of Kiencke & Nielsen, *Automotive Control Systems*, 2005, std); the
  road's friction scale multiplies the curve (1.0 = the surface set as measured).
* ``MODEL_DUGOFF`` (1): plant/tires/dugoff.py with mu = peak of the surface's Burckhardt curve x scale.

Burckhardt sets (c1, c2, c3) from Burckhardt (1993) as tabulated by Kiencke & Nielsen (std):
dry asphalt (1.2801, 23.99, 0.52), wet asphalt (0.857, 33.822, 0.347), snow (0.1946, 94.129, 0.0646).
Paper 004 adds the blown tire's radius and stiffness changes through the same call (its own C_x, C_y, F_z).
"""
from __future__ import annotations

import math

import numba as nb
import numpy as np

from vehicle_assist.plant.tires.dugoff import dugoff_forces

MODEL_BURCKHARDT, MODEL_DUGOFF = 0, 1
MODELS = {"burckhardt": MODEL_BURCKHARDT, "dugoff": MODEL_DUGOFF}
SURFACES = ("dry", "wet", "snow")
SURFACE_CODES = {name: float(i) for i, name in enumerate(SURFACES)}
# rows: dry asphalt, wet asphalt, snow; columns c1, c2, c3 (Burckhardt 1993 via Kiencke & Nielsen, std)
BURCKHARDT_SETS = np.array([[1.2801, 23.99, 0.52],
                            [0.857, 33.822, 0.347],
                            [0.1946, 94.129, 0.0646]])


@nb.njit(cache=True, nogil=True, error_model="numpy")
def burckhardt_mu(s, c1, c2, c3):
    s = min(max(s, 0.0), 1.0)
    return c1 * (1.0 - math.exp(-c2 * s)) - c3 * s


def burckhardt_peak(c1: float, c2: float, c3: float) -> tuple[float, float]:
    """(slip, mu) at the peak of the curve: d mu/ds = c1*c2*exp(-c2 s) - c3 = 0 (closed form)."""
    s = math.log(c1 * c2 / c3) / c2
    return s, c1 * (1.0 - math.exp(-c2 * s)) - c3 * s


@nb.njit(cache=True, nogil=True, error_model="numpy")
def peak_mu(c1, c2, c3):
    s = math.log(c1 * c2 / c3) / c2
    return c1 * (1.0 - math.exp(-c2 * s)) - c3 * s


@nb.njit(cache=True, nogil=True, error_model="numpy")
def tire_forces(model, slip, tan_alpha, fz_n, scale, c1, c2, c3, cx_n, cy_n):
    """(F_x forward +, F_y left +) of one tire; ``slip`` braking slip in [0, 1] (common.md 2)."""
    if fz_n <= 0.0:
        return 0.0, 0.0
    if model == MODEL_DUGOFF:
        fx, fy = dugoff_forces(slip, tan_alpha, fz_n, scale * peak_mu(c1, c2, c3), cx_n, cy_n)
        return -fx, fy
    s = min(max(slip, 0.0), 1.0)
    res = math.sqrt(s * s + tan_alpha * tan_alpha)
    if res < 1e-9:
        return 0.0, 0.0
    f = scale * burckhardt_mu(min(res, 1.0), c1, c2, c3) * fz_n
    return -f * s / res, f * tan_alpha / res
