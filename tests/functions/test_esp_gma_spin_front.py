"""The ESP's yaw-moment build-up delay (GMA) never delays the blowout compensation's spin-front wheel
(functions/esp.py, session e R: "the GMA no longer delays the spin-front wheel", limit code 5).

Reference (independent of the code's numbers): the GMA is a split-mu measure - it slows the pressure rise of the
high-mu front wheel while the other front is in ABS control (Bosch Automotive Handbook, ABS yaw-moment build-up
delay; functions/esp.py module doc step 3). The spin-front wheel is the car's yaw-stability brake (ESP oversteer
practice, tire_blowout.md), not the high-mu side of a split-mu stop: it must get neither a GMA pulse nor a GMA hold,
in whichever period and whatever the other front's ABS does.

Can fail: before this fix the GMA was ended on the spin-front wheel and re-armed on it in the same period whenever the
other front's ABS had been active in the last 0.3 s, with its start reset to now every period - the wheel got the
GMA_PULSE request (5) in every period of the spin. The control case (no spin-front rule, same ABS activity) shows
the GMA itself still arms on the other front.
"""
from __future__ import annotations

import pytest

import vehicle_assist as va
from tests.support import esp_ecu, esp_ecu_step
from vehicle_assist.functions import blowout_compensation as bc
from vehicle_assist.functions import esp
from vehicle_assist.scenarios.runner import pack_records

V_MPS = 25.0  # car speed (90 km/h), all four wheels rolling free
P_MC_PA = 30.0e5  # driver's master pressure (a light stop)


@pytest.fixture(scope="module")
def params():
    return pack_records([va.load_scenario("hba_paper_110kph_dry").vehicle.flat()])[0]


def _ecu(p):
    return esp_ecu(p, V_MPS, P_MC_PA)


_step = esp_ecu_step


def _requests_of_fr(p, spin_front: bool, periods: int = 10):
    """FR's ESP request and the GMA wheel per period, FL's ABS active (hold/dump within the 0.3 s window) throughout;
    the blowout compensation LIMITED on FR with (or without) the spin-front limit code, its state kept as set (a
    check of the ESP's GMA logic alone)."""
    e = _ecu(p)
    bst = e["bst"]
    bst[bc.S_MODE] = bc.LIMITED
    bst[bc.S_TARGET] = 1.0
    bst[bc.S_LIMIT_CODE] = bc.LIMIT_SPIN_FRONT if spin_front else bc.LIMIT_YAW_BOUND
    e["ctl"][esp.C_GMA_WHEEL] = 1.0  # armed on FR before the spin-front rule took it (R's case)
    e["ctl"][esp.C_GMA_START] = e["t"] - 0.05
    kept = bst.copy()
    out = []
    for _ in range(periods):
        e["wheels"][0, esp.A_SINCE_HD_S] = 0.0  # FL in ABS control
        _step(e, p)
        out.append((int(e["wheels"][1, esp.A_REQUEST]), int(e["ctl"][esp.C_GMA_WHEEL])))
        bst[:] = kept
    return out


def test_spin_front_wheel_gets_no_gma_request(params):
    rows = _requests_of_fr(params, spin_front=True)
    assert all(req not in (esp.R_GMA_HOLD, esp.R_GMA_PULSE) for req, _ in rows), rows
    assert all(g != 1 for _, g in rows), rows


def test_gma_still_arms_without_the_spin_front_rule(params):
    """Control: without limit code 5 the compensation's target is blocked from starting a GMA (C_GMA_BLOCK) but the
    ESP's split-mu GMA logic is unchanged - the same state leaves FR under the GMA."""
    rows = _requests_of_fr(params, spin_front=False)
    assert any(g == 1 for _, g in rows), rows
