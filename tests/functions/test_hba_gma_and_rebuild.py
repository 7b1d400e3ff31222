"""Issue #9 third review (paper 002): HBA never worse than no HBA in path and steering on split-mu, and in stopping
distance where the driver is just above the lock pressure.

References (independent of the code under test): the same stop with HBA off (conventions "never worse than no
assist"; the twin shares the car, road and driver, only ``brake_assist.enabled_flag`` differs), and the UN R13-H
Annex 6 split-surface steering limits 120 deg in the first 2 s / 240 deg in all (as recalled; the clause text
could not be retrieved, see data/requirements/brake_assist.toml). Each check is also run with its seeded defect
(``vehicle.esp.gma_hba_flag=0``: the pump lifts the high-mu front wheel past the yaw-moment build-up delay;
``vehicle.esp.hba_master_rebuild_flag=0``: the pump re-builds a circuit whose source is undecided) to show it fails.
"""
from __future__ import annotations

import pytest

import vehicle_assist as va

SPLIT = "hba_split_mu_80kph"


def _split_pair(defect: bool):
    sets = ["vehicle.esp.gma_hba_flag=0"] if defect else []
    on, off = va.simulate_batch([va.load_scenario(SPLIT, sets=sets),
                                 va.load_scenario(SPLIT, sets=[*sets, "vehicle.brake_assist.enabled_flag=0"])]).metrics
    return on, off


def _split_not_worse(on, off) -> list[str]:
    """Names of the path/steering measures where HBA is worse than no HBA (floors as the requirement rows)."""
    worse = []
    for metric, floor in (("lateral_deviation_max_m", 0.01), ("heading_max_deg", 0.1),
                          ("steering_correction_max_deg", 1.0)):
        if on[metric] > max(floor, off[metric]):
            worse.append(f"{metric}: {on[metric]:.3f} with HBA vs {off[metric]:.3f} without")
    return worse


@pytest.fixture(scope="module")
def split_fixed():
    return _split_pair(defect=False)


def test_split_mu_hba_is_not_worse_in_offset_heading_and_steering(split_fixed):
    on, off = split_fixed
    assert on["hba_activated_flag"] == 1.0
    assert _split_not_worse(on, off) == []
    # and not longer (before: 70.0 vs 75.7 m, bought with the extra yaw moment)
    assert on["stopping_distance_m"] <= off["stopping_distance_m"] + 1e-9


def test_split_mu_steering_within_the_recalled_r13h_split_surface_limits(split_fixed):
    on, _ = split_fixed
    assert on["steering_correction_2s_deg"] <= 120.0  # R13-H Annex 6 (as recalled): initial 2 s
    assert on["steering_correction_max_deg"] <= 240.0  # R13-H Annex 6 (as recalled): in all


def test_split_mu_check_fails_with_the_pump_past_the_gma():
    """Seeded defect: before the fix 2.04 vs 1.56 m, 7.8 vs 4.9 deg, 229 vs 55 deg (issue #9 OPEN 1)."""
    on, off = _split_pair(defect=True)
    worse = _split_not_worse(on, off)
    assert len(worse) == 3, worse


def _p147(hba: int, defect: bool):
    """The CMA-ES counterexample: 128.6 km/h, wet, mu scale 0.763, 1769 kg, 98 N at 17 /s, held to standstill."""
    level, rate = 0.098, 17.0
    sets = [f"driver.brake_pedal={{time_s=[0,0.1,{0.1 + level / rate},40],frac=[0,0,{level},{level}]}}",
            "run.initial_speed_kph=128.6", "road.friction_mu=0.763", 'vehicle.surface.left="wet"',
            'vehicle.surface.right="wet"', "run.duration_s=40", "vehicle.body.mass_kg=1769",
            f"vehicle.brake_assist.enabled_flag={hba}"]
    if defect:
        sets.append("vehicle.esp.hba_master_rebuild_flag=0")
    return va.load_scenario("hba_paper_110kph_dry", sets=sets)


def _assert_hba_not_longer(build, defect: bool, defect_longer_m: float):
    """HBA on vs off at one point: never longer; with the seeded defect longer by more than ``defect_longer_m``."""
    on, off = va.simulate_batch([build(1, defect), build(0, defect)]).metrics
    assert on["hba_activated_flag"] == 1.0
    longer = on["stopping_distance_m"] - off["stopping_distance_m"]
    if defect:
        assert longer > defect_longer_m
    else:
        assert longer <= 0.0


@pytest.mark.parametrize("defect", [False, True])
def test_driver_just_above_the_lock_pressure_hba_not_longer(defect):
    _assert_hba_not_longer(_p147, defect, 0.05)  # the seeded defect brings the counterexample back (0.107 m)


def _easing_split(hba: int, defect: bool):
    """Easing driver on split-mu: 73.1 km/h, mu scale 0.837, 1685 kg, panic 115 N in 4 ms, eased to 53 N from 0.48 s
    after the peak over 0.3 s, held (HBA exits on the pressure drop).

    History: CMA-ES seed 2026 found the defect at 94.8 km/h, mu scale 0.771, 1804 kg, 123 N eased to 35 N (HBA 0.047 m
    longer than none with the flag at 0, 447e251); with the 3-sample ABS wheel deceleration (2493eb2) that point gives
    only +0.0014 m, so the seeded defect no longer showed there. This point is from a random search of the
    brake_assist envelope ranges (split surface, driver 'ease', panic rates 5-30 /s; 64 points, 2 with the defect
    worse than no HBA, none with the shipped flag) at 7f24564: with these rounded coordinates 83.45 m with the flag
    at 0 vs 83.06 m without HBA (+0.389 m), shipped flag 83.06 m (equal). Of 24 neighbours within +-3 % of every
    coordinate 16 have the defect longer by 0.35-1.01 m, 1 equal, 7 shorter (the defect changes the ABS phase on
    the snow side, so its sign is not smooth); the shipped flag is equal to no HBA at all 24."""
    level, t_peak = 0.11488, 0.1 + 0.11488 / 27.52915
    sets = [f"driver.brake_pedal={{time_s=[0.1,{t_peak},{t_peak + 0.47784},{t_peak + 0.77784}],"
            f"frac=[0,{level},{level},{level * 0.45721}]}}", "run.initial_speed_kph=73.07556",
            "road.friction_mu=0.83734", 'vehicle.surface.left="dry"', 'vehicle.surface.right="snow"',
            "run.duration_s=40", "vehicle.body.mass_kg=1685.2823", f"vehicle.brake_assist.enabled_flag={hba}"]
    if defect:
        sets.append("vehicle.esp.hba_rampout_pumped_only_flag=0")
    return va.load_scenario("hba_paper_110kph_dry", sets=sets)


@pytest.mark.parametrize("defect", [False, True])
def test_easing_driver_on_split_mu_hba_not_longer(defect):
    """The ramp-out must not act on pressure the driver left by easing off (a circuit the pump never served)."""
    _assert_hba_not_longer(_easing_split, defect, 0.02)  # seeded defect: +0.389 m (0.047 m at the 447e251 point)


def _release_split(hba: int, defect: bool):
    """Random seed 7 counterexample: 85 km/h, split-mu, mu scale 0.949, 1788 kg, panic 99 N in 11 ms, released at
    1.88 s over 0.2 s (the car rolls on, steering held). The driver's falling pressure left the GMA-held high-mu
    front above it; latching that as 'pump-served' pumped the circuit's rear wheel."""
    sets = ["driver.brake_pedal={time_s=[0.1,0.110921,1.883317,2.083317],frac=[0,0.0985538693975539,"
            "0.0985538693975539,0]}", "run.initial_speed_kph=85.01145599256003", "road.friction_mu=0.9486069004847877",
            'vehicle.surface.left="dry"', 'vehicle.surface.right="snow"', "run.duration_s=40",
            "vehicle.body.mass_kg=1787.8428451225968", f"vehicle.brake_assist.enabled_flag={hba}"]
    if defect:
        sets.append("vehicle.esp.hba_rampout_pumped_only_flag=0")
    return va.load_scenario("hba_paper_110kph_dry", sets=sets)


@pytest.mark.parametrize("defect", [False, True])
def test_released_pedal_on_split_mu_hba_not_worse_in_path(defect):
    on, off = va.simulate_batch([_release_split(1, defect), _release_split(0, defect)]).metrics
    assert on["hba_activated_flag"] == 1.0
    worse = on["lateral_deviation_max_m"] - max(0.01, off["lateral_deviation_max_m"])
    if defect:
        assert worse > 0.1  # seeded defect: 44.24 vs 43.64 m (the car rolls on for 38 s after the release)
    else:
        assert worse <= 0.0
