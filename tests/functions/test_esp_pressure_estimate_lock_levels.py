"""The ESP's lock levels - the wheel pressure at which ABS began a dump - read on ONE estimate, the line-lag one, and
I12's front lock levels forgotten once ABS is quiet on the wheel (session j, J2; review RI4, session i).

* ``esp.lock_level_line_flag`` (1 shipped, 0 = the code before): braking_lock_floor's level (and the wheel compared with
  its floor) and gma_rejected_split_flag's front levels (functions/esp.py C_LOCK_P0/1) read A_P_LINE, not A_P_EST.
  Reference: the plant's wheel cylinder in mode N follows the source through the line lag tau_line (plant/brakes/
  esp_unit.py row N, integrated here at the plant step): one ESP period after a 20 -> 167.8 bar source step the wheel
  holds ~62 bar, so a dump that starts then locks the wheel at ~62 bar, not at the 167.8-bar source A_P_EST jumps to.
  Bound: 5 bar, the master-pressure sensor accuracy class assumed by tests/functions/test_esp_pressure_estimate.py.
* ``blowout_compensation.gma_rejected_split_quiet_flag`` (1 shipped, 0 = the code before): a front's level is forgotten
  once ABS is quiet on it for 0.3 s (no hold or dump: not ABS-active, brake_assist.md 4.3 - the window braking_lock_floor
  uses). Reference: the GMA (yaw-moment build-up delay) acts on split-mu, started by ABS activity on ONE front (Bosch
  Automotive Handbook, ABS yaw-moment build-up delay); with both fronts in ABS control the road is no split-mu road and
  the ESP without the blowout function starts no GMA. The case: FR (the rejected front) locked on the snow side of a
  split stretch (15 bar) while FL was held by ABS without a dump (no level yet); then the road is even (dry): FR runs
  below its limit (quiet 0.4 s), FL's first dump marks 50 bar, and both fronts are in ABS together, FR first with a
  hold (its level not renewed). The stale 15-bar level reads 'FR low-mu side', its activity counts while FL's stays
  masked: one-sided activity, a GMA on FL. The GMA, once started, runs for the rest of the stop.
"""
from __future__ import annotations

import numpy as np
import pytest

import vehicle_assist as va
from tests.functions.test_esp_pressure_estimate import ERROR_BOUND_PA, plant_fill
from tests.support import esp_ecu, esp_ecu_step
from vehicle_assist.functions import abs as abs_fn
from vehicle_assist.functions import blowout_compensation as bc
from vehicle_assist.functions import esp
from vehicle_assist.scenarios.runner import pack_records

BAR = 1.0e5
LINE = "vehicle.esp.lock_level_line_flag"
QUIET = "vehicle.blowout_compensation.gma_rejected_split_quiet_flag"


def _params(*sets):
    return pack_records([va.load_scenario("blowout_panic_stop_80kph", list(sets)).vehicle.flat()])[0]


def _dump_after_source_step(*sets):
    """The ESP controller alone (HBA off): driver at 20 bar, then 167.8 bar (I1's panic source) for one ESP period with
    the wheels in N; FR, made the blowout compensation's wheel (FL blown, BUILD), slows to 70 % of the car's speed and
    ABS dumps it. Returns (ECU state, params, FR's A_P_EST and A_P_LINE of the period before the dump)."""
    p = _params("vehicle.brake_assist.enabled_flag=0", *sets)
    e = esp_ecu(p, 20.0, 20.0 * BAR, 20)
    e["meas"].master_pressure_pa = 167.8 * BAR
    esp_ecu_step(e, p)
    assert int(e["wheels"][1, esp.A_WHEEL_MODE]) == esp.W_N  # premise: the wheel is on the driver's pressure
    before = (float(e["wheels"][1, esp.A_P_EST]), float(e["wheels"][1, esp.A_P_LINE]))
    e["bst"][bc.S_MODE], e["bst"][bc.S_TARGET], e["bst"][bc.S_BLOWN] = bc.BUILD, 1.0, 0.0
    e["meas"].wheel_speed_fr_radps = 14.0 / p.body_wheel_radius_m
    esp_ecu_step(e, p)
    assert int(e["wheels"][1, esp.A_MODE]) == abs_fn.DUMP, "premise: ABS dumps FR"
    return e, p, before


@pytest.mark.parametrize("flag", [None, 1])  # None = the shipped SUV file
def test_front_lock_level_is_the_wheel_pressure(flag):
    """C_LOCK_P1 (gma_rejected_split_flag's FR level) stored at the dump's start = the plant's wheel one period after the
    source step (row N from 20 bar: ~62 bar), within 5 bar."""
    e, p, _ = _dump_after_source_step(*([] if flag is None else [f"{LINE}={flag}"]))
    wheel = plant_fill(p, 20.0 * BAR, 167.8 * BAR, 1)[-1]
    stored = float(e["ctl"][esp.C_LOCK_P1])
    assert abs(stored - wheel) <= ERROR_BOUND_PA, f"stored {stored / BAR:.1f} vs wheel {wheel / BAR:.1f} bar"


def test_front_lock_level_code_before_reads_the_source():
    """Seeded defect (flag 0, the code before): the level is the 167.8-bar source, > 100 bar above the wheel."""
    e, p, _ = _dump_after_source_step(f"{LINE}=0")
    assert float(e["ctl"][esp.C_LOCK_P1]) > plant_fill(p, 20.0 * BAR, 167.8 * BAR, 1)[-1] + 100.0 * BAR


def _floor_level(flag):
    """braking_lock_floor (functions/blowout_compensation.py) fed the ECU's own estimates of FR around that dump
    (A_P_EST, and A_P_LINE through S_P_LINE as functions/esp.py writes it): the period before the dump, then the
    dump's first period (both estimates fall). Returns the lock level it stores (S_LOCK_P) and the wheel's pressure."""
    e, p, (est0, line0) = _dump_after_source_step(f"{LINE}={flag}")
    st = bc.initial_state()
    st[bc.S_ABS_ACTIVE + 1] = 1.0  # FR ABS-active (it dumps)
    st[bc.S_P_REQ] = 200.0 * BAR  # the balance above both: the dump criterion reads the estimate alone
    st[bc.S_LOCK_PREV] = -1.0
    for est, line in ((est0, line0), (float(e["wheels"][1, esp.A_P_EST]), float(e["wheels"][1, esp.A_P_LINE]))):
        p_est = [0.0, est, 0.0, 0.0]
        st[bc.S_P_LINE + 1] = line
        bc.braking_lock_floor(st, 1, 200.0 * BAR, np.array(p_est), p)
    return float(st[bc.S_LOCK_P]), plant_fill(p, 20.0 * BAR, 167.8 * BAR, 1)[-1]


def test_lock_floor_level_is_the_wheel_pressure():
    """braking_lock_floor's level at this dump = the plant's wheel at the dump's start (~62 bar), within 5 bar."""
    stored, wheel = _floor_level(1)
    assert abs(stored - wheel) <= ERROR_BOUND_PA, f"stored {stored / BAR:.1f} vs wheel {wheel / BAR:.1f} bar"


def test_lock_floor_level_code_before_reads_the_source():
    """Seeded defect (flag 0): the floor's level is the 167.8-bar source."""
    stored, wheel = _floor_level(0)
    assert stored > wheel + 100.0 * BAR, f"stored {stored / BAR:.1f} vs wheel {wheel / BAR:.1f} bar"


# ---- lifetime of gma_rejected_split_flag's levels --------------------------------------------------------------------
def _gma_after_even_road(quiet_flag, fr_quiet_s):
    """Post-rejection ECU (FR rejected, FL the compensating front: its block, C_GMA_BLOCK): FR has just dumped on the
    snow side at 15 bar; FL is in an ABS hold (no dump yet: no level, so no split reading and no GMA). FR then runs below
    its limit for ``fr_quiet_s`` on the even dry road (FL still held), FL's first dump there marks 50 bar, and both fronts
    are ABS-active together (FR holding: its level not renewed) for 0.1 s. Returns the GMA wheel (-1 none)."""
    p = _params(*([] if quiet_flag is None else [f"{QUIET}={quiet_flag}"]))
    e = esp_ecu(p, 80.0 / 3.6, 60.0 * BAR)
    c, w, b = e["ctl"], e["wheels"], e["bst"]
    b[bc.S_REJECTED] = 1.0
    c[esp.C_GMA_BLOCK] = 1.0  # FL's block (the compensating front), kept while FL's ABS is not OFF
    c[esp.C_LOCK_REJ] = 2.0  # FR's post-rejection skip already spent
    c[esp.C_LOCK_P0], c[esp.C_LOCK_P1] = 0.0, 15.0 * BAR
    w[1, esp.A_SINCE_HD_S] = 0.0  # FR's last dump (on the snow side) just now

    def step(fr_active):
        w[0, esp.A_MODE], w[0, esp.A_SINCE_HD_S] = abs_fn.HOLD, 0.0  # FL in ABS control throughout
        if fr_active:
            w[1, esp.A_MODE], w[1, esp.A_SINCE_HD_S] = abs_fn.HOLD, 0.0
        esp_ecu_step(e, p)

    n_quiet = int(round(fr_quiet_s / p.esp_period_s))
    for _ in range(n_quiet):
        step(False)
        assert int(c[esp.C_GMA_WHEEL]) == -1  # premise: both masked (FL has no level yet): no GMA
    c[esp.C_LOCK_P0] = 50.0 * BAR  # FL's first dump, on the dry road
    for _ in range(int(round(0.1 / p.esp_period_s))):
        step(True)
        if int(c[esp.C_GMA_WHEEL]) >= 0:
            return int(c[esp.C_GMA_WHEEL])
    return -1


def test_stale_split_level_starts_no_gma_on_an_even_road():
    """Shipped file: after 0.4 s of ABS quiet on FR its snow level is gone; both fronts in ABS -> no GMA."""
    assert _gma_after_even_road(None, 0.4) == -1


def test_stale_split_level_code_before_starts_a_gma():
    """Seeded defect (quiet flag 0, the code before: levels kept until the pedal is off): the 15-bar snow level of
    FR reads split against FL's 50 bar, FR's activity counts, FL's is masked -> a GMA on FL with both fronts in ABS."""
    assert _gma_after_even_road(0, 0.4) == 0


def test_fresh_split_level_still_counts():
    """The rule itself still acts on a fresh level: FR quiet only 0.1 s (< 0.3 s) -> its activity counts, GMA on FL."""
    assert _gma_after_even_road(None, 0.1) == 0
