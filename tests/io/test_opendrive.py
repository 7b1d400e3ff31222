"""OpenDRIVE reader (io/opendrive.py, issue #11).

References: analytic curvature of every geometry type (line 0, arc 1/R, clothoid linear in s), for poly3 and
paramPoly3 the curvature formula of a parametric curve evaluated here with the arc length from scipy's
adaptive quadrature and a root finder (independent of the reader's Simpson grid); a file written by another
tool (scenariogeneration, whose element start poses come from its own clothoid library, pyclothoids);
the closed ends of the shipped proving-ground loop; malformed input naming element and line.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import brentq

from vehicle_assist.io.opendrive import OpenDriveError, find_curves, parse_opendrive, read_opendrive

ROADS = Path(__file__).resolve().parents[2] / "src" / "vehicle_assist" / "data" / "roads"


def _doc(geometries: str, extra: str = "", length: str = "") -> str:
    return f"""<?xml version="1.0"?>
<OpenDRIVE>
  <header revMajor="1" revMinor="6"/>
  <road id="7" name="t" {length} junction="-1">
    <planView>
{geometries}
    </planView>
{extra}
  </road>
</OpenDRIVE>
"""


def test_line_arc_spiral_analytic():
    geo = """      <geometry s="0" x="0" y="0" hdg="0" length="100"><line/></geometry>
      <geometry s="100" x="100" y="0" hdg="0" length="50"><spiral curvStart="0" curvEnd="0.02"/></geometry>
      <geometry s="150" x="0" y="0" hdg="0" length="80"><arc curvature="0.02"/></geometry>
      <geometry s="230" x="0" y="0" hdg="0" length="40"><arc curvature="-0.0125"/></geometry>"""
    road = parse_opendrive(_doc(geo))
    s = np.array([0.0, 50.0, 99.9, 100.0, 112.5, 125.0, 149.99, 150.0, 200.0, 229.9, 240.0, 269.0])
    expected = np.array([0, 0, 0, 0, 0.005, 0.01, 0.02 * 49.99 / 50, 0.02, 0.02, 0.02, -1 / 80, -1 / 80])
    np.testing.assert_allclose(road.curvature_at(s), expected, atol=1e-12)
    assert road.length_m == pytest.approx(270.0)
    assert road.road_id == "7"


def _param_curvature(du, dv, ddu, ddv):
    return (du * ddv - dv * ddu) / (du * du + dv * dv) ** 1.5


@pytest.mark.parametrize("kind", ["poly3", "paramPoly3_normalized", "paramPoly3_arcLength"])
def test_polynomials_against_quadrature(kind):
    if kind == "poly3":
        a, b, c, d = 0.0, 0.05, 0.004, -2e-5
        cu, cv = (0.0, 1.0, 0.0, 0.0), (a, b, c, d)
        length = 80.0
        # the element ends where the arc length of v(u) reaches 80 m
        arc = lambda u_: quad(lambda u: math.sqrt(1 + (b + 2 * c * u + 3 * d * u * u) ** 2), 0, u_)[0]  # noqa: E731
        p_end = brentq(lambda u_: arc(u_) - length, 1.0, length)
        inner = f'<poly3 a="{a}" b="{b}" c="{c}" d="{d}"/>'
    else:
        cu, cv = (0.0, 60.0, -5.0, 1.0), (0.0, 2.0, 14.0, -3.0)
        p_end = 1.0
        if kind.endswith("arcLength"):
            # the same shape with p in [0, L]: coefficients scaled by 1/L^k
            length = quad(lambda p: math.hypot(cu[1] + 2 * cu[2] * p + 3 * cu[3] * p * p,
                                               cv[1] + 2 * cv[2] * p + 3 * cv[3] * p * p), 0, 1)[0]
            scale = [length ** -k for k in range(4)]
            cu = tuple(x * sc for x, sc in zip(cu, scale))
            cv = tuple(x * sc for x, sc in zip(cv, scale))
            p_end = length
            prange = "arcLength"
        else:
            length = quad(lambda p: math.hypot(cu[1] + 2 * cu[2] * p + 3 * cu[3] * p * p,
                                               cv[1] + 2 * cv[2] * p + 3 * cv[3] * p * p), 0, 1)[0]
            prange = "normalized"
        inner = (f'<paramPoly3 aU="{cu[0]}" bU="{cu[1]}" cU="{cu[2]}" dU="{cu[3]}" aV="{cv[0]}" bV="{cv[1]}" '
                 f'cV="{cv[2]}" dV="{cv[3]}" pRange="{prange}"/>')
    geo = f'      <geometry s="10" x="0" y="0" hdg="0.3" length="{length!r}">{inner}</geometry>'
    road = parse_opendrive(_doc(geo))

    def speed(p):
        return math.hypot(cu[1] + 2 * cu[2] * p + 3 * cu[3] * p * p, cv[1] + 2 * cv[2] * p + 3 * cv[3] * p * p)

    for ds in (0.0, 7.0, 0.25 * length, 0.5 * length, 0.9 * length, length):
        p = 0.0 if ds == 0 else brentq(lambda q: quad(speed, 0, q)[0] - ds, 0.0, p_end * 1.01)
        du = cu[1] + 2 * cu[2] * p + 3 * cu[3] * p * p
        dv = cv[1] + 2 * cv[2] * p + 3 * cv[3] * p * p
        k_ref = _param_curvature(du, dv, 2 * cu[2] + 6 * cu[3] * p, 2 * cv[2] + 6 * cv[3] * p)
        assert road.curvature_at(10.0 + ds)[0] == pytest.approx(k_ref, rel=1e-5, abs=1e-9), ds


def test_elevation_grade():
    elev = """    <elevationProfile>
      <elevation s="0" a="10" b="0.03" c="0" d="0"/>
      <elevation s="50" a="11.5" b="0.03" c="-0.0003" d="1e-6"/>
    </elevationProfile>"""
    road = parse_opendrive(_doc('      <geometry s="0" x="0" y="0" hdg="0" length="100"><line/></geometry>', elev))
    assert road.grade_at(20.0)[0] == pytest.approx(math.atan(0.03))
    d = 30.0
    assert road.grade_at(50.0 + d)[0] == pytest.approx(math.atan(0.03 - 2 * 0.0003 * d + 3e-6 * d * d))
    assert road.elevation_at(50.0 + d)[0] == pytest.approx(11.5 + 0.03 * d - 0.0003 * d * d + 1e-6 * d ** 3)


def test_file_written_by_scenariogeneration(tmp_path):
    """A road written by another tool: our curvature is what was asked of the tool, and the positions we
    integrate from the curvature land on the start poses the tool computed for the next elements."""
    from scenariogeneration import xodr  # the dev extra (pyproject): a missing reference fails, never skips
    geoms = [xodr.Line(120), xodr.Spiral(0.0, 1 / 65, length=30), xodr.Arc(1 / 65, length=70),
             xodr.Spiral(1 / 65, -1 / 200, length=40), xodr.Arc(-1 / 200, length=60), xodr.Line(50)]
    road = xodr.create_road(geoms, id=0, left_lanes=1, right_lanes=1)
    odr = xodr.OpenDrive("from_scenariogeneration")
    odr.add_road(road)
    odr.adjust_roads_and_lanes()
    path = tmp_path / "gen.xodr"
    odr.write_xml(str(path))
    ours = read_opendrive(path)
    assert [g.kind for g in ours.geometries] == ["line", "spiral", "arc", "spiral", "arc", "line"]
    assert ours.length_m == pytest.approx(370.0)
    assert ours.curvature_at(135.0)[0] == pytest.approx(0.5 / 65)
    assert ours.curvature_at(190.0)[0] == pytest.approx(1 / 65)
    assert ours.curvature_at(240.0)[0] == pytest.approx(1 / 65 + (-1 / 200 - 1 / 65) * 0.5)
    assert ours.curvature_at(300.0)[0] == pytest.approx(-1 / 200)
    sampled = ours.sample(0.05)
    for g in ours.geometries[1:]:
        i = int(np.argmin(np.abs(sampled["s_m"] - g.s_m)))
        # the end of the previous element, integrated by us, against the tool's start pose of this one
        prev = [h for h in ours.geometries if h.s_m < g.s_m][-1]
        k = prev.curvature(np.linspace(0, prev.length_m, 4001))
        hdg = prev.hdg_rad + np.concatenate([[0.0], np.cumsum(0.5 * (k[1:] + k[:-1]) * prev.length_m / 4000)])
        hm = 0.5 * (hdg[1:] + hdg[:-1])
        x_end = prev.x_m + np.sum(np.cos(hm)) * prev.length_m / 4000
        y_end = prev.y_m + np.sum(np.sin(hm)) * prev.length_m / 4000
        assert math.hypot(x_end - g.x_m, y_end - g.y_m) < 0.02, (g.s_m, x_end, y_end, g.x_m, g.y_m)
        assert abs(hdg[-1] - g.hdg_rad) < 1e-6
        assert sampled["x_m"][i] == pytest.approx(g.x_m, abs=0.02)  # our sampled line at the boundary


def test_shipped_roads_read_and_close():
    loop = read_opendrive(ROADS / "proving_ground_loop.xodr")
    sm = loop.sample(0.05)
    # closed loop: the integrated end lands on the start, heading turned by 2*pi
    assert math.hypot(sm["x_m"][-1] - sm["x_m"][0], sm["y_m"][-1] - sm["y_m"][0]) < 0.05
    assert sm["heading_rad"][-1] - sm["heading_rad"][0] == pytest.approx(2 * math.pi, abs=1e-6)
    curves = find_curves(sm["s_m"], sm["curvature_per_m"])
    assert [round(c.radius_m, 6) for c in curves] == [10.0, 10.0]
    assert curves[0].start_m == pytest.approx(400.0, abs=0.2)  # clothoid from 400 m (curvature > 1/1000 after 0.15 m)
    assert curves[0].length_m == pytest.approx(15 + (math.pi - 1.5) / 0.1 + 15, abs=0.4)
    r65 = read_opendrive(ROADS / "curve_r65.xodr")
    c = find_curves(*[r65.sample(0.5)[k] for k in ("s_m", "curvature_per_m")])
    assert len(c) == 1 and c[0].radius_m == pytest.approx(65.0) and c[0].direction == 1
    for name in ("curve_r65_clothoids", "curve_r65_grade"):
        road = read_opendrive(ROADS / f"{name}.xodr")
        assert road.length_m == pytest.approx(1000.0)
    assert read_opendrive(ROADS / "curve_r65_grade.xodr").grade_at(300.0)[0] == pytest.approx(math.atan(-0.04))


BAD = [
    ("<OpenDRIVE><road", "not well-formed XML at line 1"),
    ("<?xml version='1.0'?>\n<Other/>", "<Other> at line 2 is not <OpenDRIVE>"),
    ("<OpenDRIVE>\n</OpenDRIVE>", "holds no <road>"),
    (_doc('      <geometry s="0" x="0" y="0" hdg="0"><line/></geometry>'), "<geometry> at line 6 has no attribute 'length'"),
    (_doc('      <geometry s="0" x="0" y="0" hdg="0" length="10"><clothoid/></geometry>'),
     "<clothoid> at line 6 is not a supported geometry"),
    (_doc('      <geometry s="0" x="0" y="0" hdg="0" length="10"><arc curvature="abc"/></geometry>'),
     "<arc> at line 6: curvature='abc' is not a number"),
    (_doc('      <geometry s="0" x="0" y="0" hdg="0" length="10"><arc curvature="inf"/></geometry>'), "must be finite"),
    (_doc('      <geometry s="0" x="0" y="0" hdg="0" length="-1"><line/></geometry>'), "length=-1 must be > 0"),
    (_doc('      <geometry s="0" x="0" y="0" hdg="0" length="10"/>'), "must hold exactly one of"),
    (_doc('      <geometry s="0" x="0" y="0" hdg="0" length="10"><line/></geometry>\n'
          '      <geometry s="50" x="0" y="0" hdg="0" length="10"><line/></geometry>'), "line 7: s=50 does not follow"),
    (_doc('      <geometry s="0" x="0" y="0" hdg="0" length="10"><paramPoly3 aU="0" bU="1" cU="0" dU="0" aV="0" '
          'bV="0" cV="0" dV="0" pRange="degrees"/></geometry>'), "pRange='degrees'"),
    (_doc('      <geometry s="0" x="0" y="0" hdg="0" length="10"><line/></geometry>', length='length="20"'),
     "length=20 but its geometries add up to 10"),
    (_doc(""), "<planView> at line 5 holds no <geometry>"),
]


@pytest.mark.parametrize("text,message", BAD)
def test_malformed_input_names_element_and_line(text, message):
    with pytest.raises(OpenDriveError) as err:
        parse_opendrive(text, "bad.xodr")
    assert message in str(err.value)
    assert "\n" not in str(err.value)
    assert str(err.value).startswith("bad.xodr: ")


def test_unreadable_file_and_road_id(tmp_path):
    with pytest.raises(OpenDriveError, match="cannot read"):
        read_opendrive(tmp_path / "missing.xodr")
    with pytest.raises(OpenDriveError, match="no <road> with id='9'; roads in the file: 1"):
        read_opendrive(ROADS / "curve_r65.xodr", road_id="9")


def test_find_curves_starts_where_the_file_says():
    """The map's curve list from the shipped roads. Reference: the files' geometry. curve_r65.xodr: a line to 400 m,
    a 100 m arc (a curvature step: the sampled table keeps the step, the curve starts at 400 m, not one grid
    step later); proving_ground_loop.xodr: a spiral 0 -> 0.1 1/m over 15 m from 400 m, so |k| passes 1/1000 m at
    400 + 0.15 m, and the hairpin ends 0.15 m before the second spiral's end at 446.416 m."""
    from importlib import resources

    roads = Path(str(resources.files("vehicle_assist") / "data" / "roads"))
    sm = read_opendrive(roads / "curve_r65.xodr").sample(1.0)
    (c,) = find_curves(sm["s_m"], sm["curvature_per_m"])
    assert c.start_m == pytest.approx(400.0, abs=1e-5) and c.length_m == pytest.approx(100.0, abs=1e-5)
    assert c.radius_m == pytest.approx(65.0, rel=1e-6)
    sm = read_opendrive(roads / "proving_ground_loop.xodr").sample(1.0)
    c1 = find_curves(sm["s_m"], sm["curvature_per_m"])[0]
    assert c1.start_m == pytest.approx(400.15, abs=1e-6)
    assert c1.start_m + c1.length_m == pytest.approx(446.415927 - 0.15, abs=1e-5)
    assert c1.radius_m == pytest.approx(10.0)
