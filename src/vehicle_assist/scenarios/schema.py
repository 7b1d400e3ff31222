"""Scenario files: vehicle + road + driver inputs + events + run settings + checks, validated on load.

Units are explicit in the keys (``slope_deg``, ``duration_s``). Every table's breakpoints must be
strictly increasing, every number finite, every key known. See docs/scenarios.md for the format.
"""
from __future__ import annotations

from typing import Annotated, Literal

from pydantic import BaseModel, ConfigDict, Field, model_validator

from vehicle_assist.core.table_spec import TableSpec

MAX_SLOPE_DEG = 45.0


class Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)


Time = Annotated[float, Field(ge=0, le=3600)]
Frac = Annotated[float, Field(ge=0, le=1)]
Slope = Annotated[float, Field(ge=-MAX_SLOPE_DEG, le=MAX_SLOPE_DEG)]
Distance = Annotated[float, Field(ge=-1e6, le=1e6)]


class SlopeTable(TableSpec):
    distance_m: list[Distance] = Field(min_length=1)
    slope_deg: list[Slope] = Field(min_length=1)


class CoeffTable(TableSpec):
    distance_m: list[Distance] = Field(min_length=1)
    coeff: list[Annotated[float, Field(ge=0, le=0.2)]] = Field(min_length=1)


class FrictionTable(TableSpec):
    distance_m: list[Distance] = Field(min_length=1)
    mu: list[Annotated[float, Field(ge=0, le=2)]] = Field(min_length=1)


class RadiusTable(TableSpec):
    """Curve radius over distance (reserved for curve-aware shifting; validated, not yet simulated)."""

    distance_m: list[Distance] = Field(min_length=1)
    radius_m: list[Annotated[float, Field(ge=5)]] = Field(min_length=1)


class Road(Strict):
    slope_deg: Slope | None = None
    slope: SlopeTable | None = None
    rolling_resistance_coeff: Annotated[float, Field(ge=0, le=0.2)] | None = None
    rolling_resistance: CoeffTable | None = None
    friction_mu: Annotated[float, Field(ge=0.05, le=1.5)] | None = None
    friction: FrictionTable | None = None
    curve_radius: RadiusTable | None = None
    opendrive: Annotated[str, Field(min_length=1, max_length=4096)] | None = None  # .xodr reference line (issue #11)
    opendrive_road_id: str | None = None

    @model_validator(mode="after")
    def _one(self):
        if self.opendrive is not None and self.curve_radius is not None:
            raise ValueError("give either opendrive (a .xodr road) or curve_radius (a table), not both")
        if self.slope_deg is not None and self.slope is not None:
            raise ValueError("give either slope_deg (constant) or slope (table over distance), not both")
        if self.rolling_resistance_coeff is not None and self.rolling_resistance is not None:
            raise ValueError("give either rolling_resistance_coeff or rolling_resistance (table), not both")
        if self.friction_mu is not None and self.friction is not None:
            raise ValueError("give either friction_mu (constant) or friction (table over distance), not both")
        return self


class PedalTable(TableSpec):
    time_s: list[Time] = Field(min_length=1)
    frac: list[Frac] = Field(min_length=1)


class GearTable(TableSpec):
    time_s: list[Time] = Field(min_length=1)
    gear: list[str] = Field(min_length=1)


class SwitchTable(TableSpec):
    time_s: list[Time] = Field(min_length=1)
    released: list[Annotated[int, Field(ge=0, le=1)]] = Field(min_length=1)


class SteeringTable(TableSpec):
    time_s: list[Time] = Field(min_length=1)
    angle_deg: list[Annotated[float, Field(ge=-720, le=720)]] = Field(min_length=1)


class Driver(Strict):
    model: Literal["scripted"] = "scripted"
    accelerator: PedalTable | None = None
    brake_pedal: PedalTable | None = None
    gear_lever: GearTable | None = None
    hand_valve: SwitchTable | None = None
    steering: SteeringTable | None = None


class Run(Strict):
    duration_s: Annotated[float, Field(gt=0, le=3600)]
    plant_step_s: Annotated[float, Field(ge=1e-5, le=0.01)] = 0.001
    controller_period_s: Annotated[float, Field(ge=1e-4, le=0.1)] = 0.01
    record_period_s: Annotated[float, Field(ge=1e-5, le=1.0)] = 0.01
    seed: Annotated[int, Field(ge=0)] = 0
    initial_speed_kph: Annotated[float, Field(ge=-50, le=250)] = 0.0
    initial_position_m: Distance = 0.0
    # body-axis lateral speed v at the start (left +; two-track layouts only, e.g. a car already sliding sideways)
    initial_lateral_speed_mps: Annotated[float, Field(ge=-50, le=50)] = 0.0

    @model_validator(mode="after")
    def _rates(self):
        for name in ("controller_period_s", "record_period_s"):
            ratio = getattr(self, name) / self.plant_step_s
            if abs(ratio - round(ratio)) > 1e-6 or round(ratio) < 1:
                raise ValueError(f"{name} = {getattr(self, name):g} must be a whole multiple of plant_step_s = {self.plant_step_s:g}")
        return self


class Sensor(Strict):
    """Per-sensor options; noise and bias keys carry the sensor's unit (e.g. noise_std_rpm)."""

    model_config = ConfigDict(extra="allow", frozen=True, allow_inf_nan=False)
    delay_s: Annotated[float, Field(ge=0, le=1)] = 0.0


class Condition(Strict):
    signal: str
    above: float | None = None
    below: float | None = None

    @model_validator(mode="after")
    def _one(self):
        if (self.above is None) == (self.below is None):
            raise ValueError("a condition needs exactly one of 'above' or 'below'")
        return self


class EventSpec(Strict):
    at_s: Time | None = None
    when: Condition | None = None
    action: Literal["set_input", "sensor_fault", "actuator_fault", "stop"]
    input: str | None = None
    value: float | str | None = None
    sensor: str | None = None
    actuator: str | None = None
    fault: Literal["lost", "stuck", "bias", "unpowered", "stuck_deenergized", "stuck_energized", "limited"] | None = None
    model_config = ConfigDict(extra="allow", frozen=True, allow_inf_nan=False)  # bias_<unit>

    @model_validator(mode="after")
    def _shape(self):
        for key in self.model_extra or {}:  # extras are unit-suffixed fault values only; a typo is not kept
            allowed = (self.action == "sensor_fault" and key.startswith("bias_")) or (
                self.action == "actuator_fault" and key == "limit_bar")
            if not allowed:
                import difflib

                close = difflib.get_close_matches(key, list(type(self).model_fields) + ["bias_rpm", "limit_bar"], n=1)
                hint = f" (did you mean {close[0]!r}?)" if close else ""
                raise ValueError(f"unknown key {key!r}{hint} for action {self.action!r}; known keys: "
                                 f"{', '.join(type(self).model_fields)}, bias_<unit> (sensor_fault bias), limit_bar (ehb fault)")
        if self.at_s is None and self.when is None:
            raise ValueError("an event needs 'at_s' (a time) or 'when' (a condition), or both")
        if self.action == "set_input" and (self.input is None or self.value is None):
            raise ValueError("action 'set_input' needs 'input' and 'value'")
        if self.action == "sensor_fault" and (self.sensor is None or self.fault not in ("lost", "stuck", "bias")):
            raise ValueError("action 'sensor_fault' needs 'sensor' and 'fault' (lost, stuck or bias)")
        if self.action == "actuator_fault" and (
                self.actuator is None or self.fault not in ("unpowered", "stuck_deenergized", "stuck_energized", "limited")):
            raise ValueError("action 'actuator_fault' needs 'actuator' and 'fault' (valve_32: unpowered, stuck_deenergized, "
                             "stuck_energized; ehb: limited with limit_bar)")
        return self


class Check(Strict):
    metric: str
    min: float | None = None
    max: float | None = None
    expect: Literal["pass", "fail"] = "pass"
    why: str = ""

    @model_validator(mode="after")
    def _bound(self):
        if self.min is None and self.max is None:
            raise ValueError("a check needs 'min' or 'max' (or both)")
        if self.min is not None and self.max is not None and self.min > self.max:
            raise ValueError(f"min = {self.min:g} is above max = {self.max:g}; no value can pass; swap them")
        return self


class VehicleRef(Strict):
    model_config = ConfigDict(extra="allow", frozen=True, allow_inf_nan=False)  # subsystem overrides
    base: str


class RequirementSpec(Strict):
    """A requirement attached to a scenario (see verification/requirements.py): a shipped one by ``id``
    (``hill_start_amt.no_rollback``), or inline with ``id``, ``formula`` (STL over trace channels) and ``why``."""

    id: Annotated[str, Field(min_length=1)]
    formula: str | None = None
    why: str = ""
    unit: str = ""
    kind: Literal["stl", "no_worse_than_baseline"] = "stl"
    expect: Literal["pass", "fail"] = "pass"
    rollback_floor_m: Annotated[float, Field(ge=0)] = 0.01
    # comparative kind: the run metric compared with the no-assist twin's (smaller is better); several joined by commas
    # are each compared with the twin's same metric, the least robustness counts (verification/requirements.py)
    metric: Annotated[str, Field(pattern=r"^[a-z][a-z0-9_]*(,[a-z][a-z0-9_]*)*$")] = "rollback_distance_m"
    baseline: list[str] = []


class Scenario(Strict):
    name: str
    description: str = ""
    source: str = ""
    vehicle: VehicleRef
    road: Road = Road()
    driver: Driver = Driver()
    run: Run
    sensors: dict[str, Sensor] = {}
    events: list[EventSpec] = []
    checks: list[Check] = []
    requirements: list[str | RequirementSpec] = []
    paper: str = ""
