"""Registry of vehicle compositions ("layouts"): what each simulates, senses, records and accepts.

A layout module provides ``LAYOUT``, ``SENSORS``, ``CHANNELS``, ``MACHINES``, ``INPUTS``,
``EVENT_SIGNALS``, ``DEFAULT_GEAR_INDEX``, ``gear_names(model)``, ``derived(flat)``,
``controller_states()`` and the compiled ``simulate``. New vehicles (two-track, ESP unit, ...) add a
module and one line here; the loader, runner, batch and CLI stay as they are.
"""
from __future__ import annotations

import importlib
from types import ModuleType

_MODULES = {
    "truck_amt": "vehicle_assist.vehicles.truck_amt",
    "ev_ehb": "vehicle_assist.vehicles.ev_ehb",
    "sedan_esp": "vehicle_assist.vehicles.sedan_esp",
    "amt_car": "vehicle_assist.vehicles.amt_car",
}


def get(layout: str) -> ModuleType:
    try:
        return importlib.import_module(_MODULES[layout])
    except KeyError:
        raise KeyError(f"unknown layout {layout!r}; known: {', '.join(_MODULES)}") from None


def names() -> list[str]:
    return list(_MODULES)
