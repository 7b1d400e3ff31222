"""Run a shipped scenario, look at its metrics, events and a few channels.

Run: .venv/bin/python examples/01_run_scenario.py
"""
import vehicle_assist as va
from vehicle_assist.units import rpm

sc = va.load_scenario("truck_11deg_late_release")
result = va.simulate(sc)

print(f"{sc.name}: {sc.model.description}")
for name, value in result.metrics.items():
    print(f"  {name:28s} {value:12.4g}")
print("mode changes:")
for e in result.events:
    print(f"  {e.time_s:6.3f} s  {e.machine:10s} {e.from_mode:>9s} -> {e.to_mode:<9s} ({e.reason})")

df = result.trace.to_pandas()
lowest = df.loc[df["engine_speed_radps"].idxmin()]
print(f"engine pulled down to {rpm(lowest.engine_speed_radps):.0f} rpm at t = {lowest.time_s:.2f} s "
      f"(clutch at {lowest.clutch_position_frac:.2f}, park brake force {lowest.park_brake_force_n / 1e3:.1f} kN)")
