"""Issue #9 second review (paper 002): a driver who eases off after a panic application.

References (independent of the code under test):
* hydraulics: an ABS inlet valve has a return check valve in parallel (std: Bosch Automotive Handbook, ABS
  hydraulic modulator), so with the switching valve open (plain-ABS hold H, pulsed build from the master BPM) a
  wheel pressure above the master pressure flows back to the master cylinder when the driver eases off: the
  wheel never stays above the driver's pressure by more than the line lag. Before the fix a plain-ABS hold kept
  56.6 bar on the front wheels for ~1 s while the driver had eased to 35.8 bar (dry, mu scale 0.6, 80 km/h).
* conventions "never worse than no assist": with HBA the same stop is not longer than without it. Before the fix
  the no-HBA twin gained from that trapped pressure (HBA correctly ramps out to the driver, paper P8), and HBA
  was up to 6.7 m "worse" on a 192-pair grid of panic-then-ease pedals (23 pairs worse by > 1 mm).
"""
from __future__ import annotations

import numpy as np
import pytest

import vehicle_assist as va
from vehicle_assist.plant.brakes import esp_unit as U

W = ("fl", "fr", "rl", "rr")


def _ease(peak, ease, v_kph, mu, surface="dry", mass=1600, hba=1):
    left, right = ("dry", "snow") if surface == "split" else (surface, surface)
    return va.load_scenario("hba_paper_110kph_dry", sets=[
        f"driver.brake_pedal={{time_s=[0,0.1,0.112,0.4,0.7,40],frac=[0,0,{peak},{peak},{peak * ease},{peak * ease}]}}",
        f"run.initial_speed_kph={v_kph}", f'vehicle.surface.left="{left}"', f'vehicle.surface.right="{right}"',
        "run.duration_s=40", f"vehicle.body.mass_kg={mass}", f"road.friction_mu={mu}",
        f"vehicle.brake_assist.enabled_flag={hba}"])


@pytest.mark.parametrize("mode", [U.H, U.BPM])
def test_open_circuit_modes_let_a_higher_wheel_pressure_back_to_the_master(mode):
    """Plain-ABS hold and pulsed build with the switching valve open: wheel 60 bar, driver 30 bar -> falls."""
    p, p_src, dt, tau = 60e5, 30e5, 5e-4, 0.015
    new = U.wheel_pressure_step(mode, p, p_src, dt, tau, 300e5, 200e5, 0.3, 0.03, 1e5, 200e5, 300e5)
    assert p_src <= new < p
    for _ in range(400):  # 0.2 s = 13 tau_line
        p = U.wheel_pressure_step(mode, p, p_src, dt, tau, 300e5, 200e5, 0.3, 0.03, 1e5, 200e5, 300e5)
    assert p == pytest.approx(p_src, abs=0.1e5)
    # HI (switching valve closed, HBA hold) keeps the pressure: the return path ends at the closed USV
    assert U.wheel_pressure_step(U.HI, 60e5, 30e5, dt, tau, 300e5, 200e5, 0.3, 0.03, 1e5, 200e5, 300e5) == 60e5


def test_plain_abs_wheel_follows_an_easing_driver_down():
    """No HBA, panic 200 N then eased to 60 N at 0.7 s: 0.2 s later no front wheel is > 1 bar above the master."""
    tr = va.simulate(_ease(0.2, 0.3, 80, 0.6, hba=0)).trace
    t = tr["time_s"]
    late = (t >= 0.9) & (tr["speed_mps"] > 1.0)
    for w in ("fl", "fr"):
        excess = tr[f"wheel_pressure_{w}_pa"][late] - tr["master_pressure_pa"][late]
        assert np.max(excess) <= 1e5, (w, np.max(excess) / 1e5)


EASE_CASES = [(0.2, 0.3, 80, 0.6, "dry", 1600), (0.2, 0.3, 120, 0.6, "dry", 1600), (0.12, 0.3, 40, 1.0, "split", 2000),
              (0.12, 0.3, 120, 0.6, "wet", 2000), (0.12, 0.3, 80, 0.6, "wet", 1600)]


def test_hba_not_worse_than_no_hba_when_the_driver_eases_off():
    scs = [_ease(*c[:4], surface=c[4], mass=c[5], hba=h) for c in EASE_CASES for h in (1, 0)]
    m = va.simulate_batch(scs).metrics
    for i, case in enumerate(EASE_CASES):
        on, off = m[2 * i]["stopping_distance_m"], m[2 * i + 1]["stopping_distance_m"]
        assert on <= off + 1e-3, (case, on, off)
