"""Paper 000 in a few lines: the same hill starts with and without the hill-start assist.

Cases: the paper's two test points with a driver who opens the hand park valve together with the service-brake
release (the early release that rolls a truck back), and a start the issue found dangerous (28 t on 13 deg in
1st gear at pedal 0.4: without the assist the engine stalls after the release and the truck rolls back). With
the assist the 3/2 valve keeps the spring brake applied until the clutch carries the grade, the clutch never
asks more than the engine gives, and where a start is impossible it refuses with the brake held.
Run: .venv/bin/python examples/04_hill_start_assist.py
"""
import vehicle_assist as va
from vehicle_assist.vehicles.truck_amt import REFUSAL_REASONS

EARLY = 'driver.hand_valve={time_s=[0.0, 1.0], released=[0, 1]}'
CASES = {
    "S1 30 t 14 deg C, early valve": ("hsa_truck_full_14deg_8p0bar", [EARLY]),
    "13 t 11 deg 1st, early valve": ("truck_11deg_early_release", []),  # pedal only from 2 s
    "28 t 13 deg 1st, pedal 0.4": ("hsa_truck_full_14deg_8p0bar", ["vehicle.body.mass_kg=28000", "road.slope_deg=13",
                                                                  'driver.gear_lever.gear=["1"]',
                                                                  "driver.accelerator.frac=[0,0,0.4]"]),
    "30 t 14 deg 1st (too steep)": ("hsa_truck_full_14deg_8p0bar", ['driver.gear_lever.gear=["1"]']),
}
print(f"{'case':32s} {'assist':>6s} {'rollback [m]':>13s} {'stall':>6s}  refusal")
for label, (name, sets) in CASES.items():
    for enabled in (1, 0):
        m = va.simulate(va.load_scenario(name, [*sets, f"vehicle.hill_start_assist.enabled_flag={enabled}"])).metrics
        code = int(m["assist_refusal_code"])
        print(f"{label:32s} {'on' if enabled else 'off':>6s} {m['rollback_distance_m']:13.3f} "
              f"{'yes' if m['engine_stalled_flag'] else 'no':>6s}  {REFUSAL_REASONS[code - 1] if code else '-'}")
