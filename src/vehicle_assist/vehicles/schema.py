"""Vehicle parameter files: validated, frozen records with a source for every number.

A vehicle file is TOML with ``name``, ``layout`` (which composition simulates it), ``description``,
``source`` (the overall provenance) and one table per subsystem. Keys carry units (``mass_kg``,
``idle_speed_rpm``); external units (rpm, bar, deg) are converted to SI when the record is built.
Every numeric key of a subsystem needs an entry in that subsystem's ``source`` table (paper, standard,
data sheet, or "assumed: why"). A file may start from another with ``base = "name"`` and override keys.

Bounds are physical plausibility ranges: a value outside is an input error, not a modelling choice.
"""
from __future__ import annotations

from typing import Annotated, Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, model_validator

from vehicle_assist.core.table_spec import TableSpec
from vehicle_assist.core.tables import Table


class Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)


Pos = Annotated[float, Field(gt=0)]
NonNeg = Annotated[float, Field(ge=0)]
Frac = Annotated[float, Field(ge=0, le=1)]


class TorqueCurve(TableSpec):
    speed_rpm: list[Annotated[float, Field(ge=0, le=10000)]]
    torque_nm: list[Annotated[float, Field(ge=0, le=20000)]]
    extrapolation: Literal["clamp", "linear"] = "clamp"


class PedalMap(TableSpec):
    accelerator_frac: list[Frac]
    torque_nm: list[Annotated[float, Field(ge=-5000, le=5000)]]


class Body(Strict):
    """Rigid body and wheels of the longitudinal model (common.md 3-5)."""

    mass_kg: Annotated[float, Field(ge=100, le=100000)]
    wheel_radius_m: Annotated[float, Field(ge=0.1, le=1.5)]
    wheel_inertia_total_kgm2: Annotated[float, Field(ge=0, le=2000)]
    drag_area_m2: Annotated[float, Field(ge=0, le=20)]
    rolling_resistance_coeff: Annotated[float, Field(ge=0, le=0.2)]


class Engine(Strict):
    """All-speed governed diesel (hill_start_amt.md 5.1)."""

    idle_speed_rpm: Annotated[float, Field(ge=300, le=1500)]
    high_idle_speed_rpm: Annotated[float, Field(ge=800, le=6000)]
    governor_gain_nm_per_rpm: Annotated[float, Field(gt=0, le=1000)]
    inertia_kgm2: Annotated[float, Field(gt=0, le=50)]
    stall_speed_rpm: Annotated[float, Field(ge=50, le=1000)]
    friction_offset_nm: Annotated[float, Field(ge=0, le=1000)]
    friction_slope_nm_per_rpm: Annotated[float, Field(ge=0, le=10)]
    full_load_torque: TorqueCurve
    governor_droop_frac: Annotated[float, Field(ge=0, le=0.5)] = 0.0  # > 0: proportional droop replaces the gain

    @model_validator(mode="after")
    def _order(self):
        if not self.stall_speed_rpm < self.idle_speed_rpm < self.high_idle_speed_rpm:
            raise ValueError(
                f"need stall_speed_rpm < idle_speed_rpm < high_idle_speed_rpm, got {self.stall_speed_rpm:g} / "
                f"{self.idle_speed_rpm:g} / {self.high_idle_speed_rpm:g}"
            )
        return self


class Clutch(Strict):
    """Dry clutch and its actuator (hill_start_amt.md 5.2)."""

    max_torque_nm: Annotated[float, Field(gt=0, le=20000)]
    kiss_point_frac: Annotated[float, Field(ge=0, lt=1)]
    capacity_exponent: Annotated[float, Field(ge=0.5, le=4)]
    input_inertia_kgm2: Annotated[float, Field(gt=0, le=20)]
    actuator_time_constant_s: Annotated[float, Field(gt=0, le=2)]
    actuator_max_rate_per_s: Annotated[float, Field(gt=0, le=100)]


class Gearbox(Strict):
    """Stepped AMT gearbox and final drive (gear 0 = neutral, 1..n = ratios in this order)."""

    gear_names: list[str] = Field(min_length=1, max_length=24)
    ratios: list[Annotated[float, Field(gt=0, le=30)]] = Field(min_length=1, max_length=24)
    final_drive_ratio: Annotated[float, Field(gt=0, le=20)]
    efficiency_frac: Annotated[float, Field(gt=0.5, le=1)]
    shift_time_s: Annotated[float, Field(ge=0, le=5)]

    @model_validator(mode="after")
    def _names(self):
        if len(self.gear_names) != len(self.ratios):
            raise ValueError(f"gear_names has {len(self.gear_names)} entries but ratios has {len(self.ratios)}; give one name per ratio")
        if len(set(self.gear_names)) != len(self.gear_names) or "N" in self.gear_names:
            raise ValueError("gear_names must be unique and must not use 'N' (neutral is gear 0)")
        return self


class AirServiceBrake(Strict):
    """Air service brake, lumped: ground force capacity proportional to pedal after a lag."""

    max_force_n: Annotated[float, Field(gt=0, le=1e6)]
    time_constant_s: Annotated[float, Field(gt=0, le=5)]


class SpringParkBrake(Strict):
    """Spring park brake with relay valve and reservoir (hill_start_amt.md 3, 5.3)."""

    reservoir_pressure_bar: Annotated[float, Field(ge=0, le=15)]
    fill_time_constant_s: Annotated[float, Field(gt=0, le=30)]
    exhaust_time_constant_s: Annotated[float, Field(gt=0, le=30)]
    release_start_pressure_bar: Annotated[float, Field(ge=0, le=15)]
    release_full_pressure_bar: Annotated[float, Field(gt=0, le=15)]
    lamp_pressure_bar: Annotated[float, Field(gt=0, le=15)]
    max_force_n: Annotated[float, Field(gt=0, le=1e6)]

    @model_validator(mode="after")
    def _order(self):
        if not self.release_start_pressure_bar < self.release_full_pressure_bar:
            raise ValueError("release_start_pressure_bar must be below release_full_pressure_bar")
        return self


class AmtLaunch(Strict):
    """Parameters of the AMT's normal start program (functions/amt_launch.py)."""

    period_s: Annotated[float, Field(ge=1e-4, le=0.1)]
    launch_accelerator_frac: Frac
    approach_rate_per_s: Annotated[float, Field(gt=0, le=20)]
    engage_rate_per_s: Annotated[float, Field(gt=0, le=20)]
    back_off_rate_per_s: Annotated[float, Field(ge=0, le=20)]
    anti_stall_speed_rpm: Annotated[float, Field(ge=0, le=2000)]
    lockup_slip_rpm: Annotated[float, Field(gt=0, le=1000)]
    lockup_rate_per_s: Annotated[float, Field(gt=0, le=20)]
    moving_speed_mps: Annotated[float, Field(ge=0, le=5)]
    lockup_min_speed_rpm: Annotated[float, Field(ge=0, le=3000)]


class TruckAxles(Strict):
    """Static axle-load split of a truck with a driven rear tandem, and the grade load transfer (common.md 9):
    F_z,rear = m*g*(cos(alpha)*phi_r(m) + sin(alpha)*h(m)/l); the payload adds at its own split and height."""

    wheelbase_m: Annotated[float, Field(gt=1, le=15)]
    empty_mass_kg: Annotated[float, Field(ge=100, le=100000)]
    empty_rear_load_frac: Frac
    payload_rear_load_frac: Frac
    empty_cg_height_m: Annotated[float, Field(gt=0, le=5)]
    payload_cg_height_m: Annotated[float, Field(gt=0, le=5)]


class TractionMotor(Strict):
    max_torque_nm: Annotated[float, Field(gt=0, le=5000)]
    max_power_kw: Annotated[float, Field(gt=0, le=1000)]
    rotor_inertia_kgm2: Annotated[float, Field(ge=0, le=5)]
    time_constant_s: Annotated[float, Field(gt=0, le=2)]
    reduction_ratio: Annotated[float, Field(gt=0, le=30)]
    efficiency_frac: Annotated[float, Field(gt=0.5, le=1)]
    pedal_map: PedalMap


class HydraulicBrakes(Strict):
    """Four hydraulic disc brakes fed by one EHB pressure (common.md 7.1)."""

    front_piston_diameter_m: Annotated[float, Field(gt=0.01, le=0.15)]
    rear_piston_diameter_m: Annotated[float, Field(gt=0.01, le=0.15)]
    front_effective_radius_m: Annotated[float, Field(gt=0.03, le=0.5)]
    rear_effective_radius_m: Annotated[float, Field(gt=0.03, le=0.5)]
    pad_friction_coeff: Annotated[float, Field(gt=0.05, le=1)]
    efficiency_frac: Annotated[float, Field(gt=0.5, le=1)]
    friction_faces_count: Annotated[float, Field(ge=1, le=2)]


class EvChassis(Strict):
    """Axle geometry of the EV for the static axle loads with grade load transfer (common.md 9)."""

    wheelbase_m: Annotated[float, Field(gt=1.0, le=5.0)]
    cg_to_front_axle_m: Annotated[float, Field(gt=0.1, le=4.9)]
    cg_height_m: Annotated[float, Field(gt=0.1, le=2.0)]
    driven_axle: Literal["front", "rear"]

    @model_validator(mode="after")
    def _inside(self):
        if not self.cg_to_front_axle_m < self.wheelbase_m:
            raise ValueError("cg_to_front_axle_m must be below wheelbase_m (the centre of gravity lies between the axles)")
        return self


class Ehb(Strict):
    """Electro-hydraulic brake actuator (hill_start_ehb.md 2.5) and its by-wire pedal map."""

    time_constant_s: Annotated[float, Field(gt=0, le=2)]
    build_rate_bar_per_s: Annotated[float, Field(gt=0, le=10000)]
    release_rate_bar_per_s: Annotated[float, Field(gt=0, le=10000)]
    max_pressure_bar: Annotated[float, Field(gt=0, le=300)]
    pedal_full_pressure_bar: Annotated[float, Field(gt=0, le=300)]


class ReleaseTimeTable(TableSpec):
    reservoir_pressure_bar: list[Annotated[float, Field(ge=0, le=15)]]
    release_time_s: list[Annotated[float, Field(gt=0, le=60)]]


class HillStartAssist(Strict):
    """Hill-start assist of paper 000 (functions/hill_start_amt.py; hill_start_amt.md 6, 7.2)."""

    enabled_flag: Annotated[int, Field(ge=0, le=1)]
    period_s: Annotated[float, Field(ge=1e-4, le=0.1)]
    release_mode: Literal["preset_position", "load_adaptive"]
    release_position_frac: list[Frac] = Field(min_length=1, max_length=24)
    release_load_frac: Annotated[float, Field(gt=0, le=2)]
    phase3_torque_frac: Annotated[float, Field(ge=1, le=5)]
    max_hold_torque_frac: Annotated[float, Field(gt=0, le=1.5)]
    approach_rate_per_s: Annotated[float, Field(gt=0, le=20)]
    engage_rate_fast_per_s: Annotated[float, Field(gt=0, le=5)]
    engage_rate_mid_per_s: Annotated[float, Field(gt=0, le=5)]
    engage_rate_slow_per_s: Annotated[float, Field(gt=0, le=5)]
    back_off_rate_per_s: Annotated[float, Field(ge=0, le=20)]
    speed_drop_fast_rpm_per_s: Annotated[float, Field(gt=0, le=10000)]
    speed_drop_slow_rpm_per_s: Annotated[float, Field(gt=0, le=10000)]
    speed_rate_filter_s: Annotated[float, Field(gt=0, le=2)]
    input_accel_fast_rpm_per_s: Annotated[float, Field(gt=0, le=100000)] = 300.0
    input_accel_slow_rpm_per_s: Annotated[float, Field(ge=0, le=100000)] = 50.0
    guard_speed_rpm: Annotated[float, Field(ge=0, le=2000)]
    lockup_slip_rpm: Annotated[float, Field(gt=0, le=1000)]
    lockup_rate_per_s: Annotated[float, Field(gt=0, le=20)]
    moving_speed_mps: Annotated[float, Field(ge=0, le=5)]
    standstill_speed_mps: Annotated[float, Field(gt=0, le=1)]
    brake_applied_frac: Annotated[float, Field(gt=0, le=1)]
    accelerator_on_frac: Annotated[float, Field(gt=0, le=1)]
    reservoir_min_bar: Annotated[float, Field(ge=0, le=15)]
    release_time: ReleaseTimeTable
    release_timeout_margin_s: Annotated[float, Field(ge=0, le=30)]
    lockup_engine_check_flag: Annotated[int, Field(ge=0, le=1)]
    rollback_catch_flag: Annotated[int, Field(ge=0, le=1)]
    launch_speed_min_rpm: Annotated[float, Field(ge=0, le=3000)]
    hold_torque_margin_frac: Annotated[float, Field(ge=1, le=3)]
    lockup_torque_margin_frac: Annotated[float, Field(ge=0.5, le=3)]
    ceiling_frac: Annotated[float, Field(gt=0, le=1)]
    refusal_delay_s: Annotated[float, Field(ge=0, le=30)]
    sync_slip_rpm: Annotated[float, Field(gt=0, le=500)]
    sync_time_s: Annotated[float, Field(gt=0, le=5)]
    sync_torque_min_nm: Annotated[float, Field(ge=0, le=1000)]
    rollback_catch_speed_mps: Annotated[float, Field(gt=0, le=2)]
    grade_settle_s: Annotated[float, Field(ge=0, le=5)]

    @model_validator(mode="after")
    def _order(self):
        if not (self.engage_rate_slow_per_s <= self.engage_rate_mid_per_s <= self.engage_rate_fast_per_s):
            raise ValueError("need engage_rate_slow_per_s <= engage_rate_mid_per_s <= engage_rate_fast_per_s")
        if not self.speed_drop_slow_rpm_per_s < self.speed_drop_fast_rpm_per_s:
            raise ValueError("need speed_drop_slow_rpm_per_s < speed_drop_fast_rpm_per_s")
        return self


class HillStartEhb(Strict):
    """Hill-start assist of paper 001 (functions/hill_start_ehb.py; hill_start_ehb.md 2-3)."""

    enabled_flag: Annotated[int, Field(ge=0, le=1)]
    period_s: Annotated[float, Field(ge=1e-4, le=0.1)]
    release_mode: Literal["follow_torque", "immediate"]
    calibration_mass_kg: Annotated[float, Field(ge=100, le=100000)]
    lightest_mass_kg: Annotated[float, Field(ge=100, le=100000)]
    jerk_limit_flag: Annotated[int, Field(ge=0, le=1)]
    jerk_design_frac: Annotated[float, Field(gt=0, le=1)]
    adhesion_ratio_frac: Annotated[float, Field(gt=0, lt=1)]
    wheel_radius_m: Annotated[float, Field(ge=0.1, le=1.5)]
    brake_gain_nm_per_bar: Annotated[float, Field(gt=0, le=10000)]
    rolling_resistance_coeff: Annotated[float, Field(ge=0, le=0.2)]
    rotating_mass_factor: Annotated[float, Field(ge=1, le=3)]
    hold_safety_frac: Annotated[float, Field(ge=1, le=3)]
    margin_rolling_frac: Annotated[float, Field(ge=0, le=2)]
    slope_min_deg: Annotated[float, Field(ge=0, le=10)]
    accelerator_on_frac: Annotated[float, Field(gt=0, le=1)]
    start_speed_mps: Annotated[float, Field(ge=0, le=2)]
    standstill_speed_mps: Annotated[float, Field(gt=0, le=1)]
    brake_applied_frac: Annotated[float, Field(gt=0, le=1)]
    jerk_max_mps3: Annotated[float, Field(gt=0, le=10)]
    max_hold_time_s: Annotated[float, Field(gt=0, le=3600)]
    settle_time_s: Annotated[float, Field(gt=0, le=10)]
    rollback_speed_mps: Annotated[float, Field(gt=0, le=1)]
    rollback_gain_n_per_s: Annotated[float, Field(ge=0, le=1e7)]


class Vcu(Strict):
    """EV vehicle control unit (functions/ev_vcu.py)."""

    period_s: Annotated[float, Field(ge=1e-4, le=0.1)]


class TruckAmt(Strict):
    name: str
    layout: Literal["truck_amt"]
    description: str
    source: str
    body: Body
    axles: TruckAxles
    engine: Engine
    clutch: Clutch
    gearbox: Gearbox
    service_brake: AirServiceBrake
    park_brake: SpringParkBrake
    amt_launch: AmtLaunch
    hill_start_assist: HillStartAssist

    @model_validator(mode="after")
    def _gears(self):
        n = len(self.gearbox.ratios)
        if len(self.hill_start_assist.release_position_frac) != n:
            raise ValueError(f"hill_start_assist.release_position_frac has {len(self.hill_start_assist.release_position_frac)} "
                             f"entries but the gearbox has {n} gears; give one release position per gear")
        return self


class EvEhb(Strict):
    name: str
    layout: Literal["ev_ehb"]
    description: str
    source: str
    body: Body
    chassis: EvChassis
    motor: TractionMotor
    brakes: HydraulicBrakes
    ehb: Ehb
    vcu: Vcu
    hill_start_assist: HillStartEhb


LAYOUTS: dict[str, type[Strict]] = {"truck_amt": TruckAmt, "ev_ehb": EvEhb}
TABLE_KEYS = {"full_load_torque": ("speed_rpm", "torque_nm"), "pedal_map": ("accelerator_frac", "torque_nm"),
              "release_time": ("reservoir_pressure_bar", "release_time_s")}
NON_NUMERIC = {"gear_names"}
CODES = {"release_mode": {"preset_position": 0.0, "load_adaptive": 1.0,   # truck (hill_start_amt)
                          "follow_torque": 0.0, "immediate": 1.0},        # EV (hill_start_ehb)
         "driven_axle": {"front": 0.0, "rear": 1.0}}                      # EV chassis


def flatten_vehicle(model: Strict) -> dict[str, float | Table | np.ndarray]:
    """SI flat record ``section_key`` -> value (tables and arrays kept as such)."""
    flat: dict[str, float | Table | np.ndarray] = {}
    for section_name, section in model:
        if isinstance(section, BaseModel):
            flat.update(flatten_section(section_name, section))
    return flat


def flatten_section(section_name: str, section: Strict) -> dict[str, float | Table | np.ndarray]:
    """SI record entries of one subsystem."""
    from vehicle_assist.units import to_si

    flat: dict[str, float | Table | np.ndarray] = {}
    for key, value in section:
        if key in NON_NUMERIC:
            continue
        if key in CODES:
            flat[f"{section_name}_{key}"] = CODES[key][value]
            continue
        if isinstance(value, BaseModel):
            xk, yk = TABLE_KEYS[key]
            xs, ys = getattr(value, xk), getattr(value, yk)
            xn, _ = to_si(xk, 0.0)
            yn, _ = to_si(yk, 0.0)
            xf = to_si(xk, 1.0)[1]
            yf = to_si(yk, 1.0)[1]
            extrap = getattr(value, "extrapolation", "clamp")
            flat[f"{section_name}_{key}"] = Table(xn, yn, tuple(v * xf for v in xs), tuple(v * yf for v in ys), extrap)
        elif isinstance(value, list):
            flat[f"{section_name}_{key}"] = np.asarray(value, dtype=float)
        else:
            name, si = to_si(key, float(value))
            flat[f"{section_name}_{name}"] = si
    return flat


# passenger car with an ESP unit (issue #9): its schema lives in sedan_schema.py
from vehicle_assist.vehicles import sedan_schema as _sedan_schema  # noqa: E402

LAYOUTS["sedan_esp"] = _sedan_schema.SedanEspVehicle
CODES.update(_sedan_schema.CODES)

# AMT car of paper 003 (issue #11): its schema lives in amt_car_schema.py
from vehicle_assist.vehicles import amt_car_schema as _amt_car_schema  # noqa: E402

LAYOUTS["amt_car"] = _amt_car_schema.AmtCar
