"""The 100,000-variant sweep on dask (issue #13): one `vehicle-assist sweep` command, results persisted to
Parquet, on a local cluster (default) or any scheduler (--scheduler tcp://host:8786).

Reports wall time, variants per second, the client's peak memory (its own ru_maxrss, read when the command
exits: the client process of a local cluster also hosts the dask scheduler) and the summed peak memory of
the worker processes (polled once a second). The target: client peak < 1 GiB (issue #13); the command
exits 1 past it or when the Parquet file does not hold one row per variant. Times are for information
(this 2-core machine is shared and varies by +-20 %).

    .venv/bin/python benchmarks/dist_sweep.py                      # make bench-dist
    .venv/bin/python benchmarks/dist_sweep.py --variants 2000      # a quick look
"""
from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent
LIMIT_BYTES = 1 << 30
SCENARIO = "truck_11deg_late_release"  # the 20 s truck scenario of `make bench`

# runs the CLI in this process and, at exit, writes the process's own peak RSS (the client's, not the workers')
WRAPPER = r"""
import atexit, json, resource, sys
PEAK_FILE = sys.argv[1]
def _peak():
    with open(PEAK_FILE, "w") as f:
        json.dump({"client_peak_rss_bytes": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024}, f)
atexit.register(_peak)
from vehicle_assist.cli import main
sys.argv = ["vehicle-assist", *sys.argv[2:]]
main()
"""


def grid_for(n: int) -> list[str]:
    """mass (100 values) x reservoir pressure (10) x clutch engagement rate (n / 1000): the axes of `make bench`."""
    if n % 1000 or n < 1000:
        raise SystemExit("--variants: give a multiple of 1000")
    k = n // 1000
    mass = [round(13000 + 17000 * i / 99, 3) for i in range(100)]
    pressure = [round(6.5 + 1.5 * i / 9, 6) for i in range(10)]
    rate = [round(0.10 + 0.10 * i / max(k - 1, 1), 6) for i in range(k)]
    return [f"vehicle.body.mass_kg={','.join(map(str, mass))}",
            f"vehicle.park_brake.reservoir_pressure_bar={','.join(map(str, pressure))}",
            f"vehicle.amt_launch.engage_rate_per_s={','.join(map(str, rate))}"]


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--variants", type=int, default=100_000)
    ap.add_argument("--scheduler", default="local", help="local, threads or a dask scheduler address")
    ap.add_argument("--chunk", type=int, default=500)
    ap.add_argument("--out", default="out/bench-dist")
    ap.add_argument("--resume", action="store_true", help="keep an existing --out (resume) instead of starting fresh")
    args = ap.parse_args()
    import psutil

    out = Path(args.out)
    if out.exists() and not args.resume:
        shutil.rmtree(out)
    peak_file = Path(f"{out}.peak.json")
    cmd = [sys.executable, "-c", WRAPPER, str(peak_file), "sweep", SCENARIO, *[a for g in grid_for(args.variants) for a in ("--grid", g)],
           "--chunk", str(args.chunk), "--out", str(out), "--scheduler", args.scheduler, "--yes"]
    t0 = time.perf_counter()
    proc = subprocess.Popen(cmd, env={**os.environ, "COLUMNS": "120"})
    workers_peak = 0
    client = psutil.Process(proc.pid)
    while proc.poll() is None:
        try:
            rss = sum(c.memory_info().rss for c in client.children(recursive=True))
            workers_peak = max(workers_peak, rss)
        except psutil.Error:
            pass
        time.sleep(1.0)
    wall = time.perf_counter() - t0
    if proc.returncode != 0:
        print(f"the sweep failed (exit {proc.returncode})", file=sys.stderr)
        return proc.returncode
    import pyarrow.parquet as pq

    rows = pq.read_metadata(out / "sweep.parquet").num_rows
    client_peak = json.loads(peak_file.read_text())["client_peak_rss_bytes"]
    peak_file.unlink()
    result = {"variants": args.variants, "rows": rows, "scheduler": args.scheduler, "chunk": args.chunk,
              "wall_s": round(wall, 1), "variants_per_s": round(args.variants / wall, 1),
              "client_peak_rss_bytes": client_peak, "client_peak_rss_gib": round(client_peak / 2**30, 3),
              "workers_peak_rss_bytes_sum": workers_peak, "cpus": os.cpu_count(),
              "client_peak_under_1_gib": client_peak < LIMIT_BYTES, "date_utc": time.strftime("%Y-%m-%d %H:%M", time.gmtime())}
    print(json.dumps(result, indent=1))
    (ROOT / "results").mkdir(exist_ok=True)
    (ROOT / "results" / "dist_sweep.json").write_text(json.dumps(result, indent=1) + "\n")
    return 0 if rows == args.variants and client_peak < LIMIT_BYTES else 1


if __name__ == "__main__":
    sys.exit(main())
