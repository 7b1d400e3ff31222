"""Brake-pedal force programmes of the passenger-car tests (brake_assist.md 7; UN R139 pedal corridor),
written as the scripted driver's pedal table (``driver.brake_pedal`` fractions of ``pedal.full_scale_force_n``).

* :func:`panic` - fast, light application (paper 002 P13, spec S1): 0 -> F in ``rise_s``, hold, release.
* :func:`normal` - slow, firm application (spec S2): 0 -> F in ``rise_s`` (about 1 s), hold.
* :func:`r139_reference` - slow linear ramp (spec 5.3: 80 N/s assumed) until the end of the run.
* :func:`r139_category_b` - quick application to a peak, eased into the corridor [0.5, 0.7]*F_ABS before
  t0 + 0.8 s and held there (spec 5.4, S8); t0 = the instant the force reaches 20 N.
Each returns (time_s, force_n) breakpoints; :func:`as_sets` turns them into ``--set`` strings.
"""
from __future__ import annotations

T0_FORCE_N = 20.0  # UN R139 / paper 002 P12: t0 = pedal force reaches 20 N


def panic(force_n: float, rise_s: float = 0.012, hold_until_s: float = 3.0, release_s: float = 0.5,
          start_s: float = 0.1) -> tuple[list[float], list[float]]:
    return ([0.0, start_s, start_s + rise_s, hold_until_s, hold_until_s + release_s],
            [0.0, 0.0, force_n, force_n, 0.0])


def normal(force_n: float, rise_s: float = 1.0, start_s: float = 0.1) -> tuple[list[float], list[float]]:
    return [0.0, start_s, start_s + rise_s], [0.0, 0.0, force_n]


def r139_reference(rate_n_per_s: float = 80.0, max_force_n: float = 400.0, start_s: float = 0.1):
    return [0.0, start_s, start_s + max_force_n / rate_n_per_s], [0.0, 0.0, max_force_n]


def r139_category_b(f_abs_n: float, rise_rate_n_per_s: float = 8000.0, peak_frac: float = 0.9,
                    hold_frac: float = 0.6, start_s: float = 0.1, ease_s: float = 0.3):
    """Spec S8: ramp at 8000 N/s to 0.9*F_ABS, hold, ease in 0.3 s to 0.6*F_ABS, reached before t0 + 0.8 s."""
    peak = peak_frac * f_abs_n
    t_peak = start_s + peak / rise_rate_n_per_s
    t0 = start_s + T0_FORCE_N / rise_rate_n_per_s
    t_ease_end = t0 + 0.8 - 0.05
    t_ease = t_ease_end - ease_s
    return [0.0, start_s, t_peak, t_ease, t_ease_end], [0.0, 0.0, peak, peak, hold_frac * f_abs_n]


def as_fracs(times: list[float], forces: list[float], full_scale_force_n: float) -> str:
    """TOML inline table of the pedal fractions."""
    ts = ", ".join(f"{t:.6g}" for t in times)
    fs = ", ".join(f"{min(max(f / full_scale_force_n, 0.0), 1.0):.6g}" for f in forces)
    return f"{{time_s=[{ts}], frac=[{fs}]}}"


def as_sets(times: list[float], forces: list[float], full_scale_force_n: float = 1000.0) -> list[str]:
    return [f"driver.brake_pedal={as_fracs(times, forces, full_scale_force_n)}"]
