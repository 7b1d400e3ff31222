"""Proof that the falsifier finds what matters (issue #8): evaluations to the first counterexample of
CMA-ES against plain random search with the same budget, over several seeds, for seeded defects and
deliberately weakened variants of both hill-start assists.

Each row is (envelope, requirement, fixed overrides). A control row without a defect says whether the
requirement already fails on the unmodified function (then the defect rows measure that, not the defect).
Output: a Markdown table on stdout (pasted into docs/verification.md) and benchmarks/results/falsify_defects.json.

    .venv/bin/python benchmarks/falsify_defects.py --seeds 5 --budget 150
"""
from __future__ import annotations

import argparse
import json
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent

CASES = [
    # (label, envelope, requirement, overrides)
    ("control: truck as shipped", "hill_start_amt", "hill_start_amt.no_worse_than_no_assist", []),
    ("truck: lock-up without the engine check (seeded flag)", "hill_start_amt", "hill_start_amt.no_worse_than_no_assist",
     ["vehicle.hill_start_assist.lockup_engine_check_flag=0"]),
    ("truck: no rollback catch after release (seeded flag)", "hill_start_amt", "hill_start_amt.no_worse_than_no_assist",
     ["vehicle.hill_start_assist.rollback_catch_flag=0"]),
    ("truck: weak clutch (max torque 1620 -> 700 N*m)", "hill_start_amt", "hill_start_amt.no_worse_than_no_assist",
     ["vehicle.clutch.max_torque_nm=700"]),
    ("truck: slow park-brake valve (fill 2.55 -> 8 s, exhaust 0.5 -> 4 s)", "hill_start_amt",
     "hill_start_amt.no_worse_than_no_assist",
     ["vehicle.park_brake.fill_time_constant_s=8.0", "vehicle.park_brake.exhaust_time_constant_s=4.0"]),
    ("truck: slope sensor biased (longitudinal accel -1.0 m/s^2)", "hill_start_amt", "hill_start_amt.no_worse_than_no_assist",
     ["sensors.longitudinal_accel.bias_mps2=-1.0"]),
    # EV rows on the part of the envelope where holding is physically possible and the assist is active:
    # slope 3-25 deg (the assist stands down below slope_min_deg = 1 deg) and mu 0.5-1.0 (tan 25 deg = 0.47)
    ("control: EV as shipped (slope 3-25 deg, mu 0.5-1)", "hill_start_ehb", "hill_start_ehb.no_rollback", [],
     {"slope": (3.0, 25.0), "mu": (0.5, 1.0)}),
    ("EV: assist calibrated for a lighter car (1800 -> 1300 kg)", "hill_start_ehb", "hill_start_ehb.no_rollback",
     ["vehicle.hill_start_assist.calibration_mass_kg=1300"], {"slope": (3.0, 25.0), "mu": (0.5, 1.0)}),
]


def run(seeds: int, budget: int, batch: int, cases=CASES, console=None) -> list[dict]:
    from vehicle_assist.verification.falsify import run_falsification

    rows = []
    from vehicle_assist.verification.envelope import load_envelope

    for label, envelope, requirement, sets, *more in cases:
        limits = more[0] if more else {}
        env = load_envelope(envelope).restrict(**limits) if limits else envelope
        row = {"case": label, "envelope": envelope, "requirement": requirement, "sets": sets, "limits": limits,
               "budget": budget}
        for optimizer in ("cma", "random"):
            found, mins = [], []
            t0 = time.perf_counter()
            for seed in range(seeds):
                res = run_falsification(env, requirement, budget=budget, seed=seed, optimizer=optimizer,
                                        batch=batch, sets=sets, progress=False)
                found.append(res.evaluations_to_first)
                mins.append(res.best.robustness)
            n_found = sum(f is not None for f in found)
            # median with "not found" as +inf (censored at the budget)
            med = statistics.median([f if f is not None else float("inf") for f in found])
            row[optimizer] = {"evaluations_to_first": found, "found": n_found, "median": med,
                              "min_robustness": mins, "wall_s": time.perf_counter() - t0}
        rows.append(row)
        if console:
            console(_line(row))
    return rows


def _fmt_med(cell: dict, budget: int) -> str:
    med = cell["median"]
    return f">{budget}" if med == float("inf") else f"{med:g}"


def _line(row: dict) -> str:
    b = row["budget"]
    c, r = row["cma"], row["random"]
    return (f"| {row['case']} | `{row['requirement'].split('.', 1)[1]}` | {_fmt_med(c, b)} ({c['found']}/{len(c['evaluations_to_first'])}) "
            f"| {_fmt_med(r, b)} ({r['found']}/{len(r['evaluations_to_first'])}) "
            f"| {min(c['min_robustness'] + r['min_robustness']):.3g} |")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--seeds", type=int, default=5)
    ap.add_argument("--budget", type=int, default=150)
    ap.add_argument("--batch", type=int, default=8)
    ap.add_argument("--out", type=Path, default=ROOT / "results" / "falsify_defects.json")
    args = ap.parse_args(argv)
    print(f"evaluations to the first counterexample, median over seeds 0..{args.seeds - 1} (found/seeds), budget {args.budget}, batch {args.batch}")
    print("| case | requirement | CMA-ES | random | min robustness |")
    print("|---|---|---|---|---|")
    rows = run(args.seeds, args.budget, args.batch, console=lambda s: print(s, flush=True))
    args.out.parent.mkdir(parents=True, exist_ok=True)
    from vehicle_assist.io.results import write_json

    write_json({"seeds": args.seeds, "budget": args.budget, "batch": args.batch, "rows": rows}, args.out)
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
