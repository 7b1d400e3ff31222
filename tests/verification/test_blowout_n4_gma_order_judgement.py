"""L7's GMA pressure-order rule (``esp.gma_pressure_order_flag`` value 1) under the session-n judgement (session
2026-11-25 n, task N4; tire_blowout_findings.md "N4 (session n)").

Value 1 (L7) was not shipped at the 5-s window because faultsT t_r41 #51 became a new violation: the car without the
rule spins like its twin (both ~9.7 m off), with it the car does not spin but drifts 10.09 m out. Since session n both
cars are judged over the whole stop and on the road (``blowout_lateral_deviation_road_max_m``: clipped at the road edge
ROAD_EDGE_M, two cars that both leave the road tie) and by a second row, ``no_earlier_road_departure``. N4 re-measured value 1 under
that judgement (findings N4): #72 fixed, no new violation in either row, but two no-fault real points worse (rb13
#114, rb29 #19), so the SUV still ships 2 and value 1 stays a candidate. These tests run the candidate explicitly
(``ON``) against the shipped value (``SHIPPED``, the negative control), so they pass whatever the TOML value:

* rb5 #72 (L7's point: RR blown, 100 km/h, mu 0.522, 650 m left curve, follower, pedal 0.077 from 1.09 s): never worse
  than the twin on the road - 1.635 m vs the twin's 2.186 at 1; 2.481 m at 0 and 2 (the GMA holds FL 20-23 bar
  below the ABS-rebuilt FR for ~0.9 s: a yaw moment toward the blown RR the twin does not have).
* t_r41 #51 (L7's new violation at the 5-s window: RL blown, RR's inlet stuck at 1.42 s): both cars leave the road (a
  tie in row 1) and the function's car leaves it LATER than the twin (row 2).
References independent of the function's code: the twin run (paper 004 Fig. 4 curve 2, no compensation) and the
requirement rows' own metrics.
"""
from __future__ import annotations

import pytest

from tests.support import envelope_point_run
from vehicle_assist.verification.envelope import load_envelope

ROAD = "blowout_lateral_deviation_road_max_m"
EARLY = "blowout_road_departure_earliness_s"
ON = ("vehicle.esp.gma_pressure_order_flag=1",)  # L7's candidate
SHIPPED = ("vehicle.esp.gma_pressure_order_flag=2",)  # M6's narrowing (the SUV's value until session o, which ships N6's 3): #72 untouched
DEFECT = ("vehicle.esp.gma_pressure_order_flag=0",)  # the code before
# /tmp/lead/n/h1/rb5/falsify.json history #72 (random 5 -n 128 -b 64 -R braking=brakes)
P72 = {"speed": 99.99149704319854, "mu": 0.5217520232282564, "delay": 0.4579899484382917,
       "wheel_speed_noise": 0.021128866277189573, "noise_seed": 9839.0, "brake_gain": 0.9467768763559855,
       "brake.start_s": 1.0916721241139895, "brake.level_frac": 0.07708486873809187,
       "brake.rate_per_s": 2.080834345018032, "braking": "brakes", "wheel": "rr", "driver": "follow", "curve": "r650"}
# /tmp/lead/n/h1/t_r41/falsify.json history #51 (tire_blowout_faults, random 41 -n 512 -b 64)
P51 = {"speed": 107.38585282284686, "mu": 0.47944606676299506, "delay": 0.45714186093419573,
       "wheel_speed_noise": 0.20769030651938827, "noise_seed": 2910.0, "brake_gain": 0.8709612414030437,
       "accumulator": 108.06711209376208, "fault_time": 1.4233115178415177, "brake.start_s": 1.1611478227751508,
       "brake.level_frac": 0.41011267426067577, "brake.rate_per_s": 3.1162293268697083, "braking": "brakes",
       "wheel": "rl", "driver": "fixed", "curve": "r650", "fault": "inlet_stuck_rr"}


@pytest.fixture(scope="module")
def rb5_72():
    env = load_envelope("tire_blowout")
    return {k: envelope_point_run(env, P72, sets=v) for k, v in (("on", ON), ("shipped", SHIPPED), ("defect", DEFECT))
            } | {"none": envelope_point_run(env, P72, baseline=True)}


@pytest.fixture(scope="module")
def t_r41_51():
    env = load_envelope("tire_blowout_faults")
    return envelope_point_run(env, P51, sets=ON), envelope_point_run(env, P51, baseline=True)


def test_rb5_72_never_worse_on_the_road_at_1(rb5_72):
    """no_worse_than_no_compensation at rb5 #72 with the candidate: 1.635 <= 2.186 m."""
    on, none = rb5_72["on"].metrics[ROAD], rb5_72["none"].metrics[ROAD]
    assert on <= none, (on, none)


@pytest.mark.parametrize("flag", ["shipped", "defect"])
def test_rb5_72_violation_stands_without_it(rb5_72, flag):
    """Negative control: at the shipped 2 and at 0 the same check fails (2.481 > 2.186 m) - the standstill judgement
    did not remove #72 (its run max is at 3.8 s, both cars on the road)."""
    assert rb5_72[flag].metrics[ROAD] > rb5_72["none"].metrics[ROAD]


def test_rb5_72_stays_on_the_road(rb5_72):
    """Both cars stay on the road at #72 (the road metric is the unclipped offset there: the comparisons above are
    real ones, not ties at the edge)."""
    assert all(r.metrics[EARLY] == 0.0 for r in rb5_72.values())


def test_t_r41_51_no_earlier_departure_and_tie_on_the_road(t_r41_51):
    """L7's 5-s-window violation, at the candidate: both cars leave the road (row 1 tie at the edge) and the
    function's car leaves it no earlier than the twin (row 2): measured earliness 27.695 s vs the twin's 27.955 s."""
    fn, tw = t_r41_51
    assert fn.metrics[ROAD] <= tw.metrics[ROAD], (fn.metrics[ROAD], tw.metrics[ROAD])
    assert fn.metrics[EARLY] <= tw.metrics[EARLY], (fn.metrics[EARLY], tw.metrics[EARLY])
