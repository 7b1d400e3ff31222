"""Digest of the full trace (every channel's bytes), the events and the metrics of shipped scenarios.

Used to prove that an engine change (inlining, allocation removal, batch path) leaves every trace bitwise
identical: generate the digests from the code before the change, then compare after it::

    python benchmarks/trace_digest.py --write benchmarks/results/digests_before.json   # before
    python benchmarks/trace_digest.py --compare benchmarks/results/digests_before.json # after

``--layouts truck_amt,ev_ehb`` restricts the scenarios. ``benchmarks/digests/main_<commit>.json`` holds the digests
of all shipped scenarios at that commit (now edf66c8, 84 scenarios: against the former aa291ba snapshot every trace and
event log is bitwise; the metric digests of the 35 sedan_esp scenarios changed because session n added two metrics,
blowout_lateral_deviation_road_max_m and blowout_road_departure_earliness_s, to every run of that layout - without those
two keys all 84 are equal, findings N1 and R0. The earlier snapshots were replaced the same way after intended model
changes, see docs/functions/tire_blowout_sessions.md). Work that changes
traces on purpose (a model fix) should compare against the commit just before it, and whoever lands such a change
refreshes this file in the same landing (one snapshot of one commit, never a mix of entries from several).
"""
from __future__ import annotations

import argparse
import hashlib
import json
import sys

import numpy as np


def digest_of(channels: dict, events, metrics: dict) -> dict:
    h = hashlib.sha256()
    for name in sorted(channels):
        h.update(name.encode())
        h.update(np.ascontiguousarray(channels[name], dtype=np.float64).tobytes())
    e = hashlib.sha256(json.dumps([ev.as_dict() for ev in events], sort_keys=True).encode()).hexdigest()[:16]
    m = hashlib.sha256(json.dumps({k: float(v).hex() for k, v in sorted(metrics.items())}).encode()).hexdigest()[:16]
    return {"trace": h.hexdigest()[:16], "events": e, "metrics": m}


def main() -> int:
    import vehicle_assist as va
    from vehicle_assist.scenarios.loader import _resolve  # noqa: F401
    from pathlib import Path

    ap = argparse.ArgumentParser()
    ap.add_argument("--write")
    ap.add_argument("--compare")
    ap.add_argument("--layouts", default="")
    args = ap.parse_args()
    data_dir = Path(va.__file__).parent / "data" / "scenarios"
    wanted = set(filter(None, args.layouts.split(",")))
    out = {}
    for path in sorted(data_dir.glob("*.toml")):
        try:
            sc = va.load_scenario(path.stem)
        except Exception as exc:  # noqa: BLE001
            out[path.stem] = {"error": str(exc)[:200]}
            continue
        if wanted and sc.layout not in wanted:
            continue
        r = va.simulate(sc, requirements=False)
        out[path.stem] = {"layout": sc.layout, **digest_of(r.trace.channels, r.trace.events, r.metrics)}
    if args.write:
        Path(args.write).parent.mkdir(parents=True, exist_ok=True)
        Path(args.write).write_text(json.dumps(out, indent=1, sort_keys=True))
    bad = 0
    if args.compare:
        ref = json.loads(Path(args.compare).read_text())
        for name, d in out.items():
            r = ref.get(name)
            if r is None:
                print(f"new      {name}")
                continue
            diff = [k for k in ("trace", "events", "metrics") if r.get(k) != d.get(k)]
            if diff:
                bad += 1
                print(f"DIFFERS  {name} ({d.get('layout')}): {', '.join(diff)}")
        print(f"{len(out)} scenarios compared, {bad} differ")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
