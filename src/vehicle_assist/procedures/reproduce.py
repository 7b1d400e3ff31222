"""Paper reproductions: which scenarios reproduce which paper, and the summary they produce.

Each function issue adds a :class:`Reproduction` (paper seed number, scenario names); until the first
function lands, the example scenarios of the foundation stand in (paper ``examples``). Every check of
every listed scenario becomes one summary entry: paper, scenario, criterion, value, unit, bound, pass.
"""
from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Reproduction:
    paper: str
    title: str
    scenarios: tuple[str, ...]
    figures: tuple[str, ...] = ("overview", "forces")  # plot kinds (report.plots.FIGURES)
    figure_scenarios: tuple[str, ...] | None = None  # which scenarios get figures (None: all)
    extras: tuple[str, ...] = ()  # further studies (EXTRAS below), each adding figures and criteria


HSA_MATRIX = tuple(f"hsa_truck_{load}_{slope}deg_{bar}bar" for load in ("empty", "full") for slope in (11, 14)
                   for bar in ("6p5", "7p0", "7p5", "8p0"))

REPRODUCTIONS: list[Reproduction] = [
    Reproduction(
        "000",
        "Hill-start assist, heavy AMT truck (Wang, Zhao, Liu 2009): 11/14 deg x empty/full x 6.5-8.0 bar, "
        "normal start, and the baselines without the assist",
        HSA_MATRIX + ("hsa_truck_empty_flat_normal_start", "hsa_truck_full_14deg_no_assist_early_release",
                      "hsa_truck_full_14deg_no_assist_late_release", "truck_11deg_early_release",
                      "truck_11deg_late_release"),
        figures=("hill_start",),
        figure_scenarios=("hsa_truck_full_14deg_8p0bar", "hsa_truck_empty_11deg_8p0bar", "hsa_truck_full_14deg_6p5bar",
                          "hsa_truck_full_14deg_no_assist_early_release", "hsa_truck_full_14deg_no_assist_late_release",
                          "truck_11deg_late_release"),
        extras=("hill_start_amt_study", "envelope_000", "falsify_000"),  # 9.7/9.10/9.12; issue #7 envelope; #8
    ),
    Reproduction(
        "001",
        "Hill-start assist, electric car with EHB (Tan, Huang, Yu, Shu): the paper's 5 deg case, flat road, "
        "10 deg, a hesitating driver, the negative controls, the baseline without the assist, and the calibration map",
        ("hsa_ev_5deg_paper", "hsa_ev_5deg_paper_2x_ramp", "hsa_ev_flat", "hsa_ev_10deg", "hsa_ev_10deg_2x_ramp",
         "hsa_ev_5deg_hesitating", "hsa_ev_5deg_impatient", "hsa_ev_5deg_release_too_fast",
         "hsa_ev_5deg_step_pedal", "ev_5deg_hold_and_pull_away"),
        figures=("hill_start_ehb",),
        figure_scenarios=("hsa_ev_5deg_paper", "hsa_ev_5deg_hesitating", "hsa_ev_5deg_release_too_fast",
                          "ev_5deg_hold_and_pull_away"),
        extras=("ehb_sweep", "envelope_001", "falsify_001"),
    ),
]


def ehb_sweep_extra(out_dir):
    """Calibration map of paper 001: figure, and the paper's criterion 'speed never below -1 mm/s' (P8 Fig. 8c,
    hill_start_ehb.md 5.1) at every variant the motor can start; where it cannot, the brake stays held."""
    from vehicle_assist.procedures.ehb_sweep import SPEED_BOUND_MPS, run_ehb_sweep

    figure, table, summary = run_ehb_sweep(out_dir)
    scenario = f"ehb_sweep ({summary['variants']} variants: slope 0-20 deg x mass 1300-2100 kg x accelerator rate)"
    n_unstartable = summary["variants"] - summary["startable"]
    entries = [
        {"paper": "001", "scenario": scenario, "criterion": "largest backward speed over the startable variants",
         "negative_control": False, "value": summary["max_backward_speed_startable_mps"], "unit": "m/s",
         "bound": f"<= {SPEED_BOUND_MPS:g}", "pass": summary["speed_violations_startable"] == 0,
         "why": f"paper 001 P8 (Fig. 8c) / hill_start_ehb.md 5.1: v >= -1 mm/s; {summary['speed_violations_startable']} of "
                f"{summary['startable']} startable variants violate it (table: {table.name})"},
        {"paper": "001", "scenario": scenario, "criterion": "largest rollback over the variants the motor cannot start",
         "negative_control": False, "value": summary["unstartable_max_rollback_m"], "unit": "m",
         "bound": "<= 0.01", "pass": summary["unstartable_max_rollback_m"] <= 0.01,
         "why": "issue #7: where a start is physically impossible (motor force below grade + rolling resistance) the "
                f"brake stays held (rollback <= 1 cm); {summary['unstartable_refused']} of {n_unstartable} such variants "
                "end in an explicit refusal (grade_beyond_motor_torque), the others hold while the driver has not yet "
                "asked for the motor's full torque"},
        {"paper": "001", "scenario": scenario, "criterion": "largest filtered jerk over the startable variants",
         "negative_control": False, "value": summary["max_jerk_mps3"], "unit": "m/s^3", "bound": "<= 0.1",
         "pass": summary["max_jerk_mps3"] <= 0.1,
         "why": f"paper 001 P8 (Fig. 8d) / hill_start_ehb.md 5.2, at every mass, grade and pedal rate of the map "
                f"({100 * summary['jerk_ok_frac']:.0f} % of the startable variants within the bound)"},
        {"paper": "001", "scenario": scenario, "criterion": "assist back in Step1 within 2 s after v > v_start (started variants)",
         "negative_control": False, "value": summary["max_idle_after_start_s"], "unit": "s", "bound": "<= 2",
         "pass": summary["step1_late"] == 0,
         "why": f"hill_start_ehb.md 5.5, state half ('and EHB state = Step1'): {summary['step1_late']} of "
                f"{summary['started']} started variants hand back later or not within the run (value: the latest "
                "hand-back seen); the jerk-limited torque ceiling catches up with the driver's request at the budget "
                "B, so 5.2 and 5.5 conflict for this design (docs/functions/hill_start_ehb.md, review)"},
    ]
    return [("paper 001: calibration map (backward speed, jerk)", figure)], entries


EXTRAS = {"ehb_sweep": ehb_sweep_extra}


def _hill_start_amt_study(out_dir):
    """Paper 000 criteria 9.7, 9.10 and 9.12 (procedures/hill_start_amt_study.py)."""
    from vehicle_assist.procedures.hill_start_amt_study import hill_start_amt_extra

    return hill_start_amt_extra(out_dir)


EXTRAS["hill_start_amt_study"] = _hill_start_amt_study


def _verification_extras() -> dict:
    from vehicle_assist.verification.campaign import reproduce_extras

    return reproduce_extras()


EXTRAS.update({name: (lambda out, _n=name: _verification_extras()[_n](out))
               for name in ("envelope_000", "falsify_000", "envelope_001", "falsify_001", "envelope_002", "falsify_002")})


def register(reproduction: Reproduction) -> None:
    REPRODUCTIONS.append(reproduction)


# paper 002 (issue #9): passenger car with an ESP unit, ABS and hydraulic brake assist
from vehicle_assist.procedures import brake_assist_study as _brake_assist_study  # noqa: E402

REPRODUCTIONS.append(_brake_assist_study.reproduction())
EXTRAS.update(_brake_assist_study.EXTRAS)

# paper 003 (issue #11): AMT car with curve-aware shifting and map preview
from vehicle_assist.procedures import curve_shift_study as _curve_shift_study  # noqa: E402

REPRODUCTIONS.append(_curve_shift_study.reproduction())
EXTRAS.update(_curve_shift_study.EXTRAS)

# paper 004 (issue #10): tire-blowout stabilisation by differential braking, on the sedan_esp platform
from vehicle_assist.procedures import blowout_study as _blowout_study  # noqa: E402

REPRODUCTIONS.append(_blowout_study.reproduction())
EXTRAS.update(_blowout_study.EXTRAS)
