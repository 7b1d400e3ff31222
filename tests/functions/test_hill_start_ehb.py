"""EV hill-start assist with EHB (functions/hill_start_ehb.py composed in vehicles/ev_ehb.py), paper 001.

References: hill_start_ehb.md 2 (forces, Step1..Step4, Stage-3 guard), 3 (parameters), 4 (scenarios
S1 = ``hsa_ev_5deg_paper``, S2 = ``hsa_ev_flat``, S3 = ``hsa_ev_10deg``, S4 = ``hsa_ev_5deg_hesitating``,
S5/S6 negative controls), 5 (acceptance criteria 3, 4, 6, 10: the ones the scenario checks do not cover);
the controller's docstring (added safety: rollback correction, driver's pedal wins, DEGRADED with the
reason as event, warning, parking-brake request after the maximum hold time); conventions.md "tests make
every row fire".

Fault criterion (issue "slope sensor stuck or biased by 3 deg, pressure sensor lost, EHB pressure limited: no
rollback caused by the assist, or a clear stand-down that leaves the driver's brake in control"): for each
fault run (a) the assisted car with the fault and (b) the same driver inputs *and the same fault events* with
the assist disabled (``enabled_flag=0``), and require rollback(a) <= max(0.01, rollback(b) + 0.01) m. The fault
events are applied to (b) too: the no-assist car does not read the slope or pressure sensors (ev_vcu uses gear,
accelerator and brake pedal only), so for sensor faults (b) is the plain no-assist run; an EHB pressure limit is
the car's condition and also limits the driver's by-wire pressure, so (b) must have it to isolate what the
assist adds. 0.01 m is the rollback tolerance of hill_start_ehb.md / the shipped checks (1 cm: below what a
driver notices, above the numerical creep of the stick/slip model).
"""
from __future__ import annotations

import functools
import glob
import math
import os
import tomllib

import numpy as np
import pytest

import vehicle_assist as va
from tests.support import ehb_limited, events_arg, machine_event, machine_rows, run, sensor_fault, set_input
from vehicle_assist.functions.hill_start_ehb import DEGRADED, HOLD, IDLE, MACHINE, REFUSED
from vehicle_assist.vehicles.ev_ehb import REFUSAL_REASONS
from vehicle_assist.metrics.common import filtered_jerk
from vehicle_assist.plant.longitudinal import aero_drag_n

S1 = "hsa_ev_5deg_paper"
S3 = "hsa_ev_10deg"
S4 = "hsa_ev_5deg_hesitating"
SC = {"S1": S1, "S3": S3}
HSA = "hill_start_ehb"
OFF = "vehicle.hill_start_assist.enabled_flag=0"
NO_ACCELERATOR = "driver.accelerator={time_s=[0.0], frac=[0.0]}"
ROLLBACK_TOL_M = 0.01
G = 9.81
MASS_KG = 1500.0  # compact_ev body mass
CAL_MASS_KG = 1800.0  # the assist's calibration mass (compact_ev.toml: 2100 kg gross / k_s 1.2, rounded up)
BIAS_3DEG_MPS2 = round(G * math.sin(math.radians(3.0)), 4)  # 0.5134: accelerometer reads g*sin(gamma) at rest
PACKAGE_DIR = os.path.dirname(va.__file__)
SHIPPED = sorted(os.path.basename(f)[:-5] for f in glob.glob(os.path.join(PACKAGE_DIR, "data", "scenarios", "hsa_ev_*.toml")))
BASELINE = "ev_5deg_hold_and_pull_away"


# ------------------------------------------------------------------------------------------ helpers


def hsa_rows(r) -> list[tuple[str, str, str]]:
    return machine_rows(r, HSA)


def hsa_event(r, to_mode: str, reason: str | None = None, from_mode: str | None = None):
    return machine_event(r, HSA, to_mode, reason, from_mode)


def rollback(r) -> float:
    return r.metrics["rollback_distance_m"]


def mode(r) -> np.ndarray:
    return r.trace["hsa_mode_index"]


@functools.lru_cache(maxsize=None)
def driving_time_s(sc: str) -> float:
    """When the nominal run first exceeds 1 m/s: the car is driving uphill."""
    r = run(SC[sc])
    return round(float(r.trace["time_s"][np.argmax(r.trace["speed_mps"] > 1.0)]), 2)


# ------------------------------------------------------------------------------------------ 1. faults
NOMINAL_ROWS = [
    ("IDLE", "SLOPE_CHECK", "next_1_brake_released_at_standstill"),
    ("SLOPE_CHECK", "HOLD", "next_2_on_uphill_slope"),
    ("HOLD", "FOLLOW", "next_3_accelerator_pressed"),
    ("FOLLOW", "IDLE", "motor_carries_the_grade"),
]

# case -> (situation overrides for (a) and (b), fault events for (a) and (b), expected DEGRADED entry
# (from mode, reason) or None = the assist does not report this fault)
FAULT_CASES: dict[str, tuple[tuple[str, ...], tuple[str, ...], tuple[str, str] | None]] = {
    # sensors/plant: stuck from t = 0 holds the first sample (see test_slope_sensor_stuck_from_start_*)
    "slope_stuck_from_start": ((), (sensor_fault("longitudinal_accel", "stuck", 0.0),), None),
    # the slope is read only at standstill in IDLE/SLOPE_CHECK: a sensor freezing later must change nothing
    "slope_stuck_during_follow": ((), (sensor_fault("longitudinal_accel", "stuck", 8.0),), None),
    "slope_stuck_while_driving": ((), ("STUCK_WHILE_DRIVING",), None),
    "slope_bias_plus_3deg": ((), (sensor_fault("longitudinal_accel", "bias", 0.0, f", bias_mps2={BIAS_3DEG_MPS2:g}"),), None),
    "slope_bias_minus_3deg": ((), (sensor_fault("longitudinal_accel", "bias", 0.0, f", bias_mps2={-BIAS_3DEG_MPS2:g}"),), None),
    "pressure_lost_in_hold": ((), (sensor_fault("brake_pressure", "lost", 1.5),), ("HOLD", "pressure_sensor_lost")),
    "pressure_lost_in_follow": ((), (sensor_fault("brake_pressure", "lost", 8.0),), ("FOLLOW", "pressure_sensor_lost")),
    # 5 bar cannot hold 5 or 10 deg even with the rolling-resistance reaction ((1282 - 220)/179 = 5.9 bar on 5 deg):
    # the car rolls back under the driver's own (limited) 25 bar pedal from 0.01 s, never stands, next_1 never fires
    "ehb_5bar_from_start": ((), (ehb_limited(0.0),), None),
    # limit hits while the assist holds: the pressure falls to 5 bar, pressure_not_reached after the settle time
    "ehb_5bar_in_hold": ((), (ehb_limited(1.5),), ("HOLD", "pressure_not_reached")),
    # on 4 deg 5 bar holds the car (needs 4.5 bar) but is below 0.9*p_hold (p_hold = 1.2*1800*g*sin 4 deg/179 = 8.2 bar)
    "ehb_5bar_4deg_from_start": (("road.slope_deg=4",), (ehb_limited(0.0),), ("HOLD", "pressure_not_reached")),
}


def fault_runs(sc: str, case: str):
    """(a) assisted with the fault, (b) assist disabled, same driver, same situation and fault events."""
    situation, faults, _ = FAULT_CASES[case]
    faults = tuple(sensor_fault("longitudinal_accel", "stuck", driving_time_s(sc)) if f == "STUCK_WHILE_DRIVING" else f
                   for f in faults)
    a = run(SC[sc], *situation, events_arg(*faults))
    b = run(SC[sc], *situation, events_arg(*faults), OFF)
    return a, b


@pytest.mark.parametrize("sc", sorted(SC))
@pytest.mark.parametrize("case", sorted(FAULT_CASES))
def test_fault_assist_adds_no_rollback_and_reports_degraded(sc, case) -> None:
    """Issue (faults): rollback(a) <= max(0.01, rollback(b) + 0.01) m (module docstring: 1 cm tolerance, (b) = no
    assist with the same driver and fault events). When the controller reports the fault, exactly one DEGRADED
    entry with the guard name as reason (pressure_sensor_lost / pressure_not_reached) from the expected mode, and
    warning_flag == 1 at every sample in DEGRADED and 0 before it (docstring: "raises the driver warning"); the
    parking-brake request stays 0 (only the maximum hold time raises it). Unreported faults never enter DEGRADED."""
    a, b = fault_runs(sc, case)
    assert rollback(a) <= max(ROLLBACK_TOL_M, rollback(b) + ROLLBACK_TOL_M), (rollback(a), rollback(b))
    expected = FAULT_CASES[case][2]
    degraded = [(e.from_mode, e.reason) for e in a.events if e.machine == HSA and e.to_mode == "DEGRADED"]
    if expected is None:
        assert degraded == []
        assert a.trace["warning_flag"].max() == 0.0
        return
    assert degraded == [expected]
    t = a.trace["time_s"]
    t_deg = hsa_event(a, "DEGRADED").time_s
    in_degraded = mode(a) == DEGRADED
    assert in_degraded.any()
    assert np.all(a.trace["warning_flag"][in_degraded] == 1.0)
    assert np.all(a.trace["warning_flag"][t < t_deg - 1e-9] == 0.0)
    assert a.trace["parking_brake_request_flag"].max() == 0.0


def test_slope_sensor_stuck_after_first_true_sample_runs_normal_start() -> None:
    """Slope sensor (longitudinal accelerometer) stuck from the second sample on (0.015 s; plant/sensors.py:
    stuck holds the last value) freezes the true at-rest reading g*sin(5 deg) = 0.855 m/s^2, which is what the
    assist reads at standstill anyway: the normal S1 start (same rows as the nominal run, no rollback at all)."""
    r = run(S1, events_arg(sensor_fault("longitudinal_accel", "stuck", 0.015)))
    assert hsa_rows(r) == NOMINAL_ROWS
    assert rollback(r) == 0.0
    assert r.metrics["final_speed_mps"] == pytest.approx(run(S1).metrics["final_speed_mps"], abs=1e-9)


@pytest.mark.parametrize("sc", sorted(SC))
def test_slope_sensor_stuck_from_start_runs_normal_start(sc) -> None:
    """Slope sensor stuck from t = 0 holds its first sample (plant/sensors.py), which for a car standing on the
    slope is the true at-rest reading g*sin(gamma): the assist must run the normal start (nominal rows, rollback
    0, no DEGRADED) exactly as without the fault."""
    a, _ = fault_runs(sc, "slope_stuck_from_start")
    assert hsa_rows(a) == NOMINAL_ROWS
    assert rollback(a) == 0.0


@pytest.mark.parametrize("sc", sorted(SC))
@pytest.mark.parametrize("case", ["slope_stuck_during_follow", "slope_stuck_while_driving"])
def test_slope_sensor_stuck_later_changes_nothing(sc, case) -> None:
    """Slope sensor stuck at 8 s (FOLLOW, car standing) or 1 s after the start (driving uphill): the assist reads
    the slope only at standstill in IDLE/SLOPE_CHECK, so the run is the nominal one (same rows and event times,
    no rollback, same final speed to 1e-9: the sensor has no other reader)."""
    a, _ = fault_runs(sc, case)
    nominal = run(SC[sc])
    assert [(e.time_s, e.to_mode, e.reason) for e in a.events if e.machine == HSA] == \
        [(e.time_s, e.to_mode, e.reason) for e in nominal.events if e.machine == HSA]
    assert rollback(a) == 0.0
    assert a.metrics["final_speed_mps"] == pytest.approx(nominal.metrics["final_speed_mps"], abs=1e-9)


@pytest.mark.parametrize("sc", sorted(SC))
def test_slope_bias_plus_3deg_overestimate_holds_longer_without_rollback(sc) -> None:
    """Slope sensor biased +3 deg (+0.513 m/s^2): the assist over-estimates F_ang, holds more and releases later
    (FOLLOW -> IDLE later than nominal), never rolls back (0.0 m) and still completes the start (nominal rows) when
    the run is long enough (70 s: the over-estimated grade widens the slow drive-off window)."""
    a = run(SC[sc], "run.duration_s=70", events_arg(*FAULT_CASES["slope_bias_plus_3deg"][1]))
    assert hsa_rows(a) == NOMINAL_ROWS
    assert rollback(a) == 0.0
    t_idle = hsa_event(a, "IDLE", "motor_carries_the_grade").time_s
    assert t_idle > hsa_event(run(SC[sc]), "IDLE", "motor_carries_the_grade").time_s


@pytest.mark.parametrize("sc", sorted(SC))
def test_slope_bias_minus_3deg_rollback_correction_catches_the_car(sc) -> None:
    """Slope sensor biased -3 deg: the assist under-estimates the grade (5 -> 2 deg: hold force
    1.2*1800*g*sin 2 deg + F_margin = 871 N against 1062 N the 1500 kg car needs net of rolling resistance), the car
    starts rolling back when the driver's pressure falls below what holds it, and the controller's rollback
    correction (20 kN/s while v < -0.5 mm/s) raises F_ang until the car is held again. On 10 deg the biased hold
    (1.2*1800*g*sin 7 deg = 2582 N) still holds (needs 2337 N): no correction needed.
    Asserted: rollback < 0.01 m (issue tolerance), on 5 deg the correction acted (max F_ang above the biased
    m_cal*g*sin(2 deg) by >= 1 step of 200 N), the car is held (v == 0) before the accelerator ramp starts (2 s)
    and never rolls back afterwards (not a pass criterion on backward speed: a sensor fault)."""
    a, _ = fault_runs(sc, "slope_bias_minus_3deg")
    t, v = a.trace["time_s"], a.trace["speed_mps"]
    assert rollback(a) < ROLLBACK_TOL_M
    slope_deg = 5.0 if sc == "S1" else 10.0
    biased_f_ang = CAL_MASS_KG * G * math.sin(math.radians(slope_deg - 3.0))
    if sc == "S1":
        assert a.trace["grade_force_estimate_n"].max() >= biased_f_ang + 200.0
    assert np.all(v[(t >= 1.9) & (t <= 2.0)] == 0.0)
    assert np.all(v[t >= 2.0] >= 0.0)
    jerk = filtered_jerk(a.trace)
    k = int(np.argmax(np.abs(jerk)))
    print(f"\n{sc} bias -3 deg: rollback {rollback(a) * 1e3:.2f} mm, backward speed "
          f"{a.metrics['rollback_speed_mps'] * 1e3:.1f} mm/s, peak filtered jerk {jerk[k]:.2f} m/s^3 at {t[k]:.2f} s")


@pytest.mark.parametrize("sc", sorted(SC))
@pytest.mark.parametrize("case", ["pressure_lost_in_hold", "pressure_lost_in_follow"])
def test_pressure_sensor_lost_degrades_and_still_completes_the_start(sc, case) -> None:
    """Pressure sensor lost at 1.5 s (HOLD) or 8 s (FOLLOW): DEGRADED pressure_sensor_lost at the fault time (the
    loss is seen at the same 10 ms sample), the assist keeps holding and releasing with the torque without the
    Stage-3 check (docstring), so the car never rolls back (0.0 m) and the start completes
    (DEGRADED -> IDLE motor_carries_the_grade, which clears the warning)."""
    a, _ = fault_runs(sc, case)
    e = hsa_event(a, "DEGRADED", "pressure_sensor_lost")
    assert e.time_s == pytest.approx(1.5 if case.endswith("hold") else 8.0, abs=1e-9)
    assert rollback(a) == 0.0
    assert hsa_rows(a)[-1] == ("DEGRADED", "IDLE", "motor_carries_the_grade")
    assert a.metrics["final_speed_mps"] > 1.0


@pytest.mark.parametrize("sc", sorted(SC))
def test_ehb_limited_from_start_car_rolls_under_drivers_brake_assist_stays_out(sc) -> None:
    """EHB limited to 5 bar from t = 0 on 5/10 deg: the limit also caps the driver's by-wire 25 bar, and 5 bar
    (897 N) + rolling resistance (220 N) < F_i (1282 N on 5 deg), so the car rolls back from 0.01 s, before the
    driver's pedal release; next_1 needs standstill, so the assist never engages (no event) and the run equals
    the no-assist run with the same limit (rollback to 1e-9). For the record: 87.17 m on S1 vs 83.72 m for the
    healthy no-assist car; the 3.4 m come from the EHB fault, not from the assist."""
    a, b = fault_runs(sc, "ehb_5bar_from_start")
    assert hsa_rows(a) == []
    assert rollback(a) == pytest.approx(rollback(b), abs=1e-9)
    assert a.trace["speed_mps"][a.trace["time_s"] <= 0.011].min() < 0.0


def test_ehb_limited_on_4deg_degrades_without_rollback() -> None:
    """EHB limited to 5 bar, 4 deg (S1 driver): 5 bar holds the car (needs 4.5 bar) but stays below 0.9*p_hold
    (8.2 bar), so HOLD -> DEGRADED pressure_not_reached 0.5 s (settle_time_s) + 1 period after HOLD entry,
    warning on, no rollback (0.0 m), and the start completes (DEGRADED -> IDLE motor_carries_the_grade)."""
    a, b = fault_runs("S1", "ehb_5bar_4deg_from_start")
    hold_in = hsa_event(a, "HOLD").time_s
    e = hsa_event(a, "DEGRADED", "pressure_not_reached", from_mode="HOLD")
    assert e.time_s - hold_in == pytest.approx(0.51, abs=1e-6)
    assert rollback(a) == 0.0 and rollback(b) > 1.0
    assert hsa_rows(a)[-1] == ("DEGRADED", "IDLE", "motor_carries_the_grade")
    assert a.metrics["final_speed_mps"] > 1.0


def test_ehb_limited_in_hold_degraded_assist_still_lets_the_car_pull_away() -> None:
    """EHB limited to 5 bar at 1.5 s (S1, while the assist holds): HOLD -> DEGRADED pressure_not_reached (asserted
    in the fault matrix). A stand-down must leave the driver in control: the DEGRADED assist keeps "releasing with
    the torque" (docstring), so the car pulls away like the no-assist car with the same limit (final speed
    >= 1 m/s, the S1 check) and the assist returns to IDLE (motor_carries_the_grade); F_ang stays physical
    (<= m*g)."""
    a, b = fault_runs("S1", "ehb_5bar_in_hold")
    assert b.metrics["final_speed_mps"] > 1.0
    assert a.trace["grade_force_estimate_n"].max() <= MASS_KG * G
    assert hsa_rows(a)[-1] == ("DEGRADED", "IDLE", "motor_carries_the_grade")
    assert a.metrics["final_speed_mps"] >= 1.0


# ------------------------------------------------------------------------------------------ 2. maximum hold time
MAX_HOLD_5S = "vehicle.hill_start_assist.max_hold_time_s=5"
MAX_HOLD_SETS = (NO_ACCELERATOR, MAX_HOLD_5S, "run.duration_s=15", events_arg(set_input("brake_pedal", 0.5, 12.0)))


def test_max_hold_time_degrades_requests_parking_brake_and_driver_takes_back() -> None:
    """Docstring / hill_start_ehb.md 2.3 (t_hold_max): S1 with max_hold_time_s = 5 and an accelerator never
    pressed (15 s): HOLD -> DEGRADED max_hold_time_reached once the hold time exceeds 5 s (strict '>': HOLD entry
    1.02 s + 5 s + 1 period = 6.03 s), warning and parking_brake_request_flag = 1 from then until the driver
    presses the brake (set_input brake_pedal 0.5 at 12 s) -> IDLE driver_brakes, which clears both; the car
    stays at v == 0 exactly for the whole run (the DEGRADED command F_ang + F_margin = 7.8 bar still holds)."""
    r = run(S1, *MAX_HOLD_SETS)
    t = r.trace["time_s"]
    assert hsa_rows(r) == NOMINAL_ROWS[:2] + [("HOLD", "DEGRADED", "max_hold_time_reached"),
                                             ("DEGRADED", "IDLE", "driver_brakes")]
    t_deg = hsa_event(r, "DEGRADED").time_s
    t_idle = hsa_event(r, "IDLE", "driver_brakes").time_s
    assert t_deg - hsa_event(r, "HOLD").time_s == pytest.approx(5.01, abs=1e-6)
    assert t_idle == pytest.approx(12.0, abs=1e-9)
    degraded = (t >= t_deg - 1e-9) & (t < t_idle - 1e-9)
    assert np.all(r.trace["parking_brake_request_flag"][degraded] == 1.0)
    assert np.all(r.trace["warning_flag"][degraded] == 1.0)
    assert np.all(r.trace["parking_brake_request_flag"][t < t_deg - 1e-9] == 0.0)
    assert np.all(mode(r)[t >= t_idle - 1e-9] == IDLE)
    assert np.all(r.trace["speed_mps"] == 0.0)


def test_max_hold_time_requests_parking_brake_also_when_already_degraded() -> None:
    """hill_start_ehb.md 2.3 (hold time in Step3/Step4 > t_hold_max -> hand over to a parking brake) and the
    docstring (DEGRADED: "after the maximum hold time also the parking-brake request"): pressure sensor lost at
    1.5 s (HOLD -> DEGRADED pressure_sensor_lost), accelerator never pressed, max_hold_time_s = 5: the parking
    brake must be requested once the hold time (from HOLD entry 1.02 s) exceeds 5 s, i.e. by 6.1 s."""
    r = run(S1, NO_ACCELERATOR, MAX_HOLD_5S, "run.duration_s=15", events_arg(sensor_fault("brake_pressure", "lost", 1.5)))
    assert hsa_event(r, "DEGRADED", "pressure_sensor_lost") is not None
    t = r.trace["time_s"]
    assert np.all(r.trace["parking_brake_request_flag"][t >= 6.1] == 1.0)


# ------------------------------------------------------------------------------------------ 2b. refusals
B60 = "driver.brake_pedal={time_s=[0.0, 1.0, 1.3], frac=[0.6, 0.6, 0.0]}"  # the driver holds 60 bar until 1 s
STEP_FULL = "driver.accelerator={time_s=[0.0, 1.3, 1.4], frac=[0.0, 0.0, 1.0]}"  # impatient: full pedal at once
RAMP_FULL = "driver.accelerator={time_s=[2.0, 12.0], frac=[0.0, 1.0]}"
PRESSURE_LOST = events_arg(sensor_fault("brake_pressure", "lost", 1.2))


def situation(slope_deg: float, mu: float, mass_kg: float, *more: str) -> tuple[str, ...]:
    return (f"road.slope_deg={slope_deg:g}", f"road.friction_mu={mu:g}", f"vehicle.body.mass_kg={mass_kg:g}", B60,
            "run.duration_s=30") + more


REFUSAL_CASES: dict[tuple[str, str, str], tuple[str, ...]] = {
    ("IDLE", "REFUSED", "brake_adhesion_limit"): situation(20, 0.3, 1300, STEP_FULL),
    ("HOLD", "REFUSED", "brake_adhesion_limit"): situation(17, 0.3, 2100, RAMP_FULL),
    ("FOLLOW", "REFUSED", "brake_adhesion_limit"): situation(17, 0.3, 2100, STEP_FULL),
    ("FOLLOW", "REFUSED", "traction_limit"): situation(10, 0.3, 1300, STEP_FULL),
    ("FOLLOW", "REFUSED", "grade_beyond_motor_torque"): situation(20, 1.0, 2100, RAMP_FULL),
    ("DEGRADED", "REFUSED", "brake_adhesion_limit"): situation(14, 0.3, 2100, STEP_FULL, PRESSURE_LOST),
    ("DEGRADED", "REFUSED", "traction_limit"): situation(10, 0.3, 1300, STEP_FULL, PRESSURE_LOST),
    ("DEGRADED", "REFUSED", "grade_beyond_motor_torque"): situation(20, 1.0, 2100, RAMP_FULL, PRESSURE_LOST),
    ("REFUSED", "IDLE", "driver_brakes"): situation(20, 0.3, 1300, STEP_FULL, events_arg(set_input("brake_pedal", 1.0, 4.0))),
}


def axle_loads_n(mass_kg: float, slope_deg: float) -> tuple[float, float]:
    """common.md 9 at rest on a grade, with the compact_ev chassis numbers (l = 2.70 m, l_f = 1.13 m, h = 0.55 m)."""
    a = math.radians(slope_deg)
    f_zf = mass_kg * G * (math.cos(a) * (2.70 - 1.13) - math.sin(a) * 0.55) / 2.70
    return f_zf, mass_kg * G * math.cos(a) - f_zf


def start_possible(slope_deg: float, mu: float, mass_kg: float) -> bool:
    """Front-driven: min(motor force 250*8*0.92/0.3, mu*F_zf) > m*g*(sin + f*cos), f = 0.015 (spec 3)."""
    a = math.radians(slope_deg)
    f_zf, _ = axle_loads_n(mass_kg, slope_deg)
    return min(250 * 8 * 0.92 / 0.3, mu * f_zf) > mass_kg * G * (math.sin(a) + 0.015 * math.cos(a))


def hold_possible(slope_deg: float, mu: float, mass_kg: float) -> bool:
    """Four wheels braked to locking: mu*m*g*cos + f*m*g*cos >= m*g*sin (common.md 3.3 with the tyre limit)."""
    a = math.radians(slope_deg)
    return (mu + 0.015) * math.cos(a) >= math.sin(a)


@pytest.mark.parametrize("row", sorted(REFUSAL_CASES), ids=lambda r: f"{r[0]}-{r[2]}")
def test_refusal_where_physics_says_no(row) -> None:
    """Issue #7 (refuse explicitly where physics says no): each constructed case is one where the statics computed
    here (axle loads of common.md 9, tyre limit mu*F_z, motor force 6133 N; not the controller's formulas) say the
    start or the hold is impossible. Asserted: the refusal row fires with the guard = reason, the trace channel
    assist_refusal_code equals 1 + REFUSAL_REASONS.index(reason), warning and parking-brake request are raised,
    the brake stays applied while refused (pressure >= the hold force of the calibration at refusal, to EHB
    tracking), and the car rolls back no further than max(1 cm, the same driver without the assist)."""
    sets = REFUSAL_CASES[row]
    a = run(S1, *sets)
    b = run(S1, *sets, OFF)
    slope, mu, mass = (float(x.split("=")[1]) for x in sets[:3])
    assert not (start_possible(slope, mu, mass) and hold_possible(slope, mu, mass)), "case must be physically impossible"
    assert row in hsa_rows(a)
    refusals = [e for e in a.events if e.machine == HSA and e.to_mode == "REFUSED"]
    reason = refusals[0].reason
    assert reason in REFUSAL_REASONS
    t = a.trace["time_s"]
    refused = mode(a) == REFUSED
    assert refused.any()
    assert np.all(a.trace["assist_refusal_code"][refused] == REFUSAL_REASONS.index(reason) + 1)
    assert np.all(a.trace["warning_flag"][refused] == 1.0) and np.all(a.trace["parking_brake_request_flag"][refused] == 1.0)
    assert a.metrics["assist_refusal_code"] == REFUSAL_REASONS.index(reason) + 1
    assert rollback(a) <= max(ROLLBACK_TOL_M, rollback(b)), (rollback(a), rollback(b))
    assert np.all(a.trace["hsa_pressure_command_pa"][refused] > 10e5)  # brake held (> 10 bar) while refused
    if row[0] != "REFUSED":
        assert a.metrics["peak_speed_mps"] < 0.05  # no start was attempted past the refusal


def test_refusal_reasons_contract() -> None:
    """Brief contract: vehicles/ev_ehb.REFUSAL_REASONS are the guard names of the refusal rows of the machine (code
    k >= 1 means REFUSAL_REASONS[k-1]), and the trace has the channel assist_refusal_code."""
    from vehicle_assist.vehicles import ev_ehb

    into_refused = {t.guard for t in MACHINE.transitions if t.target == "REFUSED"}
    assert set(REFUSAL_REASONS) == into_refused
    assert REFUSAL_REASONS == ("brake_adhesion_limit", "traction_limit", "grade_beyond_motor_torque")
    assert "assist_refusal_code" in ev_ehb.CHANNELS


def test_startable_case_is_not_refused_and_does_not_roll_back() -> None:
    """Control for the refusal tests: 1300 kg on 17 deg, mu 1.0 (start possible by the statics above) is started
    without a refusal, v >= -1 mm/s (paper 001 P8)."""
    a = run(S1, *situation(17, 1.0, 1300, RAMP_FULL))
    assert start_possible(17, 1.0, 1300) and hold_possible(17, 1.0, 1300)
    assert a.metrics["assist_refusal_code"] == 0
    assert a.metrics["rollback_speed_mps"] <= 1e-3
    assert a.metrics["peak_speed_mps"] > 0.05


def test_no_traction_torque_above_the_drivers_request() -> None:
    """Issue #7 item 3 (functional safety): over every shipped hsa_ev scenario and every refusal case the motor-torque
    command never exceeds the driver's own request (the former torque floor is gone); the hesitating driver is still
    held by the brake (criterion 6 is tested below)."""
    runs = [run(name) for name in SHIPPED] + [run(S1, *sets) for sets in REFUSAL_CASES.values()]
    for r in runs:
        excess = r.trace["motor_torque_request_nm"] - r.trace["driver_torque_request_nm"]
        assert excess.max() <= 1e-9


def test_seeded_defect_light_calibration_rolls_a_heavy_car_back() -> None:
    """Issue #8 seeded defect: with calibration_mass_kg = 1300 the hold is 1.2*1300*g*sin 15 deg = 3961 N, while a
    2100 kg car needs 2100*g*(sin 15 deg - 0.015*cos 15 deg) = 5033 N (statics, computed here): it must roll back
    faster than the paper's -1 mm/s; the shipped calibration (1800 kg: 4571 N + margin... 1.2*1800*g*sin 15 = 5484 N)
    holds it."""
    sets = situation(15, 1.0, 2100, RAMP_FULL)
    need = 2100 * G * (math.sin(math.radians(15)) - 0.015 * math.cos(math.radians(15)))
    assert 1.2 * 1300 * G * math.sin(math.radians(15)) < need < 1.2 * CAL_MASS_KG * G * math.sin(math.radians(15))
    weak = run(S1, *sets, "vehicle.hill_start_assist.calibration_mass_kg=1300")
    assert weak.metrics["rollback_speed_mps"] > 1e-3
    assert run(S1, *sets).metrics["rollback_speed_mps"] <= 1e-3


# driver creeping up 2 deg lifts the accelerator from 0.3 to 0.1 at 32 s (S4-like dip at 0.01 /s): the car stops and
# rolls back after the assist has handed back
LIFT_SETS = ("road.slope_deg=2", "vehicle.body.mass_kg=1900", B60, "run.duration_s=45",
             "driver.accelerator={time_s=[2.0, 32.0, 32.001, 32.67, 122.67], frac=[0.0, 0.3, 0.1, 0.1, 1.0]}")


def test_rollback_after_hand_back_is_caught() -> None:
    """Issue #7 (hesitating driver, never worse than no assist): after FOLLOW -> IDLE the driver lifts the accelerator
    while creeping up 2 deg; the 1900 kg car stops and rolls back with nobody braking. Statics (computed here): the
    remaining 0.1 pedal (5.4 N*m -> 134 N) is below 1900*g*(sin 2 deg - 0.015*cos 2 deg) = 371 N, so it must roll
    without a brake. Asserted: the assist re-holds it (IDLE -> HOLD rollback_in_drive) with no rollback behind
    the start and a backward speed of a few mm/s (detection at 0.5 mm/s + EHB build-up), against metres without
    the assist (same driver)."""
    assert 5.44 * 8 * 0.92 / 0.3 < 1900 * G * (math.sin(math.radians(2)) - 0.015 * math.cos(math.radians(2)))
    a, b = run(S1, *LIFT_SETS), run(S1, *LIFT_SETS, OFF)
    assert ("IDLE", "HOLD", "rollback_in_drive") in hsa_rows(a)
    assert rollback(b) > 1.0
    assert rollback(a) <= 1e-3 and a.metrics["rollback_speed_mps"] < 5e-3
    print(f"\nrollback after hand back: {rollback(a) * 1e3:.2f} mm at {a.metrics['rollback_speed_mps'] * 1e3:.1f} mm/s "
          f"(no assist {rollback(b):.1f} m)")


SLOPE_LOST = events_arg(sensor_fault("longitudinal_accel", "lost", 0.0))


def test_slope_sensor_lost_before_the_slope_check_stands_down_with_a_warning() -> None:
    """Review finding (issue #7, decisions from measurements only): with the longitudinal accelerometer lost from t = 0
    there is no grade reading; the assist used to decide 'level_road' from its default grade 0 and stay out silently
    (the car rolled back 83.7 m like the no-assist car, no warning). Now SLOPE_CHECK -> IDLE slope_sensor_lost and
    the driver warning stays on (HSA not available); never worse than no assist (rollback <= max(1 cm, no assist)).
    Control: the sensor lost at 0.5 s, after a valid reading at this standstill, still gives the normal start."""
    a = run(S1, SLOPE_LOST)
    b = run(S1, SLOPE_LOST, OFF)
    assert hsa_rows(a) == [NOMINAL_ROWS[0], ("SLOPE_CHECK", "IDLE", "slope_sensor_lost")]
    t_idle = hsa_event(a, "IDLE", "slope_sensor_lost").time_s
    t = a.trace["time_s"]
    assert np.all(a.trace["warning_flag"][t >= t_idle + 0.01] == 1.0)
    assert np.all(a.trace["warning_flag"][t < t_idle - 1e-9] == 0.0)
    assert rollback(a) <= max(ROLLBACK_TOL_M, rollback(b))
    later = run(S1, events_arg(sensor_fault("longitudinal_accel", "lost", 0.5)))
    assert hsa_rows(later) == NOMINAL_ROWS and rollback(later) == 0.0


# ------------------------------------------------------------------------------------------ 3. every row fires
def constructed_cases() -> list[tuple[str, tuple[str, ...], tuple[str, str, str]]]:
    """(scenario, overrides, the row it is made for) for rows that the shipped scenarios do not reach."""
    return [
        (S1, (events_arg(set_input("brake_pedal", 0.5, 2.5)),), ("HOLD", "IDLE", "driver_brakes")),  # HOLD 1.02-2.89 s
        (S1, (events_arg(set_input("brake_pedal", 0.5, 8.0)),), ("FOLLOW", "IDLE", "driver_brakes")),  # FOLLOW to 19.6 s
        (S1, (events_arg(sensor_fault("brake_pressure", "lost", 1.5)),), ("HOLD", "DEGRADED", "pressure_sensor_lost")),
        (S1, (events_arg(sensor_fault("brake_pressure", "lost", 8.0)),), ("FOLLOW", "DEGRADED", "pressure_sensor_lost")),
        (S1, ("road.slope_deg=4", events_arg(ehb_limited(0.0))), ("HOLD", "DEGRADED", "pressure_not_reached")),
        (S1, MAX_HOLD_SETS, ("HOLD", "DEGRADED", "max_hold_time_reached")),
        (S1, (MAX_HOLD_5S,), ("FOLLOW", "DEGRADED", "max_hold_time_reached")),  # FOLLOW from 2.89 s, limit at 6.03 s
        (S1, MAX_HOLD_SETS, ("DEGRADED", "IDLE", "driver_brakes")),
        (S1, (events_arg(sensor_fault("brake_pressure", "lost", 1.5)),), ("DEGRADED", "IDLE", "motor_carries_the_grade")),
    ] + [(S1, sets, row) for row, sets in REFUSAL_CASES.items()] + [(S1, LIFT_SETS, ("IDLE", "HOLD", "rollback_in_drive")),
         (S1, (SLOPE_LOST,), ("SLOPE_CHECK", "IDLE", "slope_sensor_lost"))]


def test_every_machine_row_fires() -> None:
    """conventions.md "tests make every row fire": the union of (from, to, reason) of machine hill_start_ehb over
    the shipped hsa_ev_* scenarios, the no-assist baseline, the fault runs of this file and the constructed cases
    equals the rows of MACHINE.transitions (no dead row, no event outside the table)."""
    seen: set[tuple[str, str, str]] = set()
    for name in SHIPPED + [BASELINE]:
        seen.update(hsa_rows(run(name)))
    for case in FAULT_CASES:
        for sc in SC:
            seen.update(hsa_rows(fault_runs(sc, case)[0]))
    for name, sets, _ in constructed_cases():
        seen.update(hsa_rows(run(name, *sets)))
    rows = {(t.source, t.target, t.guard) for t in MACHINE.transitions}
    assert len(rows) == len(MACHINE.transitions) == 25
    assert not rows - seen, f"rows never fired: {sorted(rows - seen)}"
    assert not seen - rows, f"events outside the table: {sorted(seen - rows)}"


def test_constructed_cases_hit_their_rows() -> None:
    """Each constructed case logs the row it was made for (the row test does not pass by luck of another run)."""
    for name, sets, row in constructed_cases():
        assert row in hsa_rows(run(name, *sets)), (row, hsa_rows(run(name, *sets)))


def test_shipped_scenarios_cover_the_nominal_rows() -> None:
    """The shipped scenarios alone fire the paper's Step1..Step4 rows and the flat-road row (S2, criterion 7)."""
    seen: set[tuple[str, str, str]] = set()
    for name in SHIPPED:
        seen.update(hsa_rows(run(name)))
    assert set(NOMINAL_ROWS) | {("SLOPE_CHECK", "IDLE", "level_road")} <= seen
    assert hsa_rows(run(BASELINE)) == []  # assist disabled: the machine never runs


# ------------------------------------------------------------------------------------------ 4. criteria of section 5
NOMINAL = [S1, S3, S4]


@pytest.mark.parametrize("name", NOMINAL)
def test_criterion_4_residual_pressure_at_p2(name) -> None:
    """hill_start_ehb.md 5.4 (paper P4): at the first recorded sample where the drive force reaches the grade
    resistance (F_t >= F_i) the brake pressure is > 0 (strictly: the criterion is qualitative; the design margin
    F_margin = 0.5*G*f*cos(gamma) gives ~0.65 bar). Checked from the trace, incl. S4 which has no P2 check."""
    r = run(name)
    f_t, f_i = r.trace["drive_force_n"], r.trace["grade_resistance_n"]
    reached = f_t >= f_i
    assert reached.any()
    k = int(np.argmax(reached))
    assert r.trace["brake_pressure_pa"][k] > 0.0


def held_before_breakaway(r) -> np.ndarray:
    """Samples from HOLD entry up to (excluding) the first sample the car is not held (breakaway)."""
    t = r.trace["time_s"]
    t_hold = hsa_event(r, "HOLD").time_s
    after_hold = t >= t_hold - 1e-9
    not_held = after_hold & (r.trace["vehicle_held_flag"] < 0.5)
    end = int(np.argmax(not_held)) if not_held.any() else len(t)
    return after_hold & (np.arange(len(t)) < end)


@pytest.mark.parametrize("name", [
    S1,
    S3,
    S4,  # hesitating driver: the brake (kept at the hold factor) covers the torque the driver takes back
])
def test_criterion_6_force_sum_invariant_while_held(name) -> None:
    """hill_start_ehb.md 5.6 (P4/P5): drive_force_n + service_brake_capacity_n >= grade_resistance_n at every
    held sample from HOLD entry to breakaway (exact inequality, no tolerance: the criterion excludes the rolling
    resistance; the follow step keeps F_b + F_tq at the hold force k_s*F_ang + F_margin)."""
    r = run(name)
    m = held_before_breakaway(r)
    assert m.sum() > 100  # the held phase is long (several seconds at 10 ms)
    assert np.all(r.trace["vehicle_held_flag"][m] == 1.0)
    slack = r.trace["drive_force_n"] + r.trace["service_brake_capacity_n"] - r.trace["grade_resistance_n"]
    k = int(np.argmin(np.where(m, slack, np.inf)))
    assert slack[k] >= 0.0, (r.trace["time_s"][k], slack[k])


@pytest.mark.parametrize("name,sets", [(S1, ()), (S3, ()), (S4, ()), (S1, MAX_HOLD_SETS)],
                         ids=["S1", "S3", "S4", "S1-max-hold"])
def test_criterion_3_standstill_exact_while_hold(name, sets) -> None:
    """hill_start_ehb.md 5.3: in Step3 (HOLD) v == 0 exactly (the stick/slip model holds the car at exactly zero
    speed, so no tolerance) and the car is held; plus p >= 0.95*p_cmd after the 0.25 s settle time, checked here for
    S4 and the long (5 s) hold (hold_force_ratio: brake capacity over the plant's true grade force >= 0.95*k_s)."""
    r = run(name, *sets)
    hold = mode(r) == HOLD
    assert hold.sum() > 100
    assert np.all(r.trace["speed_mps"][hold] == 0.0)
    assert np.all(r.trace["vehicle_held_flag"][hold] == 1.0)
    assert r.metrics["hold_force_ratio"] >= 0.95 * 1.2


def test_criterion_10_drag_formula_units() -> None:
    """hill_start_ehb.md 5.10 / common.md 3.1: C_D*A*u_a^2/21.15 (u_a in km/h) equals 0.5*1.2258*C_D*A*v^2 (v in
    m/s) within 0.1 %, with the compact_ev drag_area_m2 (C_D*A = 0.30*2.2 = 0.66 m^2) and the plant's
    aero_drag_n. The two constants differ by 0.022 % (21.15 is rounded: 2*3.6^2/1.2258 = 21.145); 0.1 % is the
    spec's tolerance."""
    with open(os.path.join(PACKAGE_DIR, "data", "vehicles", "compact_ev.toml"), "rb") as f:
        drag_area = tomllib.load(f)["body"]["drag_area_m2"]
    assert drag_area == pytest.approx(0.30 * 2.2)
    for v in (0.5, 1.0, 5.0, 13.9, 27.8, 40.0):
        u_kmh = 3.6 * v
        textbook = drag_area * u_kmh ** 2 / 21.15
        plant = aero_drag_n(drag_area, v)
        assert plant == pytest.approx(0.5 * 1.2258 * drag_area * v * v, rel=1e-12)
        assert abs(plant - textbook) / textbook < 1e-3
    assert aero_drag_n(drag_area, -10.0) == pytest.approx(-aero_drag_n(drag_area, 10.0))  # opposes motion


def test_no_idle_slope_check_flapping_on_a_level_road():
    """next_1 fires once per brake application: on a level road the pedal release gives one
    IDLE -> SLOPE_CHECK -> IDLE round trip, not one per controller period (found: 15 round trips)."""
    r = va.simulate(va.load_scenario("hsa_ev_flat"))
    rows = [(e.from_mode, e.to_mode) for e in r.events if e.machine == "hill_start_ehb"]
    assert rows == [("IDLE", "SLOPE_CHECK"), ("SLOPE_CHECK", "IDLE")]


def test_light_brake_touch_does_not_end_the_hold():
    """hill_start_ehb.md 2.3 hands back on a brake press; a touch whose own pressure (3 bar) cannot hold the car
    must not end the hold (found: 13.85 m rollback). The assist hands over only once the driver's request
    carries its pressure; the EHB applies the larger of the two meanwhile."""
    sets = ['driver.accelerator={time_s=[0.0], frac=[0.0]}', "run.duration_s=8",
            'events=[{at_s=4.0, action="set_input", input="brake_pedal", value=0.03}]']
    r = va.simulate(va.load_scenario("hsa_ev_5deg_paper", sets))
    assert r.metrics["rollback_distance_m"] == 0.0
    assert not any(e.to_mode == "IDLE" and e.reason == "driver_brakes" for e in r.events if e.machine == "hill_start_ehb")


# ------------------------------------------------------------------------------------------ 5. review (issue #7)
def test_assist_torque_ceiling_is_never_above_the_drivers_request() -> None:
    """Issue #7 item 4, at the controller (the plant's min() in vehicles/ev_ehb.py makes torque_above_driver_nm 0 by
    construction, so that metric alone cannot see a controller that asks for more): wherever the assist sets a
    ceiling (channel torque_ceiling_nm < 1e8: FOLLOW/DEGRADED), it is <= the driver's request of the same sample.
    Reference: the requirement itself (no traction torque the driver did not ask for); shipped hsa_ev scenarios,
    the refusal cases and the hand-back case."""
    runs = [run(name) for name in SHIPPED] + [run(S1, *sets) for sets in REFUSAL_CASES.values()] + [run(S1, *LIFT_SETS)]
    checked = 0
    for r in runs:
        ceiling, driver = r.trace["torque_ceiling_nm"], r.trace["driver_torque_request_nm"]
        limited = ceiling < 1e8
        checked += int(limited.sum())
        assert np.all(ceiling[limited] <= driver[limited] + 1e-9), float(np.max((ceiling - driver)[limited]))
    assert checked > 10_000  # the ceiling is set over long stretches (FOLLOW lasts ~26 s in S1 alone)


def test_torque_above_driver_metric_can_fail() -> None:
    """The metric torque_above_driver_nm is 0 in every plant run by construction; this shows that it reports an excess
    when one is there (synthetic trace: a command 12.5 N*m above the request at one sample -> 12.5)."""
    from vehicle_assist.metrics.hill_start_ehb import torque_above_driver_nm

    class T(dict):
        batch_size = None

    trace = T(motor_torque_request_nm=np.array([0.0, 50.0, 62.5, 40.0]),
              driver_torque_request_nm=np.array([0.0, 50.0, 50.0, 60.0]))
    assert torque_above_driver_nm(trace) == pytest.approx(12.5)


def test_criterion_8_reapply_equals_the_drop_of_the_motor_force() -> None:
    """hill_start_ehb.md 5.8 (S4): when the driver backs off, p rises toward (F_ang - F_tq + F_margin)*r/K_b_tot, i.e.
    the brake takes over the drive force the motor gives up (force sum of P4/P5 kept). Reference: the plant's own
    motor force channel (truth, not the controller's estimate) and K_b_tot/r computed here from the caliper data
    (53.76 N*m/bar / 0.30 m = 179.2 N/bar, as in test_ev_closed_form). The pressure rise must be >= 90 % of
    (motor force before the dip - motor force in the dip)/(K_b_tot/r) (~941 N -> 5.25 bar; the shipped check asks
    only >= 1 bar). 10 % covers the 10 ms period and the EHB lag."""
    r = run(S4)
    t, f_m, p = r.trace["time_s"], r.trace["motor_force_n"], r.trace["brake_pressure_pa"]
    k_f = 2 * 0.38 * math.pi * 0.054**2 / 4 * 0.110
    k_r = 2 * 0.38 * math.pi * 0.036**2 / 4 * 0.100
    n_per_pa = (2 * k_f + 2 * k_r) / 0.30
    before = (t > 15.2) & (t < 15.33)  # pedal at 0.30, car still held
    dip = (t > 15.6) & (t < 16.0)  # pedal at 0.10
    assert np.all(r.trace["vehicle_held_flag"][before | dip] == 1.0)
    drop_n = f_m[before].mean() - f_m[dip].mean()
    assert drop_n > 800.0  # 0.30 -> 0.10 pedal: 44 -> 5.4 N*m (spec 2.4 curve) = ~940 N at the wheels
    rise_pa = p[dip].max() - p[before].min()
    assert rise_pa >= 0.9 * drop_n / n_per_pa, (rise_pa / 1e5, drop_n / n_per_pa / 1e5)


@pytest.mark.xfail(strict=True, reason="hill_start_ehb.md 5.5 second half NOT met: the assist stays in FOLLOW (Step4) "
                   "5.5 s after v > v_start on S1 while its jerk-limited torque ceiling catches up with the driver's "
                   "request (the brake itself is at 0 after 0.45 s); see docs/functions/hill_start_ehb.md")
@pytest.mark.parametrize("name", [S1, S3])
def test_criterion_5_assist_back_in_step1_within_2s(name) -> None:
    """hill_start_ehb.md 5.5: 'p < 0.1 bar within 2 s after v first exceeds v_start, and EHB state = Step1'. The
    scenario checks cover the pressure (release_after_start_s); this is the state half (assist_idle_after_start_s,
    time from v > 0.05 m/s to IDLE). Known FAIL (strict xfail: it turns red when it starts to pass, so the note
    gets updated)."""
    r = run(name)
    assert r.metrics["release_after_start_s"] <= 2.0
    assert r.metrics["assist_idle_after_start_s"] <= 2.0, r.metrics["assist_idle_after_start_s"]


def test_refusal_reason_on_steep_low_mu_is_the_physical_one_known_weakness() -> None:
    """Refusal reason computed from measurements vs the statics of common.md 9 (computed here): 1300 kg on 22 deg,
    mu 0.6, front-driven: mu*F_zf = 3542 N < grade + rolling 4955 N < motor 6133 N, so the start is impossible because
    of *traction*, and the brakes can hold ((0.6 + 0.015)*cos 22 deg = 0.570 > sin 22 deg = 0.375). Documented
    weakness: the assist reports grade_beyond_motor_torque, because with the motor at its maximum and no wheel-spin
    signal (the lumped plant sets the motor speed to v*i_0/r, so a saturated tyre is invisible) it can tell a
    traction limit only for cars the calibration's heaviest car would be carried by the motor (k_s*m_cal*g*sin +
    F_margin <= motor force, below ~16.8 deg). Asserted: it refuses (the brake held, no start) - and that the
    reason is the wrong one, so this test turns red when a wheel-speed signal fixes it."""
    sets = situation(22, 0.6, 1300, RAMP_FULL)
    f_zf, _ = axle_loads_n(1300, 22)
    a = math.radians(22)
    need = 1300 * G * (math.sin(a) + 0.015 * math.cos(a))
    assert 0.6 * f_zf < need < 250 * 8 * 0.92 / 0.3 and hold_possible(22, 0.6, 1300)
    r = run(S1, *sets)
    reasons = [e.reason for e in r.events if e.machine == HSA and e.to_mode == "REFUSED"]
    assert reasons, "an impossible start must be refused"
    assert r.metrics["peak_speed_mps"] < 0.05
    assert reasons[0] == "grade_beyond_motor_torque"  # physically: traction_limit (see docstring)


@pytest.mark.parametrize("slope_deg", [5, 10])
def test_full_pedal_in_neutral_keeps_the_car_held(slope_deg) -> None:
    """Review finding: the driver shifts to N while held (D at next_1) and floors the accelerator. The VCU gives no
    torque in N (ev_vcu: 'N none'), so nothing but the brake holds the car; the assist's probe release at the motor's
    maximum was triggered by the driver's *request* alone and let the car creep back at up to 4.9 mm/s (8 mm on
    10 deg) in repeated bursts. Reference: paper 001 P8 / hill_start_ehb.md 5.1 (v >= -1 mm/s), and the statics:
    with zero drive force the brake must carry m*g*(sin - f*cos) - the assist's hold does, so v == 0 exactly."""
    sets = (f"road.slope_deg={slope_deg}", 'driver.gear_lever={time_s=[0.0, 1.5], gear=["D", "N"]}',
            "driver.accelerator={time_s=[0.0, 4.0, 5.0], frac=[0.0, 0.0, 1.0]}", "run.duration_s=40")
    r = run(S1, *sets)
    assert r.trace["motor_torque_nm"].max() == 0.0
    assert np.all(r.trace["speed_mps"] == 0.0), r.trace["speed_mps"].min()
