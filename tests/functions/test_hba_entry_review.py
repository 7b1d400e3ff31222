"""HBA entry conditions (4) 'pedal applied' and (5) 'pressure rising' each block the entry on their own
(issue #9 second review: the existing entry test varied only speed, sensor, ABS, pressure level and rate).

Reference: paper 002 P3 (all six entry conditions are required) and brake_assist.md 3 (rising = p_mc increased on
each of the last N_RISE = 2 samples; rate latched for T_WIN = 20 ms). Hand-made 5 ms samples, no plant.
"""
from __future__ import annotations

import pytest

import vehicle_assist as va
from vehicle_assist.functions import brake_assist as H
from vehicle_assist.scenarios.runner import pack_records


@pytest.fixture(scope="module")
def params():
    return pack_records([va.load_scenario("hba_paper_110kph_dry").vehicle.flat()])[0]


def _modes(params, samples, dt=0.005):
    st, g, out = H.initial_state(), H.guard_buffer(), []
    for p_bar, pedal in samples:
        new, _ = H.hba_step(st, p_bar * 1e5, 100.0 / 3.6, pedal, True, True, True, dt, params, g)
        out.append(H.MODES[new])
    return out


def test_no_entry_without_the_pedal_applied(params):
    """0, 20, 40, 60 bar at 4000 bar/s, 100 km/h, sensor and ABS healthy, but the brake-light switch off."""
    assert _modes(params, [(p, True) for p in (0.0, 20.0, 40.0, 60.0)])[-1] == "ACTIVE"  # control: enters
    assert all(m == "INACTIVE" for m in _modes(params, [(p, False) for p in (0.0, 20.0, 40.0, 60.0)]))


def test_no_entry_unless_the_pressure_rose_on_the_last_two_samples(params):
    """0 -> 40 bar in one 5 ms sample (8000 bar/s, latched for 20 ms) then flat at 40 bar: level, rate (latched),
    speed, pedal and health all hold inside T_WIN, but the pressure rose on one sample only, then not at all."""
    out = _modes(params, [(0.0, True), (40.0, True), (40.0, True), (40.0, True), (40.0, True)])
    assert all(m == "INACTIVE" for m in out), out
    # control: one more rising sample inside the latch window enters
    assert _modes(params, [(0.0, True), (40.0, True), (41.0, True)])[-1] == "ACTIVE"
