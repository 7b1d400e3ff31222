"""Fully resolved parameters of a vehicle or scenario, with units and sources, for ``show``."""
from __future__ import annotations

from pydantic import BaseModel

from vehicle_assist.units import to_si, unit_of


def _entry(key: str, value, source: str) -> dict:
    entry: dict = {"value": value}
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        si_key, si_value = to_si(key, float(value))
        entry["unit"] = unit_of(key) or "-"
        if si_key != key:
            entry["si_name"] = si_key
            entry["si_value"] = si_value
            entry["si_unit"] = unit_of(si_key)
    entry["source"] = source
    return entry


def resolved_vehicle(vehicle) -> dict:
    model = vehicle.model
    doc: dict = {"name": model.name, "layout": model.layout, "description": model.description,
                 "source": model.source, "file": str(vehicle.path)}
    for section, body in model:
        if not isinstance(body, BaseModel):
            continue
        out = {}
        for key, value in body:
            src = vehicle.sources.get(f"{section}.{key}", "")
            if isinstance(value, BaseModel):
                out[key] = {**value.model_dump(), "source": src}
            else:
                out[key] = _entry(key, value, src)
        doc[section] = out
    return doc


def resolved_scenario(sc) -> dict:
    m = sc.model
    doc = m.model_dump(exclude_none=True, exclude={"vehicle"})
    doc["scenario_hash"] = sc.scenario_hash()
    doc["parameter_hash"] = sc.parameter_hash()
    doc["overrides"] = list(sc.sets)
    doc["vehicle"] = resolved_vehicle(sc.vehicle)
    return doc
