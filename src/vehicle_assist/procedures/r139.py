"""UN Regulation No. 139 (brake assist systems, BAS) test procedure on the ESP sedan (issue #9, part 6).

UN R139 took the BAS provisions over from UN R13-H (in force January 2017, cite:GAR-R139 in brake_assist.md 10).
What is confirmed and what is recollection follows brake_assist.md 5 and 9; each number below says which.

* Reference test ("Test 1", spec 5.3): five runs from the test speed of 100 km/h (paper 002 P12: "five ABS
  tests from 100 km/h"), a slow linear pedal ramp that does not trigger the BAS (80 N/s: assumed, the
  regulation's ramp could not be confirmed) until ABS full cycling. F_ABS = pedal force at the onset of full
  cycling (ABS active on both front wheels, spec 4.3 harness definition); a_ABS = mean deceleration from that
  onset until 15 km/h. The five runs differ in the initial speed (99, 99.5, 100, 100.5, 101 km/h: assumed
  test-speed tolerance) - the simulation is otherwise deterministic.
* Category B activation test ("Test 2", spec 5.4 / S8, confirmed by cite:BAS-CLAUSE and paper P12): quick
  application (8000 N/s to 0.9*F_ABS: assumed manufacturer input), eased in 0.3 s into the corridor and held at
  0.6*F_ABS; t0 = the instant the pedal force reaches 20 N (paper P12, confirmed); the pedal force must stay in
  [F_ABS,lower, F_ABS,upper] = [0.5, 0.7]*F_ABS (paper eqs. 2-3, confirmed) from t0 + 0.8 s until 15 km/h.
* Verdict: mean deceleration in that window >= 0.85*a_ABS (regulation mode: [recollection, not confirmed]) and
  >= 0.70*a_ABS (paper mode: paper P12's wording). The same test with HBA off is the negative control (spec S9:
  expected to fail the 0.85 criterion).
* Category A (force-triggered BAS) is not evaluated: the paper's HBA is pressure-rate triggered (category B).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from vehicle_assist.drivers.brake_pedal import T0_FORCE_N, as_sets, r139_category_b, r139_reference

BASE_SCENARIO = "hba_off_110kph_dry"  # the sedan on dry asphalt; the procedure sets speed, pedal, HBA flag
REFERENCE_SPEEDS_KPH = (99.0, 99.5, 100.0, 100.5, 101.0)  # assumed tolerance around the 100 km/h test speed
END_SPEED_MPS = 15.0 / 3.6  # UN R139 / paper P12 (confirmed)
CORRIDOR = (0.5, 0.7)  # F_ABS,lower/upper over F_ABS: paper eqs. 2-3, confirmed by cite:BAS-CLAUSE
FACTOR_REGULATION = 0.85  # [recollection, not confirmed] brake_assist.md 5.4
FACTOR_PAPER = 0.70  # paper 002 P12
REFERENCE_RAMP_N_PER_S = 80.0  # assumed; checked against RISE_WINDOW_S below (full cycling 1.94 s after t0 here)
# Reference test validity: "full deceleration reached within 2.0 +- 0.5 s" (from t0) - Commission Regulation (EC)
# No 631/2009, BAS annex, Appendix 1 'method for determining F_ABS and a_ABS', item 3 (public text:
# umwelt-online.de/recht/eu/08_09/09_0631b.htm; that EU BAS text preceded the UN R13-H / R139 BAS provisions -
# R139 paragraph numbering not verified here)
RISE_WINDOW_S = (1.5, 2.5)
REFERENCE_MAX_FORCE_N = 400.0  # end of the reference ramp (well beyond F_ABS ~170 N, brake_assist.md 6)


@dataclass
class R139Result:
    f_abs_n: float
    a_abs_mps2: float
    a_abs_runs: list[float]
    f_abs_runs: list[float]
    rise_s_runs: list[float] = field(default_factory=list)  # t(full cycling) - t0 of each reference run
    window: dict = field(default_factory=dict)       # HBA on
    baseline: dict = field(default_factory=dict)     # HBA off
    rows: list[dict] = field(default_factory=list)   # verdict rows (quantity, value, bound, pass, clause)

    @property
    def passed(self) -> bool:
        return all(r["pass"] for r in self.rows if r.get("verdict", True))


def _load(sets: list[str]):
    from vehicle_assist.scenarios.loader import load_scenario

    return load_scenario(BASE_SCENARIO, sets)


def pedal_full_scale_n(extra_sets=()) -> float:
    """Pedal force of a scripted pedal fraction 1.0: ``pedal.full_scale_force_n`` of the test vehicle (with its
    overrides; source string in the vehicle file), so the programmes' forces in N reach the car unchanged."""
    return float(_load(list(extra_sets)).vehicle.flat()["pedal_full_scale_force_n"])


def _check_scale(forces, full_scale_n: float, what: str) -> None:
    from vehicle_assist.scenarios.errors import InputError

    if max(forces) > full_scale_n + 1e-9:
        raise InputError(f"r139 {what}: pedal force {max(forces):.0f} N exceeds pedal.full_scale_force_n = "
                         f"{full_scale_n:.0f} N of the vehicle (the scripted pedal would be clipped)")


def _full_cycling_index(tr) -> int:
    idx = np.flatnonzero(_full_cycling_mask(tr))
    return int(idx[0]) if idx.size else -1


def _full_cycling_mask(tr) -> np.ndarray:
    active = np.zeros(len(tr["time_s"]), dtype=bool)
    for w in ("fl", "fr"):
        m = tr[f"abs_mode_{w}_index"]
        recent = np.zeros(len(m), dtype=bool)
        hd = np.flatnonzero((m == 1.0) | (m == 2.0))
        t = tr["time_s"]
        for k in hd:  # "ABS active on a wheel = a hold or dump in the last 0.3 s" (spec 4.3)
            recent |= (t >= t[k]) & (t < t[k] + 0.3)
        active = (active & recent) if w == "fr" else recent
    return active


def reference_test(extra_sets: list[str] = (), rise_out: list | None = None) -> tuple[list[float], list[float]]:
    """(F_ABS per run, a_ABS per run); ``rise_out`` (if given) receives t(full cycling) - t0 of each run."""
    from vehicle_assist.scenarios.runner import simulate

    f_runs, a_runs = [], []
    full = pedal_full_scale_n(extra_sets)
    for v in REFERENCE_SPEEDS_KPH:
        times, forces = r139_reference(REFERENCE_RAMP_N_PER_S, REFERENCE_MAX_FORCE_N)
        _check_scale(forces, full, "reference test")
        sets = [f"run.initial_speed_kph={v}", "run.duration_s=12", "vehicle.brake_assist.enabled_flag=0",
                *as_sets(times, forces, full), *extra_sets]
        tr = simulate(_load(sets)).trace
        k = _full_cycling_index(tr)
        if k < 0:
            raise RuntimeError(f"reference test from {v} km/h: ABS never fully cycled")
        t, speed = tr["time_s"], tr["speed_mps"]
        ke = np.flatnonzero((t > t[k]) & (speed <= END_SPEED_MPS))
        if rise_out is not None:
            k0 = int(np.flatnonzero(tr["pedal_force_n"] >= T0_FORCE_N)[0])
            rise_out.append(float(t[k] - t[k0]))
        f_runs.append(float(tr["pedal_force_n"][k]))
        a_runs.append(float((speed[k] - speed[ke[0]]) / (t[ke[0]] - t[k])))
    return f_runs, a_runs


def category_b_test(f_abs_n: float, hba_on: bool, extra_sets: list[str] = ()) -> dict:
    from vehicle_assist.scenarios.runner import simulate

    times, forces = r139_category_b(f_abs_n)
    full = pedal_full_scale_n(extra_sets)
    _check_scale(forces, full, "category B test")
    sets = ["run.initial_speed_kph=100", "run.duration_s=8", f"vehicle.brake_assist.enabled_flag={int(hba_on)}",
            *as_sets(times, forces, full), *extra_sets]
    r = simulate(_load(sets))
    tr = r.trace
    t, force, speed = tr["time_s"], tr["pedal_force_n"], tr["speed_mps"]
    k0 = int(np.flatnonzero(force >= T0_FORCE_N)[0])
    ks = int(np.flatnonzero(t >= t[k0] + 0.8 - 1e-9)[0])
    ke = int(np.flatnonzero((t >= t[ks]) & (speed <= END_SPEED_MPS))[0])
    win = slice(ks, ke + 1)
    mean = float((speed[ks] - speed[ke]) / (t[ke] - t[ks]))
    # 0.2 s moving mean of the deceleration (spec 5.4)
    a = -tr["accel_mps2"][win]
    n = max(1, int(round(0.2 / (t[1] - t[0]))))
    moving = np.convolve(a, np.ones(n) / n, mode="valid") if len(a) >= n else a
    return {"t0_s": float(t[k0]), "window_start_s": float(t[ks]), "window_end_s": float(t[ke]),
            "pedal_min_n": float(force[win].min()), "pedal_max_n": float(force[win].max()),
            "mean_decel_mps2": mean, "min_moving_decel_mps2": float(moving.min()),
            "hba_activated": bool(r.metrics.get("hba_activated_flag", 0.0) > 0.5),
            "abs_full_cycling": bool(_full_cycling_mask(tr)[win].all()),  # throughout the evaluation window
            "hba_activation_time_s": r.metrics.get("hba_activation_time_s", float("nan")),
            "stopping_distance_m": r.metrics.get("stopping_distance_m", float("nan"))}


def run_r139(extra_sets: list[str] = ()) -> R139Result:
    rise: list[float] = []
    f_runs, a_runs = reference_test(list(extra_sets), rise)
    f_abs, a_abs = float(np.mean(f_runs)), float(np.mean(a_runs))
    res = R139Result(f_abs, a_abs, a_runs, f_runs, rise)
    res.window = category_b_test(f_abs, True, list(extra_sets))
    res.baseline = category_b_test(f_abs, False, list(extra_sets))
    lo, hi = CORRIDOR[0] * f_abs, CORRIDOR[1] * f_abs
    spread = float(np.std(a_runs) / a_abs)
    w, b = res.window, res.baseline
    res.rows = [
        {"quantity": "F_ABS (mean of 5 reference runs)", "value": f_abs, "unit": "N", "bound": "-", "pass": True,
         "clause": "UN R139 Test 1 / brake_assist.md 5.3 (pedal ramp 80 N/s assumed)", "verdict": False},
        {"quantity": "a_ABS (mean of 5 reference runs)", "value": a_abs, "unit": "m/s^2", "bound": "-", "pass": True,
         "clause": "UN R139 Test 1 / paper 002 P12 (five ABS tests from 100 km/h)", "verdict": False},
        {"quantity": "reference runs: largest |t(full ABS cycling) - t0 - 2.0 s| of the 5 runs",
         "value": max(abs(r - 2.0) for r in rise), "unit": "s", "bound": "<= 0.5",
         "pass": RISE_WINDOW_S[0] <= min(rise) and max(rise) <= RISE_WINDOW_S[1],
         "clause": "EC 631/2009 BAS annex, Appendix 1 item 3 (full deceleration within 2.0 +- 0.5 s; public text, "
                   "UN R139 numbering not verified): validity of the reference runs"},
        {"quantity": "a_ABS spread over the runs (std/mean)", "value": spread, "unit": "-", "bound": "< 0.03",
         "pass": spread < 0.03, "clause": "brake_assist.md 8 criterion 8 (repeatability of the set-up)"},
        {"quantity": "HBA activated (category B test)", "value": float(w["hba_activated"]), "unit": "-", "bound": ">= 1",
         "pass": w["hba_activated"], "clause": "UN R139 Test 2 (BAS activates), cite:BAS-CLAUSE"},
        {"quantity": "ABS fully cycling throughout [t0 + 0.8 s, 15 km/h] (category B test)", "value": float(w["abs_full_cycling"]), "unit": "-",
         "bound": ">= 1", "pass": w["abs_full_cycling"],
         "clause": "UN R139 Test 2 (the quick application makes BAS activate and ABS fully cycle), cite:BAS-CLAUSE; "
                   "full cycling = ABS active on both front wheels (spec 4.3)"},
        {"quantity": "pedal force min in [t0 + 0.8 s, 15 km/h]", "value": w["pedal_min_n"], "unit": "N",
         "bound": f">= {lo:.1f} (0.5*F_ABS)", "pass": w["pedal_min_n"] >= lo - 1e-6,
         "clause": "UN R139 Test 2 corridor, paper eq. 2 (confirmed); t0 at 20 N (paper P12)"},
        {"quantity": "pedal force max in [t0 + 0.8 s, 15 km/h]", "value": w["pedal_max_n"], "unit": "N",
         "bound": f"<= {hi:.1f} (0.7*F_ABS)", "pass": w["pedal_max_n"] <= hi + 1e-6,
         "clause": "UN R139 Test 2 corridor, paper eq. 3 (confirmed)"},
        {"quantity": "mean deceleration in the window / a_ABS (regulation mode)", "value": w["mean_decel_mps2"] / a_abs,
         "unit": "-", "bound": f">= {FACTOR_REGULATION}", "pass": w["mean_decel_mps2"] >= FACTOR_REGULATION * a_abs,
         "clause": "UN R139 Test 2 deceleration requirement, 0.85 [recollection, not confirmed] (brake_assist.md 5.4)"},
        {"quantity": "mean deceleration in the window / a_ABS (paper mode)", "value": w["mean_decel_mps2"] / a_abs,
         "unit": "-", "bound": f">= {FACTOR_PAPER}", "pass": w["mean_decel_mps2"] >= FACTOR_PAPER * a_abs,
         "clause": "paper 002 P12 (70 % of a_ABS)"},
        {"quantity": "negative control, HBA off: mean deceleration / a_ABS", "value": b["mean_decel_mps2"] / a_abs,
         "unit": "-", "bound": f"< {FACTOR_REGULATION} (must fail)", "pass": b["mean_decel_mps2"] < FACTOR_REGULATION * a_abs,
         "clause": "brake_assist.md 8 criterion 10 / S9: the test discriminates"},
    ]
    return res


NOT_CONFIRMED = (
    "0.85*a_ABS deceleration factor of the regulation (the paper says 70 %); both are reported",
    "the reference test's pedal ramp: 80 N/s used, checked only against the 2.0 +- 0.5 s rise of the EC 631/2009 "
    "text, not against the UN R139 text; test-speed tolerance 99-101 km/h used",
    "the definition of 'full cycling' used to read F_ABS (ABS active on both front wheels, spec 4.3)",
    "brake temperature conditioning (65-100 deg C) and laden/unladen state: not modelled (cold, constant mu_b)",
    "category A (force-triggered BAS) evaluation: not applicable to the pressure-rate-triggered HBA",
)
