"""Helpers shared by the tests: scenario-event strings for --set style overrides, cached runs, and the
rows a state machine logged."""
from __future__ import annotations

import functools

import vehicle_assist as va


def events_arg(*items: str) -> str:
    return "events=[" + ", ".join(items) + "]"


def sensor_fault(sensor: str, fault: str, at_s: float, extra: str = "") -> str:
    return f'{{at_s={at_s:g}, action="sensor_fault", sensor="{sensor}", fault="{fault}"{extra}}}'


def set_input(name: str, value: float, at_s: float) -> str:
    return f'{{at_s={at_s:g}, action="set_input", input="{name}", value={value:g}}}'


def valve_fault(fault: str, at_s: float = 0.0) -> str:
    return f'{{at_s={at_s:g}, action="actuator_fault", actuator="valve_32", fault="{fault}"}}'


def ehb_limited(at_s: float, limit_bar: float = 5.0) -> str:
    return f'{{at_s={at_s:g}, action="actuator_fault", actuator="ehb", fault="limited", limit_bar={limit_bar:g}}}'


@functools.lru_cache(maxsize=None)
def run(name: str, *sets: str):
    """Simulate a shipped scenario with overrides (cached: row-coverage tests reuse every run)."""
    return va.simulate(va.load_scenario(name, list(sets)))


def machine_rows(r, machine: str) -> list[tuple[str, str, str]]:
    return [(e.from_mode, e.to_mode, e.reason) for e in r.events if e.machine == machine]


def machine_event(r, machine: str, to_mode: str, reason: str | None = None, from_mode: str | None = None):
    for e in r.events:
        if e.machine == machine and e.to_mode == to_mode and (reason is None or e.reason == reason) \
                and (from_mode is None or e.from_mode == from_mode):
            return e
    return None


def reproduction(paper: str):
    """The registered reproduction of a paper (procedures/reproduce.py)."""
    from vehicle_assist.procedures.reproduce import REPRODUCTIONS

    return next(r for r in REPRODUCTIONS if r.paper == paper)


def simulate_all(names) -> dict:
    return {name: va.simulate(va.load_scenario(name)) for name in names}


def unexpected_checks(result) -> list[str]:
    """Checks whose outcome is not what the scenario expects (a negative control must fail its bound)."""
    return [f"{c.metric}={c.value:.4g} (bound {c.bound}, expect {c.expect})" for c in result.checks if not c.ok]


# a small hill-start envelope for the verification tests (falsifier and studies plant violations in it)
PLANTED_ENVELOPE = """
name = "planted"
function = "hill_start_amt"
base = "hsa_truck_full_14deg_8p0bar"
sets = ["run.duration_s=0.3", "requirements=[]"]
baseline = ["vehicle.hill_start_assist.enabled_flag=0"]
baseline_source = "issue #7"
[ranges.slope]
path = "road.slope_deg"
min = 0
max = 20
source = "issue #7 item 1"
[ranges.mass]
path = "vehicle.body.mass_kg"
min = 13000
max = 40000
source = "issue #7 item 1"
[choices.surface]
source = "issue #7 item 1"
[choices.surface.options]
gravel = { "road.friction_mu" = 0.6 }
wet = { "road.friction_mu" = 0.5 }
"""


def ecu_pressure_estimates(params, modes, p0: float = 0.0, dt: float = 0.005) -> list[float]:
    """The ESP's wheel-pressure estimate (functions/esp.py ``_estimate``) after each ESP period for a sequence of wheel
    modes, carrying the inlet-open timer as ``esp_step`` does (used by the pressure-estimate tests)."""
    from vehicle_assist.functions import esp

    p, open_s, out = p0, 0.0, []
    for wm in modes:
        p = esp._estimate(wm, p, 0.0, dt, params, open_s)
        open_s = open_s + dt if wm in (esp.W_B, esp.W_BP) else 0.0
        out.append(p)
    return out
