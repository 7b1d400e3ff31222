"""The judging window of tire_blowout's never-worse rows on braking points (session n; session m's M3 in
tire_blowout_findings.md): the regression test of the new horizon.

M3 found five no-fault violations of no_worse_than_no_compensation at the 5-s run (the lead's real sets at main
cc77c3c: rb13 #25, fb5 #33, fb5 #164, rb5 #33, fb5 #191) that were the window: without the function the ESP's reference
speed takes the blown wheel and ABS dumps the driver's pressure (campaign finding F4), so the twin brakes less and was
still moving at 5 s. Since session n the envelope's braking option runs a braking point to standstill (run.duration_s =
30 s, a derived cap; the run ends 1 s after the car is held at rest; data/envelopes/tire_blowout.toml choices.braking)
and the row compares the road deviation (blowout_lateral_deviation_road_max_m) plus the new row
no_earlier_road_departure. Reference: the requirement's own comparative robustness (tests/support.never_worse_rows),
the same car and point with the function disabled (the twin).

Both halves are asserted on each point: with an explicit run.duration_s = 5 (the old window, set after the braking
option) the violation is still there - so the test fails if the function changes at the point and the finding must be
re-read; at the envelope's own horizon there is no violation in either row, and the function's car is at rest at the
end of its run (the horizon is the stop, not the cap). Going back to a 5-s horizon (the envelope's braking option
without run.duration_s) fails the second half."""
from __future__ import annotations

import numpy as np
import pytest

from tests.support import envelope_point_run, never_worse_rows
from vehicle_assist.verification.envelope import load_envelope

OLD_WINDOW = ("run.duration_s=5",)
CAP_S = 30.0  # the braking option's run cap (tire_blowout.toml choices.braking)
REST_MPS = 0.1
POINTS = {
    "RB13_25": {'speed': 117.03508167569677, 'mu': 0.3312650161783546, 'delay': 0.47259254166249653, 'wheel_speed_noise': 0.08510411337670154, 'noise_seed': 8125.0, 'brake_gain': 1.1323021370092148, 'brake.start_s': 0.8563756630703523, 'brake.level_frac': 0.19077154406872682, 'brake.rate_per_s': 28.706500555938508, 'braking': 'brakes', 'wheel': 'rl', 'driver': 'fixed', 'curve': 'r650'},
    "FB5_33": {'speed': 110.11228852205893, 'mu': 0.37420901747149393, 'delay': 0.47908313478308584, 'wheel_speed_noise': 0.16950088378055653, 'noise_seed': 5764.0, 'brake_gain': 1.1472505612762756, 'brake.start_s': 1.0950705759934412, 'brake.level_frac': 0.03506607442251449, 'brake.rate_per_s': 6.6128454249049184, 'braking': 'brakes', 'wheel': 'fl', 'driver': 'fixed', 'curve': 'r650'},
    "FB5_164": {'speed': 116.20613982862008, 'mu': 0.477758988641995, 'delay': 0.05068340868223874, 'wheel_speed_noise': 0.2186491042833377, 'noise_seed': 8623.0, 'brake_gain': 0.8526846959848307, 'brake.start_s': 1.9994726537922196, 'brake.level_frac': 0.3551554514949492, 'brake.rate_per_s': 11.190517922025048, 'braking': 'brakes', 'wheel': 'fl', 'driver': 'fixed', 'curve': 'r650'},
    "RB5_33": {'speed': 93.63276939215716, 'mu': 0.37420901747149393, 'delay': 0.47908313478308584, 'wheel_speed_noise': 0.16950088378055653, 'noise_seed': 5764.0, 'brake_gain': 1.1472505612762756, 'brake.start_s': 1.0950705759934412, 'brake.level_frac': 0.03506607442251449, 'brake.rate_per_s': 6.6128454249049184, 'braking': 'brakes', 'wheel': 'fl', 'driver': 'fixed', 'curve': 'r650'},
    "FB5_191": {'speed': 112.27195150624298, 'mu': 0.33990166736469063, 'delay': 0.32692609457241356, 'wheel_speed_noise': 0.12191390184944517, 'noise_seed': 9845.0, 'brake_gain': 0.7699034950029712, 'brake.start_s': 0.8490498753333051, 'brake.level_frac': 0.3980537089559828, 'brake.rate_per_s': 26.97175254263363, 'braking': 'brakes', 'wheel': 'fl', 'driver': 'fixed', 'curve': 'r1000'},
}


@pytest.fixture(scope="module")
def env():
    return load_envelope("tire_blowout")


def _end(run, channel):
    return float(np.asarray(run.trace[channel])[-1])


@pytest.mark.parametrize("name", list(POINTS))
def test_violation_at_5s_is_not_one_at_standstill(env, name):
    p = POINTS[name]
    on5, tw5 = envelope_point_run(env, p, sets=OLD_WINDOW), envelope_point_run(env, p, baseline=True, sets=OLD_WINDOW)
    assert _end(tw5, "time_s") == pytest.approx(5.0, abs=0.01)
    assert never_worse_rows(on5, tw5)["no_worse_than_no_compensation"] < 0.0  # the violation M3 found (5-s window)
    assert _end(tw5, "speed_mps") > 5.0  # the twin is still moving when the 5-s run ends
    on, tw = envelope_point_run(env, p), envelope_point_run(env, p, baseline=True)  # the envelope's own horizon
    assert 5.0 < _end(on, "time_s") < CAP_S  # ended by the stop, not by the cap
    assert abs(_end(on, "speed_mps")) < REST_MPS  # the function's car is at rest
    rows = never_worse_rows(on, tw)
    assert min(rows.values()) >= 0.0, rows  # to standstill the function is no worse than no function, both rows
