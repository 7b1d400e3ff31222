"""O8 (session 2026-11-25 o): ``blowout_compensation.own_stuck_understeer_flag`` (tire_blowout_findings.md O8).

A blown FRONT whose OWN inlet is diagnosed stuck closed, the driver braking, in a curve toward the blown side: the
blown wheel is unbraked in the car without the function too (eq. 28's "blown wheel unbraked" holds in both cars), the
compensating front is the OUTER front. At the lead's fright_r41 #169 (FR blown and stuck from 0.28 s, 92 km/h, mu
0.51, 1000 m RIGHT curve, fixed steering, HBA master 141 bar) the function's car kept FL ABS-held at 40.7 bar to the
stop, went straight on and left the road 3.4 s after the blowout; its twin (ABS 34.5 bar and an all-wheel dump)
stayed on it (row no_earlier_road_departure -26.635 s). The rule (value 2) releases the outer front while the yaw
falls short of the steered reference - the curve and the shortfall judged at the detection speed.

References: the twin with the same fault (the car without the function), the road edge (lane margin + 3.0 m), mirror
symmetry (the same point with FL blown in a LEFT curve) and the rule's premise (a straight road: nothing changes).
No bound is taken from the function's own output. The rule value is set explicitly (ON), so the tests judge the
rule whatever the TOML ships; with ON at value 0 the four departure tests FAIL (numbers in the findings, O8).
"""
from __future__ import annotations

import numpy as np
import pytest

from vehicle_assist.scenarios.errors import InputError
from vehicle_assist.verification.envelope import load_envelope
from tests.support import envelope_point_run

ROAD = "blowout_lateral_deviation_road_max_m"
EARLY = "blowout_road_departure_earliness_s"
ROAD_EDGE_M = 0.978 + 3.0
KEY = "vehicle.blowout_compensation.own_stuck_understeer_flag"
ON = (f"{KEY}=2",)
OFF = (f"{KEY}=0",)
P169 = {"speed": 92.00691624679605, "mu": 0.5073698141800049, "delay": 0.2749114095275362,
        "wheel_speed_noise": 0.009973803038462247, "noise_seed": 8203.0, "brake_gain": 1.0894919285942857,
        "accumulator": 53.91460407839119, "fault_time": 0.28292944521908936, "brake.start_s": 0.5262367530538103,
        "brake.level_frac": 0.23635781721109733, "brake.rate_per_s": 14.557868408211592, "braking": "brakes",
        "wheel": "fr", "driver": "fixed", "curve": "rr1000", "fault": "inlet_stuck_fr"}
# the lead's faults set f_r41 #374 (fault from t = 0): the shipped fault envelope with fault_time 0
P374 = {"speed": 85.68907790142605, "mu": 0.3127994252955164, "delay": 0.16785183980979967,
        "wheel_speed_noise": 0.06296469571791453, "noise_seed": 9055.0, "brake_gain": 1.0466588551570348,
        "accumulator": 54.29849003504828, "fault_time": 0.0, "brake.start_s": 0.6558814587204223,
        "brake.level_frac": 0.16947125894927018, "brake.rate_per_s": 15.212707467479813, "braking": "brakes",
        "wheel": "fl", "driver": "fixed", "curve": "r1000", "fault": "inlet_stuck_fl"}
CASES = {
    "169": ("tire_blowout_faults_right", P169),
    "169_mirror": ("tire_blowout_faults", dict(P169, wheel="fl", fault="inlet_stuck_fl", curve="r1000")),
    "374": ("tire_blowout_faults", P374),
    "374_mirror": ("tire_blowout_faults_right", dict(P374, wheel="fr", fault="inlet_stuck_fr", curve="rr1000")),
}


@pytest.fixture(scope="module")
def runs():
    out = {}
    for k, (e, pt) in CASES.items():
        env = load_envelope(e)
        out[k] = {"on": envelope_point_run(env, pt, sets=ON), "none": envelope_point_run(env, pt, True)}
    return out


@pytest.mark.parametrize("case", list(CASES))
def test_no_earlier_road_departure(runs, case):
    """Row no_earlier_road_departure: the function's car leaves the road no earlier than its twin (0 = on the road).
    Value 0: #169 26.635 vs 0, mirror 26.750 vs 0, #374 26.095 vs 24.370, mirror 25.915 vs 24.165 s (all FAIL)."""
    on, none = runs[case]["on"].metrics[EARLY], runs[case]["none"].metrics[EARLY]
    assert on <= none, (on, none)


def test_169_twin_on_the_road_function_car_too(runs):
    """#169: the twin stays on the road (a real comparison, not a tie of two departures), and so must the function's
    car: value 2 3.843 m < 3.978 (value 0 3.978: off the road, FAILS). Row 1 (never worse than the twin's 3.498 m)
    stays a violation at value 2 - said in the findings, not tested as a pass."""
    assert runs["169"]["none"].metrics[ROAD] < ROAD_EDGE_M
    assert runs["169"]["on"].metrics[ROAD] < ROAD_EDGE_M, runs["169"]["on"].metrics[ROAD]


def test_169_negative_control():
    """The defect exists without the rule: value 0 leaves the road where the twin does not."""
    env = load_envelope("tire_blowout_faults_right")
    assert envelope_point_run(env, P169, sets=OFF).metrics[EARLY] > 0.0


def test_scope_straight_road_unchanged():
    """The premise: a curve toward the blown side. The mirrored #169 on a STRAIGHT road - the same blown front with its
    own inlet stuck, the same pedal - is bitwise the code before (value 2 == value 0, pressures and metrics)."""
    env = load_envelope("tire_blowout_faults")
    pt = dict(P169, wheel="fl", fault="inlet_stuck_fl", curve="straight")
    a, b = envelope_point_run(env, pt, sets=ON), envelope_point_run(env, pt, sets=OFF)
    for w in ("fl", "fr", "rl", "rr"):
        assert np.array_equal(np.asarray(a.trace[f"wheel_pressure_{w}_pa"]), np.asarray(b.trace[f"wheel_pressure_{w}_pa"]))
    assert a.metrics[ROAD] == b.metrics[ROAD] and a.metrics[EARLY] == b.metrics[EARLY]


def test_flag_out_of_range():
    env = load_envelope("tire_blowout_faults_right")
    with pytest.raises(InputError):
        envelope_point_run(env, P169, sets=(f"{KEY}=3",))
