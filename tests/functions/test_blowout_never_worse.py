"""Never worse than no compensation (requirement tire_blowout.no_worse_than_no_compensation; conventions.md
'Evidence'): the points the falsifier found (issue #10, random search budget 32 seeds 3/7/2026, CMA-ES seed 2026
budget 64, envelope data/envelopes/tire_blowout.toml) as regression variants of the paper scenario. Reference: the
same blowout without compensation (paper 004 Fig. 4 curve 2), compared as the largest lateral deviation from the
blowout to the end of the run. Each case also runs with the seeded defect ``slip_limit_flag = 0`` (the rear
compensating wheel braked past the tire's linear region, the code before the fix) and must then be worse: the
test can fail."""
from __future__ import annotations

import pytest

import vehicle_assist as va

BASE_ON, BASE_OFF = "blowout_lf_60kph_paper", "blowout_lf_60kph_off"
# the code before the rear fixes: neither the nominal rear slip limit nor the measured tire capacity (round 3: the
# capacity rule alone already keeps these points below none, so both are switched off for the negative control)
# Wheel-speed noise fix (signal_filter_flag, tests/functions/test_blowout_noise.py): the code before each rule also judged
# raw wheel samples; with the filtered reference speed (rate-bounded max of the wheels' moving means) several of these
# points are no longer worse than none even without the rule, so every negative control below switches the filter
# off too (RAW) - it then reproduces the code before the rule exactly.
RAW = ["vehicle.blowout_compensation.signal_filter_flag=0"]
# The spin-front rule's phase-plane trigger (phase_plane_flag, session 2026-11-24 e R2) rescues several of these defect
# configurations by itself (e.g. random_seed3 with both rear limits off: 2.74 vs none 5.06 m), so the negative controls
# switch it off too (PP0): the code before each rule had only the mu-0.8 bounds.
PP0 = ["vehicle.blowout_compensation.phase_plane_flag=0"]
NO_REAR_LIMITS = ["vehicle.blowout_compensation.slip_limit_flag=0", "vehicle.blowout_compensation.tire_capacity_flag=0",
                  *RAW, *PP0]
METRIC = "blowout_lateral_deviation_run_max_m"
# (name, speed km/h, road friction scale, detection delay s, blown wheel, driver, lane radius m) as found
CASES = [
    ("random_seed3", 94.39073337792571, 0.44142022469340714, 0.30305613765401995, 2, "follow", 1000),
    ("random_seed7", 113.06838892248363, 0.6079820459509571, 0.44129185599177606, 2, "follow", 0),
    ("random_seed2026", 113.47174862964775, 0.3722907498633082, 0.4722180173458564, 3, "follow", 1000),
    ("cma_seed2026", 48.96074298666105, 0.3604975040417582, 0.11195266110062706, 3, "fixed", 650),
]


def _sets(speed, mu, delay, wheel, driver, radius):
    return [f"run.initial_speed_kph={speed}", f"road.friction_mu={mu}",
            f"vehicle.blowout_compensation.detection_delay_s={delay}", f"vehicle.blowout.wheel_index={wheel}",
            f'vehicle.lane_keeper.steering_mode="{driver}"', f"vehicle.lane_keeper.lane_radius_m={radius}"]


def _run(name, sets):
    return va.simulate(va.load_scenario(name, sets=sets))


def _dev(name, sets):
    return va.simulate(va.load_scenario(name, sets=sets)).metrics[METRIC]


@pytest.fixture(scope="module", params=CASES, ids=[c[0] for c in CASES])
def case(request):
    sets = _sets(*request.param[1:])
    return {"on": _dev(BASE_ON, sets), "off": _dev(BASE_OFF, sets),
            "defect": _dev(BASE_ON, sets + NO_REAR_LIMITS)}


def test_former_counterexample_no_worse(case):
    """With the fix the compensation goes less far off the lane than no compensation."""
    assert case["on"] < case["off"]


def _worse_by_the_rows(run, reference):
    """Session n (N5): what the requirement compares - both never-worse rows of tire_blowout (tests/support.
    never_worse_rows: road deviation clipped at the road edge, and the road departure's earliness); worse = either row's
    robustness < 0. The unclipped run max of before ranked distances beyond the road edge, which the requirement no
    longer does (a correction, not a loosening)."""
    from tests.support import never_worse_rows

    rows = never_worse_rows(run, reference)
    return min(rows.values()) < 0.0, rows


# N5 (session n, class C): at these two points both the defect and the twin leave the road within the 5-s run (road
# deviation tie 3.978 m) and the defect leaves it LATER than the twin, so under the requirement's rows the defect is no
# longer worse: the old unclipped run max ranked how far beyond the road edge each car went.
_C_FORMER = {
    "random_seed3": "defect 5.418 vs twin 5.059 m unclipped; rows: road tie 3.978 m, the defect leaves the road 0.090 s "
                    "after the twin (earliness 27.730 vs 27.820 s)",
    "random_seed7": "defect 6.092 vs twin 4.404 m unclipped; rows: road tie 3.978 m, the defect leaves the road 1.385 s "
                    "after the twin (earliness 26.470 vs 27.855 s)",
}


@pytest.mark.parametrize("c", [pytest.param(c, marks=pytest.mark.xfail(strict=True, reason="N5 (session n, class C): "
                                                                          + _C_FORMER[c[0]]))
                               if c[0] in _C_FORMER else c for c in CASES], ids=[c[0] for c in CASES])
def test_former_counterexample_fails_with_the_defect(c):
    """Negative control: with the seeded defect the same point is a counterexample again - judged by both rows of the
    requirement (N5, session n). Holds at random_seed2026 and cma_seed2026; strict xfail at seeds 3 and 7 (_C_FORMER:
    both cars off the road, the defect later)."""
    sets = _sets(*c[1:])
    worse, rows = _worse_by_the_rows(_run(BASE_ON, sets + NO_REAR_LIMITS), _run(BASE_OFF, sets))
    assert worse, rows


# Points where the car is already at or beyond the stable region when the blowout is found (issue #10 round 2):
# the compensation must refuse (REFUSED, Rajamani 2012 ch. 8 bounds, functions/blowout_compensation.py) and then
# be no worse than none. (name, speed, mu scale, delay, wheel, driver, radius) as found before the refusal.
REFUSAL_CASES = [
    ("random_seed3_r650", 108.07208996733212, 0.3648911275496011, 0.48289170602925424, 2, "follow", 650),
    ("cma_seed2026_r1000", 119.6, 0.3197, 0.4246, 2, "follow", 1000),
]


# Both points are rear-left blowouts whose car crosses the yaw bound rotating toward the blown side: since the
# spin-front rule (spin_front_flag, session 2026-11-24 e) the rear wheel is released there and the right-front wheel
# braked instead (LIMITED, code 5); the refusal itself is checked with that rule off (SPIN0).
SPIN0 = ["vehicle.blowout_compensation.spin_front_flag=0"]


@pytest.fixture(scope="module", params=REFUSAL_CASES, ids=[c[0] for c in REFUSAL_CASES])
def refusal_case(request):
    sets = _sets(*request.param[1:])
    return {"on": _run(BASE_ON, sets), "off": _run(BASE_OFF, sets), "refused": _run(BASE_ON, sets + SPIN0),
            "defect": _run(BASE_ON, sets + ["vehicle.blowout_compensation.stability_refusal_flag=0",
                                             "vehicle.blowout_compensation.tire_capacity_flag=0", *RAW, *PP0])}


def test_refusal_fires_beyond_the_stable_region(refusal_case):
    """Without the spin-front rule the compensation stands down (mode REFUSED, reason code 3 = yaw rate above
    0.85*mu*g/u) and the opposite rear wheel carries no added pressure afterwards; with the refusal disabled (defect)
    it never refuses."""
    from vehicle_assist.functions import blowout_compensation as bc

    on = refusal_case["refused"]
    mode = on.trace["blowout_mode_index"]
    assert (mode == bc.REFUSED).any() and on.metrics["blowout_limit_code"] in (bc.LIMIT_YAW_BOUND, bc.LIMIT_SIDESLIP_BOUND)
    assert any(e.reason == "beyond_stable_region" for e in on.events)
    assert not (refusal_case["defect"].trace["blowout_mode_index"] == bc.REFUSED).any()


@pytest.mark.xfail(strict=True, reason=(
    "N5 (session n, class C): judged by both rows of the requirement the defect (no refusal) is no longer worse than "
    "the twin: both cars leave the road within the 5-s run (road deviation tie 3.978 m) and the defect leaves it 0.015 s "
    "AFTER the twin at both points (earliness r650 27.805 vs 27.820 s, r1000 27.740 vs 27.755 s); the unclipped 13.488 "
    "vs 12.918 m / 12.211 vs 11.740 m ranked distances beyond the road edge"))
def test_refusal_much_less_worse_than_the_defect(refusal_case):
    """Negative control: without the refusal the point is a counterexample of the requirement (worse than none). It
    was > 1 m worse while the plant froze the sliding car at u = 0 (both twins); with the plant's low-speed tyres
    (bffdbd8) the no-compensation twin slides on and the gap is 0.50-0.58 m, so the bound is the requirement's own.
    N5 (session n): judged by both rows (road deviation + departure earliness): a strict xfail (reason)."""
    worse, rows = _worse_by_the_rows(refusal_case["defect"], refusal_case["off"])
    assert worse, rows


def test_refusal_point_no_worse(refusal_case):
    """Spin-front rule: the rear wheel released and the right front braked when the yaw bound is crossed toward the
    blown side; the car does not spin (1.55 vs none 12.92 m, 2.05 vs 11.74 m at 7fc28cc + the rule)."""
    on = refusal_case["on"]
    assert on.metrics["blowout_limit_code"] == 5 and on.metrics[METRIC] <= refusal_case["off"].metrics[METRIC]


@pytest.mark.xfail(strict=True, reason=(
    "N5 (session n, class C): judged by both rows the refusal (spin_front_flag = 0) TIES the twin exactly: both leave "
    "the road (3.978 m) at the same instant (earliness r650 27.820 / 27.820 s, r1000 27.755 / 27.755 s); the 12.944 vs "
    "12.918 m / 11.782 vs 11.740 m of before were distances beyond the road edge"))
def test_refusal_point_worse_without_the_spin_front_rule(refusal_case):
    """Negative control (spin_front_flag = 0, the code before: refusal): the 30-40 ms build before the refusal leaves
    the spinning car farther off than none (12.94 vs 12.92 m, 11.78 vs 11.74 m, the former strict xfail).
    N5 (session n): judged by both rows: a strict xfail (reason)."""
    worse, rows = _worse_by_the_rows(refusal_case["refused"], refusal_case["off"])
    assert worse, rows


def test_rear_blowout_in_curve_wheel_held_stays_in_lane():
    """Issue #10 round 2 (stay-in-lane counterexample, CMA-ES seed 2026): 59 km/h, friction scale 0.68, RR blown,
    0.18 s detection, wheel held, 650 m curve. Lane margin 0.978 m = (3.75 m lane, JTG B01-2014 - 1.794 m BJ2500
    width)/2 (requirement tire_blowout.stay_in_lane). Without compensation 6.62 m. Round 3: the rear limit where
    braking starts to cut lateral force (f(H) >= 1 - s) gives 0.78 m (the round-2 H = 1 limit, d0f65ff, 1.71 m:
    this test was a strict xfail there)."""
    m = _dev(BASE_ON, _sets(59.0, 0.68, 0.18, 3, "fixed", 650))
    assert m <= 0.978


# Found by random search seed 3 with --keep-going after a less conservative rear limit (f(H) >= 1 - s, commit
# 1311689): both were worse than none with it (0.81 vs 0.68 m, 0.83 vs 0.80 m) - the ECU's mu 0.8 over-states a
# ~0.4 road and the larger rear brake force cut the lateral force the axle with the flat tire needs.
LOW_MU_REAR_CASES = [
    ("random_seed3_kg_78kph", 78.46124562420655, 0.3358241697605429, 0.282438755813943, 3, "follow", 650),
    ("random_seed3_kg_81kph", 81.3040424936105, 0.36142911936767924, 0.23297495561538864, 3, "follow", 650),
]


@pytest.mark.parametrize("c", LOW_MU_REAR_CASES, ids=[c[0] for c in LOW_MU_REAR_CASES])
def test_low_friction_rear_points_no_worse(c):
    sets = _sets(*c[1:])
    assert _dev(BASE_ON, sets) < _dev(BASE_OFF, sets)


@pytest.mark.parametrize("c", LOW_MU_REAR_CASES, ids=[c[0] for c in LOW_MU_REAR_CASES])
def test_low_friction_rear_points_fail_without_the_measured_capacity(c):
    """Round 3 negative control: with the f(H) >= 1 - s rear limit planned from the nominal mu 0.8 alone
    (tire_capacity_flag = 0) both points are worse than none again (0.81 vs 0.68 m, 0.83 vs 0.80 m)."""
    sets = _sets(*c[1:])
    assert _dev(BASE_ON, sets + ["vehicle.blowout_compensation.tire_capacity_flag=0", *RAW]) > _dev(BASE_OFF, sets)


# Issue #10 round 3: class (a) of the CMA-ES seed 2026 budget 64 --keep-going search (front blowouts, lane follower,
# friction scale 0.30-0.34 = mu 0.35-0.40, late detection, curves): the ECU planned the front compensating wheel from
# its nominal mu 0.8 with no limit, braked it deep past its linear region (q = F_x/(C_x*s/(1 - s)) ~ 0.2) and the
# lost front lateral force carried the car outward. Fixed by limiting the wheel by what its tire measurably gives
# (tire_capacity_rule, Gustafsson 1997 force-slip); the seeded defect tire_capacity_flag = 0 is the code before.
# (name, speed, mu scale, delay, wheel, driver, radius) as found; defect/off values in the comments (run max, m).
FRONT_LOW_MU_CASES = [
    ("cma2026_112kph_fl_r1000", 112.57283030308757, 0.3032300074351916, 0.4339247139156026, 0, "follow", 1000),  # 1.85 / 1.01
    ("cma2026_120kph_fl_r1000", 119.99996139537232, 0.33903447195311864, 0.3206708459184533, 0, "follow", 1000),  # 2.05 / 1.25
    ("cma2026_92kph_fl_r650", 92.28149898247781, 0.30057466097206187, 0.4999965323614959, 0, "follow", 650),  # 1.29 / 0.60
    ("cma2026_109kph_fl_fixed_r1000", 109.40785379039198, 0.30001133005956643, 0.4324565746667329, 0, "fixed", 1000),  # 3.29 / 3.04
]


@pytest.fixture(scope="module", params=FRONT_LOW_MU_CASES, ids=[c[0] for c in FRONT_LOW_MU_CASES])
def front_case(request):
    sets = _sets(*request.param[1:])
    # understeer_persist_flag (session h, H6) lowers the over-compensating outer front on a persisting yaw shortfall
    # without the capacity evidence, and by itself keeps all four points below none with the capacity rule off (0.47 /
    # 0.64 / 0.33 / 0.55 m): the negative control is the code before each rule, so it is off here too
    return {"on": _dev(BASE_ON, sets), "off": _dev(BASE_OFF, sets),
            "defect": _dev(BASE_ON, sets + ["vehicle.blowout_compensation.tire_capacity_flag=0",
                                            "vehicle.blowout_compensation.understeer_persist_flag=0", *RAW])}


def test_front_low_friction_point_no_worse(front_case):
    """With the measured tire capacity the front compensation goes less far off the lane than none."""
    assert front_case["on"] < front_case["off"]


def test_front_low_friction_point_fails_with_the_defect(front_case):
    """Negative control: planned from mu 0.8 alone (tire_capacity_flag = 0) AND without the understeer rule's
    persistence evidence (understeer_persist_flag = 0) the point is a counterexample again. The capacity rule alone
    kept them below none before session h, the persistence alone does since (0.47 / 0.64 / 0.33 / 0.55 m, tire_blowout_findings.md
    H6): this control shows that the two together are needed against the defect, not that the capacity rule alone is."""
    assert front_case["defect"] > front_case["off"]


# Rear spin points (session 2026-11-23 d, D2): the car spins with and without compensation (run max 17-22 m). Traced
# at cd00652: the compensation holds the yaw rate below none's (0.23 vs 0.31 rad/s at 2.0 s), is refused when r crosses
# 0.85*mu*g/u (1.97-1.99 s), its added pressure is gone 40-70 ms later, and from then the car spins as none does, later
# and faster: at the end of the 5 s run it was 0.7-1.0 m farther (18.84 vs 18.17 m, 21.73 vs 20.72 m; strict xfails).
# Spin-front rule (spin_front_flag, session 2026-11-24 e): at the bound, rotating toward the blown side, the rear
# compensating wheel is released and the front wheel of its side braked to the ECU's lock estimate (ESP oversteer
# intervention, ABS guarding it): the yaw rate falls from 0.25 to 0 within ~1 s and the car does not spin.
# (name, speed, mu scale, delay, wheel, driver, radius): the review's seed-42 point and F3 (random 7 #7, rounded).
SPIN_CASES = [
    ("review_seed42_101kph_rl", 101.9, 0.4685, 0.432, 2, "fixed", 650),  # 7.72 vs 18.17 m (rule off 18.84)
    ("f3_random7_110kph_rl", 110.7, 0.546, 0.293, 2, "fixed", 650),  # 6.78 vs 20.72 m (rule off 21.73)
]


@pytest.fixture(scope="module", params=SPIN_CASES, ids=[c[0] for c in SPIN_CASES])
def spin_case(request):
    sets = _sets(*request.param[1:])
    return {"on": _run(BASE_ON, sets), "off": _run(BASE_OFF, sets), "defect": _run(BASE_ON, sets + SPIN0)}


def test_rear_spin_point_no_worse(spin_case):
    """Requirement tire_blowout.no_worse_than_no_compensation (run max lateral deviation, unchanged): with the
    spin-front rule no farther off than none; the right-front wheel carries the counter-brake and the car stops
    rotating (final yaw rate below the ESP's 5 deg/s dump rate; none ends the run spinning at > 0.9 rad/s)."""
    on, off = spin_case["on"], spin_case["off"]
    assert on.metrics["blowout_limit_code"] == 5
    assert on.metrics[METRIC] <= off.metrics[METRIC]
    assert float(on.trace["wheel_pressure_fr_pa"].max()) > 5e5  # the front wheel braked (> 5 bar)
    assert abs(float(on.trace["yaw_rate_radps"][-1])) < 5.0 * 3.14159 / 180.0


@pytest.mark.xfail(strict=True, reason=(
    "N5 (session n, class C): judged by both rows the refusal (spin_front_flag = 0) is no longer worse than the twin: "
    "both spin off the road within the 5-s run (road deviation tie 3.978 m), the refusal 0.025 s (seed42) / 0.060 s (f3) "
    "AFTER the twin (earliness 28.045 vs 28.070 s, 28.120 vs 28.180 s; unclipped 18.837 vs 18.173, 21.734 vs 20.722 m)"))
def test_rear_spin_point_worse_without_the_spin_front_rule(spin_case):
    """Negative control (spin_front_flag = 0 = the refusal, the code before): a counterexample again. N5 (session n):
    judged by both rows: a strict xfail (reason)."""
    worse, rows = _worse_by_the_rows(spin_case["defect"], spin_case["off"])
    assert worse, rows


# Grid of rear blowouts (session 2026-11-24 e, R: RL/RR x 80/100/120 km/h x friction scale 0.3/0.45/0.6/0.684 x held/
# following driver x straight/650 m left curve x detection delay 0.1/0.4 s = 192 runs): the spin-front rule fired in 37,
# and in none of them was the run max larger than with the refusal (flag 0) or than none (e.g. RL 120 km/h, 0.684 = the
# paper's cement road, held, 650 m, 0.4 s: 1.93 m vs 26.00 m both ways). Kept: the points where the refusal was worse
# than none (the rule's negative control can fail). (name, speed, mu scale, delay, wheel, driver, radius)
SPIN_GRID_CASES = [
    ("grid_rl100_045_fixed_r650", 100.0, 0.45, 0.4, 2, "fixed", 650),  # rule 8.95, refusal 18.25, none 17.54 m
    ("grid_rl120_045_follow_r650", 120.0, 0.45, 0.1, 2, "follow", 650),  # rule 1.63, refusal 15.96, none 15.27 m
    ("grid_rr120_030_fixed_straight", 120.0, 0.3, 0.4, 3, "fixed", 0),  # rule 12.85, refusal 16.47, none 16.18 m
]


@pytest.fixture(scope="module", params=SPIN_GRID_CASES, ids=[c[0] for c in SPIN_GRID_CASES])
def spin_grid_case(request):
    sets = _sets(*request.param[1:])
    return {"on": _run(BASE_ON, sets), "off": _run(BASE_OFF, sets), "defect": _run(BASE_ON, sets + SPIN0)}


def test_spin_grid_point_no_worse(spin_grid_case):
    on = spin_grid_case["on"]
    assert on.metrics["blowout_limit_code"] == 5 and on.metrics[METRIC] <= spin_grid_case["off"].metrics[METRIC]


@pytest.mark.xfail(strict=True, reason=(
    "N5 (session n, class C): judged by both rows the refusal (spin_front_flag = 0) is no longer worse than the twin: "
    "both leave the road within the 5-s run (road deviation tie 3.978 m), the refusal AFTER the twin by 0.030 / 0.050 / "
    "0.035 s (earliness rl100 28.005 vs 28.035, rl120 27.945 vs 27.995, rr120 27.880 vs 27.915 s; unclipped 18.251 vs "
    "17.541, 15.957 vs 15.269, 16.475 vs 16.177 m)"))
def test_spin_grid_point_worse_without_the_spin_front_rule(spin_grid_case):
    """Negative control: spin_front_flag = 0 (the refusal) is a counterexample at these points. N5 (session n): judged
    by both rows: a strict xfail (reason)."""
    worse, rows = _worse_by_the_rows(spin_grid_case["defect"], spin_grid_case["off"])
    assert worse, rows


# F's random seed 7 #7 (round 7, envelope data/envelopes/tire_blowout.toml): RL 110.1 km/h, friction scale 0.48, light
# pedal (44 N) from t_b + 0.24 s, 1000 m, pads at 71 %. FL's ABS activity had started the ESP's split-mu GMA on FR, so
# when the spin-front rule moved the counter-brake to FR (3.39 s) the GMA held FR at the driver's 26.4 bar; the GMA no
# longer delays the spin-front wheel (functions/esp.py). Still worse than none then (17.33 vs 15.94 m: the ECU's yaw
# bound at mu 0.8 is crossed late on this road); since the phase-plane trigger 13.33 m
# (tests/functions/test_blowout_phase_plane.py); only the pressure is checked here.
F_R7_RANDOM7_7 = {"speed": 110.09750464874168, "mu": 0.4796084032566129, "delay": 0.2828648956225929,
                  "wheel_speed_noise": 0.09664899293406753, "noise_seed": 7512.0, "brake_gain": 0.7125984354008801,
                  "brake.start_s": 1.244370545130408, "brake.level_frac": 0.04426463836053247,
                  "brake.rate_per_s": 3.7104449793907452, "braking": "brakes", "wheel": "rl", "driver": "fixed",
                  "curve": "r1000"}


def test_spin_front_wheel_not_held_by_the_gma():
    """After the transfer the right front rises above the driver's (master) pressure by > 5 bar within 0.2 s (the
    build toward its lock estimate). Fails with the GMA delay kept on it (esp.py before: FR stayed at 26.4 bar)."""
    import numpy as np

    from vehicle_assist.verification.envelope import load_envelope

    r = va.simulate(load_envelope("tire_blowout").scenario(F_R7_RANDOM7_7))
    t = np.asarray(r.trace["time_s"])
    ev = [e.time_s for e in r.events if e.machine == "blowout_compensation" and e.to_mode == "LIMITED"]
    assert ev and r.metrics["blowout_limit_code"] == 5
    w = (t > ev[0]) & (t < ev[0] + 0.2)
    lift = np.asarray(r.trace["wheel_pressure_fr_pa"])[w] - np.asarray(r.trace["master_pressure_pa"])[w]
    assert lift.max() > 5e5
