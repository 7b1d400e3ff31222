"""Tables in input files: a pydantic model whose first field holds the breakpoints and second the values.

Subclasses only declare the two fields with their units and bounds (e.g. ``speed_rpm``, ``torque_nm``);
the shared validator checks them as a :class:`~vehicle_assist.core.tables.Table` (equal lengths, finite,
strictly increasing breakpoints), so every table of every file is validated the same way.
"""
from __future__ import annotations

from pydantic import BaseModel, ConfigDict, model_validator

from vehicle_assist.core.tables import Table


class TableSpec(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)

    @model_validator(mode="after")
    def _valid_table(self):
        (x_name, xs), (y_name, ys) = list(self)[:2]
        Table(x_name, y_name, tuple(float(v) for v in xs),
              tuple(float(v) if not isinstance(v, str) else 0.0 for v in ys),  # named values (gears) checked elsewhere
              getattr(self, "extrapolation", "clamp"))
        return self
