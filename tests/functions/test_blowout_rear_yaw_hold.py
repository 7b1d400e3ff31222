"""Braking rule, rear pair held while the yaw rate exceeds the steered reference toward the blown side
(``rear_oversteer_yaw_flag``, functions/blowout_compensation.py ``rear_oversteer_cap``; session 2026-11-24 g, task G6):
a front blowout while the driver brakes, the car yawing toward the blown side faster than the steering asks, the
sideslip phase plane still inside its region - before, nothing stopped ABS/HBA re-building the rear pair to the
driver's pressure (R1's random 3 b64 #58: FL 93 km/h mu 0.60, 650 m left curve, lane follower, HBA; after the build
the rears went 30 -> 56 bar while the yaw was 0.1-0.27 rad/s toward FL against a 0.04 rad/s reference).

References, independent of the rule's code: the ESP's yaw-rate oversteer criterion (measured yaw rate above the
reference yaw rate of the steering, same sense) and its intervention under braking (no rear-axle pressure build while
oversteering, the rear tires keep their lateral force - van Zanten, SAE 2000-01-1633), the function's closed-loop dead
band (1 deg/s, yaw_deadband_deg_per_s, the toml's assumed value) as the threshold, the no-compensation twin and the
code before (seeded defect rear_oversteer_yaw_flag = 0). Every check of the rule's action fails with the flag at 0."""
from __future__ import annotations

import math

import numpy as np
import pytest

import vehicle_assist as va
from vehicle_assist.functions import blowout_compensation as bc
from vehicle_assist.scenarios.runner import pack_records

DEG = math.pi / 180.0
BAR = 1.0e5
FL, FR = 0, 1
FLAG = "vehicle.blowout_compensation.rear_oversteer_yaw_flag"
METRIC = "blowout_lateral_deviation_run_max_m"

# R1's random 3 b64 #58 (tire_blowout_findings.md R1/G1/G6; /tmp/r1/drag0_rand3/falsify.json history index 58), blowout at 1.0 s
P58 = {"speed": 93.47875142795448, "mu": 0.6048965912388176, "delay": 0.40254229323044655,
       "wheel_speed_noise": 0.0165856936913082, "noise_seed": 1641.0, "brake_gain": 1.1781193320282932,
       "brake.start_s": 1.0597768920215556, "brake.level_frac": 0.39592397464005225,
       "brake.rate_per_s": 18.920911968289428, "braking": "brakes", "wheel": "fl", "driver": "follow", "curve": "r650"}


@pytest.fixture(scope="module")
def params():
    return pack_records([va.load_scenario("blowout_lf_60kph_paper").vehicle.flat()])[0]


def _rule(p, yaw_err, r_ref, mode=bc.HOLD, rears_bar=(48.0, 48.0), periods=10):
    """``periods`` ESP periods of the braking rule, FL blown and released, FR compensating, driver braking (159 bar
    master), no measured friction, the phase-plane state at rest (inside its region); the ESP would re-build the rears
    by 1 bar per period unless capped. Returns the state and the rear pressures."""
    st = bc.initial_state()
    st[bc.S_P_REQ] = 20.0 * BAR
    p_est = np.array([1.0, 45.0, rears_bar[0], rears_bar[1]]) * BAR
    for _ in range(periods):
        bc.braking_rule(st, FL, FR, mode, 1.0, -6.0, 0.0, yaw_err, 159.0 * BAR, p_est, p, r_ref)
        cap = st[bc.S_REAR_CAP]
        for i in (2, 3):  # ABS/HBA re-build toward the driver's pressure, capped by the rule (functions/esp.py)
            p_est[i] = p_est[i] + 1.0 * BAR if cap < 0.0 else min(p_est[i] + 1.0 * BAR, cap)
    return st, p_est


def test_oversteer_toward_the_blown_side_holds_the_rear_pair(params):
    """Yaw 0.14 rad/s toward FL against a 0.04 rad/s reference (error 0.10 rad/s >> 1 deg/s): the pair stays at the
    48 bar it had - not re-built."""
    st, p_est = _rule(params, yaw_err=0.10, r_ref=0.04)
    assert st[bc.S_REAR_CAP] == pytest.approx(48.0 * BAR, abs=1.0)
    assert p_est[2] == pytest.approx(48.0 * BAR, abs=1.0) and p_est[3] == pytest.approx(48.0 * BAR, abs=1.0)


def test_with_the_defect_the_rear_pair_is_rebuilt(params):
    """Negative control (flag 0, the code before): no cap inside the phase-plane region, the pair re-built to 58 bar."""
    p0 = params.copy()
    p0.blowout_compensation_rear_oversteer_yaw_flag = 0.0
    st, p_est = _rule(p0, yaw_err=0.10, r_ref=0.04)
    assert st[bc.S_REAR_CAP] < 0.0
    assert p_est[2] == pytest.approx(58.0 * BAR, abs=1.0)


@pytest.mark.parametrize("yaw_err, r_ref, mode, why", [
    (0.010, 0.04, bc.HOLD, "inside the 1 deg/s dead band (0.0175 rad/s)"),
    (-0.10, 0.04, bc.HOLD, "yawing away from the blown side (understeer in a left curve)"),
    (0.07, -0.10, bc.HOLD, "measured yaw -0.03 rad/s: the car turns right less than steered - not an oversteer"),
    (0.10, 0.04, bc.BUILD, "during the build the released wheel's own moment is still in the yaw"),
])
def test_no_hold_outside_the_oversteer(params, yaw_err, r_ref, mode, why):
    st, _ = _rule(params, yaw_err=yaw_err, r_ref=r_ref, mode=mode)
    assert st[bc.S_REAR_CAP] < 0.0, why


def test_hold_ends_with_the_oversteer(params):
    """Back inside the dead band the cap ends (no latched pressure loss: ABS and the driver again)."""
    st, p_est = _rule(params, yaw_err=0.10, r_ref=0.04)
    assert st[bc.S_REAR_CAP] >= 0.0
    bc.braking_rule(st, FL, FR, bc.HOLD, 1.0, -6.0, 0.0, 0.0, 159.0 * BAR, p_est, params, 0.04)
    assert st[bc.S_REAR_CAP] < 0.0


@pytest.fixture(scope="module")
def runs58():
    from tests.support import envelope_point_run
    from vehicle_assist.verification.envelope import load_envelope

    env = load_envelope("tire_blowout")
    # both rows at the code before esp.named_front_gma_flag (session i, I4): with it the named FL's ABS no longer starts
    # the GMA on FR, #58 is 0.133 m (none 0.357; tests/functions/test_esp_named_front.py) and this rule's window is gone
    named0 = ("vehicle.esp.named_front_gma_flag=0",)
    return {"on": envelope_point_run(env, P58, sets=named0),
            "defect": envelope_point_run(env, P58, sets=(f"{FLAG}=0",) + named0),
            "none": envelope_point_run(env, P58, baseline=True)}


def _rise_while_oversteering(r):
    """Largest rise of the rear pair's pressure [Pa] over 0.1 s windows after the build (compensation HOLD) while the
    measured yaw rate exceeded the steered reference toward FL by more than the dead band."""
    tr = r.trace.channels
    t = np.asarray(tr["time_s"])
    pk = pack_records([va.load_scenario("blowout_lf_60kph_paper").vehicle.flat()])[0]
    r_ref = np.array([bc.reference_yaw_rate(s, v, pk)
                      for s, v in zip(tr["steering_angle_rad"], tr["reference_speed_mps"])])
    err = np.asarray(tr["yaw_rate_radps"]) - r_ref
    mode = np.asarray(tr["blowout_mode_index"])
    rear = np.minimum(np.asarray(tr["wheel_pressure_rl_pa"]), np.asarray(tr["wheel_pressure_rr_pa"]))
    dead = pk.blowout_compensation_yaw_deadband_radps
    n = int(round(0.1 / (t[1] - t[0])))
    worst = 0.0
    for i in range(len(t) - n):
        if mode[i] == bc.HOLD and np.all(err[i:i + n] > dead) and np.all(np.asarray(tr["yaw_rate_radps"])[i:i + n] > 0):
            worst = max(worst, rear[i + n] - rear[i])
    return worst


def test_rear_pair_not_rebuilt_while_oversteering_at_58(runs58):
    """#58 system level: after the build, while the car yaws toward FL beyond the reference, the rear pair does not
    rise (ESP practice). The code before re-built it 30 -> 56 bar in that window."""
    assert _rise_while_oversteering(runs58["on"]) < 1.0 * BAR
    assert _rise_while_oversteering(runs58["defect"]) > 5.0 * BAR


def test_58_closer_to_no_compensation(runs58):
    """#58 lateral deviation: the rule 0.889 m against the code before 1.270 m (none 0.357 m; still a violation - see
    the strict xfail below; a local gain: 6 of 7 perturbations unchanged, tire_blowout.md Session g, G6)."""
    assert runs58["on"].metrics[METRIC] < runs58["defect"].metrics[METRIC]


@pytest.mark.xfail(strict=True, reason=(
    "#58 remains worse than no compensation: before the detection (1.0-1.435 s) the TPMS-named FL is out of the ESP "
    "reference, so the car brakes at the ABS limit (rears 41-50 bar, the diagonally unloaded RR at 8-11 % slip) and "
    "yaws to 0.225 rad/s toward FL while the twin's reference rides the flat FL (30.6 vs 25.4 m/s) and ABS holds its "
    "intact wheels at 3-26 bar (tire_blowout_findings.md G6)"))
def test_58_never_worse_than_no_compensation(runs58):
    assert runs58["on"].metrics[METRIC] <= runs58["none"].metrics[METRIC]
