"""The ECU's wheel-pressure estimate (functions/esp.py ``_estimate``) with the EHB accumulator of paper 004.

Issue #10: in blowout builds the estimate read ~30 % above the plant's wheel pressure (62 vs 49 bar at the end of
the paper test's build, 20 bar while the plant's inlet was still in its dead time): the ECU's model left out the
inlet's dead time t0 and took one explicit Euler step per 5 ms period. Reference (independent of the code): the
exponential fill through the inlet that the SUV file's accumulator time constant is derived from (tire_blowout.md
5 eq. 29 and section 7; suv_bj2500.toml esp_unit.accumulator_time_constant_s):

    p(t) = p_acc - (p_acc - p_0) * exp(-(t - t0)/tau)   for t > t0 after the inlet opens, p_0 before;

the pulsed build BP passes duty x the flow (tau/duty). With p_acc = 120 bar, tau = 78 ms, t0 = 15 ms, 5 ms periods.
"""
from __future__ import annotations

import math

import pytest

import vehicle_assist as va
from vehicle_assist.functions import esp
from tests.support import ecu_pressure_estimates

P_ACC, TAU, T0, DT, DUTY = 120e5, 0.078, 0.015, 0.005, 0.3  # suv_bj2500.toml [esp_unit], [esp] period_s


@pytest.fixture(scope="module")
def params():
    from vehicle_assist.scenarios.runner import pack_records

    return pack_records([va.load_scenario("blowout_lf_60kph_paper").vehicle.flat()])[0]


def _run(params, modes, p0=0.0):
    """ECU estimate after each period for a sequence of wheel modes, as esp_step carries the inlet timer."""
    return ecu_pressure_estimates(params, modes, p0, DT)


def test_accumulator_build_follows_the_dead_time_and_exponential_fill(params) -> None:
    """Continuous build B from 0 bar: 0 until t0, then p_acc*(1 - exp(-(t - t0)/tau)) (to 0.01 bar, 200 ms).
    The old estimate read 56.8 bar at 50 ms where the fill gives 43.4 bar."""
    est = _run(params, [esp.W_B] * 40)
    for k, p in enumerate(est):
        t = (k + 1) * DT
        ref = 0.0 if t <= T0 else P_ACC * (1.0 - math.exp(-(t - T0) / TAU))
        assert p == pytest.approx(ref, abs=1e3), t


def test_pulsed_build_and_reopened_inlet(params) -> None:
    """BP from 20 bar: duty x the flow after t0; an inlet closed in between (HI) waits t0 again when it reopens."""
    est = _run(params, [esp.W_BP] * 10 + [esp.W_HI] * 2 + [esp.W_B] * 6, p0=20e5)
    p10 = P_ACC - (P_ACC - 20e5) * math.exp(-DUTY * (10 * DT - T0) / TAU)
    assert est[9] == pytest.approx(p10, abs=1e3)
    assert est[11] == est[9]  # hold
    assert est[14] == pytest.approx(p10, abs=1e3)  # 15 ms dead time after reopening
    assert est[17] == pytest.approx(P_ACC - (P_ACC - p10) * math.exp(-3 * DT / TAU), abs=1e3)


def test_return_pump_estimate_unchanged(params) -> None:
    """The sedan's return pump (no dead time in the plant): B builds at G_pump = 300 bar/s from the first period."""
    from vehicle_assist.scenarios.runner import pack_records

    sedan = pack_records([va.load_scenario("hba_paper_110kph_dry").vehicle.flat()])[0]
    est = _run(sedan, [esp.W_B] * 4)
    assert est[0] == pytest.approx(300e5 * DT) and est[3] == pytest.approx(4 * 300e5 * DT)


# ---------------------------------------------------------------------------------------------------------------
# Mode N (session i, I9): the estimate in mode N (``esp.pressure_estimate_line_flag``;
# 0 = seeded defect, the code before: the estimate took the source pressure at once).
#
# In mode N the inlet is open and the circuit open to the master cylinder: the wheel cylinder fills (or drains) through
# the line and valve, it does not jump to the source. The ECU has no wheel-pressure sensor; its estimate must follow the
# wheel, because it is stored as the lock level at an ABS dump's start (S_P_PREDUMP: the blowout braking rule's re-build
# ceiling and braking_lock_floor's level). Finding I1 (session i): a dump one period after N stored the 167.8-bar source
# while the wheel was far below it.
#
# References, independent of ``_estimate``:
# * the plant's wheel-cylinder response (plant/brakes/esp_unit.py ``wheel_pressure_step``, row N) integrated at the
#   scenarios' plant step (0.5 ms, ten times finer than the ESP period) after a step of the source, and the closed form
#   of a first-order fill p(t) = p_src + (p0 - p_src) exp(-t/tau_line) (the plant's stated row-N law);
# * a closed-loop panic stop (blowout_panic_stop_80kph at mu 0.45, pad 0.7: I1's case), where the plant's wheel pressure
#   at every ABS dump's start is compared with the ECU model's estimate replayed along the run's valve modes and source
#   pressures.
#
# Bound: ERROR_BOUND_PA = 5 bar (assumed: the accuracy of the only pressure the ECU measures, its master-cylinder
# sensor -
# an ESP pressure sensor of 250 bar full scale at +-2 % FS; an estimate need not be better than the measurement it is
# driven by). Away from the pedal's onset ramp (where the source itself moves ~12 bar per ESP period and the estimate,
# which holds the sampled source over its period, lags the plant by that much - not judged) every comparison must be
# within it.
import numpy as np  # noqa: E402

from vehicle_assist.plant.brakes import esp_unit  # noqa: E402

FLAG = "vehicle.esp.pressure_estimate_line_flag"
PLANT_DT = 0.0005  # the scenarios' plant_step_s
ERROR_BOUND_PA = 5.0e5  # assumed, section comment (master-pressure sensor accuracy class)
BAR = 1.0e5


def _n_params(scenario, *sets):
    from vehicle_assist.scenarios.runner import pack_records

    return pack_records([va.load_scenario(scenario, list(sets)).vehicle.flat()])[0]


@pytest.fixture(scope="module")
def n_params():
    """The vehicles' parameters (the line estimate A_P_LINE runs at every value of the flag; value 1 - the whole
    estimate through the line lag, I9's candidate - was deleted in session j, J2), SUV and sedan."""
    return {
        "suv": _n_params("blowout_panic_stop_80kph"),
        "sedan": _n_params("hba_snow_60kph"),
        "suv_defect": _n_params("blowout_panic_stop_80kph", f"{FLAG}=0"),
    }


def plant_fill(p, p0, p_src, n_periods):
    """Plant wheel pressure after each ESP period, row N, source held at p_src (plant/brakes/esp_unit.py)."""
    out, pw = [], p0
    sub = int(round(DT / PLANT_DT))
    for _ in range(n_periods):
        for _ in range(sub):
            pw = esp_unit.wheel_pressure_step(esp_unit.N, pw, p_src, PLANT_DT, p.esp_unit_line_time_constant_s, 0.0,
                                              p.esp_unit_pump_relief_pa, p.esp_unit_pulse_duty_frac,
                                              p.esp_unit_dump_time_constant_s, p.esp_unit_lpa_pressure_pa,
                                              p.esp_unit_exit_rate_pa_per_s, p.esp_unit_pump_build_rate_pa_per_s)
        out.append(pw)
    return np.array(out)


def estimate_fill(p, p0, p_src, n_periods, line=True):
    """The ECU's estimate in N after each period: ``line`` = the line estimate A_P_LINE, else A_P_EST (jumps)."""
    out, pe = [], p0
    for _ in range(n_periods):
        pe = esp._estimate(esp.W_N, pe, p_src, DT, p, 0.0, line)
        out.append(pe)
    return np.array(out)


STEPS = [(0.0, 167.8 * BAR), (0.0, 60.0 * BAR), (30.0 * BAR, 120.0 * BAR),  # fills (I1: 167.8 bar panic source)
         (120.0 * BAR, 20.0 * BAR), (85.7 * BAR, 0.0)]                       # drains (driver easing / releasing)


def worst_step_error_pa(p, n_periods=12, line=True):
    """Largest |estimate - plant| (Pa) over the source steps and the ESP periods after them."""
    worst = 0.0
    for p0, p_src in STEPS:
        diff = estimate_fill(p, p0, p_src, n_periods, line) - plant_fill(p, p0, p_src, n_periods)
        worst = max(worst, float(np.max(np.abs(diff))))
    return worst


def test_plant_row_n_is_a_first_order_fill(n_params):
    """The reference itself: the plant's row N at 0.5 ms is the closed-form first-order fill, within its explicit Euler
    step's error (of order PLANT_DT / (2 tau_line) = 1.7 % of the step: 2 % allowed)."""
    p = n_params["suv"]
    tau = p.esp_unit_line_time_constant_s
    for p0, p_src in STEPS:
        t = DT * np.arange(1, 13)
        closed = p_src + (p0 - p_src) * np.exp(-t / tau)
        assert np.max(np.abs(plant_fill(p, p0, p_src, 12) - closed)) < 0.02 * abs(p_src - p0)


@pytest.mark.parametrize("vehicle", ["suv", "sedan"])
def test_estimate_follows_the_wheel_cylinder_after_a_source_step(n_params, vehicle):
    """The line estimate (A_P_LINE): after a step of the source it stays within ERROR_BOUND_PA of the plant's wheel
    cylinder at every ESP period (A_P_EST, the estimate of flag 0: 119.6 bar off after the first period)."""
    err = worst_step_error_pa(n_params[vehicle])
    assert err <= ERROR_BOUND_PA, f"{vehicle}: estimate {err / BAR:.1f} bar off the plant's wheel pressure"


def test_estimate_code_before_jumps_to_the_source(n_params):
    """Negative control: A_P_EST (the estimate of the code before, still the other readers') takes the source at once."""
    err = worst_step_error_pa(n_params["suv_defect"], line=False)
    assert err > 100.0 * BAR, f"seeded defect only {err / BAR:.1f} bar off"


def test_estimate_settles_at_the_source(n_params):
    """Not vacuous the other way: the estimate does reach the source (within 1 bar, spec 3 RAMP_SETTLED) after six
    line time constants, so a wheel in N is still seen at the driver's pressure."""
    p = n_params["suv"]
    n = int(math.ceil(6.0 * p.esp_unit_line_time_constant_s / DT))  # exp(-6) x 167.8 bar = 0.4 bar
    assert abs(estimate_fill(p, 0.0, 167.8 * BAR, n)[-1] - 167.8 * BAR) < esp.RAMP_SETTLED_PA


def _dump_onset_errors(sets):
    """Closed loop, I1's panic stop: per ABS dump start of each wheel, (time, ECU-model estimate the dump stores as its
    level - A_P_EST, or A_P_LINE with flag 2 -, plant pressure), the estimate replayed along the run's own valve modes and source pressures (as esp_step chains it)."""
    from vehicle_assist.scenarios.runner import pack_records

    sc = va.load_scenario("blowout_panic_stop_80kph").with_sets("road.friction_mu=0.45",
                                                                 "vehicle.brakes.gain_scale_frac=0.7", *sets)
    p = pack_records([sc.vehicle.flat()])[0]
    df = va.simulate(sc, requirements=False).to_pandas()
    line = p.esp_pressure_estimate_line_flag > 1.5  # flag 2: the level stored at a dump's start is A_P_LINE (esp.py)
    rows = []
    for w in ("fl", "fr", "rl", "rr"):
        wm = df[f"wheel_mode_{w}_index"].values.astype(int)
        src = df[f"source_pressure_{w}_pa"].values
        pw = df[f"wheel_pressure_{w}_pa"].values
        pe, open_s, cur = np.zeros(len(df)), 0.0, pw[0]
        for k in range(len(df)):
            cur = esp._estimate(wm[k], cur, src[k], DT, p, open_s, line)
            open_s = open_s + DT if wm[k] in (esp.W_B, esp.W_BP) else 0.0
            pe[k] = cur  # the estimate at the end of period k: the plant's pressure at row k + 1
        for k in range(1, len(df)):
            if wm[k] == esp.W_D and wm[k - 1] != esp.W_D:
                rows.append((w, float(df.time_s.values[k]), pe[k - 1], pw[k]))
    return rows


@pytest.fixture(scope="module")
def panic_rows():
    return {"rule": _dump_onset_errors([f"{FLAG}=2"]), "defect": _dump_onset_errors([f"{FLAG}=0"]),
            "shipped": _dump_onset_errors([])}


def _bad_dump_starts(rows):
    return [r for r in rows if abs(r[2] - r[3]) > ERROR_BOUND_PA]


def test_dump_start_reads_the_wheel_not_the_source(panic_rows):
    """At every ABS dump's start (the pressure stored as the lock level) the estimate is within ERROR_BOUND_PA of the
    plant's wheel pressure (flag 0: FR at 5.635 s read 167.8 bar with the wheel at 86.4)."""
    rows = panic_rows["rule"]
    assert len(rows) >= 8, "the panic stop must have ABS dumps (test premise)"
    bad = _bad_dump_starts(rows)
    assert not bad, "; ".join(f"{w} {t:.3f} s est {e / BAR:.1f} vs plant {q / BAR:.1f} bar" for w, t, e, q in bad)


def test_dump_start_code_before(panic_rows):
    """Negative control: with the seeded defect the FR dump at ~10 km/h reads the source (> 60 bar over the wheel)."""
    worst = max(r[2] - r[3] for r in panic_rows["defect"])
    assert worst > 60.0 * BAR, f"seeded defect only {worst / BAR:.1f} bar over"


def test_shipped_dump_start_reads_the_wheel(panic_rows):
    """The shipped vehicle file (whatever its flag says; SUV: 2 since session i, I11), same criterion as the rule's
    test, on the pressure the shipped ECU stores at each dump's start (flag 2: the line estimate A_P_LINE, which follows
    mode N through the line lag; fails with the SUV file at 0: FR 167.8 vs 86.4 bar)."""
    assert not _bad_dump_starts(panic_rows["shipped"])


def _stored_dump_level_pa(flag):
    """The ESP controller alone (tests/support.esp_ecu; HBA off so the pedal step is not an assist): the driver held at
    20 bar, then 167.8 bar (I1's panic source) for one ESP period with the wheels in N; FR is the blowout compensation's
    wheel (FL blown, BUILD) and its speed drops to 70 % of the car's - ABS dumps it; returns the stored lock level
    S_P_PREDUMP (the pressure at the dump's start)."""
    from tests.support import esp_ecu, esp_ecu_step
    from vehicle_assist.functions import blowout_compensation as bc

    sets = ["vehicle.brake_assist.enabled_flag=0"] + ([] if flag is None else [f"{FLAG}={flag}"])
    p = _n_params("blowout_panic_stop_80kph", *sets)
    e = esp_ecu(p, 20.0, 20.0 * BAR, 20)
    e["meas"].master_pressure_pa = 167.8 * BAR
    esp_ecu_step(e, p)
    assert int(e["wheels"][1, esp.A_WHEEL_MODE]) == esp.W_N  # test premise: the wheel is on the driver's pressure
    e["bst"][bc.S_MODE], e["bst"][bc.S_TARGET], e["bst"][bc.S_BLOWN] = bc.BUILD, 1.0, 0.0
    e["meas"].wheel_speed_fr_radps = 14.0 / p.body_wheel_radius_m
    esp_ecu_step(e, p)
    assert int(e["wheels"][1, esp.A_MODE]) == 2, "test premise: ABS dumps FR"  # abs.py DUMP
    return float(e["bst"][bc.S_P_PREDUMP]), p


@pytest.mark.parametrize("flag", [None, 2, 3])
def test_dump_start_stores_the_wheel_pressure(flag):
    """The lock level stored at the dump's start is the wheel cylinder's pressure one ESP period after the source step
    (plant row N from 20 bar: 61.9 bar), within ERROR_BOUND_PA - with flag 2 (only this stored level reads the line
    estimate A_P_LINE) and flag 3 (as 2, the braking ceiling compared on it too). Flag 0 (the code before) stores the source, 167.8 bar; the
    shipped case (None: the SUV file, 2 since session i, I11) was a strict xfail while the file said 0."""
    stored, p = _stored_dump_level_pa(flag)
    wheel = plant_fill(p, 20.0 * BAR, 167.8 * BAR, 1)[-1]
    assert abs(stored - wheel) <= ERROR_BOUND_PA, f"stored {stored / BAR:.1f} vs wheel {wheel / BAR:.1f} bar"


def test_dump_start_stores_the_source_code_before():
    """Negative control: the seeded defect (flag 0) stores the 167.8-bar source as the lock level."""
    stored, p = _stored_dump_level_pa(0)
    assert stored > plant_fill(p, 20.0 * BAR, 167.8 * BAR, 1)[-1] + 100.0 * BAR
