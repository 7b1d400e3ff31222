"""Property test over the scenario schema (issue #14): any document either loads or fails with one line.

Reference: the project rule "bad input -> one-line clear error, never a traceback". Documents are drawn by
hypothesis as random edits of a shipped scenario (a leaf replaced, a key deleted, a key added, at any depth,
with values of every TOML type including NaN, inf, huge numbers, markup and control characters) and as
wholly random documents. Each is written as a TOML file and loaded; the only allowed failure is
:class:`InputError` whose message is one line without raw control characters. The test can fail: before
issue #14, `float = 1` raised IndexError and `name = "[/]x"` crashed the CLI's error printer.
"""
from __future__ import annotations

import copy
import math
import tomllib

import pytest
import tomli_w
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from vehicle_assist.scenarios.errors import InputError
from vehicle_assist.scenarios.loader import load_scenario, shipped

BASES = {name: tomllib.loads(shipped("scenarios")[name].read_text(encoding="utf-8"))
         for name in ("truck_11deg_early_release", "hsa_ev_5deg_paper")}


def _all_keys(node, out):
    if isinstance(node, dict):
        for k, v in node.items():
            out.add(k)
            _all_keys(v, out)
    elif isinstance(node, list):
        for v in node:
            _all_keys(v, out)
    return out


KNOWN_KEYS = sorted(set().union(*(_all_keys(doc, set()) for doc in BASES.values())))
text = st.one_of(st.sampled_from(KNOWN_KEYS + ["[/]x", "[bold red]x[/]", "\x1b[2J", "\x1b]52;c;aGk=\x07", "$x^$", "1", "",
                                              "heavy_amt_truck_empty", "compact_ev", "/etc/shadow", "../x.toml"]),
                 st.text(max_size=12))
scalar = st.one_of(st.booleans(), st.integers(min_value=-2**63, max_value=2**63 - 1),
                   st.floats(allow_nan=True, allow_infinity=True), st.sampled_from([0, 1, 11, 0.001, 1e-5, 3600, 1e300, -1]),
                   text)
value = st.recursive(scalar, lambda inner: st.one_of(st.lists(inner, max_size=4),
                                                     st.dictionaries(text, inner, max_size=3)), max_leaves=8)


def _paths(node, prefix=()):
    yield prefix
    if isinstance(node, dict):
        for k, v in node.items():
            yield from _paths(v, prefix + (k,))
    elif isinstance(node, list):
        for i, v in enumerate(node):
            yield from _paths(v, prefix + (i,))


@st.composite
def documents(draw):
    if draw(st.integers(0, 9)) == 0:  # now and then a wholly random document
        return draw(st.dictionaries(text, value, max_size=5))
    doc = copy.deepcopy(BASES[draw(st.sampled_from(sorted(BASES)))])
    for _ in range(draw(st.integers(1, 3))):
        paths = [p for p in _paths(doc) if p]
        path = draw(st.sampled_from(paths))
        parent = doc
        for part in path[:-1]:
            parent = parent[part]
        op = draw(st.sampled_from(["replace", "delete", "add"]))
        if op == "replace":
            parent[path[-1]] = draw(value)
        elif op == "delete" and isinstance(parent, dict):
            del parent[path[-1]]
        elif isinstance(parent, dict):
            parent[draw(text)] = draw(value)
        elif isinstance(parent, list):
            parent.append(draw(value))
    return doc


def _has_control(message: str) -> bool:
    return any(ord(c) < 32 or 0x7f <= ord(c) <= 0x9f for c in message)


@settings(max_examples=int(__import__("os").environ.get("VA_HYPOTHESIS_EXAMPLES", "300")), deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])
@given(doc=documents())
def test_any_document_loads_or_fails_with_one_line(tmp_path, doc):
    """Property: load_scenario on any generated document returns a scenario or raises InputError with one
    line and no raw control characters; no other exception escapes."""
    try:
        text_doc = tomli_w.dumps(doc)
    except (TypeError, ValueError):
        return  # not representable as TOML (tomli_w refuses it): nothing a user could write
    path = tmp_path / "doc.toml"
    path.write_text(text_doc, encoding="utf-8")
    try:
        sc = load_scenario(path)
    except InputError as exc:
        message = str(exc)
        assert message and "\n" not in message and not _has_control(message), repr(message)
        return
    assert math.isfinite(sc.model.run.duration_s)


SET_PATHS = ["road.slope_deg", "run.duration_s", "run.plant_step_s", "run.seed", "vehicle.body.mass_kg", "vehicle.base",
             "vehicle.engine.full_load_torque", "vehicle.gearbox.gear_names", "driver.accelerator.frac", "events",
             "checks", "sensors.engine_speed.noise_std_rpm", "name", "vehicle.hill_start_assist.enabled_flag"]
set_text = st.one_of(st.sampled_from(["1", "-1", "nan", "inf", "true", '"14"', "[1, 2]", "{a = 1}", "[", "1e400", '"[/]x"',
                                      '"\\u001b[2J"', "$x^$", "", "=", "[[[[1]]]]"]), st.text(max_size=10))


@settings(max_examples=int(__import__("os").environ.get("VA_HYPOTHESIS_EXAMPLES", "300")), deadline=None)
@given(assignments=st.lists(st.tuples(st.one_of(st.sampled_from(SET_PATHS), st.text(max_size=10)), set_text),
                            min_size=1, max_size=3))
def test_any_set_override_loads_or_fails_with_one_line(assignments):
    """Property: any list of `--set path=value` on a shipped scenario, through load_scenario and through the
    sweep's fast path (LoadedScenario.with_sets), either loads or raises InputError with one clean line."""
    sets = [f"{p}={v}" for p, v in assignments]
    for attempt in (lambda: load_scenario("truck_11deg_early_release", sets),
                    lambda: load_scenario("truck_11deg_early_release").with_sets(*sets)):
        try:
            attempt()
        except InputError as exc:
            message = str(exc)
            assert message and "\n" not in message and not _has_control(message), repr(message)
