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


def esp_ecu(p, v_mps: float, p_mc_pa: float, settle_periods: int = 20) -> dict:
    """An ESP controller (functions/esp.py) on its own, all four wheels rolling free at ``v_mps``, the driver's master
    pressure ``p_mc_pa`` with the brake light on, every sensor and valve healthy, settled for ``settle_periods`` ESP
    periods (reference, pressure estimates at the driver's); step it with ``esp_ecu_step``."""
    import numpy as np

    from vehicle_assist.core.fsm import EVENT_FIELDS
    from vehicle_assist.vehicles import sedan_esp as se

    meas, ctl, wheels, hst, bst, _ = se.controller_states()
    r_w = p.body_wheel_radius_m
    for n in ("fl", "fr", "rl", "rr"):
        setattr(meas, f"wheel_speed_{n}_radps", v_mps / r_w)
        setattr(meas, f"wheel_speed_{n}_ok", 1.0)
        setattr(meas, f"inlet_valve_{n}_ok", 1.0)
    meas.master_pressure_pa = p_mc_pa
    meas.master_pressure_ok = 1.0
    meas.brake_light_switch_flag = 1.0
    meas.esp_valves_ok = 1.0
    meas.return_pump_ok = 1.0
    e = {"meas": meas, "ctl": ctl, "wheels": wheels, "hst": hst, "bst": bst, "t": 0.0, "n": np.int64(0),
         "events": np.zeros((512, EVENT_FIELDS)), "ag": np.zeros(6, dtype=np.bool_), "hg": np.zeros(8, dtype=np.bool_)}
    for _ in range(settle_periods):
        esp_ecu_step(e, p)
    return e


def esp_ecu_step(e: dict, p) -> None:
    """One ESP period of the controller built by ``esp_ecu`` (machine ids as the sedan_esp runner)."""
    from vehicle_assist.functions import esp

    e["n"] = esp.esp_step(e["ctl"], e["wheels"], e["hst"], e["meas"], p, p.esp_period_s, e["t"], 1, 5, e["events"],
                          e["n"], e["ag"], e["hg"], e["bst"], 6)
    e["t"] += p.esp_period_s


def envelope_point_run(env, point: dict, baseline: bool = False, sets=()):
    """The run (``va.simulate`` result) of the envelope point ``point`` (a falsify.json history point), the envelope's
    baseline twin with ``baseline``, extra overrides ``sets`` (e.g. a seeded defect)."""
    import vehicle_assist as va

    sc = env.scenario(point, baseline=baseline)
    return va.simulate(sc.with_sets(*sets) if sets else sc, requirements=False)


def envelope_point_metric(env, point: dict, metric: str, baseline: bool = False, sets=()) -> float:
    """``metric`` of :func:`envelope_point_run`."""
    return envelope_point_run(env, point, baseline, sets).metrics[metric]


G_MPS2 = 9.80665  # standard gravity
# peak of the SUV's dry Burckhardt set; road.friction_mu scales it (tire_blowout envelope, mu source)
MU_PEAK_DRY_SUV = 1.17


def mean_decel(run, t0: float, t1: float) -> float:
    """Mean deceleration [m/s^2] of a run between t0 and t1 (speed difference over the time difference)."""
    import numpy as np
    t = np.asarray(run.trace["time_s"])
    u = np.asarray(run.trace["speed_mps"])
    i0, i1 = int(np.argmin(abs(t - t0))), int(np.argmin(abs(t - t1)))
    return (u[i0] - u[i1]) / (t[i1] - t[i0])


def panic_stop_decel_bound(point: dict) -> float:
    """The stopping bound of a panic stop after a blowout on the tire_blowout envelope (issue #10: "a panic stop right
    after a blowout must work"; the spec states no deceleration): half the road's friction limit, 0.5 * mu_peak * g -
    UN R13-H Annex 6 asks an ABS stop for an adhesion utilisation of at least 0.75, so half the limit is a floor a
    working stop must clear, not a target."""
    return 0.5 * MU_PEAK_DRY_SUV * point["mu"] * G_MPS2


def fill_ecu_window(st, speeds, press) -> None:
    """Fill the blowout compensation's wheel-speed and pressure filter window (state ``st``) with constant per-wheel
    ``speeds`` [rad/s or m/s as the caller's rule expects] and ``press`` [Pa], as if held for a whole window."""
    from vehicle_assist.functions import blowout_compensation as bc
    n = bc.WS_WINDOW_N
    for k in range(n):
        for i in range(4):
            st[bc.S_VW_BUF + i * n + k] = speeds[i]
            st[bc.S_P_BUF + i * n + k] = press[i]
    st[bc.S_BUF_LAST] = n - 1
    st[bc.S_BUF_FILL] = n


class BlowoutEcu:
    """The blowout compensation's ECU loop on given measurements: ``reference_step`` + ``blowout_step`` every 5 ms,
    keeping the mode transitions as (from, to, reason) names in ``rows``. ``p``: packed vehicle parameters (copied;
    ``changes`` set fields on the copy); ``v_mps``: the default speed of all four wheels."""

    def __init__(self, p, v_mps: float = 60.0 / 3.6, **changes):
        import numpy as np
        from vehicle_assist.functions import blowout_compensation as bc
        self.p = p.copy()
        for k, v in changes.items():
            setattr(self.p, k, v)
        self.v = v_mps
        self.st = bc.initial_state()
        self.t = 0.0
        self.events = np.zeros((64, 5))
        self.n = 0
        self.req = np.zeros(4, dtype=np.int64)
        self.rows = []

    def run(self, s, vw=None, tpms=0.0, yaw=0.0, braking=0.0, inlet=(1, 1, 1, 1), p_est=(0, 0, 0, 0), a_x=0.0,
            a_y=0.0, p_mc=0.0, steer=0.0):
        import numpy as np
        from vehicle_assist.functions import blowout_compensation as bc
        vw = np.array((self.v,) * 4 if vw is None else vw, float)
        dt = 0.005
        for _ in range(int(round(s / dt))):
            v_ref = bc.reference_step(self.st, vw, a_x, tpms, dt, self.p)
            n0 = self.n
            self.n = bc.blowout_step(self.st, vw, v_ref, braking, a_x, yaw, steer, tpms, np.array(inlet, float),
                                     np.array(p_est, float), self.p, dt, self.t, 6, self.events, self.n, self.req,
                                     a_y, p_mc)
            for k in range(n0, self.n):
                _, _, f, to, g = self.events[k]
                self.rows.append((bc.MODES[int(f)], bc.MODES[int(to)], bc.REASONS[int(g)]))
            self.t += dt
        return self

    @property
    def mode(self):
        from vehicle_assist.functions import blowout_compensation as bc
        return bc.MODES[int(self.st[bc.S_MODE])]


def understeer_hold_state(*sets: str):
    """(blowout_compensation module, state, packed parameters) of a compensation in HOLD on FR for a blown FL of the
    shipped blowout_lf_80kph_curve vehicle (``sets`` applied): balance 40 bar from 0 bar, no capacity evidence - the
    understeer rule's unit rows (tests of understeer_persist_flag and understeer_restore_settled_flag)."""
    from vehicle_assist.functions import blowout_compensation as bc
    from vehicle_assist.scenarios.runner import pack_records
    sc = va.load_scenario("blowout_lf_80kph_curve").with_sets(*sets)
    p = pack_records([sc.vehicle.flat()])[0]
    st = bc.initial_state()
    st[bc.S_P_REQ] = 40.0e5
    st[bc.S_P_START] = 0.0
    st[bc.S_CAP_LATCHED] = 0.0
    return bc, st, p


def packed_params(scenario: str, *sets: str):
    """The packed vehicle parameters of a shipped scenario with ``sets`` applied (controller unit tests that step a
    function's ``step`` directly: the sedan's ESP of hba_snow_60kph, the SUV's of the blowout scenarios)."""
    from vehicle_assist.scenarios.runner import pack_records
    return pack_records([va.load_scenario(scenario, list(sets)).vehicle.flat()])[0]


# The two never-worse rows of tire_blowout (data/requirements/tire_blowout.toml, session n): the lateral deviation on the
# road (blowout_lateral_deviation_road_max_m, clipped at the road edge) and the road departure's earliness
# (blowout_road_departure_earliness_s). A test of "never worse than <reference run>" compares what the requirement
# compares: both rows' comparative_robustness of the run against the reference run (the twin, or a flag-0 run).
NEVER_WORSE_ROWS = ("tire_blowout.no_worse_than_no_compensation", "tire_blowout.no_earlier_road_departure")


def never_worse_rows(run, reference) -> dict:
    """{row id: robustness} of both never-worse rows, ``run`` judged against ``reference`` (>= 0: no worse in that
    row; < 0: worse by that much, m in row 1, s in row 2)."""
    from vehicle_assist.verification.requirements import comparative_robustness, get_requirement

    return {rid.split(".")[1]: comparative_robustness(get_requirement(rid), run.metrics, reference.metrics)
            for rid in NEVER_WORSE_ROWS}
