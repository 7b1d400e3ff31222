"""Requirements as Signal Temporal Logic formulas over trace channels, monitored with rtamt.

A requirement has an ``id`` (``<function>.<name>`` for shipped ones), a ``formula`` in rtamt's STL
syntax over the trace channels of the layout (``always(speed_mps >= -0.001)``), the clause it comes from
(``why``) and the unit of its robustness. Robustness is rtamt's discrete-time quantitative semantics
(Donze & Maler 2010): for ``always(x >= c)`` it is ``min_t (x(t) - c)``, the signed distance to
violation in the channel's unit; negative means violated.

* **Boolean channels** (names ending in ``_flag``) are passed to the monitor as +inf (flag >= 0.5) or
  -inf, so a comparison on them is qualitative and an implication ``always((held_flag > 0.5) ->
  (speed_mps >= -0.001))`` reports the robustness of its quantitative part, in m/s.
* **Derived channels** the monitor adds from the trace: ``displacement_m`` (position minus its first
  sample), ``jerk_filtered_mps3`` (common.md 10, as the jerk metrics), ``brake_released_flag`` (brake
  pedal below 0.05, hill_start_amt.md 6.4: released service brake).
* **Comparative requirements** (``kind = "no_worse_than_baseline"``) compare a run with its no-assist
  twin (issue #7 item 1): robustness = ``max(floor, baseline rollback) - rollback`` in metres, and -1
  (a Boolean part) if the assisted run stalls the engine while the baseline does not. ``metric`` names
  the run metric compared (default ``rollback_distance_m``; the brake assist compares
  ``stopping_distance_m``: stopping distance with HBA <= without).

Shipped requirements live in ``data/requirements/<function>.toml``.
"""
from __future__ import annotations

import functools
import math
from fractions import Fraction
import re
import threading
import tomllib
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import Annotated, Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, ValidationError

from vehicle_assist.scenarios.errors import InputError, did_you_mean, from_validation
from vehicle_assist.scenarios.schema import RequirementSpec

DATA = resources.files("vehicle_assist") / "data" / "requirements"
BRAKE_RELEASED_BELOW_FRAC = 0.05  # hill_start_amt.md 6.4 / vehicle files: brake_applied_frac = 0.05
STALL_PENALTY = -1.0  # robustness of "the assist caused a stall" (Boolean part of the comparative kind)

# STL words of rtamt's grammar (not channel names)
KEYWORDS = {
    "always", "eventually", "historically", "once", "since", "until", "unless", "precedes", "and", "or", "not",
    "implies", "iff", "xor", "abs", "sqrt", "exp", "pow", "rise", "fall", "prev", "next", "true", "false",
    "G", "F", "H", "O", "S", "U", "X", "s", "ms", "us", "ns", "inf",
}
DERIVED: dict[str, tuple[tuple[str, ...], str]] = {
    "displacement_m": (("position_m",), "position minus its first sample (uphill +)"),
    "jerk_filtered_mps3": (("time_s", "accel_mps2", "vehicle_held_flag"), "filtered jerk (common.md 10); 0 while held"),
    "brake_released_flag": (("brake_pedal_frac",), "1 while the service brake pedal is below 0.05"),
}


class Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)


class RequirementFile(Strict):
    function: str
    layout: str
    description: str = ""
    baseline: list[str] = []
    requirements: list[RequirementSpec] = Field(min_length=1)


@dataclass(frozen=True)
class Requirement:
    id: str
    formula: str
    why: str
    unit: str = ""
    kind: str = "stl"
    expect: str = "pass"
    rollback_floor_m: float = 0.01
    baseline: tuple[str, ...] = ()
    channels: tuple[str, ...] = ()  # trace channels the monitor reads (derived ones expanded)
    metric: str = "rollback_distance_m"  # comparative kind: the run metric compared with the baseline twin's

    @property
    def comparative(self) -> bool:
        return self.kind == "no_worse_than_baseline"

    def as_dict(self) -> dict:
        return {"id": self.id, "formula": self.formula, "why": self.why, "unit": self.unit, "kind": self.kind}


@dataclass
class RequirementResult:
    id: str
    robustness: float
    unit: str
    formula: str
    why: str
    expect: str = "pass"
    detail: dict = field(default_factory=dict)

    @property
    def satisfied(self) -> bool:
        return bool(self.robustness >= 0.0)

    @property
    def ok(self) -> bool:
        return self.satisfied if self.expect == "pass" else not self.satisfied

    def as_dict(self) -> dict:
        return {"id": self.id, "robustness": self.robustness, "unit": self.unit, "satisfied": self.satisfied,
                "expect": self.expect, "ok": self.ok, "formula": self.formula, "why": self.why, **self.detail}


# ------------------------------------------------------------------------------------------- parsing
def identifiers(formula: str) -> list[str]:
    """Names in a formula that are not STL words (channel names); time bounds like ``15s`` are skipped."""
    names = re.findall(r"(?<![\w.])[A-Za-z_]\w*", formula)
    return [n for n in dict.fromkeys(names) if n not in KEYWORDS]


def known_channels(layout: str) -> dict[str, str]:
    from vehicle_assist.vehicles import layouts

    out = dict(layouts.get(layout).CHANNELS)
    for name, (needs, doc) in DERIVED.items():
        if all(n in out for n in needs):
            out[name] = doc
    return out


def _needed(names: list[str], layout_channels: dict) -> tuple[str, ...]:
    out: list[str] = []
    for n in names:
        if n in DERIVED:
            out += [c for c in DERIVED[n][0] if c != "time_s"]
        else:
            out.append(n)
    return tuple(dict.fromkeys(c for c in out if c != "time_s"))


@functools.lru_cache(maxsize=256)
def _check_formula(formula: str, layout: str) -> tuple[str, ...]:
    """Parse the formula with rtamt and check its channels; returns the trace channels it reads.
    Raises ValueError with a one-line reason."""
    chans = known_channels(layout)
    names = identifiers(formula)
    for n in names:
        if n not in chans:
            raise ValueError(f"unknown channel {n!r}{did_you_mean(n, chans)} for layout {layout}")
    if not names:
        raise ValueError("the formula reads no channel")
    _spec(formula, tuple(names), 0.01)
    return _needed(names, chans)


_local = threading.local()


def _rtamt():
    """Import rtamt. Its generated ANTLR parsers (0.4.10) do ``from typing.io import TextIO``; ``typing.io``
    is deprecated and gone in Python 3.13, so provide it when missing, and keep its deprecation warning quiet."""
    import sys
    import types
    import typing
    import warnings

    if "rtamt" not in sys.modules:
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", DeprecationWarning)
                import typing.io  # noqa: F401
        except ImportError:
            shim = types.ModuleType("typing.io")
            shim.TextIO, shim.IO, shim.BinaryIO = typing.TextIO, typing.IO, typing.BinaryIO
            sys.modules["typing.io"] = shim
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        import rtamt
    return rtamt


def _spec(formula: str, names: tuple[str, ...], dt_s: float):
    """A parsed rtamt discrete-time spec (cached per thread: rtamt specs hold evaluation state)."""
    rtamt = _rtamt()
    cache = getattr(_local, "specs", None)
    if cache is None:
        cache = _local.specs = {}
    key = (formula, names, round(dt_s, 9))
    spec = cache.get(key)
    if spec is None:
        spec = rtamt.StlDiscreteTimeSpecification()
        for n in names:
            spec.declare_var(n, "float")
        spec.spec = formula
        # rtamt checks that each time bound is a whole number of sampling periods with exact fractions
        # (Fraction(period * 10**9)); a float period such as 0.001 s gives 999999.99... ns and every
        # bound fails that check. Pass the period as an exact fraction of whole nanoseconds.
        spec.set_sampling_period(Fraction(max(1, round(dt_s * 1e9)), 10**9), "s", 0.1)
        try:
            import logging

            logging.getLogger().setLevel(max(logging.getLogger().level, logging.ERROR))
            spec.parse()
        except Exception as exc:  # rtamt raises its own exception types for syntax errors
            text = " ".join(str(exc).split())
            text = text.replace("RTAMT Exception: ", "")
            text = text.split(" expecting")[0]
            raise ValueError(f"STL syntax: {text[:200]}") from None
        cache[key] = spec
    return spec


def make_requirement(spec: RequirementSpec, layout: str, where: str, prefix: str,
                     default_baseline: tuple[str, ...] = ()) -> Requirement:
    if spec.kind == "no_worse_than_baseline":
        metric = spec.metric
        from vehicle_assist.metrics import METRICS

        for name in metric_names(metric):
            # (review RI3, session i) an unknown name was read as NaN in both runs: the requirement silently "not
            # judged" everywhere, and with several metrics its NaN hid the others' violations
            if name not in METRICS:
                raise InputError(f"{where}: {prefix}.metric = {metric!r}: {name!r} is no metric"
                                 f"{did_you_mean(name, METRICS)}; see 'vehicle-assist metrics'")
        formula = spec.formula or (f"{metric} <= max({spec.rollback_floor_m:g}, baseline {metric}); "
                                   "no engine stall the baseline does not have")
        baseline = tuple(spec.baseline) or default_baseline or ("vehicle.hill_start_assist.enabled_flag=0",)
        return Requirement(spec.id, formula, spec.why, spec.unit or "m", spec.kind, spec.expect, spec.rollback_floor_m,
                           baseline, ("position_m",), metric)
    if not spec.formula:
        raise InputError(f"{where}: {prefix}.formula: required for an STL requirement")
    try:
        channels = _check_formula(spec.formula, layout)
    except ValueError as exc:
        raise InputError(f"{where}: {prefix}.formula = {spec.formula!r}: {exc}") from None
    unit = spec.unit or _unit_guess(spec.formula)
    return Requirement(spec.id, spec.formula, spec.why, unit, spec.kind, spec.expect, spec.rollback_floor_m, (), channels)


def _unit_guess(formula: str) -> str:
    from vehicle_assist.units import unit_of

    for n in identifiers(formula):
        if not n.endswith("_flag"):
            return unit_of(n) or ""
    return ""


# ------------------------------------------------------------------------------------------- files
def shipped_requirement_files() -> dict[str, Path]:
    folder = Path(str(DATA))
    return {p.stem: p for p in sorted(folder.glob("*.toml"))}


@functools.lru_cache(maxsize=32)
def _load_file_cached(path_text: str, mtime: int) -> tuple[RequirementFile, dict[str, Requirement]]:
    path = Path(path_text)
    try:
        raw = tomllib.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise InputError(f"{path}: file not found") from None
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"{path}: not valid TOML ({exc}); fix the syntax at that place") from None
    try:
        model = RequirementFile.model_validate(raw, strict=True)  # strict: "0.01" and true are not numbers
    except ValidationError as exc:
        raise from_validation(exc, RequirementFile, str(path)) from None
    from vehicle_assist.vehicles import layouts

    if model.layout not in layouts.names():
        raise InputError(f"{path}: layout = {model.layout!r}: unknown{did_you_mean(model.layout, layouts.names())}")
    reqs: dict[str, Requirement] = {}
    for i, spec in enumerate(model.requirements):
        full = f"{model.function}.{spec.id}"
        if full in reqs:
            raise InputError(f"{path}: requirements.{i}.id = {spec.id!r}: defined twice")
        r = make_requirement(spec, model.layout, str(path), f"requirements.{i}", tuple(model.baseline))
        reqs[full] = Requirement(full, r.formula, r.why, r.unit, r.kind, r.expect, r.rollback_floor_m, r.baseline, r.channels,
                                 r.metric)
    return model, reqs


def load_requirement_file(name_or_path: str | Path) -> dict[str, Requirement]:
    files = shipped_requirement_files()
    path = files.get(str(name_or_path)) or Path(name_or_path)
    if not path.exists():
        raise InputError(f"no requirement file {str(name_or_path)!r}{did_you_mean(str(name_or_path), files)}; shipped: {', '.join(files)}")
    return dict(_load_file_cached(str(path.resolve()), path.stat().st_mtime_ns)[1])


def all_shipped() -> dict[str, Requirement]:
    out: dict[str, Requirement] = {}
    for name in shipped_requirement_files():
        out.update(load_requirement_file(name))
    return out


def get_requirement(rid: str) -> Requirement:
    reqs = all_shipped()
    if rid not in reqs:
        raise InputError(f"requirement {rid!r}: unknown{did_you_mean(rid, reqs)}; shipped: {', '.join(reqs)}")
    return reqs[rid]


def resolve(specs, layout: str, where: str) -> list[Requirement]:
    """Requirements attached to a scenario (``requirements = [...]``): shipped ids or inline specs."""
    out = []
    for i, item in enumerate(specs):
        prefix = f"requirements.{i}"
        if isinstance(item, str):
            item = RequirementSpec(id=item)
        if item.formula is None and item.kind == "stl":
            reqs = all_shipped()
            if item.id not in reqs:
                raise InputError(f"{where}: {prefix} = {item.id!r}: no shipped requirement of that id{did_you_mean(item.id, reqs)}; "
                                 "give a shipped id (see data/requirements) or an inline formula")
            req = reqs[item.id]
            if not req.comparative:
                _ok = [c for c in req.channels if c not in known_channels(layout)]
                if _ok:
                    raise InputError(f"{where}: {prefix} = {item.id!r}: reads channel {_ok[0]!r}, which layout {layout} has not")
            if item.expect != "pass":
                req = Requirement(req.id, req.formula, req.why, req.unit, req.kind, item.expect, req.rollback_floor_m,
                                  req.baseline, req.channels, req.metric)
            out.append(req)
        else:
            out.append(make_requirement(item, layout, where, prefix))
    return out


# ------------------------------------------------------------------------------------------- monitoring
def monitor_inputs(trace, names: list[str]) -> dict[str, list]:
    """Channel samples for rtamt: flags as +-inf, derived channels computed from the trace."""
    data: dict[str, list] = {"time": np.asarray(trace["time_s"], dtype=float).tolist()}
    for n in names:
        if n == "displacement_m":
            x = np.asarray(trace["position_m"], dtype=float)
            v = x - x[0]
        elif n == "jerk_filtered_mps3":
            from vehicle_assist.metrics.common import filtered_jerk

            v = np.asarray(filtered_jerk(trace), dtype=float)
        elif n == "brake_released_flag":
            v = np.where(np.asarray(trace["brake_pedal_frac"]) < BRAKE_RELEASED_BELOW_FRAC, np.inf, -np.inf)
        else:
            v = np.asarray(trace[n], dtype=float)
        if n.endswith("_flag") and n != "brake_released_flag":
            v = np.where(v >= 0.5, np.inf, -np.inf)
        data[n] = v.tolist()
    return data


def robustness(req: Requirement, trace) -> float:
    """Robustness of an STL requirement on one trace (at time 0), in the requirement's unit."""
    if req.comparative:
        raise ValueError(f"{req.id} compares with the baseline twin; use comparative_robustness")
    names = tuple(identifiers(req.formula))
    t = np.asarray(trace["time_s"], dtype=float)
    dt = float(np.median(np.diff(t))) if len(t) > 1 else 0.01
    spec = _spec(req.formula, names, dt)
    try:
        rob = spec.evaluate(monitor_inputs(trace, list(names)))
    except Exception as exc:  # rtamt's own exception types (e.g. a bound that is not a whole number of samples)
        text = " ".join(str(exc).split()).replace("RTAMT Exception: ", "")
        raise InputError(f"requirement {req.id}: {req.formula!r} cannot be evaluated on a trace recorded every "
                         f"{dt:g} s: {text}; choose run.record_period_s that divides the formula's time bounds") from None
    value = float(rob[0][1]) if rob else float("nan")
    return value


def no_worse_robustness(metrics: dict, baseline_metrics: dict, metric: str, floor: float) -> float:
    """``max(floor, baseline value) - value`` [unit of ``metric``]; STALL_PENALTY if the assisted run stalls and the
    baseline does not (issue #7 item 1: never worse than no assist). Shared by the requirement kind
    ``no_worse_than_baseline`` and the envelope study (verification/study.py)."""
    rb = float(metrics.get(metric, float("nan")))
    rb0 = float(baseline_metrics.get(metric, float("nan")))
    if math.isnan(rb0):
        # no baseline value (e.g. the car without HBA never stops after the driver released the pedal): nothing to
        # compare with; max(floor, nan) took the floor and scored an assisted stop of 76.9 m as 76.9 m 'worse'
        return float("nan")
    if math.isnan(rb):
        # the assisted run has no value where its twin has one (e.g. the HBA car never stopped, the no-HBA car did):
        # worse, a Boolean failure like the stall (independent review of issue #9: r was NaN, 'not counted')
        return STALL_PENALTY
    r = max(floor, rb0) - rb
    if metrics.get("engine_stalled_flag", 0.0) >= 0.5 and baseline_metrics.get("engine_stalled_flag", 0.0) < 0.5:
        r = min(r, STALL_PENALTY)
    return float(r) if math.isfinite(r) else float("nan")


def metric_names(text: str) -> list[str]:
    """The metric names of a comparative requirement's ``metric`` field: one name or several joined by commas."""
    return [m.strip() for m in text.split(",") if m.strip()]


def comparative_metrics(req: Requirement) -> list[str]:
    """The run metrics a ``no_worse_than_baseline`` requirement compares, each with the twin's own value of the same
    metric (e.g. the lane exceedance per side)."""
    return metric_names(req.metric)


def comparative_robustness(req: Requirement, metrics: dict, baseline_metrics: dict) -> float:
    """Robustness of a ``no_worse_than_baseline`` requirement (``no_worse_robustness`` on its metric and floor; with
    several metrics the least of them: each must be no worse than the twin's). A metric AT the floor in both runs (a
    clipped reading such as the lane exceedance, 0 anywhere inside the lane: it carries no margin) is left out of the
    least when another is not: its robustness 0 cannot be a violation, and it would hide the margin of the others. A
    signed metric below the floor (e.g. the lane overshoot, negative inside the lane) stays in: floor - value is then the
    real distance to a violation on that side (review RI3, session i: leaving out every metric at OR below the floor
    reported a clean side's neighbour's margin, +0.3 m where the car was ~0 m from the marking)."""
    names = comparative_metrics(req)
    robs = [no_worse_robustness(metrics, baseline_metrics, m, req.rollback_floor_m) for m in names]
    if any(math.isnan(r) for r in robs):
        # a metric the twin has no value of cannot be judged; a violation on another still stands (review RI3,
        # session i: the NaN hid it - the conjunction is violated whatever the unjudged part)
        worst = min((r for r in robs if not math.isnan(r)), default=float("nan"))
        return float(worst) if worst < 0.0 else float("nan")
    floor = req.rollback_floor_m
    live = [r for m, r in zip(names, robs)
            if not (float(metrics.get(m, float("nan"))) == floor and float(baseline_metrics.get(m, float("nan"))) == floor)]
    return float(min(live or robs))


def evaluate(reqs: list[Requirement], trace, metrics: dict | None = None, baseline_metrics: dict | None = None
             ) -> list[RequirementResult]:
    out = []
    for r in reqs:
        if r.comparative:
            value = comparative_robustness(r, metrics or {}, baseline_metrics or {})
            detail = ({"rollback_m": (metrics or {}).get("rollback_distance_m"),
                       "baseline_rollback_m": (baseline_metrics or {}).get("rollback_distance_m")}
                      if r.metric == "rollback_distance_m" else
                      {k: v for m in comparative_metrics(r) for k, v in
                       ((m, (metrics or {}).get(m)), (f"baseline_{m}", (baseline_metrics or {}).get(m)))})
        else:
            value, detail = robustness(r, trace), {}
        out.append(RequirementResult(r.id, value, r.unit, r.formula, r.why, r.expect, detail))
    return out
