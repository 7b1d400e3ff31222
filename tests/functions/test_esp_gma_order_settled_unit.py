"""``esp.gma_pressure_order_flag`` value 3 (N6's candidate) on the ESP controller alone (review O1, session o;
tire_blowout_findings.md "O1").

N6's scenario tests (tests/verification/test_blowout_n6_gma_order_settled.py) judge value 3 at two envelope points. At
rb5 #72 the ABS front leaves ABS straight into the driver's circuit (wheel mode N, its estimate IS the driver's
pressure), so the rule's band "estimate within RAMP_SETTLED_PA of p_mc" never binds there, and #114 never sees the ABS
front OFF while the GMA runs: a rule without the band, or one reading the wrong wheel's ABS mode, passed those tests
(review O1 mutants). These rows pin the rule's premise on the controller, one ESP period at a time, with the GMA set on
the front opposite a TPMS-named rear and the other front's ABS mode and estimate placed by hand:

* the other front OFF at the driver's pressure  -> the GMA's delayed front re-builds (R_BUILD) at 3; at 2 / 0 the GMA
  keeps pulsing it (the test fails at 2 and at 0);
* the other front OFF but > 1 bar below the driver's (not yet carrying the driver's pressure) -> GMA as before;
* the other front still in ABS (its re-build, ABS mode BUILD) at the driver's estimate -> GMA as before (the estimate
  runs ahead of a pulsed re-build, N6 rb13 #114);
* no named / blown wheel (the ESP of the car without the function) -> GMA as before;
* mirror symmetry: RR named with FL delayed and RL named with FR delayed give the same requests.
Independent reference: the GMA's premise (Bosch Automotive Handbook, ABS yaw-moment build-up delay: the high-mu front's
pressure build is delayed while the other front is held at its lower lock level) - a front that carries the full
driver's pressure with its ABS off is no low-mu side - and the mirror symmetry of the car.
"""
from __future__ import annotations

import pytest

from tests.support import esp_ecu, esp_ecu_step
from vehicle_assist.functions import abs as abs_fn
from vehicle_assist.functions import esp
from vehicle_assist.scenarios.runner import pack_records
from vehicle_assist.verification.envelope import load_envelope

# /tmp/lead/n/fin/rb5/falsify.json history #72 (only its vehicle, the SUV of the tire_blowout envelope, is used)
P72 = {"speed": 99.99149704319854, "mu": 0.5217520232282564, "delay": 0.4579899484382917,
       "wheel_speed_noise": 0.021128866277189573, "noise_seed": 9839.0, "brake_gain": 0.9467768763559855,
       "brake.start_s": 1.0916721241139895, "brake.level_frac": 0.07708486873809187,
       "brake.rate_per_s": 2.080834345018032, "braking": "brakes", "wheel": "rr", "driver": "follow", "curve": "r650"}
P_MC_PA = 46.0e5  # driver's pressure (rb5 #72's)
P_HELD_PA = 22.0e5  # the GMA-held front (rb5 #72: 20-23 bar)
V_MPS = 100.0 / 3.6


@pytest.fixture(scope="module")
def params():
    env = load_envelope("tire_blowout")
    out = {}
    for v in (0, 2, 3):
        sc = env.scenario(P72).with_sets(f"vehicle.esp.gma_pressure_order_flag={v}")
        out[v] = pack_records([dict(sc.vehicle.flat())])[0]
    return out


def _request(p, p_other_pa, mode_other=abs_fn.OFF, named=4):
    """The GMA's delayed front's request after one ESP period: TPMS names wheel ``named`` (1..4, 0 none), the GMA is
    on the front opposite it (FL for RR, FR for RL), 0.2 s old, that front held below the other front, whose ABS mode
    and pressure estimate are placed by hand."""
    e = esp_ecu(p, V_MPS, P_MC_PA)
    e["meas"].tpms_alarm_wheel_index = float(named)
    e["meas"].tpms_alarm_wheel_ok = 1.0
    esp_ecu_step(e, p)
    g = 0 if named in (0, 4) else 1
    w, c = e["wheels"], e["ctl"]
    c[esp.C_GMA_WHEEL] = float(g)
    c[esp.C_GMA_START] = e["t"] - 0.2
    w[g, esp.A_MODE] = abs_fn.OFF
    w[g, esp.A_P_EST] = P_HELD_PA
    w[1 - g, esp.A_MODE] = mode_other
    w[1 - g, esp.A_P_EST] = p_other_pa
    esp_ecu_step(e, p)
    assert int(c[esp.C_GMA_WHEEL]) == g  # the GMA is still on the delayed front
    return int(w[g, esp.A_REQUEST])


@pytest.mark.parametrize("named", [4, 3])
def test_other_front_off_at_driver_pressure_rebuilds_at_3(params, named):
    """Value 3: the other front OFF at the driver's pressure -> the delayed front re-builds (R_BUILD); both mirrors."""
    assert _request(params[3], P_MC_PA, named=named) == esp.R_BUILD


@pytest.mark.parametrize("flag", [2, 0])
@pytest.mark.parametrize("named", [4, 3])
def test_negative_control_gma_keeps_pulsing_at_2_and_0(params, flag, named):
    """Negative control: the same state at 2 / 0 keeps the GMA's pulse/hold (the code before)."""
    assert _request(params[flag], P_MC_PA, named=named) in (esp.R_GMA_PULSE, esp.R_GMA_HOLD)


@pytest.mark.parametrize("named", [4, 3])
def test_other_front_off_below_driver_pressure_keeps_gma(params, named):
    """The band: OFF but 6 bar below the driver's pressure (> RAMP_SETTLED_PA) -> GMA as before (a rule without the
    band, review O1 mutant m1, re-builds here)."""
    assert P_MC_PA - 40.0e5 > esp.RAMP_SETTLED_PA
    assert _request(params[3], 40.0e5, named=named) in (esp.R_GMA_PULSE, esp.R_GMA_HOLD)


@pytest.mark.parametrize("named", [4, 3])
def test_other_front_still_in_abs_keeps_gma(params, named):
    """The ABS-OFF condition: the other front in its ABS re-build with its estimate at the driver's -> GMA as before
    (a rule taking any mode but HOLD/DUMP, mutant m2, or no mode condition, m4, re-builds here)."""
    assert _request(params[3], P_MC_PA, mode_other=abs_fn.BUILD, named=named) in (esp.R_GMA_PULSE, esp.R_GMA_HOLD)


def test_no_named_wheel_keeps_gma(params):
    """The ESP without the function (no named / blown wheel): value 3 does nothing."""
    assert _request(params[3], P_MC_PA, named=0) in (esp.R_GMA_PULSE, esp.R_GMA_HOLD)
