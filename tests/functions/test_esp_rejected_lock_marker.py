"""gma_rejected_split_flag's skip marker on the rejected front's lock level (functions/esp.py C_LOCK_P0/1 = -1, set once
per rejection in the GMA section) - review RJ3, session j (tire_blowout_findings.md "RJ3").

The rule's own statement (functions/esp.py, gma_rejected_split_flag; suv_bj2500.toml): after a FRONT rejection the rejected
front is re-applied at once to the driver's pressure (reject_reapply_flag), "so its first dump marks that step, not the
road": its lock level counts from its SECOND dump after the rejection.

What the code does: the marker is written in the GMA section, AFTER the per-wheel ABS loop of the first period in which
the ECU sees mode REJECTED (blowout_step runs later in the period, so that is the period after the rejection). The
re-apply step typically dumps the wheel in exactly that period (lead fa_cau_signed #26: rejected 2.055 s, FR's ABS dump
2.06 s, lock_threatened): that dump stores its level in the loop, the marker then overwrites it with -1, and the marker
skips the SECOND dump - the first road reading. The level counts from the third dump.

Reference: the rule's documented intent above (not the code's formula). Fixed in session j (J10,
blowout_compensation.gma_rejected_marker_dump_flag = 1): 0 is written instead of -1 when the rejected front began its dump
in the same period. The flag-0 row (the code before) must show the defect (measured: -1, 0, 57.9 bar after dumps 1, 2, 3).
"""
from __future__ import annotations

import pytest

import vehicle_assist as va
from tests.support import esp_ecu, esp_ecu_step
from vehicle_assist.functions import abs as abs_fn
from vehicle_assist.functions import blowout_compensation as bc
from vehicle_assist.functions import esp
from vehicle_assist.scenarios.runner import pack_records

BAR = 1.0e5


def _levels_at_dumps(sets=()):
    """ECU alone (SUV file, HBA off), 80 km/h, driver 60 bar: FR just rejected (mode REJECTED, FL the compensating
    front's block, FL in ABS control), FR slips to 70 % of the car's speed in the first period (the re-apply step's
    dump), then again 0.2 s and 0.4 s later (road locks). Returns C_LOCK_P1 after each of FR's dumps and C_LOCK_REJ."""
    p = pack_records([va.load_scenario("blowout_panic_stop_80kph", ["vehicle.brake_assist.enabled_flag=0", *sets]).vehicle.flat()])[0]
    v = 80.0 / 3.6
    e = esp_ecu(p, v, 60.0 * BAR)
    c, w, b, m = e["ctl"], e["wheels"], e["bst"], e["meas"]
    b[bc.S_MODE], b[bc.S_REJECTED], b[bc.S_TARGET] = bc.REJECTED, 1.0, -1.0
    c[esp.C_GMA_BLOCK] = 1.0  # FL's block (the compensating front), kept while FL's ABS is not OFF
    levels = []
    for k in range(120):
        w[0, esp.A_MODE], w[0, esp.A_SINCE_HD_S] = abs_fn.HOLD, 0.0
        m.wheel_speed_fr_radps = (0.7 if k in (0, 1, 40, 41, 80, 81) else 1.0) * v / p.body_wheel_radius_m
        old = int(w[1, esp.A_MODE])
        esp_ecu_step(e, p)
        if int(w[1, esp.A_MODE]) == abs_fn.DUMP and old != abs_fn.DUMP:
            levels.append(float(c[esp.C_LOCK_P1]))
    return levels, int(c[esp.C_LOCK_REJ])


def test_premise_three_dumps_and_the_marker_is_set():
    """Premise: FR dumps three times and the skip marker was armed for FR (C_LOCK_REJ = FR + 1)."""
    levels, rej = _levels_at_dumps()
    assert len(levels) == 3 and rej == 2, (levels, rej)


FLAG0 = ("vehicle.blowout_compensation.gma_rejected_marker_dump_flag=0",)


@pytest.mark.parametrize("sets", [(), pytest.param(FLAG0, marks=pytest.mark.xfail(
    strict=True, reason="flag 0 = the code before: the marker is set after the re-apply step's dump of the same period "
    "and skips the first road dump (RJ3: C_LOCK_P1 -1, 0, 57.9 bar after dumps 1, 2, 3)"))], ids=["shipped", "flag0"])
def test_rejected_front_level_counts_from_its_second_dump(sets):
    """The second dump after the rejection (the first road lock) stores a level (> 0)."""
    levels, _ = _levels_at_dumps(sets)
    assert levels[1] > 0.0, [x / BAR for x in levels]
