"""rear_accel_circle_flag's friction from the measured acceleration must be a LOWER bound of the road friction
(``rear_accel_bound_flag``; review RI2, session i, tire_blowout_findings.md "RI2 (session i)").

The accelerometers read the specific force: every contact and air force over m. Two parts of it are not tire friction
bounded by mu*F_z of a healthy wheel: the air drag and rolling resistance (common.md 3.1, 3.3), and the blown front's
rim drag D = mu_blow*F'_z (tire_blowout.md 4, eqs. 22-25, mu_blow <= mu), which acts on top of that wheel's own tire
force. |a|/g therefore over-reads the friction: in the plant at the two curve points of
test_blowout_rear_circle_cap.py it reached 0.558 / 0.486 for a road peak of 0.489 / 0.423 and the rear cap sat outside
the physical friction circle.

Independent reference: Newton's second law for a car whose four tires all work at the road's friction mu (resultant
mu*m*g) with the blown front dragging D = mu*F'_z (paper's worst case) and the plant's own resistances (air at
rho = 1.2258, C_D*A of the vehicle file; rolling f = 0.012 of the vehicle file); the blown front's load from statics
(m*g*l_r/(2*l) + m*|a_x|*h/(2*l)); the rear cap must then fit the Kamm circle at the TRUE mu on the most load a rear
wheel can have (statics, ``max_rear_load_n``). Each check fails with the flag at 0 (I2's |a|/g)."""
from __future__ import annotations

import math

import numpy as np
import pytest

from tests.functions.test_blowout_rear_circle_cap import R_TOWARD, _params, max_rear_load_n

FL, FR = 0, 1
G = 9.81
RHO = 1.2258  # conventions.RHO_AIR_KGPM3 (common.md 3.1)
FLAG0 = "vehicle.blowout_compensation.rear_accel_bound_flag=0"


def measured_accels(p, mu, a_y, v):
    """(a_x, a_y) an accelerometer reads when all four tires use the road friction mu (resultant mu*m*g, lateral part
    m*a_y), the blown FL drags its rim with mu*F'_z on top (statics load, iterated with a_x) and air/rolling resistance
    act at speed v (the plant's C_D*A and f)."""
    m, l, l_r, h = (p.body_mass_kg, p.chassis_wheelbase_m, p.chassis_wheelbase_m - p.chassis_cg_to_front_axle_m,
                    p.chassis_cg_height_m)
    f_tire_x = math.sqrt((mu * m * G) ** 2 - (m * a_y) ** 2)
    res = 0.5 * RHO * p.body_drag_area_m2 * v * v + p.body_rolling_resistance_coeff * m * G
    a_x = -(f_tire_x + res) / m
    for _ in range(20):
        fz_blown = m * G * l_r / (2.0 * l) + m * abs(a_x) * h / (2.0 * l)
        a_x = -(f_tire_x + mu * fz_blown + res) / m
    return a_x, a_y


def rear_cap_n(p, a_x, a_y, v, mu_meas=0.15):
    """The rear pair's cap [N per wheel] from one braking_rule call (FL blown, FR compensating in HOLD and ABS-active,
    measured friction ``mu_meas``, the driver at 100 bar, a left curve toward FL, reference speed v); -1 = no cap."""
    from vehicle_assist.functions import blowout_compensation as bc

    st = bc.initial_state()
    st[bc.S_BLOWN], st[bc.S_TARGET], st[bc.S_MODE] = FL, FR, bc.HOLD
    st[bc.S_P_REQ] = 5.0e5
    st[bc.S_MU_MEAS] = mu_meas
    st[bc.S_ABS_ACTIVE + FR] = 1.0
    p_est = np.zeros(4)
    p_est[FR] = 5.0e5
    bc.braking_rule(st, FL, FR, bc.HOLD, 1.0, a_x, a_y, 0.0, 100.0e5, p_est, p, R_TOWARD, a_y, v)
    cap = st[bc.S_REAR_CAP]
    return cap * p.brakes_rear_gain_nm_per_pa / p.body_wheel_radius_m if cap >= 0.0 else -1.0


def rule_circle_n(p, a_x, a_y, mu):
    """The select-low rear circle of the rule's own load model (ECU loads at a_x with the flat's transfer, lateral share
    for a_y) at friction ``mu``: the cap the rule would set if it knew the true friction."""
    from vehicle_assist.functions import blowout_compensation as bc

    gl = bc.blown_ecu_loads(FL, a_x, p)
    return min(bc.wheel_circle_limit_mu(2, gl[2], a_y, mu, FL, p), bc.wheel_circle_limit_mu(3, gl[3], a_y, mu, FL, p))


CASES = [(mu, a_y, v) for mu in (0.35, 0.42, 0.49, 0.6) for a_y in (0.5, 2.0) for v in (15.0, 30.0)]


def _violations(p):
    """Cases where the cap exceeds the circle at the road's TRUE friction: (a) on the most load a rear wheel can have
    (statics), (b) the rule's own circle (its loads and lateral shares) evaluated at the true mu."""
    out_a, out_b = [], []
    for mu, a_y, v in CASES:
        a_x, a_y_m = measured_accels(p, mu, a_y, v)
        f_x = rear_cap_n(p, a_x, a_y_m, v)
        assert f_x >= 0.0, (mu, a_y, v)  # the rule acts (curve toward the blown side, front ABS-active)
        f_y = p.body_mass_kg * a_y * p.chassis_cg_to_front_axle_m / p.chassis_wheelbase_m / 2.0
        excess = math.hypot(f_x, f_y) - mu * max_rear_load_n(p, a_x, a_y_m)
        if excess > 1.0:
            out_a.append((mu, a_y, v, round(excess)))
        excess_b = f_x - rule_circle_n(p, a_x, a_y_m, mu)
        if excess_b > 1.0:
            out_b.append((mu, a_y, v, round(excess_b)))
    return out_a, out_b


def test_rear_cap_inside_the_true_friction_circle():
    """Worst case for the bound (every tire at the friction limit, rim drag mu*F'_z, resistances at v): the cap is
    inside the Kamm circle at the road's true friction - on the most-loaded rear wheel (statics) and as the rule's own
    circle at the true mu."""
    assert _violations(_params()) == ([], [])


def test_rear_cap_outside_the_true_circle_with_the_defect():
    """Negative control: rear_accel_bound_flag = 0 (|a|/g, I2's reading) puts the cap above the rule's circle at the
    true friction in every case (measured: 16 of 16) and outside the statics circle in 5 of 16 (30 m/s or a_y 2)."""
    out_a, out_b = _violations(_params(FLAG0))
    assert len(out_b) == len(CASES)
    assert len(out_a) >= 1


def test_bound_still_rises_with_the_stop():
    """The bound is no constant: a harder stop (more tire force) proves more friction, so the cap rises."""
    p = _params()
    low = rear_cap_n(p, *measured_accels(p, 0.3, 1.0, 25.0), 25.0)
    high = rear_cap_n(p, *measured_accels(p, 0.5, 1.0, 25.0), 25.0)
    assert high > low > 0.0



def test_fr_blown_in_a_right_curve_is_the_mirror_of_fl_in_a_left_curve():
    """Gate sign and wheel indices for the RIGHT side: FR blown in a right curve (r_ref < 0, a_y < 0) is the mirror
    image of FL in a left curve, so the rule acts and the select-low cap of RL/RR is the same force (mirror symmetry
    of the car: loads, lateral shares and the flat's diagonal transfer swap sides). Independent of the flags."""
    from tests.functions.test_blowout_rear_circle_cap import rear_cap_n as cap_any

    p = _params()
    for a_x, a_y in ((-2.0, 1.5), (-3.5, 2.5)):
        left = cap_any(p, a_x, a_y, R_TOWARD, blown=FL)
        right = cap_any(p, a_x, -a_y, -R_TOWARD, blown=FR)
        assert left > 0.0
        assert right == pytest.approx(left, rel=1e-9)
