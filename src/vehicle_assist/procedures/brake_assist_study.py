"""Paper 002 in ``vehicle-assist reproduce``: the scenarios, a brake-assist figure, and two studies (issue #9):

* ``hba_benefit``: the paper's stop with and without HBA (issue #9: HBA off has the longer stopping distance),
  reported with activation time, MFDD, peak pressures;
* ``r139``: the UN R139 procedure (procedures/r139.py) with its verdict rows;
* ``hba_calibration``: detection / false-activation map and ROC over the thresholds (procedures/hba_calibration.py).
"""
from __future__ import annotations

from pathlib import Path

from vehicle_assist.report.plots import FIGURES, Line, Panel, _render
from vehicle_assist.units import BAR_TO_PA, KPH_TO_MPS

_W = ("fl", "fr", "rl", "rr")
BRAKE_PANELS = [
    Panel("Vehicle", "speed [km/h]", (Line("speed_mps", "speed", 1.0 / KPH_TO_MPS),
                                      Line("reference_speed_mps", "ESP reference speed", 1.0 / KPH_TO_MPS, "--")),
          right_ylabel="deceleration [m/s^2]", right_lines=(Line("accel_mps2", "-a (decel)", -1.0, ":"),)),
    Panel("Driver", "pedal force [N]", (Line("pedal_force_n", "pedal force"),)),
    Panel("Pressures", "pressure [bar]", (Line("master_pressure_pa", "master", 1.0 / BAR_TO_PA, "--"),)
          + tuple(Line(f"wheel_pressure_{w}_pa", w, 1.0 / BAR_TO_PA) for w in _W)),
    Panel("Wheel slip", "slip [-]", tuple(Line(f"wheel_slip_{w}_frac", w) for w in _W), ylim=(-0.02, 1.02)),
    Panel("Modes", "index", (Line("hba_mode_index", "HBA (0 off, 1 active, 2 ramp-out)"),
                             Line("abs_mode_fl_index", "ABS fl (1 hold, 2 dump, 3 build)", 1.0, "--"),
                             Line("abs_mode_rl_index", "ABS rl", 1.0, ":"))),
]


def brake_assist_png(trace, path, title) -> Path:
    return _render(trace, [p for p in BRAKE_PANELS if p.present(trace)], path, title)


FIGURES["brake_assist"] = brake_assist_png


def hba_benefit_extra(out_dir: Path):
    from vehicle_assist.scenarios.loader import load_scenario
    from vehicle_assist.scenarios.runner import simulate

    on = simulate(load_scenario("hba_paper_110kph_dry")).metrics
    off = simulate(load_scenario("hba_off_110kph_dry")).metrics
    d_on, d_off = on["stopping_distance_m"], off["stopping_distance_m"]
    entry = {"paper": "002", "scenario": "hba_paper_110kph_dry vs hba_off_110kph_dry",
             "criterion": "stopping distance without HBA - with HBA", "negative_control": False,
             "value": d_off - d_on, "unit": "m", "bound": "> 0", "pass": d_off > d_on,
             "why": (f"issue #9: the same stop with HBA off is longer: {d_on:.1f} m with HBA (activation "
                     f"{1000 * on['hba_activation_time_s']:.0f} ms after t0, MFDD {on['mfdd_mps2']:.2f} m/s^2, "
                     f"front wheel {on['front_pressure_master_below_60bar_pa'] / 1e5:.0f} bar at master < 60 bar) vs "
                     f"{d_off:.1f} m without (MFDD {off['mfdd_mps2']:.2f} m/s^2), 110 km/h, 100 N in 12 ms")}
    return [], [entry]


def r139_extra(out_dir: Path):
    from vehicle_assist.procedures.r139 import NOT_CONFIRMED, run_r139

    res = run_r139()
    entries = []
    for row in res.rows:
        if not row.get("verdict", True):
            continue
        entries.append({"paper": "002", "scenario": "UN R139 category B test (procedures/r139.py)",
                        "criterion": row["quantity"], "negative_control": False,
                        "value": row["value"], "unit": row["unit"], "bound": row["bound"].replace(" (must fail)", ""),
                        "pass": bool(row["pass"]),
                        "why": f"{row['clause']}; F_ABS = {res.f_abs_n:.0f} N, a_ABS = {res.a_abs_mps2:.2f} m/s^2; "
                               f"not confirmed: {NOT_CONFIRMED[0]}"})
    return [], entries


def reproduction():
    from vehicle_assist.procedures.reproduce import Reproduction

    scenarios = ("hba_paper_110kph_dry", "hba_off_110kph_dry", "hba_exit_by_release_110kph", "hba_normal_slow_100kph",
                 "hba_normal_firm_50kph", "hba_normal_firm_100kph", "hba_normal_firm_130kph", "hba_panic_12kph",
                 "hba_wet_110kph", "hba_snow_60kph", "hba_split_mu_80kph", "hba_fault_pressure_sensor_lost",
                 "hba_fault_pressure_sensor_stuck", "hba_fault_abs_failed", "hba_fault_pump_failed",
                 "hba_fault_pump_fails_during_assist")
    return Reproduction(
        "002",
        "Hydraulic brake assist in an ESP unit (paper 002): the paper's 110 km/h test with and without HBA, normal "
        "braking, low speed, wet, snow, split-mu, faults, and the UN R139 category B test",
        scenarios, figures=("brake_assist",),
        figure_scenarios=("hba_paper_110kph_dry", "hba_off_110kph_dry", "hba_exit_by_release_110kph", "hba_split_mu_80kph"),
        extras=("hba_benefit", "r139", "hba_calibration", "envelope_002", "falsify_002"))  # issue #9 envelope + campaign


def calibration_extra(out_dir: Path):
    from vehicle_assist.procedures.hba_calibration import calibration_extra as run

    return run(out_dir)


EXTRAS = {"hba_benefit": hba_benefit_extra, "r139": r139_extra, "hba_calibration": calibration_extra}
