"""Unit conversions at the I/O edge, and the unit carried by a name's suffix.

SI inside (common.md section 1). File keys may use the external units listed in
``FILE_UNITS``; :func:`to_si` maps such a key and value to the internal SI name.
"""
from __future__ import annotations

import math

RPM_TO_RADPS = math.pi / 30.0
BAR_TO_PA = 1.0e5
KPH_TO_MPS = 1.0 / 3.6
DEG_TO_RAD = math.pi / 180.0
TONNE_TO_KG = 1000.0

# file suffix -> (SI suffix, factor): value_si = value_file * factor
FILE_UNITS: dict[str, tuple[str, float]] = {
    "_deg": ("_rad", DEG_TO_RAD),
    "_rpm": ("_radps", RPM_TO_RADPS),
    "_bar": ("_pa", BAR_TO_PA),
    "_kph": ("_mps", KPH_TO_MPS),
    "_bar_per_s": ("_pa_per_s", BAR_TO_PA),
    "_rpm_per_s": ("_radps2", RPM_TO_RADPS),
    "_deg_per_s": ("_radps", DEG_TO_RAD),
    "_nm_per_rpm": ("_nm_per_radps", 1.0 / RPM_TO_RADPS),
    "_nm_per_bar": ("_nm_per_pa", 1.0 / BAR_TO_PA),
    "_kw": ("_w", 1000.0),
}

# SI suffix -> unit string (longest suffix first when matching)
SUFFIX_UNITS: dict[str, str] = {
    "_pa_per_s": "Pa/s",
    "_radps2": "rad/s^2",
    "_radps": "rad/s",
    "_mps3": "m/s^3",
    "_mps2": "m/s^2",
    "_mps": "m/s",
    "_kgm2": "kg*m^2",
    "_kg": "kg",
    "_nm": "N*m",
    "_n": "N",
    "_pa": "Pa",
    "_rad": "rad",
    "_s": "s",
    "_m": "m",
    "_w": "W",
    "_j": "J",
    "_frac": "1",
    "_per_s": "1/s",
    "_coeff": "1",
    "_index": "1",
    "_std": "",
    "_ratio": "1",
    "_flag": "1",
    "_count": "1",
    "_code": "1",  # an enumerated code (e.g. assist_refusal_code: 0 none, k = 1 + index in REFUSAL_REASONS)
    "_hz": "Hz",
    "_m2": "m^2",
    "_nm_per_pa": "N*m/Pa",
    "_nm_per_radps": "N*m/(rad/s)",
    "_n_per_m": "N/m",
    # external units (files, reports); the compound ones first so that '_nm_per_rpm' is not read as 'rpm'
    "_nm_per_rpm": "N*m/rpm",
    "_nm_per_bar": "N*m/bar",
    "_bar_per_s": "bar/s",
    "_rpm_per_s": "rpm/s",
    "_deg_per_s": "deg/s",
    "_kw": "kW",
    "_deg": "deg",
    "_rpm": "rpm",
    "_bar": "bar",
    "_kph": "km/h",
}
_SUFFIXES = sorted(SUFFIX_UNITS, key=len, reverse=True)


def unit_of(name: str) -> str:
    """The unit a name carries in its suffix ('1' for dimensionless, '' if none is known)."""
    for suffix in _SUFFIXES:
        if name.endswith(suffix):
            return SUFFIX_UNITS[suffix]
    return ""


def to_si(name: str, value: float) -> tuple[str, float]:
    """Map a file key in external units to its SI name and value (unchanged if already SI)."""
    for suffix in sorted(FILE_UNITS, key=len, reverse=True):
        if name.endswith(suffix):
            si_suffix, factor = FILE_UNITS[suffix]
            return name[: -len(suffix)] + si_suffix, value * factor
    return name, value


def si_name(name: str) -> str:
    return to_si(name, 0.0)[0]


def rpm(radps: float) -> float:
    return radps / RPM_TO_RADPS


def bar(pa: float) -> float:
    return pa / BAR_TO_PA
