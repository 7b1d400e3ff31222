"""OpenDRIVE (.xodr) reader: the reference line of a road as curvature, heading, position and grade over s.

No maintained Python library returns the curvature of an OpenDRIVE reference line, so this is a small,
tested reader of the parts the curve-aware shift strategy needs (ASAM OpenDRIVE 1.4-1.8, planView and
elevationProfile of one road):

    <geometry s x y hdg length>  with one of
      <line/>                                   kappa = 0
      <arc curvature="k"/>                      kappa = k                     (k > 0: left turn, CCW)
      <spiral curvStart="k0" curvEnd="k1"/>     kappa(ds) = k0 + (k1 - k0)*ds/length   (clothoid)
      <poly3 a b c d/>                          local v(u) = a + b*u + c*u^2 + d*u^3, u along the local x
                                                kappa = v''/(1 + v'^2)^(3/2)
      <paramPoly3 aU..dU aV..dV pRange/>        u(p), v(p) cubic in p (p in [0, 1] "normalized" or
                                                [0, length] "arcLength");
                                                kappa = (u'v'' - v'u'')/(u'^2 + v'^2)^(3/2)
    <elevation s a b c d/>                      z(ds) = a + b*ds + c*ds^2 + d*ds^3, grade = atan(dz/ds)

poly3 and paramPoly3 are not parametrised by arc length; the reader maps s to the parameter with the arc
length integrated on a fine grid (Simpson on 4096 intervals) and inverts it by interpolation. Position and
heading are integrated from the curvature (the geometry's own start x, y, hdg restart each element).
Signs: ISO 8855 / OpenDRIVE, curvature > 0 turns left (counter-clockwise seen from above).

Malformed or unsupported input raises :class:`OpenDriveError` with one line naming the file, the element
and its line number (the XML is parsed with expat, which reports line numbers).
"""
from __future__ import annotations

import math
import xml.parsers.expat
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

MAX_FILE_BYTES = 50_000_000  # a road network of a few hundred km; anything larger is refused
MAX_GEOMETRIES = 100_000
BOUNDARY_STEP_M = 1e-6  # a curvature jump at an element boundary is sampled as a step of this width
PARAM_GRID = 4096  # intervals of the arc-length integration of poly3 / paramPoly3 (even: Simpson)
GEOMETRY_TYPES = ("line", "arc", "spiral", "poly3", "paramPoly3")


class OpenDriveError(ValueError):
    """A malformed or unsupported OpenDRIVE file; the message is one line naming the element and line."""


@dataclass
class _Node:
    tag: str
    attrib: dict
    line: int
    children: list = field(default_factory=list)

    def find(self, tag: str):
        for c in self.children:
            if c.tag == tag:
                return c
        return None

    def findall(self, tag: str) -> list:
        return [c for c in self.children if c.tag == tag]


def _parse_xml(text: bytes, where: str) -> _Node:
    """Minimal element tree with line numbers (expat)."""
    parser = xml.parsers.expat.ParserCreate()
    root: list[_Node] = []
    stack: list[_Node] = []

    def start(tag, attrib):
        node = _Node(tag.split("}")[-1], dict(attrib), parser.CurrentLineNumber)
        if stack:
            stack[-1].children.append(node)
        else:
            root.append(node)
        stack.append(node)

    def end(tag):
        stack.pop()

    parser.StartElementHandler = start
    parser.EndElementHandler = end
    # no external entities, no DTD expansion beyond expat's defaults
    parser.SetParamEntityParsing(xml.parsers.expat.XML_PARAM_ENTITY_PARSING_NEVER)
    try:
        parser.Parse(text, True)
    except xml.parsers.expat.ExpatError as exc:
        raise OpenDriveError(f"{where}: not well-formed XML at line {exc.lineno}, column {exc.offset}: "
                             f"{xml.parsers.expat.ErrorString(exc.code)}") from None
    if not root:
        raise OpenDriveError(f"{where}: no XML element found")
    return root[0]


def _num(node: _Node, key: str, where: str, default: float | None = None) -> float:
    text = node.attrib.get(key)
    if text is None:
        if default is not None:
            return default
        raise OpenDriveError(f"{where}: <{node.tag}> at line {node.line} has no attribute {key!r}")
    try:
        value = float(text)
    except ValueError:
        raise OpenDriveError(f"{where}: <{node.tag}> at line {node.line}: {key}={text!r} is not a number") from None
    if not math.isfinite(value):
        raise OpenDriveError(f"{where}: <{node.tag}> at line {node.line}: {key}={text!r} must be finite")
    return value


# ----------------------------------------------------------------------------------------- geometries
@dataclass(frozen=True)
class Geometry:
    """One planView element: start s, x, y, heading, length, kind and its coefficients."""

    s_m: float
    x_m: float
    y_m: float
    hdg_rad: float
    length_m: float
    kind: str
    coeffs: tuple[float, ...] = ()
    normalized: bool = True  # paramPoly3 pRange
    line: int = 0

    def curvature(self, ds: np.ndarray) -> np.ndarray:
        """Curvature [1/m] at distances ``ds`` (0..length) from the element's start."""
        ds = np.asarray(ds, dtype=float)
        if self.kind == "line":
            return np.zeros_like(ds)
        if self.kind == "arc":
            return np.full_like(ds, self.coeffs[0])
        if self.kind == "spiral":
            k0, k1 = self.coeffs
            return k0 + (k1 - k0) * ds / self.length_m
        p = self._param_at(ds)
        du, dv, ddu, ddv = self._derivs(p)
        return (du * ddv - dv * ddu) / (du * du + dv * dv) ** 1.5

    # -- poly3 / paramPoly3 in a common (u(p), v(p)) form: poly3 is u = p, v = a + b p + c p^2 + d p^3
    def _poly(self) -> tuple[np.ndarray, np.ndarray]:
        if self.kind == "poly3":
            return np.array([0.0, 1.0, 0.0, 0.0]), np.array(self.coeffs)
        c = self.coeffs
        return np.array(c[:4]), np.array(c[4:])

    def _derivs(self, p: np.ndarray):
        cu, cv = self._poly()
        du = cu[1] + 2 * cu[2] * p + 3 * cu[3] * p * p
        dv = cv[1] + 2 * cv[2] * p + 3 * cv[3] * p * p
        ddu = 2 * cu[2] + 6 * cu[3] * p
        ddv = 2 * cv[2] + 6 * cv[3] * p
        return du, dv, ddu, ddv

    def _param_table(self) -> tuple[np.ndarray, np.ndarray]:
        cached = self.__dict__.get("_ptab")
        if cached is not None:
            return cached
        if self.kind == "paramPoly3":
            p_end = 1.0 if self.normalized else self.length_m
        else:  # poly3: find u_end where the arc length equals the element length (u_end <= length)
            p_end = self._poly3_u_end()
        p = np.linspace(0.0, p_end, PARAM_GRID + 1)
        du, dv, _, _ = self._derivs(p)
        speed = np.sqrt(du * du + dv * dv)
        s = np.zeros_like(p)
        # cumulative Simpson on pairs of intervals, midpoints by the trapezoid of the neighbours
        h = p[1] - p[0]
        s[1:] = np.cumsum(0.5 * h * (speed[1:] + speed[:-1]))
        s[2::2] = np.cumsum(h / 3.0 * (speed[0:-2:2] + 4 * speed[1:-1:2] + speed[2::2]))
        object.__setattr__(self, "_ptab", (s, p))
        return s, p

    def _poly3_u_end(self) -> float:
        cu, cv = self._poly()
        lo, hi = 0.0, self.length_m
        for _ in range(60):  # bisection on the arc length (monotone in u)
            mid = 0.5 * (lo + hi)
            u = np.linspace(0.0, mid, 2049)
            dv = cv[1] + 2 * cv[2] * u + 3 * cv[3] * u * u
            arc = np.trapezoid(np.sqrt(1 + dv * dv), u)
            if arc < self.length_m:
                lo = mid
            else:
                hi = mid
        return 0.5 * (lo + hi)

    def _param_at(self, ds: np.ndarray) -> np.ndarray:
        s, p = self._param_table()
        return np.interp(ds, s, p)

    def local_xy(self, ds: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Exact local (u, v) of poly3 / paramPoly3 at distances ``ds`` (for drawing and tests)."""
        cu, cv = self._poly()
        p = self._param_at(np.asarray(ds, dtype=float))
        return (cu[0] + cu[1] * p + cu[2] * p ** 2 + cu[3] * p ** 3,
                cv[0] + cv[1] * p + cv[2] * p ** 2 + cv[3] * p ** 3)


@dataclass(frozen=True)
class Elevation:
    s_m: float
    coeffs: tuple[float, float, float, float]


@dataclass
class OpenDriveRoad:
    """Reference line of one road, sampled; ``curvature_at`` and ``grade_at`` evaluate exactly per element."""

    name: str
    road_id: str
    length_m: float
    geometries: list[Geometry]
    elevations: list[Elevation]
    path: str = ""

    def _geometry_index(self, s: np.ndarray) -> np.ndarray:
        starts = np.array([g.s_m for g in self.geometries])
        return np.clip(np.searchsorted(starts, s, side="right") - 1, 0, len(starts) - 1)

    def curvature_at(self, s) -> np.ndarray:
        s = np.atleast_1d(np.asarray(s, dtype=float))
        idx = self._geometry_index(s)
        out = np.zeros_like(s)
        for i in np.unique(idx):
            g = self.geometries[i]
            m = idx == i
            out[m] = g.curvature(np.clip(s[m] - g.s_m, 0.0, g.length_m))
        return out

    def _elevation_pieces(self, s: np.ndarray):
        """Each elevation record with the samples it covers: (record, mask, ds from the record's start)."""
        starts = np.array([e.s_m for e in self.elevations])
        idx = np.clip(np.searchsorted(starts, s, side="right") - 1, 0, len(starts) - 1)
        for i in np.unique(idx):
            m = idx == i
            yield self.elevations[i], m, s[m] - self.elevations[i].s_m

    def elevation_at(self, s) -> np.ndarray:
        s = np.atleast_1d(np.asarray(s, dtype=float))
        out = np.zeros_like(s)
        for e, m, d in (self._elevation_pieces(s) if self.elevations else ()):
            a, b, c, dd = e.coeffs
            out[m] = a + b * d + c * d * d + dd * d ** 3
        return out

    def grade_at(self, s) -> np.ndarray:
        """Grade angle [rad], uphill + in the direction of increasing s: atan(dz/ds)."""
        s = np.atleast_1d(np.asarray(s, dtype=float))
        out = np.zeros_like(s)
        for e, m, d in (self._elevation_pieces(s) if self.elevations else ()):
            _, b, c, dd = e.coeffs
            out[m] = np.arctan(b + 2 * c * d + 3 * dd * d * d)
        return out

    def sample(self, step_m: float = 1.0) -> dict[str, np.ndarray]:
        """s, curvature, heading, x, y, grade on a grid (element starts included). x, y and heading are
        integrated from the curvature (trapezoid on the grid) from each element's start pose."""
        s_all, k_all, x_all, y_all, h_all = [], [], [], [], []
        for g in self.geometries:
            n = max(2, int(math.ceil(g.length_m / step_m)) + 1)
            ds = np.linspace(0.0, g.length_m, n)
            k = g.curvature(ds)
            hdg = g.hdg_rad + np.concatenate([[0.0], np.cumsum(0.5 * (k[1:] + k[:-1]) * np.diff(ds))])
            if g.kind in ("poly3", "paramPoly3"):
                u, v = g.local_xy(ds)
                c, sn = math.cos(g.hdg_rad), math.sin(g.hdg_rad)
                u0, v0 = g.local_xy(np.array([0.0]))
                x = g.x_m + (u - u0[0]) * c - (v - v0[0]) * sn
                y = g.y_m + (u - u0[0]) * sn + (v - v0[0]) * c
            else:
                hm = 0.5 * (hdg[1:] + hdg[:-1])
                x = g.x_m + np.concatenate([[0.0], np.cumsum(np.cos(hm) * np.diff(ds))])
                y = g.y_m + np.concatenate([[0.0], np.cumsum(np.sin(hm) * np.diff(ds))])
            s_all.append(g.s_m + ds)
            k_all.append(k)
            x_all.append(x)
            y_all.append(y)
            h_all.append(hdg)
        s = np.concatenate(s_all)
        k_cat = np.concatenate(k_all)
        # an element boundary appears twice (end of one, start of the next): where the curvature jumps there
        # (line -> arc) keep both, the end moved back by BOUNDARY_STEP_M, so that the table has the step at the
        # boundary (the old grid kept only the end value: an arc starting at 400 m read as starting at 401 m);
        # where it is continuous drop the repeat
        rep = np.concatenate([[False], np.diff(s) <= 1e-9])
        jump = rep & (np.abs(k_cat - np.roll(k_cat, 1)) > 1e-12)
        prev_of_jump = np.roll(jump, -1)
        s = np.where(prev_of_jump, s - BOUNDARY_STEP_M, s)
        keep = ~rep | jump
        s = s[keep]
        return {"s_m": s, "curvature_per_m": k_cat[keep], "x_m": np.concatenate(x_all)[keep],
                "y_m": np.concatenate(y_all)[keep], "heading_rad": np.concatenate(h_all)[keep],
                "grade_rad": self.grade_at(s)}


# ----------------------------------------------------------------------------------------- reading
def _geometry(node: _Node, where: str) -> Geometry:
    s = _num(node, "s", where)
    x = _num(node, "x", where)
    y = _num(node, "y", where)
    hdg = _num(node, "hdg", where)
    length = _num(node, "length", where)
    if length <= 0.0:
        raise OpenDriveError(f"{where}: <geometry> at line {node.line}: length={length:g} must be > 0")
    if s < 0.0:
        raise OpenDriveError(f"{where}: <geometry> at line {node.line}: s={s:g} must be >= 0")
    kinds = [c for c in node.children if c.tag in GEOMETRY_TYPES]
    others = [c for c in node.children if c.tag not in GEOMETRY_TYPES and c.tag not in ("userData", "dataQuality")]
    if others:
        c = others[0]
        raise OpenDriveError(f"{where}: <{c.tag}> at line {c.line} is not a supported geometry; supported: "
                             f"{', '.join(GEOMETRY_TYPES)}")
    if len(kinds) != 1:
        raise OpenDriveError(f"{where}: <geometry> at line {node.line} must hold exactly one of "
                             f"{', '.join(GEOMETRY_TYPES)} (found {len(kinds)})")
    k = kinds[0]
    common = dict(s_m=s, x_m=x, y_m=y, hdg_rad=hdg, length_m=length, kind=k.tag, line=k.line)
    if k.tag == "line":
        return Geometry(**common)
    if k.tag == "arc":
        curv = _num(k, "curvature", where)
        return Geometry(**common, coeffs=(curv,))
    if k.tag == "spiral":
        return Geometry(**common, coeffs=(_num(k, "curvStart", where), _num(k, "curvEnd", where)))
    if k.tag == "poly3":
        coeffs = tuple(_num(k, n, where) for n in "abcd")
        return Geometry(**common, coeffs=coeffs)
    coeffs = tuple(_num(k, n, where) for n in ("aU", "bU", "cU", "dU", "aV", "bV", "cV", "dV"))
    prange = k.attrib.get("pRange", "normalized")
    if prange not in ("normalized", "arcLength"):
        raise OpenDriveError(f"{where}: <paramPoly3> at line {k.line}: pRange={prange!r} must be 'normalized' or 'arcLength'")
    if coeffs[1] == 0.0 and coeffs[2] == 0.0 and coeffs[3] == 0.0 and coeffs[5] == 0.0 and coeffs[6] == 0.0 and coeffs[7] == 0.0:
        raise OpenDriveError(f"{where}: <paramPoly3> at line {k.line} is a single point (all derivatives zero)")
    return Geometry(**common, coeffs=coeffs, normalized=prange == "normalized")


def parse_opendrive(text: bytes | str, where: str = "<string>", road_id: str | None = None) -> OpenDriveRoad:
    """Read one road (the first, or the one with ``id == road_id``) from OpenDRIVE text."""
    if isinstance(text, str):
        text = text.encode()
    root = _parse_xml(text, where)
    if root.tag != "OpenDRIVE":
        raise OpenDriveError(f"{where}: root element <{root.tag}> at line {root.line} is not <OpenDRIVE>")
    roads = root.findall("road")
    if not roads:
        raise OpenDriveError(f"{where}: <OpenDRIVE> at line {root.line} holds no <road>")
    if road_id is not None:
        chosen = [r for r in roads if r.attrib.get("id") == road_id]
        if not chosen:
            ids = ", ".join(r.attrib.get("id", "?") for r in roads)
            raise OpenDriveError(f"{where}: no <road> with id={road_id!r}; roads in the file: {ids}")
        road = chosen[0]
    else:
        road = roads[0]
    plan = road.find("planView")
    if plan is None:
        raise OpenDriveError(f"{where}: <road> at line {road.line} has no <planView>")
    geo_nodes = plan.findall("geometry")
    if not geo_nodes:
        raise OpenDriveError(f"{where}: <planView> at line {plan.line} holds no <geometry>")
    if len(geo_nodes) > MAX_GEOMETRIES:
        raise OpenDriveError(f"{where}: <planView> at line {plan.line}: {len(geo_nodes)} geometries, at most {MAX_GEOMETRIES}")
    geoms = [_geometry(g, where) for g in geo_nodes]
    for a, b, node in zip(geoms, geoms[1:], geo_nodes[1:]):
        if b.s_m < a.s_m + a.length_m - 1e-3 * max(1.0, a.length_m) or b.s_m > a.s_m + a.length_m + 1e-2:
            raise OpenDriveError(f"{where}: <geometry> at line {node.line}: s={b.s_m:g} does not follow the previous element "
                                 f"(s={a.s_m:g} + length={a.length_m:g}); the reference line must be continuous in s")
    length = geoms[-1].s_m + geoms[-1].length_m
    declared = road.attrib.get("length")
    if declared is not None:
        total = _num(road, "length", where)
        if abs(total - (length - geoms[0].s_m)) > max(0.01, 1e-4 * total):
            raise OpenDriveError(f"{where}: <road> at line {road.line}: length={total:g} but its geometries add up to "
                                 f"{length - geoms[0].s_m:g}")
    elevations = []
    prof = road.find("elevationProfile")
    if prof is not None:
        last = -math.inf
        for e in prof.findall("elevation"):
            s = _num(e, "s", where)
            if s < last:
                raise OpenDriveError(f"{where}: <elevation> at line {e.line}: s={s:g} is below the previous entry's s={last:g}")
            last = s
            elevations.append(Elevation(s, tuple(_num(e, n, where) for n in "abcd")))
    return OpenDriveRoad(road.attrib.get("name", ""), road.attrib.get("id", ""), length, geoms, elevations, where)


def read_opendrive(path: str | Path, road_id: str | None = None) -> OpenDriveRoad:
    """Read a .xodr file (one road; see :func:`parse_opendrive`)."""
    path = Path(path)
    try:
        size = path.stat().st_size
        regular = path.is_file()
    except (OSError, ValueError) as exc:
        raise OpenDriveError(f"{path}: cannot read ({getattr(exc, 'strerror', None) or exc})") from None
    if not regular:
        raise OpenDriveError(f"{path}: cannot read it (not a regular file); give a .xodr file")
    if size > MAX_FILE_BYTES:
        raise OpenDriveError(f"{path}: {size} bytes; OpenDRIVE files of at most {MAX_FILE_BYTES} bytes are read")
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise OpenDriveError(f"{path}: cannot read ({exc.strerror or exc})") from None
    return parse_opendrive(data, str(path), road_id)


# ----------------------------------------------------------------------------------------- curves
@dataclass(frozen=True)
class Curve:
    """A curve of the road: start distance, length and smallest radius (the map's 'next curve')."""

    start_m: float
    length_m: float
    radius_m: float
    direction: int  # +1 left, -1 right


def _crossing(s_out: float, s_in: float, k_out: float, k_in: float, threshold: float) -> float:
    """Where |k| (linear between a sample outside and one inside the curve) reaches the threshold."""
    if k_in <= k_out:
        return s_in
    return s_out + (threshold - k_out) / (k_in - k_out) * (s_in - s_out)


def find_curves(s_m: np.ndarray, curvature_per_m: np.ndarray, max_radius_m: float = 1000.0,
                min_length_m: float = 5.0) -> list[Curve]:
    """Stretches where the radius is below ``max_radius_m`` (transitions up to that radius included)."""
    k = np.asarray(curvature_per_m, dtype=float)
    s = np.asarray(s_m, dtype=float)
    inside = np.abs(k) > 1.0 / max_radius_m
    curves = []
    i = 0
    n = len(s)
    while i < n:
        if not inside[i]:
            i += 1
            continue
        j = i
        while j + 1 < n and inside[j + 1] and np.sign(k[j + 1]) == np.sign(k[i]):
            j += 1
        # the table is read with linear interpolation: the curve begins and ends where |k| crosses the threshold
        start = s[i] if i == 0 else _crossing(s[i - 1], s[i], abs(k[i - 1]), abs(k[i]), 1.0 / max_radius_m)
        end = s[j] if j == n - 1 else _crossing(s[j + 1], s[j], abs(k[j + 1]), abs(k[j]), 1.0 / max_radius_m)
        length = end - start
        if length >= min_length_m:
            kmax = float(np.max(np.abs(k[i:j + 1])))
            curves.append(Curve(float(start), float(length), 1.0 / kmax, int(np.sign(k[i]))))
        i = j + 1
    return curves
