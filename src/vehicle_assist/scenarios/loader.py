"""Load vehicle and scenario files, apply dotted-path overrides, and build the SI records the
compiled kernels read. All user-facing failures raise :class:`InputError` with a one-line message."""
from __future__ import annotations

import copy
import functools
import hashlib
import json
import math
import os
import tomllib
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np
from pydantic import BaseModel, ValidationError

from vehicle_assist.core.tables import Table, TableError
from vehicle_assist.plant.sensors import FAULTS
from vehicle_assist.scenarios.errors import InputError, did_you_mean, from_validation
from vehicle_assist.scenarios.guards import MAX_BASE_CHAIN, MAX_DEPTH, check_path_text, read_bounded, toml_depth
from vehicle_assist.scenarios.schema import Scenario
from vehicle_assist.units import DEG_TO_RAD, KPH_TO_MPS, to_si
from vehicle_assist.vehicles import layouts
from vehicle_assist.vehicles.common import ACTIONS, EVENT_CAPACITY, INPUTS, OP_ABOVE, OP_BELOW
from vehicle_assist.vehicles.schema import LAYOUTS, flatten_vehicle

DATA = resources.files("vehicle_assist") / "data"


def shipped(kind: str) -> dict[str, Path]:
    """Shipped files of a kind ('vehicles' or 'scenarios'), by name."""
    folder = Path(str(DATA / kind))
    return {p.stem: p for p in sorted(folder.glob("*.toml"))}


def _read_toml(path: Path) -> dict:
    """Parsed TOML of a regular .toml file of bounded size (a fresh copy; parsing is cached by the file's
    device, inode, modification time and size). Nesting deeper than MAX_DEPTH is refused."""
    text, identity = read_bounded(Path(path))
    cached = _parsed.get(identity)
    if cached is None or cached[0] != text:
        cached = (text, _parse_toml(text, Path(path)))
        if len(_parsed) > 256:
            _parsed.clear()
        _parsed[identity] = cached
    return copy.deepcopy(cached[1])


_parsed: dict[tuple, tuple[str, dict]] = {}


def _parse_toml(text: str, path: Path) -> dict:
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"{path}: not valid TOML ({exc}); fix the syntax at that place") from None
    except RecursionError:
        raise InputError(f"{path}: nested too deeply to parse; tables and arrays may nest at most {MAX_DEPTH} levels") from None
    if toml_depth(doc) > MAX_DEPTH:
        raise InputError(f"{path}: nested too deeply; tables and arrays may nest at most {MAX_DEPTH} levels")
    return doc


def _resolve(name_or_path: str | Path, kind: str, anchor: Path | None = None) -> Path:
    """A shipped name, or a path; a relative path is taken relative to ``anchor`` (the directory of the
    file that names it), else to the working directory."""
    files = shipped(kind)
    if not isinstance(name_or_path, (str, Path)):
        raise InputError(f"{name_or_path!r}: give a shipped {kind[:-1]} name or a .toml file path (a string)")
    text = str(name_or_path)
    if text in files:
        return files[text]
    check_path_text(text, f"{kind[:-1]} file")
    path = Path(text)
    if path.suffix == ".toml" or "/" in text:
        return anchor / path if anchor is not None and not path.is_absolute() else path
    raise InputError(f"no shipped {kind[:-1]} named {text!r}{did_you_mean(text, files)}; a file must be given as a path "
                     "ending in .toml; see 'vehicle-assist list'")


def deep_merge(base: dict, over: dict) -> dict:
    out = copy.deepcopy(base)
    for key, value in over.items():
        if isinstance(value, dict) and isinstance(out.get(key), dict) and key not in ("full_load_torque", "pedal_map"):
            out[key] = deep_merge(out[key], value)
        else:
            out[key] = copy.deepcopy(value)
    return out


# --------------------------------------------------------------------------------------------- vehicles
@dataclass(frozen=True, repr=False)
class Vehicle:
    model: BaseModel
    sources: dict[str, str]
    path: Path
    raw: dict

    def __repr__(self) -> str:
        return f"<Vehicle {self.model.name} (layout {self.model.layout}, {self.path.name})>"

    @property
    def layout(self) -> str:
        return self.model.layout

    def flat(self) -> dict:
        """SI record of the vehicle (computed once per Vehicle, then shared; do not mutate it)."""
        cached = self.__dict__.get("_flat")
        if cached is None:
            cached = layouts.get(self.layout).derived(flatten_vehicle(self.model))
            object.__setattr__(self, "_flat", cached)
        return cached


def _vehicle_raw(name_or_path: str | Path, seen: tuple = (), anchor: Path | None = None) -> tuple[dict, dict[str, str], Path]:
    """The merged raw vehicle dict (base chain applied), its sources and its path; a fresh copy.

    ``seen``: real paths of the files that led here (cycle detection, chain length at most MAX_BASE_CHAIN)."""
    path = _resolve(name_or_path, "vehicles", anchor)
    real = os.path.realpath(path)
    if real in seen:
        raise InputError(f"{path}: the base chain makes a cycle (this file is its own base, directly or through others)")
    if len(seen) >= MAX_BASE_CHAIN:
        raise InputError(f"{path}: the base chain is longer than {MAX_BASE_CHAIN} files; start from a shipped vehicle")
    raw, sources, p = _vehicle_raw_cached(str(path), _chain_stamp(path), seen + (real,))
    return copy.deepcopy(raw), dict(sources), p


def _chain_stamp(path: Path) -> tuple:
    """Identities of a vehicle file and its base chain: the cache key of the merged result."""
    stamp = []
    seen: set[str] = set()
    current: Path | None = path
    while current is not None and str(current) not in seen and len(stamp) <= MAX_BASE_CHAIN:
        seen.add(str(current))
        try:
            st = os.stat(current)
            stamp.append((str(current), st.st_dev, st.st_ino, st.st_mtime_ns, st.st_size))
            base = _read_toml(current).get("base")
            current = _resolve(base, "vehicles", current.parent) if isinstance(base, str) else None
        except (OSError, ValueError, InputError):
            break  # the real load reports the problem
    return tuple(stamp)


@functools.lru_cache(maxsize=64)
def _vehicle_raw_cached(path_text: str, stamp: tuple, seen: tuple) -> tuple[dict, dict[str, str], Path]:
    path = Path(path_text)
    raw = _read_toml(path)
    if not isinstance(raw.get("layout"), str) and not isinstance(raw.get("base"), str):
        # said without listing the file's keys: a base may point at any file, whose keys are not ours to show
        raise InputError(f"{path}: not a vehicle file (it needs layout = \"...\" or base = \"...\")")
    base = raw.pop("base", None)
    sources: dict[str, str] = {}
    if base is not None:
        if not isinstance(base, str):
            raise InputError(f"{path}: base = {base!r}: give a shipped vehicle name or a .toml path (a string)")
        for section, body in raw.items():  # a value changed here must say where the new value comes from
            if isinstance(body, dict):
                own = body.get("source") if isinstance(body.get("source"), dict) else {}
                for key in body:
                    if key != "source" and key not in own:
                        raise InputError(f"{path}: {section}.{key} overrides the value of base {base!r} but has no source "
                                         f"of its own; add it to [{section}.source] (paper, standard, data sheet or 'assumed: why')")
        try:
            base_raw, sources, _ = _vehicle_raw(base, seen, path.parent)
        except InputError as exc:
            raise InputError(f"{path}: base: {exc}") from None
        raw = deep_merge(base_raw, raw)
    for section, body in raw.items():
        if isinstance(body, dict) and isinstance(body.get("source"), dict):
            for key, text in body["source"].items():
                sources[f"{section}.{key}"] = str(text)
    return raw, sources, path


def load_vehicle(name_or_path: str | Path, overrides: dict | None = None, override_where: str = "",
                 anchor: Path | None = None, credits: dict[str, str] | None = None) -> Vehicle:
    """``credits``: source strings of overridden keys ("section.key" -> where the value was set)."""
    raw, sources, path = _vehicle_raw(name_or_path, anchor=anchor)
    if overrides:
        for section, body in overrides.items():
            if section not in raw or not isinstance(raw[section], dict):
                known = [k for k, v in raw.items() if isinstance(v, dict)]
                raise InputError(f"{override_where or path}: vehicle.{section}: unknown subsystem{did_you_mean(section, known)}; known: {', '.join(known)}")
            if not isinstance(body, dict):
                raise InputError(f"{override_where or path}: vehicle.{section} must be a table of overrides")
            own = body.get("source") if isinstance(body.get("source"), dict) else {}
            for key in body:
                if key != "source":
                    default = (credits or {}).get(f"{section}.{key}", f"override in {override_where or 'caller'}")
                    sources[f"{section}.{key}"] = str(own.get(key, default))
        raw = deep_merge(raw, overrides)
    layout = raw.get("layout")
    if layout not in LAYOUTS:
        raise InputError(f"{path}: layout = {layout!r} unknown{did_you_mean(layout, LAYOUTS)}; use one of {', '.join(LAYOUTS)}")
    model_cls = LAYOUTS[layout]
    clean = {}
    for section, body in raw.items():
        if isinstance(body, dict):
            body = {k: v for k, v in body.items() if k != "source"}
            field = model_cls.model_fields.get(section)
            known = getattr(field.annotation, "model_fields", {}) if field is not None else {}
            for key in body:
                if key in known and f"{section}.{key}" not in sources:
                    raise InputError(f"{path}: {section}.{key} has no source; add it to [{section}.source] (paper, standard, data sheet or 'assumed: why')")
        clean[section] = body
    try:
        model = model_cls.model_validate(clean, strict=True)  # strict: "14" and true are not numbers
    except ValidationError as exc:
        loc = exc.errors()[0]["loc"]
        over = (overrides or {}).get(loc[0]) if loc else None
        if override_where and isinstance(over, dict) and (len(loc) < 2 or loc[1] in over):
            raise from_validation(exc, model_cls, override_where, "vehicle") from None
        raise from_validation(exc, model_cls, str(path)) from None
    except TableError as exc:
        raise InputError(f"{path}: {exc}") from None
    return Vehicle(model, sources, path, clean)


# --------------------------------------------------------------------------------------------- overrides
def parse_value(text: str) -> Any:
    try:
        value = tomllib.loads(f"v = {text}")["v"]
    except tomllib.TOMLDecodeError:
        return text
    except RecursionError:
        raise InputError(f"value {text[:40]!r}...: nested too deeply (at most {MAX_DEPTH} levels)") from None
    if isinstance(value, (dict, list)) and toml_depth(value) > MAX_DEPTH:
        raise InputError(f"value {text[:40]!r}...: nested too deeply (at most {MAX_DEPTH} levels)")
    return value


def apply_set(raw: dict, assignment: str, where: str) -> dict:
    """Apply ``dotted.path=value`` to a raw scenario dict; the path's parents must exist or be known tables."""
    if "=" not in assignment:
        raise InputError(f"--set {assignment!r}: write it as dotted.path=value, e.g. vehicle.body.mass_kg=30000")
    path, text = assignment.split("=", 1)
    keys = [k.strip() for k in path.strip().split(".") if k.strip()]
    if not keys:
        raise InputError(f"--set {assignment!r}: the path is empty")
    if len(keys) > MAX_DEPTH:
        raise InputError(f"--set {path[:60]!r}...: {len(keys)} levels; paths may have at most {MAX_DEPTH}")
    out = copy.deepcopy(raw)
    node = out
    for depth, key in enumerate(keys[:-1]):
        if key not in node:
            if depth == 0 and key not in Scenario.model_fields:
                raise InputError(f"--set {path}: unknown section {key!r}{did_you_mean(key, Scenario.model_fields)}")
            node[key] = {}
        if not isinstance(node[key], dict):
            raise InputError(f"--set {path}: {'.'.join(keys[: depth + 1])} is a value, not a table")
        node = node[key]
    node[keys[-1]] = parse_value(text.strip())
    return out


def _check_vehicle_override_keys(vehicle_raw: dict, overrides: dict, where: str) -> None:
    for section, body in overrides.items():
        if isinstance(body, dict) and isinstance(vehicle_raw.get(section), dict):
            for key in body:
                if key != "source" and key not in vehicle_raw[section]:
                    known = [k for k in vehicle_raw[section] if k != "source"]
                    raise InputError(f"{where}: vehicle.{section}.{key}: unknown key{did_you_mean(key, known)}; known keys here: {', '.join(known)}")


# --------------------------------------------------------------------------------------------- scenarios
@dataclass(repr=False)
class LoadedScenario:
    """A validated scenario with its vehicle, ready to simulate."""

    def __repr__(self) -> str:  # one line (the dataclass repr printed ~25,000 characters of raw data)
        sets = f", {len(self.sets)} overrides" if self.sets else ""
        return f"<LoadedScenario {self.model.name} (vehicle {self.vehicle.model.name}, layout {self.layout}{sets})>"

    model: Scenario
    vehicle: Vehicle
    path: Path | None
    raw: dict
    sets: tuple[str, ...] = ()
    flat: dict = field(default_factory=dict)

    @property
    def name(self) -> str:
        return self.model.name

    @property
    def layout(self) -> str:
        return self.vehicle.layout

    def scenario_hash(self) -> str:
        return hashlib.sha256(json.dumps(self.raw, sort_keys=True, default=str).encode()).hexdigest()[:16]

    def parameter_hash(self) -> str:
        items = {k: (list(v.x) + list(v.y) if isinstance(v, Table) else np.asarray(v).tolist()) for k, v in self.vehicle.flat().items()}
        return hashlib.sha256(json.dumps(items, sort_keys=True).encode()).hexdigest()[:16]

    def with_sets(self, *assignments: str) -> "LoadedScenario":
        """A new scenario with further dotted overrides (this one is not changed).

        Overrides of vehicle parameters (``vehicle.<subsystem>.<key>=value``) re-validate only that
        subsystem (fast enough for sweeps of 10,000 variants); anything else reloads the scenario.
        """
        fast = all(a.split("=", 1)[0].count(".") == 2 and a.startswith("vehicle.") and "=" in a for a in assignments)
        if not fast:
            return scenario_from_raw(self.raw, self.path, self.sets + tuple(assignments), already_set=self.sets)
        where = str(self.path) if self.path else "scenario"
        raw = self.raw
        model = self.vehicle.model
        sources = dict(self.vehicle.sources)
        for assignment in assignments:
            raw = apply_set(raw, assignment, where)
            path, text = assignment.split("=", 1)
            _, section, key = path.strip().split(".")
            current = getattr(model, section, None)
            if not isinstance(current, BaseModel):
                known = [k for k, v in model if isinstance(v, BaseModel)]
                raise InputError(f"{where}: vehicle.{section}: unknown subsystem{did_you_mean(section, known)}; known: {', '.join(known)}")
            if key not in type(current).model_fields:
                known = list(type(current).model_fields)
                raise InputError(f"{where}: vehicle.{section}.{key}: unknown key{did_you_mean(key, known)}; known keys here: {', '.join(known)}")
            data = current.model_dump()
            data[key] = parse_value(text.strip())
            try:
                new_section = type(current).model_validate(data, strict=True)
            except ValidationError as exc:
                raise from_validation(exc, type(current), where, f"vehicle.{section}") from None
            except TableError as exc:
                raise InputError(f"{where}: vehicle.{section}.{key}: {exc}") from None
            model = model.model_copy(update={section: new_section})
            sources[f"{section}.{key}"] = f"override: {assignment.strip()}"
        vehicle = Vehicle(model, sources, self.vehicle.path, self.vehicle.raw)
        # incremental SI record: the base record with only the touched subsystems flattened again
        from vehicle_assist.vehicles.schema import flatten_section

        flat = dict(self.vehicle.flat())
        for section in {a.split("=", 1)[0].strip().split(".")[1] for a in assignments}:
            flat.update(flatten_section(section, getattr(model, section)))
        object.__setattr__(vehicle, "_flat", layouts.get(vehicle.layout).derived(flat))
        out = LoadedScenario(self.model, vehicle, self.path, raw, self.sets + tuple(assignments))
        # the scenario record reads the vehicle's rolling resistance (road default) and gear names
        touched = {a.split("=", 1)[0].strip().rsplit(".", 1)[1] for a in assignments}
        out.flat = build_scenario_record(out, where) if touched & {"rolling_resistance_coeff", "gear_names"} else self.flat
        return out


def load_scenario(name_or_path: str | Path, sets: list[str] | tuple[str, ...] = ()) -> LoadedScenario:
    path = _resolve(name_or_path, "scenarios")
    raw = _read_toml(path)
    if not any(key in raw for key in ("name", "vehicle", "run")):
        # said without listing the file's keys: any TOML file could be named here
        raise InputError(f"{path}: not a scenario file (it needs name, vehicle and run; see docs/scenarios.md)")
    return scenario_from_raw(raw, path, tuple(sets))


def scenario_from_raw(raw: dict, path: Path | None, sets: tuple[str, ...], already_set: tuple[str, ...] = ()) -> LoadedScenario:
    where = str(path) if path else "scenario"
    for assignment in sets[len(already_set):]:
        raw = apply_set(raw, assignment, where)
    try:
        model = Scenario.model_validate(raw, strict=True)  # strict: "14" and true are not numbers
    except ValidationError as exc:
        raise from_validation(exc, Scenario, where) from None
    except TableError as exc:
        raise InputError(f"{where}: {exc}") from None
    overrides = {k: v for k, v in (model.vehicle.model_extra or {}).items()}
    # a relative base is taken relative to the scenario file; one given with --set, relative to the working directory
    base_from_set = any(a.split("=", 1)[0].strip() == "vehicle.base" for a in sets)
    anchor = path.parent if path is not None and not base_from_set else None
    credits = {}
    for a in sets:
        keys = a.split("=", 1)[0].strip().split(".")
        if len(keys) == 3 and keys[0] == "vehicle":
            credits[f"{keys[1]}.{keys[2]}"] = f"override on the command line: --set {a.strip()}"
    try:
        base_raw, _, _ = _vehicle_raw(model.vehicle.base, anchor=anchor)
    except InputError as exc:
        raise InputError(f"{where}: vehicle.base: {exc}") from None
    _check_vehicle_override_keys(base_raw, overrides, where)
    vehicle = load_vehicle(model.vehicle.base, overrides, override_where=where, anchor=anchor, credits=credits)
    loaded = LoadedScenario(model, vehicle, path, raw, sets)
    loaded.flat = build_scenario_record(loaded, where)
    return loaded


def _table(tab, x_key: str, y_key: str, x_name: str, y_name: str, y_factor: float = 1.0, interpolation: str = "linear") -> Table:
    xs = tuple(float(v) for v in getattr(tab, x_key))
    ys = tuple(float(v) * y_factor for v in getattr(tab, y_key))
    return Table(x_name, y_name, xs, ys, "clamp", interpolation)


def build_scenario_record(sc: LoadedScenario, where: str) -> dict:
    m = sc.model
    lay = layouts.get(sc.layout)
    v = sc.vehicle.model
    flat: dict[str, Any] = {
        "duration_s": m.run.duration_s,
        "plant_step_s": m.run.plant_step_s,
        "controller_period_s": m.run.controller_period_s,
        "record_period_s": m.run.record_period_s,
        "initial_position_m": m.run.initial_position_m,
        "initial_speed_mps": m.run.initial_speed_kph * KPH_TO_MPS,
        "initial_lateral_speed_mps": m.run.initial_lateral_speed_mps,
    }
    for key, value in sc.vehicle.flat().items():
        if key.endswith("_period_s"):
            ratio = value / m.run.controller_period_s
            if abs(ratio - round(ratio)) > 1e-6 or round(ratio) < 1:
                section = key[: -len("_period_s")]
                raise InputError(f"{where}: vehicle.{section}.period_s = {value:g} must be a whole multiple of "
                                 f"run.controller_period_s = {m.run.controller_period_s:g} (the sensor sampling tick)")
    road = m.road
    if not getattr(lay, "ROAD_GRADE", True) and (road.slope is not None or (road.slope_deg or 0.0) != 0.0):
        raise InputError(f"{where}: road.slope_deg / road.slope: the {sc.layout} vehicle has no road grade in its "
                         "plant (flat road only); remove it or use a vehicle of a layout with a grade force")
    if road.slope is not None:
        flat["road_slope"] = _table(road.slope, "distance_m", "slope_deg", "distance_m", "slope_rad", DEG_TO_RAD)
    else:
        flat["road_slope"] = Table.constant("distance_m", "slope_rad", (road.slope_deg or 0.0) * DEG_TO_RAD)
    if road.rolling_resistance is not None:
        flat["road_rolling_resistance"] = _table(road.rolling_resistance, "distance_m", "coeff", "distance_m", "coeff")
    else:
        coeff = road.rolling_resistance_coeff if road.rolling_resistance_coeff is not None else v.body.rolling_resistance_coeff
        flat["road_rolling_resistance"] = Table.constant("distance_m", "coeff", coeff)
    flat["road_friction"] = (_table(road.friction, "distance_m", "mu", "distance_m", "mu") if road.friction is not None
                             else Table.constant("distance_m", "mu", road.friction_mu if road.friction_mu is not None else 1.0))
    road_hook = getattr(lay, "scenario_record", None)  # layouts that drive along the road's curvature (amt_car)
    if road_hook is not None:
        flat.update(road_hook(sc, where))
    elif road.opendrive is not None:
        raise InputError(f"{where}: road.opendrive: the {sc.layout} vehicle does not follow a road's curvature; "
                         "use a vehicle of the amt_car layout")

    d = m.driver
    for name in ("hand_valve", "steering", "gear_lever"):
        if getattr(d, name) is not None and name not in lay.INPUTS:
            raise InputError(f"{where}: driver.{name}: the {sc.layout} vehicle has no such input; it takes {', '.join(lay.INPUTS)}")
    flat["driver_accelerator"] = _table(d.accelerator, "time_s", "frac", "time_s", "frac") if d.accelerator else Table.constant("time_s", "frac", 0.0)
    flat["driver_brake_pedal"] = _table(d.brake_pedal, "time_s", "frac", "time_s", "frac") if d.brake_pedal else Table.constant("time_s", "frac", 0.0)
    gear_names = lay.gear_names(v)
    if d.gear_lever is not None:
        idx = []
        for i, g in enumerate(d.gear_lever.gear):
            if g not in gear_names:
                raise InputError(f"{where}: driver.gear_lever.gear.{i} = {g!r}: not a gear of {v.name}{did_you_mean(g, gear_names)}; gears: {', '.join(gear_names)}")
            idx.append(float(gear_names.index(g)))
        flat["driver_gear_lever"] = Table("time_s", "gear_index", tuple(d.gear_lever.time_s), tuple(idx), "clamp", "previous")
    else:
        flat["driver_gear_lever"] = Table.constant("time_s", "gear_index", float(lay.DEFAULT_GEAR_INDEX))
    if d.hand_valve is not None:
        flat["driver_hand_valve"] = Table("time_s", "released_flag", tuple(d.hand_valve.time_s), tuple(float(x) for x in d.hand_valve.released), "clamp", "previous")
    else:
        flat["driver_hand_valve"] = Table.constant("time_s", "released_flag", 1.0)
    flat["driver_steering"] = (_table(d.steering, "time_s", "angle_deg", "time_s", "angle_rad", DEG_TO_RAD) if d.steering
                               else Table.constant("time_s", "angle_rad", 0.0))

    # sensors
    names = [s.rsplit("_", 1)[0] for s in lay.SENSORS]
    noise = np.zeros(len(lay.SENSORS))
    bias = np.zeros(len(lay.SENSORS))
    delay = np.zeros(len(lay.SENSORS))
    for key, spec in m.sensors.items():
        if key not in names:
            raise InputError(f"{where}: sensors.{key}: unknown sensor{did_you_mean(key, names)}; sensors of {sc.layout}: {', '.join(names)}")
        i = names.index(key)
        unit_suffix = lay.SENSORS[i][len(key):]
        delay[i] = spec.delay_s
        for extra, value in (spec.model_extra or {}).items():
            si_key, si_value = to_si(extra, float(value)) if isinstance(value, (int, float)) else (extra, value)
            if not isinstance(value, (int, float)) or isinstance(value, bool) or not math.isfinite(float(value)):
                raise InputError(f"{where}: sensors.{key}.{extra} = {value!r}: give a finite number")
            if si_key == f"noise_std{unit_suffix}":
                if si_value < 0:
                    raise InputError(f"{where}: sensors.{key}.{extra} = {value!r}: must be >= 0")
                noise[i] = si_value
            elif si_key == f"bias{unit_suffix}":
                bias[i] = si_value
            else:
                raise InputError(f"{where}: sensors.{key}.{extra}: unknown key; use delay_s, noise_std{unit_suffix} or bias{unit_suffix} (or the same in an external unit, e.g. _rpm, _bar, _deg)")
    flat["sensor_noise_std"] = noise
    flat["sensor_bias"] = bias
    flat["sensor_delay_s"] = delay

    # events
    if len(m.events) > EVENT_CAPACITY:
        raise InputError(f"{where}: events: {len(m.events)} events, at most {EVENT_CAPACITY} are supported")
    ev = {k: np.zeros(EVENT_CAPACITY) for k in ("time_s", "signal", "op", "threshold", "action", "target", "value", "value2")}
    for i, e in enumerate(m.events):
        if e.at_s is not None and e.at_s > m.run.duration_s:
            raise InputError(f"{where}: events.{i}.at_s = {e.at_s:g}: after the end of the run (run.duration_s = "
                             f"{m.run.duration_s:g}); give at_s <= {m.run.duration_s:g} or a longer run")
        ev["time_s"][i] = e.at_s or 0.0
        ev["signal"][i] = -1
        if e.when is not None:
            if e.when.signal not in lay.EVENT_SIGNALS:
                raise InputError(f"{where}: events.{i}.when.signal = {e.when.signal!r}: unknown{did_you_mean(e.when.signal, lay.EVENT_SIGNALS)}; signals: {', '.join(lay.EVENT_SIGNALS)}")
            ev["signal"][i] = lay.EVENT_SIGNALS.index(e.when.signal)
            ev["op"][i] = OP_ABOVE if e.when.above is not None else OP_BELOW
            ev["threshold"][i] = e.when.above if e.when.above is not None else e.when.below
        ev["action"][i] = ACTIONS.index(e.action)
        if e.action == "set_input":
            if e.input not in lay.INPUTS:
                raise InputError(f"{where}: events.{i}.input = {e.input!r}: unknown{did_you_mean(e.input, lay.INPUTS)}; inputs: {', '.join(lay.INPUTS)}")
            ev["target"][i] = INPUTS.index(e.input)
            if e.input == "gear_lever":
                if str(e.value) not in gear_names:
                    raise InputError(f"{where}: events.{i}.value = {e.value!r}: not a gear{did_you_mean(str(e.value), gear_names)}")
                ev["value"][i] = gear_names.index(str(e.value))
            else:
                if isinstance(e.value, str):
                    raise InputError(f"{where}: events.{i}.value = {e.value!r}: give a number, not a string (write it without quotes)")
                try:
                    ev["value"][i] = float(e.value)
                except (TypeError, ValueError):
                    raise InputError(f"{where}: events.{i}.value = {e.value!r}: give a number") from None
                if not math.isfinite(ev["value"][i]):
                    raise InputError(f"{where}: events.{i}.value: NaN or inf is not allowed")
        elif e.action == "actuator_fault":
            actuators = getattr(lay, "ACTUATORS", ())
            if e.actuator not in actuators:
                raise InputError(f"{where}: events.{i}.actuator = {e.actuator!r}: unknown{did_you_mean(e.actuator, actuators)}; "
                                 f"actuators of {sc.layout}: {', '.join(actuators) or 'none'}")
            from vehicle_assist.plant.brakes.pneumatic import VALVE_FAULTS

            ev["target"][i] = actuators.index(e.actuator)
            extra = dict(e.model_extra or {})
            if e.actuator == "ehb":
                if e.fault != "limited" or "limit_bar" not in extra or not isinstance(extra["limit_bar"], (int, float)) \
                        or not math.isfinite(float(extra["limit_bar"])) or float(extra["limit_bar"]) < 0:
                    raise InputError(f"{where}: events.{i}: the ehb actuator fault is fault = \"limited\" with limit_bar = "
                                     "a pressure >= 0 the EHB can still build")
                ev["value"][i] = 1.0
                ev["value2"][i] = float(extra["limit_bar"]) * 1e5
            else:
                if e.fault not in VALVE_FAULTS or extra:
                    raise InputError(f"{where}: events.{i}: valve_32 faults are unpowered, stuck_deenergized or stuck_energized")
                ev["value"][i] = VALVE_FAULTS[e.fault]
        elif e.action == "sensor_fault":
            if e.sensor not in names:
                raise InputError(f"{where}: events.{i}.sensor = {e.sensor!r}: unknown sensor{did_you_mean(e.sensor, names)}; sensors: {', '.join(names)}")
            si = names.index(e.sensor)
            ev["target"][i] = si
            ev["value"][i] = FAULTS[e.fault]
            unit_suffix = lay.SENSORS[si][len(e.sensor):]
            for extra, value in (e.model_extra or {}).items():
                if not isinstance(value, (int, float)) or isinstance(value, bool) or not math.isfinite(float(value)):
                    raise InputError(f"{where}: events.{i}.{extra} = {value!r}: give a finite number (bias{unit_suffix} or the same in an external unit)")
                si_key, si_value = to_si(extra, float(value))
                if si_key != f"bias{unit_suffix}":
                    raise InputError(f"{where}: events.{i}.{extra}: unknown key; a bias fault takes bias{unit_suffix}")
                ev["value2"][i] = si_value
    flat["event_count"] = float(len(m.events))
    for key, arr in ev.items():
        flat[f"event_{key}"] = arr

    # checks name known metrics
    from vehicle_assist.metrics import known_metric_names

    known = known_metric_names()
    for i, c in enumerate(m.checks):
        if c.metric not in known:
            raise InputError(f"{where}: checks.{i}.metric = {c.metric!r}: unknown metric{did_you_mean(c.metric, known)}; see 'vehicle-assist metrics'")
    if m.requirements:  # STL requirements: syntax and channel names checked here (verification/requirements.py)
        from vehicle_assist.verification.requirements import resolve

        try:
            resolve(m.requirements, sc.layout, where)
        except ValidationError as exc:  # a requirement built from user text: still one line
            first = exc.errors()[0]
            loc = ".".join(str(p) for p in first.get("loc", ()))
            raise InputError(f"{where}: requirements: {loc + ' ' if loc else ''}= {first.get('input')!r}: "
                             f"{str(first.get('msg', 'invalid')).lower()}") from None
    return flat
