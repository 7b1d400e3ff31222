"""Map preview (electronic horizon) as a sensor: the next curve's distance, radius and length from the road map.

The map is the scenario's road (an OpenDRIVE reference line or a radius table) cut into curves
(io/opendrive.py ``find_curves``: stretches with radius below ``CURVE_MAX_RADIUS_M``). The true preview at
position x is the first curve whose end lies ahead:

    distance = start - x (negative inside the curve), radius = smallest radius of the curve, length

and ``valid = 1`` while such a curve exists within ``range_m``. Map errors are vehicle-file values
(``[map_preview]``): ``available_flag = 0`` (no map: valid = 0 everywhere), ``radius_scale_frac`` (a map whose
radii are off, e.g. 1.5 = 50 % too large), ``distance_offset_m`` (a position error along the road).
The sensor layer (plant/sensors.py) adds what every sensor has: noise (``sensors.curve_radius.noise_std_m``),
latency (``sensors.curve_distance.delay_s``) and dropouts (a ``sensor_fault`` event with ``fault = "lost"`` on
``curve_valid``, or on any preview channel: the controller then sees an invalid preview).
"""
from __future__ import annotations

import numba as nb

CURVE_MAX_RADIUS_M = 1000.0  # assumed: the map marks stretches below this radius as curves
CURVE_MIN_LENGTH_M = 5.0  # assumed: shorter kinks are not curves


@nb.njit(cache=True, nogil=True, error_model="numpy")
def next_curve(s, position_m):
    """(distance to start, radius, length, index) of the first curve whose end lies ahead; index -1 if none."""
    for i in range(int(s.road_curve_count)):
        start = s.road_curve_start_m[i]
        length = s.road_curve_length_m[i]
        if start + length > position_m:
            return start - position_m, s.road_curve_radius_m[i], length, i
    return 0.0, 0.0, 0.0, -1


@nb.njit(cache=True, nogil=True, error_model="numpy")
def preview(p, s, position_m):
    """(distance_m, radius_m, length_m, valid_flag) as the map reports them (before sensor noise/latency)."""
    if p.map_preview_available_flag < 0.5:
        return 0.0, 0.0, 0.0, 0.0
    d, radius, length, idx = next_curve(s, position_m + p.map_preview_distance_offset_m)
    if idx < 0 or d > p.map_preview_range_m:
        return 0.0, 0.0, 0.0, 0.0
    return d, radius * p.map_preview_radius_scale_frac, length, 1.0
