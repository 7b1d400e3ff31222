"""A driver who brakes around a rear blowout (issue #10: 'a panic stop right after a blowout must work'; review item 5:
no never-worse test failed with slip_limit_flag = 0 while braking). Points of the extended envelope
(data/envelopes/tire_blowout.toml: braking driver, wheel-speed noise, brake-gain error), found by the falsifier
campaign and a grid around them (findings of the #10 envelope campaign, F4 and P5).

References: the same blowout without compensation (paper 004 Fig. 4 curve 2; conventions.md 'Evidence'), compared as
the requirement does (largest lateral deviation from t_b to the end of the run); and the friction limit mu*g of the
road for a braking car (an ABS stop uses most of it: UN R13-H Annex 6 asks for an adhesion utilisation of at least
0.75; the bound here is half the limit, far below that)."""
from __future__ import annotations

import numpy as np
import pytest

from vehicle_assist.verification.envelope import load_envelope
from tests.support import envelope_point_run
from tests.support import mean_decel as _decel
from tests.support import panic_stop_decel_bound as _bound

METRIC = "blowout_lateral_deviation_run_max_m"
NO_SLIP_LIMIT = "vehicle.blowout_compensation.slip_limit_flag=0"

# Review item 5: RR blowout at 78 km/h on mu scale 0.37 (mu 0.43) in a 650 m curve, lane-following driver, light pedal
# (80 N, ~48 bar) 0.3 s after the blowout; no noise, nominal brake gain. Found by a grid over speed x mu x driver x
# curve x pedal (rear wheel, light pedal); its neighbourhood (75-78 km/h, mu 0.35-0.37, 70-90 N, delay 0.08-0.12 s,
# pedal at +0.30..0.35 s) keeps the order with >= 0.22 m on both sides at bffdbd8: 0.51 m < none 0.75 m < 0.98 m.
# 7d6f650/787c4a6 broke it (1.51/1.72 m), 776678e fixed it (0.63 m). Since ceccfdb the no-compensation twin brakes
# (ESP reference plausibility, finding F4): none 1.77 m, so the point now shows a large benefit (0.63 vs 1.77 m).
P5 = dict(speed=78.0, mu=0.37, delay=0.1, wheel_speed_noise=0.0, noise_seed=0, brake_gain=1.0, braking="brakes",
          wheel="rr", driver="follow", curve="r650", **{"brake.level_frac": 0.08, "brake.start_s": 1.3, "brake.rate_per_s": 2.0})

# F4 (CMA-ES seed 2026 budget 64 #57): RR at 107.8 km/h, mu scale 0.382, delay 0.47 s, follower, 650 m curve; the driver
# brakes 164 N (98 bar master, HBA on) 0.61 s after the blowout.
F4 = {"speed": 107.84044038487475, "mu": 0.38220997676664165, "delay": 0.4709871427852446,
      "wheel_speed_noise": 0.0038020704162375434, "noise_seed": 6367, "brake_gain": 1.0418679260855557,
      "brake.start_s": 1.6079657469722903, "brake.level_frac": 0.1639736652999174, "brake.rate_per_s": 17.743480952695002,
      "braking": "brakes", "wheel": "rr", "driver": "follow", "curve": "r650"}


@pytest.fixture(scope="module")
def env():
    return load_envelope("tire_blowout")


_run = envelope_point_run


@pytest.fixture(scope="module")
def p5(env):
    return {"on": _run(env, P5).metrics[METRIC], "off": _run(env, P5, True).metrics[METRIC],
            "defect": _run(env, P5, sets=[NO_SLIP_LIMIT]).metrics[METRIC]}


def test_light_braking_rear_blowout_never_worse(p5):
    """Item 5: the rear compensating wheel kept in its linear region while the driver brakes lightly: the compensated
    car goes less far off the lane than the same car without compensation."""
    assert p5["on"] < p5["off"]


@pytest.mark.xfail(strict=True, reason=(
    "E2 (esp.reference_plausibility_flag, finding F4): the no-compensation twin's ABS no longer dumps the driver's 48 bar "
    "(its reference speed used to ride the 1.5x-fast blown wheel: 0.749 m, hardly braking); it now brakes ~4 m/s^2 and "
    "goes 1.765 m off (its ABS judges the blown RR wheel's slip with the nominal radius: true slip 0.3-0.45). With "
    "slip_limit_flag = 0 the compensated car (1.059 m) is no longer worse than that fair baseline, so this point no "
    "longer shows the never-worse test failing with the defect (on 0.628 m). Restated by F at ceccfdb: a grid of 192 "
    "rear-blowout points with a light pedal (RR; 60/75/90/105 km/h x mu scale 0.35/0.45/0.55 x held/following driver x "
    "straight/650 m x 40/80 N x pedal at t_b-0.2/+0.3 s; delay 0.1 s, no noise, nominal gain) has NO point where "
    "slip_limit_flag = 0 is worse than the fair no-compensation twin: review item 5's point existed only against the "
    "non-braking baseline. Kept as a strict xfail so a point where it fails again is noticed."))
def test_light_braking_rear_blowout_worse_without_slip_limit(p5):
    """Negative control (seeded defect slip_limit_flag = 0, the rear wheel braked past the linear region): the same
    point is then worse than no compensation - the test above can fail."""
    assert p5["defect"] > p5["off"]




def test_panic_stop_after_rear_blowout_brakes_with_compensation(env):
    """Issue #10: with compensation the driver's stop works after a rear blowout: mean deceleration from 0.3 s to 1.3 s
    after the pedal is at least half the road's friction limit."""
    t0 = F4["brake.start_s"] + 0.3
    assert _decel(_run(env, F4), t0, t0 + 1.0) >= _bound(F4)


def test_panic_stop_after_rear_blowout_brakes_without_compensation(env):
    """Finding F4 (was a strict xfail): without the blowout function the ESP's reference speed took the blown wheel
    (~1.5x faster), ABS dumped every intact wheel (1.36 m/s^2). The ESP now leaves an implausibly fast wheel out of
    its reference (esp.reference_plausibility_flag; tests/functions/test_esp_reference_plausibility.py)."""
    t0 = F4["brake.start_s"] + 0.3
    assert _decel(_run(env, F4, baseline=True), t0, t0 + 1.0) >= _bound(F4)
