"""HBA's rear select-low while a wheel is only NAMED by the TPMS (``esp.hba_rear_select_low_tpms_flag``,
functions/esp.py; session 2026-11-24 g, task G1; finding of the independent review r1, session f).

Falsifier tire_blowout random seed 29 (b64 #46 = braking-only b128 #46): FL blown at 106 km/h on mu 0.49 in a 1000 m
curve, the follower driver, a 76 N pedal with HBA. The TPMS names FL before the wheel-speed detection; the ESP
excludes FL from its reference and, for an excluded wheel, switched its HBA rules off (``blown < 0`` gates): the pump
lifted FR past the driver, FR's circuit became pump-served and its rear RL was pumped to 78-83 bar against RR's
driver 31-36 bar - a yaw moment toward the blown side that no part of the function asked for (the compensation was
still idle). The car yawed toward FL, the detection was refused (beyond the stable region) and the car spun: 8.64 m
against 2.01 m without compensation. With the rule (the rear select-low on pressure kept while the wheel is only
named) 0.60 m.

References, independent of the code: the requirement tire_blowout.no_worse_than_no_compensation (the
no-compensation twin, paper 004 Fig. 4 curve 2) for the lateral deviation and for the peak yaw rate (a blowout
assist must not turn the car faster than it turns without the assist). Both fail with the seeded defect
hba_rear_select_low_tpms_flag = 0 (the code before)."""
from __future__ import annotations

import numpy as np
import pytest

import vehicle_assist as va
from tests.support import envelope_point_metric
from vehicle_assist.verification.envelope import load_envelope

METRIC = "blowout_lateral_deviation_run_max_m"
# the code before the rule; esp.named_front_gma_flag (session i, I4) off too: it alone keeps #46 below the twin (0.83 m
# with this flag at 0, twin 2.01) - the negative control is the code before both
DEFECT = ("vehicle.esp.hba_rear_select_low_tpms_flag=0", "vehicle.esp.named_front_gma_flag=0")
# review RI1 (session i): with only the two rows (shipped, DEFECT) the rule could be removed unnoticed - at the shipped
# code hba_rear_select_low_tpms_flag = 0 alone is 0.83 m < twin 2.01, and DEFECT turns both flags off. The ISOLATED row
# runs this rule alone on the code before named_front_gma_flag (0.22 m; 8.21 m with this flag at 0): it fails with
# hba_rear_select_low_tpms_flag = 0 in the toml
ISOLATED = ("vehicle.esp.named_front_gma_flag=0",)
P29_46 = {"speed": 106.16548480207601, "mu": 0.49110694692641554, "delay": 0.4615046677329761,
          "wheel_speed_noise": 0.08060224589792808, "noise_seed": 6328, "brake_gain": 0.8796034279216752,
          "brake.start_s": 0.8650976900899694, "brake.level_frac": 0.07615910582509652,
          "brake.rate_per_s": 23.697692276117564, "braking": "brakes", "wheel": "fl", "driver": "follow",
          "curve": "r1000"}


@pytest.fixture(scope="module")
def env():
    return load_envelope("tire_blowout")


@pytest.mark.parametrize("sets,worse", [((), False), (ISOLATED, False), (DEFECT, True)])
def test_tpms_named_front_hba_no_worse_than_none(env, sets, worse):
    """With the rule: no worse than the car without compensation (0.60 vs 2.01 m); the defect row is its negative
    control (8.64 m)."""
    on = envelope_point_metric(env, P29_46, METRIC, sets=sets)
    assert (on > envelope_point_metric(env, P29_46, METRIC, baseline=True)) == worse, f"{on:.2f} m"


def _peak_yaw(sc) -> float:
    return float(np.abs(np.asarray(va.simulate(sc, requirements=False).trace["yaw_rate_radps"])).max())


@pytest.mark.parametrize("sets,spins", [((), False), (ISOLATED, False), (DEFECT, True)])
def test_tpms_named_front_hba_does_not_turn_the_car_faster_than_none(env, sets, spins):
    """Peak |yaw rate| over the run no higher than without compensation (twin 0.154 rad/s; the rule 0.085; the defect
    1.51 rad/s: the spin toward the blown side)."""
    sc = env.scenario(P29_46)
    on = _peak_yaw(sc.with_sets(*sets) if sets else sc)
    assert (on > _peak_yaw(env.scenario(P29_46, baseline=True))) == spins, f"{on:.3f} rad/s"
