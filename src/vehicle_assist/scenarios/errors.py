"""Input errors that name the file, the field, the bad value and the fix, on one line."""
from __future__ import annotations

import difflib
import re
from typing import Any

from pydantic import BaseModel, ValidationError


_TOML_TYPES = {"str": "string", "bool": "boolean", "float": "fraction", "list": "array", "dict": "table"}
_TYPE_TAGS = {"float", "int", "str", "bool", "list", "dict", "none"}


# C0 controls (ESC, BEL, CR, LF ...), DEL, C1 controls (CSI, OSC as single bytes) and the bidirectional
# overrides/isolates: shown as visible escapes so user text can never drive a terminal or reorder a line
_CONTROL = re.compile("[\x00-\x1f\x7f-\x9f\u200e\u200f\u202a-\u202e\u2066-\u2069]")
_NAMED = {"\n": "\\n", "\r": "\\r", "\t": "\\t"}


def plain(text) -> str:
    """``text`` with every control character shown as a visible escape (``\\x1b``, ``\\n``, ``\\u202e``)."""
    text = str(text)
    if not _CONTROL.search(text):
        return text
    return _CONTROL.sub(lambda m: _NAMED.get(m.group(), f"\\x{ord(m.group()):02x}" if ord(m.group()) < 0x100
                                         else f"\\u{ord(m.group()):04x}"), text)


class InputError(ValueError):
    """Bad user input (scenario, vehicle, override). ``str(err)`` is one line meant for the user; control
    characters from keys or values (line breaks, ESC sequences) are shown escaped."""

    def __init__(self, message: str) -> None:
        super().__init__(plain(message))


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


def _clean_loc(model: type[BaseModel], loc: tuple, kind: str) -> tuple:
    """``loc`` without the type tags pydantic adds inside unions ("float", "function-after[...]"); a part
    that is a real key (a field of the model there, or the unknown key itself) is kept even if it reads
    like a tag (``[run] list = 3``, ``float = 1``)."""
    import typing

    out: list = []
    dict_key = False  # the part after a dict-valued field is a user key (e.g. a sensor name), never a tag
    for i, part in enumerate(loc):
        holder = _model_at(model, tuple(out)) if out else model
        if isinstance(part, str) and (part in _TYPE_TAGS or "[" in part) and not dict_key:
            last = i == len(loc) - 1
            is_field = holder is not None and part in holder.model_fields
            if not (is_field or (last and kind == "extra_forbidden")):
                continue
        field = holder.model_fields.get(part) if holder is not None and isinstance(part, str) and not dict_key else None
        dict_key = field is not None and typing.get_origin(field.annotation) is dict
        out.append(part)
    return tuple(out)


def from_validation(err: ValidationError, model: type[BaseModel], where: str, prefix: str = "") -> InputError:
    """One-line message for the first error (and a count of the others)."""
    try:
        return _from_validation(err, model, where, prefix)
    except Exception:  # the formatter must never turn an input error into a traceback
        first = err.errors()[0] if err.errors() else {"loc": (), "msg": "invalid"}
        path = ".".join(str(p) for p in ((prefix,) if prefix else ()) + tuple(first.get("loc", ())))
        return InputError(f"{where}: {path or '(top level)'}: {str(first.get('msg', 'invalid')).lower()}")


def _from_validation(err: ValidationError, model: type[BaseModel], where: str, prefix: str = "") -> InputError:
    # an unknown key first: a misspelt key also makes the intended one "missing", and the did-you-mean is the fix
    errors = sorted(err.errors(), key=lambda e: e["type"] != "extra_forbidden")
    first = errors[0]
    # drop the type tags pydantic adds inside unions ("value.float", "function-after[...]")
    kind = first["type"]
    loc = _clean_loc(model, tuple(first["loc"]), kind)
    path = ".".join(str(p) for p in ((prefix,) if prefix else ()) + loc) or "(top level)"
    value = first.get("input")
    if kind == "extra_forbidden" and loc:
        holder = _model_at(model, loc[:-1]) if loc[:-1] else model
        known = list(holder.model_fields) if holder else []
        msg = f"unknown key {loc[-1]!r}{did_you_mean(loc[-1], known)}; known keys here: {', '.join(known)}"
    elif kind == "missing":
        msg = "required key is missing; add it"
    elif kind == "finite_number":
        msg = f"= {value!r}: NaN or inf is not allowed; give a finite number{_range_of(model, loc)}"
    elif kind in ("greater_than", "greater_than_equal", "less_than", "less_than_equal"):
        msg = f"= {value!r}: {first['msg'].lower()}{_range_of(model, loc)}"
    elif kind in ("float_type", "int_type", "int_from_float", "float_parsing", "int_parsing"):
        shown = str(value).lower() if isinstance(value, bool) else repr(value)
        number = "a whole number" if kind.startswith("int") else "a number"
        msg = (f"= {shown}: give {number}, not a {_TOML_TYPES.get(type(value).__name__, type(value).__name__)}"
               f"{' (write it without quotes)' if isinstance(value, str) else ''}{_range_of(model, loc)}")
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
