"""The paper 002 HBA stop (sedan, 110 km/h, dry, 100 N in 12 ms) with wheel-speed sensor noise (G's finding after
2493eb2): does ABS keep the adhesion utilisation of an ABS when the four wheel speeds carry 0.1 / 0.2 rad/s of noise?

Reference (independent of the code under test), the method of tests/functions/test_abs_noise.py: epsilon = z/k >= 0.75
(UN R13 Annex 13 para 5.2 / R13-H Annex 6, as recalled [recollection]; clause text not retrieved), z from the time the
speed takes from 40 to 20 km/h (z = 0.566/t: UN R13-H Annex 6 Appendix 2's determination of k, as recalled,
not retrieved; not EU 2015/68, the agricultural-vehicle regulation, cited here before), k = the peak of
the sedan's dry Burckhardt curve (brake_assist.md 4.4, c1 1.2801, c2 23.99, c3 0.52: peak 1.17 at 17 % slip). Caveat as
in that file: R13 measures z with one axle braked at a time; here all four wheels brake with HBA, which is at least
as demanding on the ABS. The pedal is held to standstill (15 s) so the 40 -> 20 km/h window is always reached when the
car stops; a run that never gets below 20 km/h scores 0.

Measured at 51fe1aa (noise-free epsilon 0.988, 48.02 m): at 0.1 rad/s seed 11 0.988 (48.36 m) but seeds 5 / 1 / 2 / 3
0.10 / 0.59 / 0.75 / 0.64 with the car yawing 52 / 42 / 26 / 39 deg (steering held straight); at 0.2 rad/s seeds
5 / 11 / 1 / 2 / 3 0.70-0.74, 65.6-71.7 m, 9-28 deg. Without HBA the same noise gives 73.8 / 77.9 m and 0 / 14.6 deg
(vs 72.9 m noise-free). Diagnosis (trace, seed 5 at 0.1 rad/s): the reference speed is not where it starts. At the
HBA onset (0.12 s) the pump build makes both front wheels' deceleration cross A_DUMP = 30 m/s^2 (noise-free both dump
at 0.125 s); with noise (3-sample slope, ~4.4 m/s^2 rms at 0.1 rad/s) only FL crosses, so ABS is active on one front
wheel only and functions/esp.py arms the yaw-moment build-up delay (GMA, a split-mu measure) on dry asphalt: FR is
held at ~27-60 bar for the whole stop (and with gma_hba_flag its circuit stays on the driver's pressure) while the pump
lifts FL and the diagonal RR to 83 / 134 bar. The car yaws (r = 0.48 rad/s, lateral speed -2.5 m/s); the accelerometer
reads the body-frame a_x = du/dt - v*r, 1.2 m/s^2 less deceleration than the body speed's for 1.5 s, and the reference
speed (rate-bounded by |a_x| + 0.05 m/s^2 while every wheel slips) ends 1.65 m/s above the car - the "reference runs
high" of the finding is the consequence, the noise ratchet of the max of four wheels is only +0.05-0.15 m/s. An arming
rule for the GMA on slip evidence (the one-sided wheel's slip beyond the hold threshold for 1-10 periods) was tried:
0.1 rad/s 9-10 of 10 seeds at 48.8-50.0 m, 0.2 rad/s 53.6-58.4 m, but hba_split_mu_80kph then fails the never-worse
heading / steering rows of test_hba_gma_and_rebuild.py by 0.05-0.15 deg / 0.8-1.2 deg (50 ms: HBA 3.1 m longer than
none) - not shipped.

Fix (esp.gma_follow_flag, engineer K): the GMA limits the high-mu wheel's pressure relative to the low-mu wheel's, so
once the pump has served the other front's circuit and lifted it above the driver's pressure, the GMA's wheel is pumped
up to (not past) the other front's pressure instead of being capped at the driver's for the whole stop. Measured, seeds
1-10: 0.1 rad/s 49.1-55.1 m, heading <= 13.0 deg, epsilon 0.93-0.99 (flag 0: 7/10 do not stop in 12 s, 38-54 deg,
epsilon 0.08-0.76); 0.2 rad/s 55.6-62.3 m, <= 12.4 deg, epsilon 0.76-0.94 (flag 0: 63.5-73.9 m, 11-28 deg,
0.71-0.76); noise-free and hba_split_mu_80kph unchanged (48.02 m; 71.16 m, 1.84 m, 5.17 deg). Without HBA the same
noise: 73.4-77.2 m, <= 1.4 deg: HBA still yaws up to 13 deg more than no HBA here (not traced: open).
"""
from __future__ import annotations

import numpy as np
import pytest

import vehicle_assist as va

G = 9.80665
K_DRY = 1.17  # brake_assist.md 4.4: peak of the Burckhardt dry asphalt curve (c1 1.2801, c2 23.99, c3 0.52)
EPS_MIN = 0.75  # UN R13 Annex 13 para 5.2 / R13-H Annex 6 adhesion utilisation of an ABS [recollection]
WHEELS = ("fl", "fr", "rl", "rr")
# (sigma, seed): epsilon with esp.gma_follow_flag = 0 (before the fix) in the comment
CASES = [
    (0.1, 11),  # 0.988
    (0.1, 5),  # 0.10, car yaws 52 deg
    (0.1, 1),  # 0.59, 42 deg
    (0.1, 2),  # 0.745, 26 deg
    (0.1, 3),  # 0.64, 39 deg
    (0.1, 7),  # 0.08, 54 deg
    (0.1, 10),  # 0.12, 51 deg
    (0.2, 5),  # 0.74, 18 deg
    (0.2, 11),  # 0.70, 9 deg
    (0.2, 1),  # 0.73, 24 deg
    (0.2, 3),  # 0.71, 28 deg
]
DEFECT = "vehicle.esp.gma_follow_flag=0"  # seeded defect: the GMA stays armed whatever the pressures


def _scenario(sigma: float, seed: int, extra: tuple[str, ...] = ()):
    sets = [f"sensors.wheel_speed_{w}.noise_std_radps={sigma}" for w in WHEELS] + [
        f"run.seed={seed}", "run.duration_s=15", "driver.brake_pedal={time_s=[0,0.1,0.112,15],frac=[0,0,0.1,0.1]}",
        *extra]
    return va.load_scenario("hba_paper_110kph_dry", sets=sets)


def _utilisation(t: np.ndarray, u: np.ndarray) -> float:
    if u.min() > 20.0 / 3.6:
        return 0.0
    t40 = t[np.argmax(u <= 40.0 / 3.6)]
    t20 = t[np.argmax(u <= 20.0 / 3.6)]
    return (20.0 / 3.6) / (t20 - t40) / (K_DRY * G)


@pytest.fixture(scope="module")
def eps():
    keys = [(0.0, 5)] + CASES
    res = va.simulate_batch([_scenario(*k) for k in keys], keep_channels=["time_s", "speed_mps"])
    return {k: _utilisation(np.asarray(res.channels[i]["time_s"]), np.asarray(res.channels[i]["speed_mps"]))
            for i, k in enumerate(keys)}


def test_noise_free_paper_stop_reaches_the_adhesion_utilisation(eps):
    assert eps[(0.0, 5)] >= EPS_MIN  # 0.988 at 51fe1aa


@pytest.mark.parametrize("sigma,seed", CASES)
def test_paper_stop_keeps_the_adhesion_utilisation_with_wheel_speed_noise(eps, sigma, seed):
    assert eps[(sigma, seed)] >= EPS_MIN


def test_adhesion_check_fails_with_the_gma_armed_on_a_dry_road():
    """Seeded defect (esp.gma_follow_flag = 0): 0.1 rad/s seeds 5 / 7 / 10 epsilon 0.10 / 0.08 / 0.12, the
    car yawing 51-54 deg."""
    keys = [(0.1, 5), (0.1, 7), (0.1, 10)]
    res = va.simulate_batch([_scenario(*k, extra=(DEFECT,)) for k in keys], keep_channels=["time_s", "speed_mps"])
    low = [_utilisation(np.asarray(c["time_s"]), np.asarray(c["speed_mps"])) for c in res.channels]
    assert all(e < EPS_MIN for e in low), low
