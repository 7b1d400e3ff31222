"""Low-speed tire kinematics and the standstill hold of the two-track car (issue #10, the stop freeze).

The car used to be held as soon as its LONGITUDINAL speed u fell below 0.05 m/s, even while it still slid
sideways (and the slip angle was taken as 0 for u ~ 0): a spinning car after a blowout stopped dead. Now the slip
angle is tan(alpha) = -v_lat/max(|v_long|, v_eps) (SAE J670 / ISO 8855 with a bounded denominator) and the car is
held only once the planar speed and the yaw rate are both small.

Independent references: Coulomb sliding of a rigid body - a car sliding purely sideways on four unbraked wheels
decelerates at mu_slide*g (the tire force is mu*F_z along the slip velocity, the F_z sum is m*g, the yaw moments
cancel because l_f*F_zf = l_r*F_zr); with the Burckhardt dry set the fully sliding value is
mu(1) = c1*(1 - exp(-c2)) - c3 = 0.760 (brake_assist.md 4.4), with the Dugoff tire the peak mu (0.8 for the
SUV files' road scale 0.684 x 1.17, tire_blowout.md 9); v^2 = v0^2 - 2*mu*g*x for the sliding distance;
kinetic energy 1/2 m (u^2 + v^2) + 1/2 I_z r^2 + sum 1/2 J omega^2 can only fall without drive torque (the tire
forces oppose the slip velocities; the sedan's m 1600 kg, I_z 2600 kg m^2, J 1.0 kg m^2 from sedan_1p8t.toml).
"""
from __future__ import annotations

import math

import numpy as np
import pytest

import vehicle_assist as va
from vehicle_assist.plant.chassis.two_track import at_rest, wheel_kinematics

G = 9.81
MU_LOCKED_DRY = 1.2801 * (1.0 - math.exp(-23.99)) - 0.52  # 0.760, Burckhardt dry at s_res = 1


def _slide(scenario: str, v0: float, extra: tuple[str, ...] = ()):
    sets = ["run.initial_speed_kph=0", f"run.initial_lateral_speed_mps={v0}", "run.duration_s=3.0",
            "driver.brake_pedal.frac=[0.0, 0.0, 0.0" + (", 0.0, 0.0]" if scenario.startswith("hba") else "]"), *extra]
    return va.simulate(va.load_scenario(scenario, sets), requirements=False).trace


def test_slip_angle_is_finite_and_opposes_sideways_sliding_at_zero_u() -> None:
    """u = 0, sliding left at 3 m/s: tan(alpha) = -3/v_eps < 0 (force to the right); above v_eps the exact angle."""
    _, ta = wheel_kinematics(0.0, 3.0, 0.0, 0.0, 1.0, 0.8)
    assert ta == pytest.approx(-3.0)
    _, ta = wheel_kinematics(20.0, 1.0, 0.0, 0.0, 1.0, 0.8)
    assert ta == pytest.approx(-1.0 / 20.0)
    _, ta = wheel_kinematics(-2.0, 1.0, 0.0, 0.0, 1.0, 0.8)  # rolling backward: |v_long| (SAE J670)
    assert ta == pytest.approx(-0.5)


def test_at_rest_needs_planar_speed_and_yaw_rate_small() -> None:
    assert at_rest(0.04, 0.0, 0.0, 1.9)
    assert not at_rest(0.0, 2.0, 0.0, 1.9)  # u = 0 but sliding sideways: the old rule held it here
    assert not at_rest(0.0, 0.0, 0.5, 1.9)  # spinning on the spot
    assert not at_rest(0.04, 0.04, 0.0, 1.9)


@pytest.mark.parametrize("scenario,mu", [("hba_off_110kph_dry", MU_LOCKED_DRY), ("blowout_braking_60kph", 0.684 * 1.1697)])
def test_sideways_slide_decelerates_at_mu_g_until_it_stops(scenario: str, mu: float) -> None:
    """A car sliding sideways at 5 m/s with u = 0 (no brakes, no steering, no blowout) keeps sliding and
    decelerates at mu*g while fully sliding (|v| > 1.2 m/s: tan(alpha) > 1), then comes to rest and is held."""
    extra = ("vehicle.blowout.wheel_index=-1", "vehicle.blowout_compensation.enabled_flag=0") if scenario.startswith("blowout") else ()
    tr = _slide(scenario, 5.0, extra)
    t = np.asarray(tr["time_s"])
    v = np.asarray(tr["lateral_speed_mps"])
    a_y = np.asarray(tr["lateral_accel_mps2"])
    sliding = (v > 1.2) & (np.asarray(tr["vehicle_held_flag"]) == 0)
    assert sliding.sum() > 50  # the old hold froze the car at the first step (v = 0 from 1 ms on)
    assert np.median(-a_y[sliding]) == pytest.approx(mu * G, rel=0.02)
    if scenario.startswith("hba"):  # Burckhardt: force proportional to F_z, the moments cancel (Dugoff: only nearly,
        assert np.abs(np.asarray(tr["yaw_rate_radps"])).max() < 1e-3  # its H < 1 branch is not linear in F_z)
    assert np.abs(np.asarray(tr["speed_mps"])).max() < 0.05
    # sliding distance to 1.2 m/s from v^2 = v0^2 - 2 mu g y (Coulomb): the car moves sideways, not frozen
    k = np.argmax(v <= 1.2)
    assert float(tr["y_m"][k]) == pytest.approx((25.0 - 1.2 ** 2) / (2 * mu * G), rel=0.03)
    held = np.asarray(tr["vehicle_held_flag"]) > 0
    assert held.any() and t[np.argmax(held)] < 5.0 / (mu * G) + 0.3  # at rest soon after the Coulomb stop time


def test_no_energy_is_created_while_sliding_to_rest() -> None:
    """Kinetic energy (body + yaw + wheels) never rises along the slide (no drive torque anywhere)."""
    tr = _slide("hba_off_110kph_dry", 4.0)
    e = 0.5 * 1600.0 * (np.asarray(tr["speed_mps"]) ** 2 + np.asarray(tr["lateral_speed_mps"]) ** 2) \
        + 0.5 * 2600.0 * np.asarray(tr["yaw_rate_radps"]) ** 2 \
        + sum(0.5 * 1.0 * np.asarray(tr[f"wheel_speed_{w}_radps"]) ** 2 for w in ("fl", "fr", "rl", "rr"))
    assert e[0] == pytest.approx(0.5 * 1600.0 * 16.0)
    assert np.all(np.diff(e) <= 1e-9 * e[0])
    assert e[-1] == 0.0


def test_straight_stop_still_ends_held_at_u_small() -> None:
    """A straight braked stop (v = r = 0 throughout) is held exactly as before: at the first step with u <= 0.05."""
    tr = va.simulate(va.load_scenario("hba_paper_110kph_dry"), requirements=False).trace
    held = np.asarray(tr["vehicle_held_flag"]) > 0
    k = np.argmax(held)
    assert held.any() and np.all(np.asarray(tr["lateral_speed_mps"]) == 0.0)
    assert 0.0 <= float(tr["speed_mps"][k - 1]) < 1.0  # the last moving row: slow, forward
