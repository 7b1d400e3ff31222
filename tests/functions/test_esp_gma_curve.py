"""The ESP's yaw-moment build-up delay (GMA) judges yaw as the deviation from the driver's steered reference, so a
curve's own yaw rate does not dump the delayed front (functions/esp.py, ``esp.gma_yaw_reference_flag``; tire_blowout_findings.md
H2/H7, session h).

Reference (independent of the code's numbers):
* the GMA slows the pressure rise of the high-mu front while the other front is in ABS control, so the driver has time
  to counter-steer the yaw moment of the brake-force difference (Bosch Automotive Handbook, ABS yaw-moment build-up
  delay; BS-Wiki, Giermomentenabschwaechung); an ESP judges yaw as the error between the yaw rate the driver asks
  for with the steering and the measured one (van Zanten, SAE 2000-01-1633; GM VSES service description);
* a steady curve of radius R driven at speed u has the yaw rate u/R (kinematics) and needs the steer angle of the
  textbook steady-state cornering relation delta = l/R + K_us * u^2/R, K_us = W_f/C_af - W_r/C_ar over m*g
  (Gillespie, Fundamentals of Vehicle Dynamics, ch. 6: axle loads over AXLE cornering stiffnesses), written here from
  the vehicle file's geometry, mass and per-tire stiffness - not the ECU's reference function;
* the limitation's own thresholds (hold 2, dump 5 deg/s toward the delayed front's side: data/vehicles, esp table).
A 200 m curve at 80 km/h has 6.4 deg/s of yaw - above the dump threshold - all of it asked for by the steering.

SHIPPED OFF (vehicle files: gma_yaw_reference_flag = 0, the code before): enabling it cost never-worse points on the
tire_blowout envelope (tire_blowout_findings.md H7); the rule's tests set the flag to 1 explicitly, and the last test of each pair
shows the code before fails the same check.

Can fail: with the defect (flag 0 = the code before, raw yaw rate) the outer front's ABS starting the GMA on the inner
front in that curve dumps the inner front every period (the H2 mechanism: false-alarm CMA 2026 #25, FL 29.9 -> 15.8 bar
on the curve's own yaw, the car turned out of the curve). Whole run (isolated from H2's gma_rejected_flag, which stops
the GMA from starting there at all): 2.131 m with the defect, inside the lane bound with the rule.
"""
from __future__ import annotations

import math

import pytest

import vehicle_assist as va
from tests.support import esp_ecu, esp_ecu_step
from vehicle_assist.functions import esp
from vehicle_assist.scenarios.runner import pack_records

FLAG = "esp_gma_yaw_reference_flag"
V_MPS = 80.0 / 3.6  # 80 km/h
RADIUS_M = 200.0
P_MC_PA = 60.0e5  # driver's master pressure (brake light on)
DEG = math.pi / 180.0


def _params(scenario: str, flag: int | None = None):
    """The vehicle's parameters; ``flag`` None = the shipped vehicle file's value."""
    flat = dict(va.load_scenario(scenario).vehicle.flat())
    assert FLAG in flat, sorted(k for k in flat if "gma" in k)
    if flag is not None:
        flat[FLAG] = flag
    return pack_records([flat])[0]


def _steady_steer_rad(p, u: float, radius: float) -> float:
    """Textbook steady-state steer angle (Gillespie ch. 6) of the vehicle's nominal data."""
    m, l, l_f = p.body_mass_kg, p.chassis_wheelbase_m, p.chassis_cg_to_front_axle_m
    w_f = m * (l - l_f) / l  # axle load / g [kg]
    w_r = m * l_f / l
    c_f = 2.0 * p.tires_cornering_stiffness_front_n_per_rad  # axle stiffness
    c_r = 2.0 * p.tires_cornering_stiffness_rear_n_per_rad
    k_us = w_f / c_f - w_r / c_r  # rad per (m/s^2)
    return l / radius + k_us * u * u / radius


def _gma_requests(p, left_curve: bool, extra_yaw_radps: float = 0.0, periods: int = 40):
    """Per period the inner front's request: steady curve (yaw u/R, steer for it), the OUTER front in ABS (a hold or
    dump within the ABS window every period), which starts the GMA on the inner front."""
    e = esp_ecu(p, V_MPS, P_MC_PA)
    sgn = 1.0 if left_curve else -1.0
    e["meas"].steering_angle_rad = sgn * _steady_steer_rad(p, V_MPS, RADIUS_M)
    e["meas"].yaw_rate_radps = sgn * (V_MPS / RADIUS_M + extra_yaw_radps)
    inner, outer = (0, 1) if left_curve else (1, 0)
    out = []
    for _ in range(periods):
        e["wheels"][outer, esp.A_SINCE_HD_S] = 0.0
        esp_ecu_step(e, p)
        assert int(e["ctl"][esp.C_GMA_WHEEL]) == inner  # the GMA runs on the inner front (split-mu evidence)
        out.append(int(e["wheels"][inner, esp.A_REQUEST]))
    return out


def test_curve_yaw_is_above_the_dump_threshold():
    """The case is the defect's: the curve's own yaw rate exceeds the limitation's dump threshold."""
    p = _params("blowout_lf_80kph_curve", 1)
    assert V_MPS / RADIUS_M > p.esp_yaw_dump_rate_radps


@pytest.mark.parametrize("scenario", ["blowout_lf_80kph_curve", "hba_split_mu_80kph"])  # SUV, sedan
@pytest.mark.parametrize("left_curve", [True, False])
def test_curve_yaw_does_not_dump_the_gma_wheel(scenario, left_curve):
    """Steady curve, yaw = what the steering asks for: the GMA delays (pulses) the inner front, never dumps it."""
    reqs = _gma_requests(_params(scenario, 1), left_curve)
    assert esp.R_DUMP not in reqs, reqs
    assert esp.R_GMA_PULSE in reqs, reqs  # the delay itself still acts


@pytest.mark.parametrize("left_curve", [True, False])
def test_yaw_beyond_the_reference_still_dumps(left_curve):
    """The limitation stays: 6 deg/s toward the delayed front's side beyond the steered reference dumps it."""
    reqs = _gma_requests(_params("blowout_lf_80kph_curve", 1), left_curve, extra_yaw_radps=6.0 * DEG)
    assert all(r == esp.R_DUMP for r in reqs), reqs


@pytest.mark.parametrize("left_curve", [True, False])
def test_seeded_defect_dumps_on_the_curve_yaw(left_curve):
    """flag 0 (the code before: raw yaw rate): the curve's yaw dumps the inner front every period."""
    reqs = _gma_requests(_params("blowout_lf_80kph_curve", 0), left_curve)
    assert all(r == esp.R_DUMP for r in reqs), reqs


# Whole run: false-alarm CMA-ES 2026 #25 (H2's point, tests/verification/test_blowout_false_alarm_envelope.py), with
# gma_rejected_flag 0 so the GMA does start on FL after the rejection (H2's mechanism) and only this rule acts.
# Bound: the lane (JTG B01-2014 3.75 m lane, BJ2500 width), as that file; the car without the function: 0.346 m.
@pytest.fixture(scope="module")
def cma25_runs():
    from tests.verification.test_blowout_false_alarm_envelope import CMA25, DEV, GMA_REJECTED_OFF, LANE_BOUND_M
    from vehicle_assist.verification.envelope import load_envelope
    env = load_envelope("tire_blowout_false_alarm")

    def dev(*sets):
        return va.simulate(env.scenario(CMA25).with_sets(GMA_REJECTED_OFF, *sets), requirements=False).metrics[DEV]
    return {"rule": dev("vehicle.esp.gma_yaw_reference_flag=1"), "defect": dev("vehicle.esp.gma_yaw_reference_flag=0", "vehicle.blowout_compensation.reject_heading_return_flag=0"),  # (J5: isolated)
            "bound": LANE_BOUND_M}


def test_cma25_gma_on_the_curve_yaw_stays_in_lane(cma25_runs):
    """The GMA started on FL by the re-applied FR no longer dumps FL on the curve's own yaw: in the lane (0.638 m)."""
    assert cma25_runs["rule"] <= cma25_runs["bound"], cma25_runs


def test_cma25_seeded_defect_leaves_the_lane(cma25_runs):
    """flag 0 (raw yaw rate): FL dumped 29.9 -> 15.8 bar against FR's 45.7 bar, out of the lane (2.131 m)."""
    assert cma25_runs["defect"] > cma25_runs["bound"], cma25_runs
