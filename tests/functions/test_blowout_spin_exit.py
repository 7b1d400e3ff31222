"""Exit of the spin-front rule (``spin_exit_flag``, functions/blowout_compensation.py ``spin_stopped``; open item 5 of
session 2026-11-24 e, findings_F.md Z): once the car has stayed back inside the stable region - the mu-0.8 refusal
bounds (Rajamani 2012 ch. 8), the sideslip phase plane (Inagaki et al. 1994), the yaw deviation from the steered
reference within the closed-loop dead band and the spin's heading taken back - for the settling time of the ECU's
single-track yaw mode, the front wheel is released and the rear compensating wheel re-planned to the balance.
References: the requirement tire_blowout.no_worse_than_no_compensation against the no-compensation twin, and what an
ESP's oversteer intervention does once the oversteer is over (the outer front wheel released). The rule's own unit
checks are in tests/functions/test_blowout_compensation.py (row LIMITED->BUILD spin_stopped). Each check below fails
with the seeded defect spin_exit_flag = 0 (no exit: the front wheel braked to the end of the run)."""
from __future__ import annotations

import pytest

import vehicle_assist as va

BASE_ON, BASE_OFF = "blowout_lf_60kph_paper", "blowout_lf_60kph_off"
METRIC = "blowout_lateral_deviation_run_max_m"
EXIT0 = ["vehicle.blowout_compensation.spin_exit_flag=0"]


def _sets(speed, mu, delay, wheel, driver, radius):
    return [f"run.initial_speed_kph={speed}", f"road.friction_mu={mu}",
            f"vehicle.blowout_compensation.detection_delay_s={delay}", f"vehicle.blowout.wheel_index={wheel}",
            f'vehicle.lane_keeper.steering_mode="{driver}"', f"vehicle.lane_keeper.lane_radius_m={radius}"]


# R2's rear grid (session 2026-11-24 e: RL/RR x 80/100/120 km/h x friction scale x driver x straight/650 m x delay
# 0.1/0.4 s): the three points where the phase-plane trigger left the car 0.11-0.42 m farther off than the mu-0.8
# trigger alone - the front wheel held to the end of the run, the car drifting out of the curve at 5 s.
# (name, speed km/h, friction scale, delay s, wheel, driver, radius m): no exit / exit / none [m]
CASES = [
    ("rl120_030_fixed_r650", 120.0, 0.3, 0.1, 2, "fixed", 650),  # 1.388 / 0.660 / 6.328
    ("rl120_030_follow_r650", 120.0, 0.3, 0.1, 2, "follow", 650),  # 1.851 / 1.309 (0.984 before the re-entry) / 6.932
    ("rl120_045_follow_r650", 120.0, 0.45, 0.1, 2, "follow", 650),  # 1.737 / 1.708 / 15.269
]


@pytest.fixture(scope="module", params=CASES, ids=[c[0] for c in CASES])
def case(request):
    sets = _sets(*request.param[1:])
    return {"on": va.simulate(va.load_scenario(BASE_ON, sets=sets)),
            "off": va.simulate(va.load_scenario(BASE_OFF, sets=sets)),
            "defect": va.simulate(va.load_scenario(BASE_ON, sets=sets + EXIT0))}


def _exits(r):
    return [e.time_s for e in r.events if e.machine == "blowout_compensation" and e.reason == "spin_stopped"]


def _front_released_after_exit(r):
    """The right front (the spin-front wheel of an RL blowout) below 1 bar at some sample after the first exit."""
    c = r.trace.channels
    ex = _exits(r)
    if not ex:
        return False
    after = c["time_s"] >= ex[0]
    return bool((c["wheel_pressure_fr_pa"][after] < 1.0e5).any())


def test_spin_front_wheel_released_once_the_spin_is_over(case):
    """The oversteer intervention ends: the spin stopped (row LIMITED->BUILD spin_stopped) and the right front wheel
    goes back to the driver's pressure (none here: < 1 bar); the run no farther off than without compensation."""
    on = case["on"]
    assert _exits(on) and _front_released_after_exit(on)
    assert on.metrics[METRIC] <= case["off"].metrics[METRIC]


def test_without_the_exit_the_front_stays_braked(case):
    """Negative control (spin_exit_flag = 0, the code before): no exit, the right front braked to the end (> 5 bar)."""
    d = case["defect"]
    assert not _exits(d) and not _front_released_after_exit(d)
    assert float(d.trace.channels["wheel_pressure_fr_pa"][-1]) > 5.0e5


# Re-entry after an exit (spin_reentry_flag, functions/blowout_compensation.py spin_resumed): the rear-grid point where
# the exit did most harm (findings_F.md Z: RL 120 km/h, friction scale 0.45, wheel held, 650 m, detection 0.4 s): after
# the exit at 3.10 s the rear re-planned at the nominal mu 0.8 and the car oversteered slowly inside both stability
# bounds to the end. No exit 1.688 m, exit without re-entry 2.524 m, with it 1.709 m (none 13.958 m).
REENTRY_PT = (120.0, 0.45, 0.4, 2, "fixed", 650)
REENTRY0 = ["vehicle.blowout_compensation.spin_reentry_flag=0"]


@pytest.fixture(scope="module")
def reentry_case():
    sets = _sets(*REENTRY_PT)
    return {"on": va.simulate(va.load_scenario(BASE_ON, sets=sets)),
            "defect": va.simulate(va.load_scenario(BASE_ON, sets=sets + REENTRY0)),
            "no_exit": va.simulate(va.load_scenario(BASE_ON, sets=sets + EXIT0)),
            "off": va.simulate(va.load_scenario(BASE_OFF, sets=sets))}


def _reentries(r):
    ex = _exits(r)
    return [e.time_s for e in r.events if e.machine == "blowout_compensation" and e.to_mode == "LIMITED"
            and ex and e.time_s > ex[0]]


def test_spin_front_taken_up_again_after_the_exit(reentry_case):
    """After the exit the yaw deviation toward the blown side leaves the dead band: the front counter-brake is taken up
    again (BUILD/HOLD -> LIMITED after the first spin_stopped) and the car ends less far off than with the exit alone
    (the negative control, spin_reentry_flag = 0: the slow oversteer to the end of the run, no re-entry)."""
    on, d = reentry_case["on"], reentry_case["defect"]
    assert _reentries(on) and not _reentries(d)
    assert on.metrics[METRIC] < d.metrics[METRIC]
    assert on.metrics[METRIC] <= reentry_case["off"].metrics[METRIC]


@pytest.mark.xfail(strict=True, reason="open (findings_F.md Z, task Z2): with the re-entry 1.709 m vs 1.688 m without "
                   "the exit (RL 100/120 km/h 0.3 held 0.4 s: 3.639/3.077 vs 3.402/2.875 m) - the front released at "
                   "the exit and the rear re-planned at mu 0.8 let the car yaw toward the blown side until re-entry")
def test_reentry_point_no_worse_than_without_the_exit(reentry_case):
    """Acceptance of task Z2: no rear-grid point worse than with spin_exit_flag = 0."""
    assert reentry_case["on"].metrics[METRIC] <= reentry_case["no_exit"].metrics[METRIC]
