"""Curve-shift envelope and requirements (data/envelopes/curve_shift.toml, data/requirements/curve_shift.toml).

The falsifier found (issue #11) that the upshift inhibit held 2nd gear to 4008 rpm on a 6 deg downhill curve exit
with a 1 s late preview (94.7 km/h, R = 30 m), where the normal schedule stayed below 3430 rpm; the engine-protection
release (upshift_release_speed_rpm) fixes it. Reference: n_max_dn = 4000 rpm (curve_shift.md 5.2) and the no-assist
twin of the same point. The defect is restored by setting the release above the cut-off: the requirement must fail.
"""
from __future__ import annotations

import vehicle_assist as va
from vehicle_assist.verification.envelope import load_envelope

POINT = dict(entry_speed=94.69, sight_distance=176.7, preview_radius_noise=2.549, preview_latency=0.9552,
             driver_style=0.9161, grade=-5.86, radius="r30", preview="ok")


def _rob(sc, rid):
    return {r.id: r.robustness for r in va.simulate(sc).requirements}[rid]


def test_envelope_loads_and_base_meets_requirements():
    env = load_envelope("curve_shift")
    assert env.layout == "amt_car"
    base = va.simulate(va.load_scenario("curve_envelope_base"))
    assert base.ok and all(r.robustness >= 0 for r in base.requirements)


def test_falsifier_finding_is_fixed_and_the_defect_fails():
    env = load_envelope("curve_shift")
    sc = env.scenario(POINT)
    assert _rob(sc, "curve_shift.no_overspeed") > 0
    twin = va.simulate(env.scenario(POINT, baseline=True)).trace
    assert twin["engine_speed_radps"].max() < 418.879  # the normal schedule alone is safe here
    defect = sc.with_sets("vehicle.curve_shift.upshift_release_speed_rpm=9000")
    assert _rob(defect, "curve_shift.no_overspeed") < 0
