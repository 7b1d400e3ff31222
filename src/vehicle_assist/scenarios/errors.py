"""Input errors that name the file, the field, the bad value and the fix, on one line."""
from __future__ import annotations

import difflib
import re
from typing import Any

from pydantic import BaseModel, ValidationError


_TYPE_TAGS = {"float", "int", "str", "bool", "list", "dict", "none"}


class InputError(ValueError):
    """Bad user input (scenario, vehicle, override). ``str(err)`` is one line meant for the user."""

    def __init__(self, message: str) -> None:
        # one line even when a key or value from the file holds a line break
        super().__init__(str(message).replace("\r", "\\r").replace("\n", "\\n"))


def did_you_mean(word: str, options) -> str:
    close = difflib.get_close_matches(str(word), [str(o) for o in options], n=1, cutoff=0.6)
    return f" (did you mean {close[0]!r}?)" if close else ""


def _model_at(model: type[BaseModel], loc: tuple) -> type[BaseModel] | None:
    """The pydantic model class that holds the field at ``loc`` (None if not a model)."""

    current: Any = model
    for part in loc:
        if isinstance(part, int) or current is None:
            continue
        if not (isinstance(current, type) and issubclass(current, BaseModel)):
            return None
        field = current.model_fields.get(str(part))
        if field is None:
            return current
        current = _first_model(field.annotation)
    return current if isinstance(current, type) and issubclass(current, BaseModel) else None


def _first_model(annotation):
    import typing

    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        return annotation
    for arg in typing.get_args(annotation):
        found = _first_model(arg)
        if found is not None:
            return found
    return None


def _range_of(model: type[BaseModel], loc: tuple) -> str:
    """'allowed: a <= x <= b' from the field's constraints, if it has any."""
    import annotated_types as at
    import typing

    parent = _model_at(model, loc[:-1] if not isinstance(loc[-1], int) else loc[:-2])
    name = next((p for p in reversed(loc) if isinstance(p, str)), None)
    if parent is None or name is None or name not in parent.model_fields:
        return ""
    field = parent.model_fields[name]
    metas = list(field.metadata)

    def collect(annotation):
        for arg in typing.get_args(annotation):
            for meta in getattr(arg, "__metadata__", ()):
                # Annotated[float, Field(ge=..)] nested in a list or Optional keeps a FieldInfo here
                metas.extend(getattr(meta, "metadata", None) or [meta])
            collect(arg)

    collect(field.annotation)
    lo = hi = ""
    for m in metas:
        if isinstance(m, at.Ge):
            lo = f"{m.ge:g} <= "
        elif isinstance(m, at.Gt):
            lo = f"{m.gt:g} < "
        elif isinstance(m, at.Le):
            hi = f" <= {m.le:g}"
        elif isinstance(m, at.Lt):
            hi = f" < {m.lt:g}"
    if not (lo or hi):
        return ""
    return f"; allowed: {lo}{name}{hi}"


def from_validation(err: ValidationError, model: type[BaseModel], where: str, prefix: str = "") -> InputError:
    """One-line message for the first error (and a count of the others)."""
    # an unknown key first: a misspelt key also makes the intended one "missing", and the did-you-mean is the fix
    errors = sorted(err.errors(), key=lambda e: e["type"] != "extra_forbidden")
    first = errors[0]
    # drop the type tags pydantic adds inside unions ("value.float", "function-after[...]")
    loc = tuple(p for p in first["loc"] if not (isinstance(p, str) and (p in _TYPE_TAGS or "[" in p)))
    path = ".".join(str(p) for p in ((prefix,) if prefix else ()) + loc)
    kind = first["type"]
    value = first.get("input")
    if kind == "extra_forbidden":
        holder = _model_at(model, loc[:-1])
        known = list(holder.model_fields) if holder else []
        msg = f"unknown key {loc[-1]!r}{did_you_mean(loc[-1], known)}; known keys here: {', '.join(known)}"
    elif kind == "missing":
        msg = "required key is missing; add it"
    elif kind == "finite_number":
        msg = f"= {value!r}: NaN or inf is not allowed; give a finite number{_range_of(model, loc)}"
    elif kind in ("greater_than", "greater_than_equal", "less_than", "less_than_equal"):
        msg = f"= {value!r}: {first['msg'].lower()}{_range_of(model, loc)}"
    elif kind == "literal_error":
        msg = f"= {value!r}: {first['msg'].lower()}"
    elif kind == "value_error":
        msg = first["msg"].removeprefix("Value error, ")
        # "time_s: breakpoints must ..." from a validator of driver.accelerator -> driver.accelerator.time_s: ...
        head = re.match(r"(\w+)(: | )", msg)
        holder = _model_at(model, loc)
        if head and holder is not None and head.group(1) in holder.model_fields:
            path = f"{path}.{head.group(1)}" if path else head.group(1)
            msg = msg[head.end():] if head.group(2) == ": " else msg[len(head.group(1)):]
    else:
        msg = f"= {value!r}: {first['msg'].lower()}"
    more = f" (and {len(errors) - 1} more problem{'s' if len(errors) > 2 else ''})" if len(errors) > 1 else ""
    sep = "" if msg.startswith(" ") else " " if msg.startswith("=") else ": "
    return InputError(f"{where}: {path}{sep}{msg}{more}")
