"""The 5-s horizon of tire_blowout.no_worse_than_no_compensation on braking points (session m, M3;
tire_blowout_findings.md M3). No rule: a finding for the requirement, kept as a test so that it can be re-checked.

Reference: the spec's never-worse requirement - the same car, same point, the function disabled (the twin: ESP/ABS
alone), the metric blowout_lateral_deviation_run_max_m; the requirement's own text says a car that stops keeps its last
offset and the run max covers it - which holds only if the cars stop inside the run. The envelope runs 5 s
(max_duration_s). Without the function the ESP's reference speed takes the blown wheel and ABS dumps the driver's
pressure (campaign finding F4): the twin brakes less and is still moving at 5 s. Points: the lead's real sets at main
cc77c3c (rb13 #25, fb5 #33, fb5 #164, rb5 #33, fb5 #191), each a no-fault violation at 5 s. Run to standstill
(run.duration_s = 12: the function's car stopped, so its run max is final and the twin's can only grow),
each function run is no worse than its twin. Both halves are asserted: the
5-s violation (so the test fails once the function changes there and the finding must be re-read) and the standstill
verdict (fails if the function's car ends worse)."""
from __future__ import annotations

import numpy as np
import pytest

import vehicle_assist as va
from vehicle_assist.verification.envelope import load_envelope

M = "blowout_lateral_deviation_run_max_m"
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


def _run(env, point, baseline, seconds):
    sc = env.scenario(point, baseline=baseline)
    if seconds is not None:
        sc = sc.with_sets(f"run.duration_s={seconds}")
    return va.simulate(sc, requirements=False)


@pytest.mark.parametrize("name", list(POINTS))
def test_violation_at_5s_is_not_one_at_standstill(env, name):
    p = POINTS[name]
    # the 5-s window of session m, given explicitly (session n: the envelope runs braking points to standstill)
    on5, tw5 = _run(env, p, False, 5), _run(env, p, True, 5)
    t5 = np.asarray(tw5.trace["time_s"])
    assert t5[-1] == pytest.approx(5.0, abs=0.01)
    assert on5.metrics[M] > tw5.metrics[M]  # the violation the falsifier found (5-s horizon)
    assert np.asarray(tw5.trace["speed_mps"])[-1] > 5.0  # the twin is still moving when the run ends
    on, tw = _run(env, p, False, 12), _run(env, p, True, 12)
    # the function's car has stopped, so its run max is final; the twin's can only grow with a longer run (a max over
    # time): fn <= twin at 12 s holds for every longer run (rb13 #25's twin is spinning backwards at 12 s)
    assert abs(np.asarray(on.trace["speed_mps"])[-1]) < 0.1
    assert on.metrics[M] <= tw.metrics[M]  # to standstill the function is no worse than no function
