"""A panic stop after a FRONT blowout (issue #10: 'a panic stop right after a blowout must work') - independent review
RG, session 2026-11-24 g. The absolute stop check of tests/verification/test_blowout_braking_driver.py (mean
deceleration from 0.3 s to 1.3 s after the pedal >= half the road's friction limit) existed for a REAR blowout only;
the requirement tire_blowout.no_worse_than_no_compensation compares the lateral deviation alone, so a compensation
that halves the driver's deceleration passes it.

Point: falsifier tire_blowout random seed 17 budget 64 #36 (also -R braking=brakes seed 17 #36; main e47e97c): FR
blown at 40 km/h on mu scale 0.387 in a 650 m left curve, steering fixed, detected at 1.27 s (HOLD from 1.32 s), the
driver brakes 476 N (166 bar master, HBA on) from 1.92 s. With compensation the braking rule holds the compensating FL
at 13.3 bar and the rear pair at 7.0 bar (no wheel ABS-active) to the end of the run; the twin's ABS carries FL 20-31,
FR 12-17, rears 34 bar and stops at 4.0 s. Mean deceleration 2.13 m/s^2 vs 4.86 without compensation (bound 2.22);
with tire_capacity_flag = 0 3.88 m/s^2: the measured friction S_MU_MEAS caps the braking rule's front circle and rear
linear limit. The lateral deviation also exceeds the twin's (0.956 vs 0.855 m), a violation of the requirement; the
same late-pedal front points at 60/80 km/h or mu 0.45/0.55 keep 0.5-0.6 x the twin's deceleration
(2.6-3.6 vs 4.7-6.2 m/s^2), above the bound.

References (independent of the code): the road's friction limit mu*g (UN R13-H Annex 6 asks an ABS stop for an adhesion
utilisation of at least 0.75; the bound is half the limit, as in test_blowout_braking_driver.py) and the
no-compensation twin. Not fixed (strict xfail): the caps are the braking rule's stability design (rear pair in its
Dugoff linear region at the measured friction); what to change is for the owner of the braking rule."""
from __future__ import annotations

import numpy as np
import pytest

from tests.support import envelope_point_run
from vehicle_assist.verification.envelope import load_envelope

G = 9.80665
MU_PEAK_DRY = 1.17  # peak of the SUV's dry Burckhardt set; road.friction_mu scales it (tire_blowout envelope, mu source)
METRIC = "blowout_lateral_deviation_run_max_m"
# falsifier tire_blowout random seed 17 budget 64 (batch 32), point #36
R17_36 = {"speed": 40.34745521612098, "mu": 0.386809375569746, "delay": 0.23535598241927075,
          "wheel_speed_noise": 0.11795677364947249, "noise_seed": 440, "brake_gain": 1.1904652217551854,
          "brake.start_s": 1.9164320213559898, "brake.level_frac": 0.47602531016613836,
          "brake.rate_per_s": 12.731445072470526, "braking": "brakes", "wheel": "fr", "driver": "fixed",
          "curve": "r650"}


@pytest.fixture(scope="module")
def env():
    return load_envelope("tire_blowout")


def _decel(run, t0, t1):
    t = np.asarray(run.trace["time_s"])
    u = np.asarray(run.trace["speed_mps"])
    i0, i1 = int(np.argmin(abs(t - t0))), int(np.argmin(abs(t - t1)))
    return (u[i0] - u[i1]) / (t[i1] - t[i0])


def _bound(point):
    return 0.5 * MU_PEAK_DRY * point["mu"] * G


def test_front_blowout_panic_stop_without_compensation_meets_the_bound(env):
    """The twin (no compensation) stops with ABS: 4.86 m/s^2 >= 2.22 (the bound is reachable on this road)."""
    t0 = R17_36["brake.start_s"] + 0.3
    assert _decel(envelope_point_run(env, R17_36, baseline=True), t0, t0 + 1.0) >= _bound(R17_36)


@pytest.mark.xfail(strict=True, reason="RG session g: braking rule caps (measured friction S_MU_MEAS: FL 13.3 bar, "
                   "rear pair 7 bar) under a 166-bar panic pedal after a front blowout: 2.13 m/s^2 vs bound 2.22, "
                   "none 4.86; not fixed")
def test_front_blowout_panic_stop_with_compensation_meets_the_bound(env):
    t0 = R17_36["brake.start_s"] + 0.3
    assert _decel(envelope_point_run(env, R17_36), t0, t0 + 1.0) >= _bound(R17_36)


@pytest.mark.xfail(strict=True, reason="RG session g: same point, lateral deviation 0.956 vs none 0.855 m (the "
                   "under-braked car runs on in the curve); not fixed")
def test_front_blowout_panic_stop_no_worse_than_without_compensation(env):
    on = envelope_point_run(env, R17_36).metrics[METRIC]
    assert on <= envelope_point_run(env, R17_36, baseline=True).metrics[METRIC]
