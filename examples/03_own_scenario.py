"""Write a scenario file of your own (an EV hesitating on 8 deg) and run it with a sensor fault.

Run: .venv/bin/python examples/03_own_scenario.py
"""
import tempfile
from pathlib import Path

import vehicle_assist as va

SCENARIO = """
name = "ev_8deg_hesitating_driver"
description = "EV on 8 deg: the driver lets the brake go, hesitates, then pulls away"
source = "example"

[vehicle]
base = "compact_ev"

[road]
slope_deg = 8

[driver]
brake_pedal = { time_s = [0, 1.0, 1.3], frac = [0.3, 0.3, 0.0] }
accelerator = { time_s = [0, 1.5, 2.5, 3.0, 4.0], frac = [0, 0, 0.3, 0.3, 0.6] }

[run]
duration_s = 8

[[events]]
at_s = 3.0
action = "sensor_fault"
sensor = "vehicle_speed"
fault = "lost"

[[checks]]
metric = "final_speed_mps"
min = 0.5
"""

with tempfile.TemporaryDirectory() as tmp:
    path = Path(tmp) / "ev_8deg.toml"
    path.write_text(SCENARIO)
    result = va.simulate(va.load_scenario(path))
print(f"rollback {result.metrics['rollback_distance_m']:.3f} m, final speed {result.metrics['final_speed_mps']:.2f} m/s")
print("checks:", ", ".join(f"{c.metric} {'ok' if c.ok else 'FAILED'}" for c in result.checks))
print("events:", "; ".join(f"{e.time_s:.2f} s {e.machine} -> {e.to_mode} ({e.reason})" for e in result.events))
