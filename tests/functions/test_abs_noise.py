"""ABS of the passenger-car ESP (functions/esp.py, abs.py) under wheel-speed sensor noise (issue #10 campaign, finding
F2: with the wheel deceleration differenced from raw samples, 0.2 rad/s of noise on the four wheel speeds took the
SUV's ABS stop on mu scale 0.684 from 6.88 to 2.51 m/s^2 - ABS dumped on noise).

Reference (independent of the code under test): the adhesion utilisation an ABS must reach, epsilon = z_AL/k >= 0.75
(UN R13 Annex 13 para 5.2 / R13-H Annex 6, as recalled [recollection]; the clause text was not retrieved), with k the
road's peak adhesion coefficient and z_AL the braking rate with ABS, here read as the regulation reads k: from the time
t the speed takes from 40 to 20 km/h (z = 0.566/t in g: the determination of k in UN R13-H Annex 6 Appendix 2, as recalled, not retrieved; the
agricultural-vehicle regulation EU 2015/68 cited here before repeats the formula but is not the passenger-car clause). k is the surface's
published peak: dry-asphalt Burckhardt peak 1.17 (brake_assist.md 4.4) times the road scale (the SUV's Dugoff mu is that
peak, suv_bj2500.toml tires.source). Surfaces: scale 0.684 (k = 0.80) and 0.2564 (k = 0.30, the low-adhesion surface
of the ABS tests: 71/320/EEC Annex X 5.1.1.2, "0.3 or less"). Pedal 250 N (146 bar master, more than twice the
wheels' lock pressure: the ABS governs all four wheels for the whole window), 60 km/h.

Noise: sigma = 0.2 rad/s white on each of the four wheel-speed sensors per ESP period (two thirds of the tire_blowout
envelope's 0.3 rad/s maximum, data/envelopes/tire_blowout.toml: tone-wheel edge timing, assumed there; at 60 km/h
0.2 rad/s is 0.4 % of the wheel speed, the order of a tone wheel's tooth-pitch error). At 0.3 rad/s the 3-sample
slope still crosses the 30 m/s^2 dump threshold on high friction (strict xfail below: an honest limit). Noise-free the
filtered ABS reaches the same utilisation as before (0.88 / 1.00).

Seeded defect: ``vehicle.esp.abs_signal_filter_flag=0`` (raw one-period difference, the code before the fix) must fail
the same check.
"""
from __future__ import annotations

import numpy as np
import pytest

import vehicle_assist as va

G = 9.80665
MU_PEAK_DRY = 1.17  # brake_assist.md 4.4: Burckhardt dry asphalt peak; road.friction_mu scales it
EPS_MIN = 0.75  # UN R13 Annex 13 para 5.2 / R13-H Annex 6 adhesion utilisation of an ABS [recollection]
SIGMA_RADPS = 0.2
SURFACES = {"k080": 0.684, "k030": 0.2564}  # road scale -> k = 1.17 x scale = 0.80 / 0.30
SEEDS = (5, 11)
WHEELS = ("fl", "fr", "rl", "rr")


def _scenario(scale: float, sigma: float, seed: int, flag: int):
    sets = [f"sensors.wheel_speed_{w}.noise_std_radps={sigma}" for w in WHEELS] + [
        "vehicle.blowout.wheel_index=-1", f"road.friction_mu={scale}",
        "driver.brake_pedal={time_s = [0.0, 0.5, 0.52], frac = [0.0, 0.0, 0.25]}", f"run.seed={seed}", "run.duration_s=12",
        f"vehicle.esp.abs_signal_filter_flag={flag}"]
    return va.load_scenario("blowout_lf_60kph_off", sets=sets)


def _utilisation(result, scale: float) -> float:
    """epsilon = z/k with z from the 40 -> 20 km/h time (the regulation's reading of a braking rate)."""
    t = np.asarray(result.trace["time_s"])
    u = np.asarray(result.trace["speed_mps"])
    assert u.min() <= 20.0 / 3.6, "the stop did not pass 20 km/h in the run"
    t40 = t[np.argmax(u <= 40.0 / 3.6)]
    t20 = t[np.argmax(u <= 20.0 / 3.6)]
    z_mps2 = (20.0 / 3.6) / (t20 - t40)
    return z_mps2 / (MU_PEAK_DRY * scale * G)


def _batch(cases):
    return {c: _utilisation(va.simulate(_scenario(*c), requirements=False), c[0]) for c in cases}


@pytest.fixture(scope="module")
def eps():
    cases = [(scale, s, seed, flag) for scale in SURFACES.values() for seed in SEEDS
             for (s, flag) in ((0.0, 1), (SIGMA_RADPS, 1), (SIGMA_RADPS, 0))]
    return _batch(cases)


@pytest.mark.parametrize("surface", SURFACES)
def test_noise_free_abs_reaches_the_adhesion_utilisation(eps, surface):
    scale = SURFACES[surface]
    for seed in SEEDS:
        assert eps[(scale, 0.0, seed, 1)] >= EPS_MIN


@pytest.mark.parametrize("surface", SURFACES)
@pytest.mark.parametrize("seed", SEEDS)
def test_abs_keeps_the_adhesion_utilisation_with_wheel_speed_noise(eps, surface, seed):
    """Filtered wheel deceleration: noise on the four wheel speeds does not make the ABS throw the driver's pressure
    away (epsilon noise-free 0.88 / 1.00, with 0.2 rad/s 0.83 / 1.00 on k = 0.80 / 0.30, seed 5; 0.84 / 1.00 seed 11)."""
    assert eps[(SURFACES[surface], SIGMA_RADPS, seed, 1)] >= EPS_MIN


@pytest.mark.parametrize("surface", SURFACES)
@pytest.mark.parametrize("seed", SEEDS)
def test_check_fails_with_the_raw_differenced_wheel_deceleration(eps, surface, seed):
    """Seeded defect (flag 0, the code before the fix): ABS dumps on noise (epsilon 0.31 / 0.66 on k = 0.80 / 0.30,
    seed 5; 0.32 / 0.67 seed 11)."""
    assert eps[(SURFACES[surface], SIGMA_RADPS, seed, 0)] < EPS_MIN


@pytest.mark.xfail(strict=True, reason="at 0.3 rad/s (the envelope maximum) the 3-sample slope's noise, "
                   "0.3*0.359/(0.005*sqrt(2)) = 15 m/s^2 rms, still crosses the 30 m/s^2 dump threshold ~2 % of the "
                   "periods on high friction: epsilon 0.54 / 0.51 (seeds 5 / 11) on k = 0.80 (raw: 0.15); a longer "
                   "slope (4 samples: 0.82) delays the noise-free dumps and breaks HBA never-worse points "
                   "(tests/functions/test_hba_gma_and_rebuild.py, P147 +0.14 m)")
def test_abs_adhesion_utilisation_at_the_envelope_maximum_noise():
    scale = SURFACES["k080"]
    assert _batch([(scale, 0.3, 5, 1)])[(scale, 0.3, 5, 1)] >= EPS_MIN
