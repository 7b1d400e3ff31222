"""Blowout formulas (plant/tires/blowout.py, functions/blowout_compensation.py) against the worked example of
tire_blowout.md section 7 (the spec's own numbers, derived independently there), closed forms and symmetry."""
from __future__ import annotations

import math

import numpy as np
import pytest

from vehicle_assist.functions import blowout_compensation as bc
from vehicle_assist.plant.tires import blowout as bo
from vehicle_assist.plant.tires.dugoff import dugoff_forces

# tire_blowout.md 7 (BJ2500 set)
M, G, L, LF = 1700.0, 9.81, 2.576, 1.159
LR = L - LF
BF = BR = 1.473 / 2
R_OUT, R_IN = 0.359, 0.24
KSF, KSR = 28e3, 32e3
MU, CX = 0.8, 60e3
STATIC = (M * G * LR / L / 2, M * G * LR / L / 2, M * G * LF / L / 2, M * G * LF / L / 2)
KB = 3.421e-3 * 0.11 * 0.38 * 0.95 * 2  # eq. 26 gain A_p*r_b*mu_b*eta_b*n_f


def loads(blown):
    f = bo.transfer_n(blown, *STATIC, R_OUT - R_IN, KSF, KSR)
    return f, bo.redistributed_loads(blown, *STATIC, f)


def rel(a, b):
    return abs(a - b) / abs(b)


def test_worked_example_loads_to_1pct():
    """Reference: spec 7 (static 4586/3752 N, f = 889 N, F' = 3698/5475/4641/2864 N)."""
    assert rel(STATIC[0], 4586) < 0.01 and rel(STATIC[2], 3752) < 0.01
    f, new = loads(0)
    assert rel(f, 889) < 0.01
    for got, want in zip(new, (3698, 5475, 4641, 2864)):
        assert rel(got, want) < 0.01
    assert abs(sum(new) - sum(STATIC)) < 1e-9 * sum(STATIC)  # criterion 1: load conservation
    # closed form for straight driving (spec 3)
    assert f == pytest.approx((R_OUT - R_IN) * KSF * KSR / (2 * (KSF + KSR)), rel=1e-12)


def test_general_form_with_unequal_loads_matches_spec_formula():
    """Reference: spec 3 general f for LF with F_zfl != F_zfr (the written-out formula)."""
    fz = (4200.0, 4900.0, 3900.0, 3600.0)
    want = ((R_OUT - R_IN) + (fz[0] - fz[1]) / KSF + (fz[3] - fz[2]) / KSR) / (2 * (1 / KSF + 1 / KSR))
    assert bo.transfer_n(0, *fz, R_OUT - R_IN, KSF, KSR) == pytest.approx(want, rel=1e-12)


def test_no_blowout_zero_transfer_and_moment():
    """Criterion 1: f = 0 when R_in = R_out; no blown wheel -> no moment."""
    assert bo.transfer_n(0, *STATIC, 0.0, KSF, KSR) == 0.0
    assert bc.added_yaw_moment_nm(-1, *STATIC, 0.0, MU, MU, CX, CX, BF, BR) == 0.0


@pytest.mark.parametrize("s,want", [(0.0, 2179), (0.01, 1732), (0.02, 1281), (0.05, 621)])
def test_worked_example_yaw_moment_to_1pct(s, want):
    """Reference: spec 7 M_z_blow at s = 0, 0.01 (H >= 1), 0.02 (mixed), 0.05 (H < 1)."""
    _, new = loads(0)
    got = bc.added_yaw_moment_nm(0, *new, s, MU, MU, CX, CX, BF, BR)
    assert rel(got, want) < 0.01


@pytest.mark.parametrize("s", [0.0, 0.01, 0.02, 0.05, 0.15])
def test_left_right_equal_and_opposite(s):
    """Criterion 3: mirror symmetry, LF vs RF and LR vs RR."""
    for left, right in ((0, 1), (2, 3)):
        ml = bc.added_yaw_moment_nm(left, *loads(left)[1], s, MU, MU, CX, CX, BF, BR)
        mr = bc.added_yaw_moment_nm(right, *loads(right)[1], s, MU, MU, CX, CX, BF, BR)
        assert ml > 0 and mr == pytest.approx(-ml, rel=1e-12)


def test_rear_blowout_transfers_on_its_diagonal():
    """Spec 3: RR blown -> RR and FL lose f, FR and RL gain it."""
    f, new = loads(3)
    assert f > 0
    assert new[3] == pytest.approx(STATIC[3] - f) and new[0] == pytest.approx(STATIC[0] - f)
    assert new[1] == pytest.approx(STATIC[1] + f) and new[2] == pytest.approx(STATIC[2] + f)


def test_pressure_and_valve_time_worked_example():
    """Reference: spec 7 (1732 N*m -> M_b 844 N*m, p_w 3.11 MPa, 0.041 s; n_f = 1: 6.21 MPa, 0.081 s)."""
    p = bc.required_pressure_pa(1732.0, R_OUT, BF, KB)
    assert rel(p * KB, 844) < 0.01 and rel(p, 3.11e6) < 0.01
    t, sat = bc.valve_time_s(p, 12e6, 0.015, 0.060, 0.200)
    assert rel(t, 0.041) < 0.01 and not sat
    p1 = bc.required_pressure_pa(1732.0, R_OUT, BF, KB / 2)
    assert rel(p1, 6.21e6) < 0.01
    assert rel(bc.valve_time_s(p1, 12e6, 0.015, 0.060, 0.200)[0], 0.081) < 0.015


def test_valve_map_round_trip_and_saturation():
    """Criterion 4: t(p1) = t1, t(p2) = t2, p(t(p)) = p, strictly increasing; S6 saturation (p_max 4 MPa)."""
    pm, t0, t1, t2 = 12e6, 0.015, 0.06, 0.2
    assert bc.valve_time_s(0.45 * pm, pm, t0, t1, t2)[0] == pytest.approx(t1)
    assert bc.valve_time_s(0.9 * pm, pm, t0, t1, t2)[0] == pytest.approx(t2)
    ps = np.linspace(1e3, 0.9 * pm, 200)
    ts = [bc.valve_time_s(q, pm, t0, t1, t2)[0] for q in ps]
    assert np.all(np.diff(ts) > 0)
    for q, t in zip(ps, ts):
        assert bc.valve_pressure_pa(t, pm, t0, t1, t2) == pytest.approx(q, rel=1e-9)
    p_s0 = bc.required_pressure_pa(2179.0, R_OUT, BF, KB)  # s = 0 moment of spec 7: 3.91 MPa > 0.9*4 MPa
    t, sat = bc.valve_time_s(p_s0, 4e6, t0, t1, t2)
    assert sat and t == t2


def test_dugoff_branches_and_limits():
    """Criterion 2: continuity across H = 1, F_x(s -> 1) = mu*F_z, linear branch, |F_x| <= mu*F_z; the
    closed forms of the estimator equal the tire model at alpha = 0."""
    fz = 4000.0
    ss = np.linspace(1e-4, 0.999, 3000)
    fx = np.array([dugoff_forces(s, 0.0, fz, MU, CX, 50e3)[0] for s in ss])
    assert np.all(fx <= MU * fz + 1e-6)
    assert np.max(np.abs(np.diff(fx))) < 30.0  # no jump at H = 1 (step ~3e-4 in s)
    assert dugoff_forces(1.0, 0.0, fz, MU, CX, 50e3)[0] == pytest.approx(MU * fz)
    assert dugoff_forces(0.999999, 0.0, fz, MU, CX, 50e3)[0] == pytest.approx(MU * fz, rel=1e-3)
    assert dugoff_forces(0.01, 0.0, fz, MU, CX, 50e3)[0] == pytest.approx(CX * 0.01 / 0.99)
    for s in (0.005, 0.02, 0.04, 0.2):
        assert bc.intact_braking_force_n(s, fz, MU, CX) == pytest.approx(dugoff_forces(s, 0.0, fz, MU, CX, 50e3)[0])


def test_dugoff_friction_reduction_with_slip_speed():
    """Spec 2.3: eps_r = 0 is plain Dugoff; eps_r > 0 lowers the sliding force by (1 - eps_r*u*s)."""
    assert bo.dugoff_full(1.0, 0.0, 4000, MU, CX, 50e3, 0.0, 20.0)[0] == pytest.approx(MU * 4000)
    assert bo.dugoff_full(1.0, 0.0, 4000, MU, CX, 50e3, 0.01, 20.0)[0] == pytest.approx(MU * 4000 * 0.8)


def test_deflation_ramp():
    """Spec 3 eq. 21: R goes linearly R_out -> R_in over t_blow."""
    assert bo.deflation_frac(0.99, 1.0, 0.1) == 0.0
    assert bo.deflation_frac(1.05, 1.0, 0.1) == pytest.approx(0.5)
    assert bo.deflation_frac(2.0, 1.0, 0.1) == 1.0
    assert bo.blown_radius_m(0.5, R_OUT, R_IN) == pytest.approx(0.5 * (R_OUT + R_IN))


def test_blowout_at_a_position():
    """Issue #10: the event can be placed by position: at 60 km/h (16.67 m/s, coasting slows the car by well under
    1 %) a blowout at 30 m starts at t = 30/16.67 = 1.8 s (one 0.5 ms step and the slight coast-down allowed)."""
    import numpy as np

    import vehicle_assist as va

    r = va.simulate(va.load_scenario("blowout_lf_60kph_off", sets=["vehicle.blowout.position_m=30"]))
    t = np.asarray(r.trace["time_s"])
    phi = np.asarray(r.trace["blowout_frac"])
    t_b = t[np.flatnonzero(phi > 0.0)[0]]
    assert 30.0 / (60 / 3.6) <= t_b <= 30.0 / (60 / 3.6) * 1.01 + 0.01
    assert np.all(np.asarray(r.trace["blowout_wheel_index"])[phi > 0.0] == 0)
