"""Vehicle-file schema of the AMT car of paper 003 (layout ``amt_car``, vehicles/amt_car.py).

Registered into :data:`vehicle_assist.vehicles.schema.LAYOUTS` by the last lines of schema.py. Every numeric key
needs a source in the file (schema.py); bounds are physical plausibility ranges.
"""
from __future__ import annotations

from typing import Annotated, Literal

from pydantic import Field, model_validator

from vehicle_assist.vehicles.schema import AirServiceBrake, Body, Frac, Gearbox, Strict, TorqueCurve

Flag = Annotated[int, Field(ge=0, le=1)]


class CarChassis(Strict):
    """Single-track mode of the car platform (plant/chassis/single_track.py) and its handling-diagram axles."""

    wheelbase_m: Annotated[float, Field(gt=1.5, le=4.5)]
    cg_to_front_axle_m: Annotated[float, Field(gt=0.3, le=4.0)]
    yaw_inertia_kgm2: Annotated[float, Field(ge=100, le=20000)]
    cornering_stiffness_front_n_per_rad: Annotated[float, Field(gt=1e3, le=2e6)]
    cornering_stiffness_rear_n_per_rad: Annotated[float, Field(gt=1e3, le=2e6)]
    peak_friction_front: Annotated[float, Field(gt=0.1, le=2)]
    peak_friction_rear: Annotated[float, Field(gt=0.1, le=2)]
    magic_formula_shape: Annotated[float, Field(gt=1.0, lt=2.0)]

    @model_validator(mode="after")
    def _inside(self):
        if not self.cg_to_front_axle_m < self.wheelbase_m:
            raise ValueError("cg_to_front_axle_m must be below wheelbase_m (the centre of gravity lies between the axles)")
        return self


class CarEngine(Strict):
    """Torque-demand engine: T_e = theta*T_full(n) + (1 - theta)*T_mot(n), T_mot = -(c0 + c1*n), idle governor."""

    idle_speed_rpm: Annotated[float, Field(ge=300, le=1500)]
    idle_governor_gain_nm_per_rpm: Annotated[float, Field(gt=0, le=100)]
    inertia_kgm2: Annotated[float, Field(gt=0, le=5)]
    friction_offset_nm: Annotated[float, Field(ge=0, le=500)]
    friction_slope_nm_per_rpm: Annotated[float, Field(ge=0, le=1)]
    full_load_torque: TorqueCurve


class ShiftSchedule(Strict):
    """Normal shift lines [m/s] over throttle (functions/shift_schedule.py): rows up 1->2 .. (n-1)->n and
    down 2->1 .. n->(n-1)."""

    throttle_frac: list[Frac] = Field(min_length=2, max_length=16)
    up_mps: list[list[Annotated[float, Field(gt=0, le=100)]]] = Field(min_length=1, max_length=23)
    down_mps: list[list[Annotated[float, Field(gt=0, le=100)]]] = Field(min_length=1, max_length=23)

    @model_validator(mode="after")
    def _shape(self):
        th = self.throttle_frac
        if any(b <= a for a, b in zip(th, th[1:])):
            raise ValueError("throttle_frac must be strictly increasing")
        if len(self.up_mps) != len(self.down_mps):
            raise ValueError(f"up_mps has {len(self.up_mps)} lines but down_mps {len(self.down_mps)}; give one pair per gear step")
        for name in ("up_mps", "down_mps"):
            for i, row in enumerate(getattr(self, name)):
                if len(row) != len(th):
                    raise ValueError(f"{name}.{i} has {len(row)} speeds but throttle_frac has {len(th)} breakpoints")
        for i, (up, dn) in enumerate(zip(self.up_mps, self.down_mps)):
            if any(d >= u for u, d in zip(up, dn)):
                raise ValueError(f"down_mps.{i} (line {i + 2}->{i + 1}) must lie below up_mps.{i} (line {i + 1}->{i + 2}) "
                                 "at every throttle (hysteresis)")
        return self


class CurveShift(Strict):
    """Curve-aware strategy of paper 003 (functions/curve_shift.py)."""

    enabled_flag: Flag
    period_s: Annotated[float, Field(ge=1e-3, le=0.1)]
    driver_style_k: Annotated[float, Field(gt=0, le=1)]
    fit_radius_min_m: Annotated[float, Field(ge=5, le=100)]
    fit_radius_max_m: Annotated[float, Field(ge=100, le=600)]
    command_distance_m: Annotated[float, Field(gt=0, le=2000)]
    command_needs_deceleration_flag: Flag
    max_downshift_speed_rpm: Annotated[float, Field(gt=1000, le=10000)]
    guard_speed_rpm: Annotated[float, Field(gt=1000, le=10000)]
    upshift_release_speed_rpm: Annotated[float, Field(gt=1000, le=10000)]
    dwell_time_s: Annotated[float, Field(ge=0, le=10)]
    fixed_kj_ratio: Annotated[float, Field(ge=-1, le=20)]
    advance_horizon_flag: Flag
    plausibility_check_flag: Flag
    plausibility_curvature_ratio: Annotated[float, Field(gt=1.0, le=5.0)]
    plausibility_onset_frac: Annotated[float, Field(gt=0.0, lt=1.0)]
    plausibility_distance_tol_m: Annotated[float, Field(ge=0, le=500)]
    plausibility_confirm_time_s: Annotated[float, Field(ge=0, le=5)]


class MapPreview(Strict):
    """Electronic horizon (plant/map_preview.py); the errors of a wrong map."""

    available_flag: Flag
    range_m: Annotated[float, Field(gt=0, le=10000)]
    radius_scale_frac: Annotated[float, Field(gt=0.05, le=20)]
    distance_offset_m: Annotated[float, Field(ge=-1000, le=1000)]


class CurveDriver(Strict):
    """Five-phase curve driver of paper 003 (drivers/curve_driver.py); enabled_flag = 0: the scripted driver."""

    enabled_flag: Flag
    sight_distance_m: Annotated[float, Field(gt=0, le=2000)]
    lift_time_s: Annotated[float, Field(gt=0, le=10)]
    brake_delay_s: Annotated[float, Field(ge=0, le=10)]
    straight_throttle_frac: Frac
    speed_gain_per_mps: Annotated[float, Field(ge=0, le=2)]
    speed_integral_gain: Annotated[float, Field(ge=0, le=2)]
    curve_throttle_base_frac: Frac
    curve_throttle_gain: Annotated[float, Field(ge=0, le=2)]
    curve_throttle_max_frac: Frac
    exit_throttle_frac: Frac
    steer_time_constant_s: Annotated[float, Field(gt=0, le=2)]


class AmtCar(Strict):
    name: str
    layout: Literal["amt_car"]
    description: str
    source: str
    body: Body
    chassis: CarChassis
    engine: CarEngine
    gearbox: Gearbox
    brakes: AirServiceBrake
    shift_schedule: ShiftSchedule
    curve_shift: CurveShift
    map_preview: MapPreview
    curve_driver: CurveDriver

    @model_validator(mode="after")
    def _gears(self):
        n = len(self.gearbox.ratios)
        if len(self.shift_schedule.up_mps) != n - 1:
            raise ValueError(f"shift_schedule has {len(self.shift_schedule.up_mps)} up lines but the gearbox has {n} gears; "
                             f"give {n - 1}")
        return self
