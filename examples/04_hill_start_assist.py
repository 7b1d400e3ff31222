"""Paper 000 in a few lines: the same hill starts with and without the hill-start assist.

The driver opens the hand park valve together with the service-brake release (the early release that
rolls a truck back). With the assist, the 3/2 valve keeps the spring brake applied until the clutch
carries the grade. Run: .venv/bin/python examples/04_hill_start_assist.py
"""
import vehicle_assist as va
from vehicle_assist.units import rpm

EARLY_DRIVER = 'driver.hand_valve={time_s=[0.0, 1.0], released=[0, 1]}'
print(f"{'scenario':28s} {'assist':>6s} {'rollback [m]':>13s} {'release phase':>14s} {'peak engine [rpm]':>18s}")
for name in ("hsa_truck_empty_11deg_80bar", "hsa_truck_full_14deg_80bar", "hsa_truck_full_14deg_65bar"):
    for enabled in (1, 0):
        sc = va.load_scenario(name, [EARLY_DRIVER, f"vehicle.hill_start_assist.enabled_flag={enabled}"])
        m = va.simulate(sc).metrics
        print(f"{name:28s} {'on' if enabled else 'off':>6s} {m['rollback_distance_m']:13.3f} "
              f"{m['park_release_phase_index']:14.0f} {rpm(m['engine_speed_peak_radps']):18.0f}")
