"""Bad scenario and vehicle input: one clear line naming the file, the field, the bad value and the fix.

Requirement (issue): "Bad input gets a clear one-line error naming the file, the field, the bad value
and the allowed range: negative mass, a slope beyond +-45 deg, NaN or inf anywhere, an unknown key (with
a did-you-mean), a missing file, a table with non-monotonic breakpoints."

Every case starts from the text of a shipped file (scenario ``truck_11deg_early_release``, vehicle
``heavy_amt_truck_empty``), changes one thing and checks that :func:`load_scenario` raises
:class:`InputError` (never a raw KeyError/TypeError/ValueError) whose message is a single line holding
the file path and every expected fragment (dotted field, bad value, allowed range or fix).
"""
from __future__ import annotations

from pathlib import Path

import pytest

from vehicle_assist.scenarios.errors import InputError
from vehicle_assist.scenarios.loader import load_scenario, shipped

SCENARIO = shipped("scenarios")["truck_11deg_early_release"]
VEHICLE = shipped("vehicles")["heavy_amt_truck_empty"]
BASE_LINE = 'base = "heavy_amt_truck_empty"'
MASS_RANGE = "allowed: 100 <= mass_kg <= 100000"
SLOPE_RANGE = "allowed: -45 <= slope_deg <= 45"
FINITE = "NaN or inf is not allowed"


def _line_of(scenario: str, text: str) -> int:
    """1-based line of ``text`` in a shipped scenario (keeps line-number expectations true when files change)."""
    lines = shipped("scenarios")[scenario].read_text(encoding="utf-8").splitlines()
    return next(i + 1 for i, line in enumerate(lines) if text in line)

# A scenario section, appended to the file, that overrides vehicle.body keys.
BODY_OVERRIDE = "\n[vehicle.body]\n"  # TOML allows a sub-table of [vehicle] after other tables


def edit(text: str, *replacements: tuple[str, str]) -> str:
    """Apply (old, new) replacements, each of which must match (a changed shipped file fails loudly)."""
    for old, new in replacements:
        assert old in text, f"shipped file no longer contains {old!r}; update the test"
        text = text.replace(old, new, 1)
    return text


def write_case(tmp_path: Path, scenario_edits=(), vehicle_edits=None, append: str = "") -> tuple[Path, Path | None]:
    """Scenario file (and, if ``vehicle_edits`` is given, a vehicle file it is based on) in tmp_path."""
    scenario_text = SCENARIO.read_text(encoding="utf-8")
    vehicle_path = None
    if vehicle_edits is not None:
        vehicle_path = tmp_path / "my_truck.toml"
        vehicle_path.write_text(edit(VEHICLE.read_text(encoding="utf-8"), *vehicle_edits), encoding="utf-8")
        scenario_text = edit(scenario_text, (BASE_LINE, f'base = "{vehicle_path}"'))
    scenario_path = tmp_path / "my_scenario.toml"
    scenario_path.write_text(edit(scenario_text, *scenario_edits) + append, encoding="utf-8")
    return scenario_path, vehicle_path


def load_error(path_or_name, sets=()) -> str:
    """The message of the InputError that loading raises; fails if it is not one line."""
    with pytest.raises(InputError) as info:
        load_scenario(path_or_name, list(sets))
    message = str(info.value)
    assert "\n" not in message and "\r" not in message, f"not one line: {message!r}"
    return message


def assert_names(message: str, *fragments: str) -> None:
    missing = [f for f in fragments if f not in message]
    assert not missing, f"message lacks {missing}: {message}"


# ---------------------------------------------------------------------------------------------- scenario
# (scenario edits, text appended to the scenario, --set assignments, fragments: field, value, range / fix)
SCENARIO_CASES = [
    # negative mass
    pytest.param((), BODY_OVERRIDE + "mass_kg = -5\n", (),
                 ("vehicle.body.mass_kg", "= -5", MASS_RANGE), id="mass-negative-override"),
    pytest.param((), "", ("vehicle.body.mass_kg=-5",),
                 ("vehicle.body.mass_kg", "= -5", MASS_RANGE), id="mass-negative-set"),
    # slope beyond +-45 deg, constant and table
    pytest.param((("slope_deg = 11", "slope_deg = 95"),), "", (),
                 ("road.slope_deg", "= 95", SLOPE_RANGE), id="slope-95-constant"),
    pytest.param((("slope_deg = 11", "slope_deg = -46"),), "", (),
                 ("road.slope_deg", "= -46", SLOPE_RANGE), id="slope-minus46-constant"),
    pytest.param((("slope_deg = 11", "slope = { distance_m = [0, 50], slope_deg = [11, 95] }"),), "", (),
                 ("road.slope.slope_deg.1", "= 95", SLOPE_RANGE), id="slope-95-table"),
    pytest.param((("slope_deg = 11", "slope = { distance_m = [0, 50], slope_deg = [-46, 11] }"),), "", (),
                 ("road.slope.slope_deg.0", "= -46", SLOPE_RANGE), id="slope-minus46-table"),
    pytest.param((), "", ("road.slope_deg=95",),
                 ("road.slope_deg", "= 95", SLOPE_RANGE), id="slope-95-set"),
    # NaN and inf: scalars, inside table lists, through --set, in events
    pytest.param((("slope_deg = 11", "slope_deg = nan"),), "", (),
                 ("road.slope_deg", "= nan", FINITE, SLOPE_RANGE), id="nan-scalar"),
    pytest.param((("duration_s = 20", "duration_s = inf"),), "", (),
                 ("run.duration_s", "= inf", FINITE, "allowed: 0 < duration_s <= 3600"), id="inf-scalar"),
    pytest.param((("slope_deg = 11", "slope_deg = -inf"),), "", (),
                 ("road.slope_deg", "= -inf", FINITE, SLOPE_RANGE), id="minus-inf-scalar"),
    pytest.param((("frac = [0.0, 0.0, 0.27]", "frac = [0.0, nan, 0.27]"),), "", (),
                 ("driver.accelerator.frac.1", "= nan", FINITE, "allowed: 0 <= frac <= 1"), id="nan-in-table-values"),
    pytest.param((("time_s = [0.0, 2.0, 2.5]", "time_s = [0.0, 2.0, inf]"),), "", (),
                 ("driver.accelerator.time_s.2", "= inf", FINITE, "allowed: 0 <= time_s <= 3600"), id="inf-in-table-breakpoints"),
    pytest.param((("slope_deg = 11", "slope = { distance_m = [-inf, 0], slope_deg = [11, 11] }"),), "", (),
                 ("road.slope.distance_m.0", "= -inf", FINITE), id="minus-inf-in-road-table"),
    pytest.param((), "", ("road.slope_deg=nan",),
                 ("road.slope_deg", "= nan", FINITE, SLOPE_RANGE), id="nan-set"),
    pytest.param((), "", ("run.duration_s=inf",),
                 ("run.duration_s", "= inf", FINITE), id="inf-set"),
    pytest.param((), "", ("vehicle.body.mass_kg=-inf",),
                 ("vehicle.body.mass_kg", "= -inf", FINITE, MASS_RANGE), id="minus-inf-set-vehicle"),
    pytest.param((), "", ("sensors.engine_speed.noise_std_rpm=nan",),
                 ("sensors.engine_speed.noise_std_rpm", "= nan", "give a finite number"), id="nan-set-sensor"),
    pytest.param((), '\n[[events]]\nat_s = 3\naction = "sensor_fault"\nsensor = "engine_speed"\nfault = "bias"\nbias_rpm = nan\n', (),
                 ("events.0.bias_rpm", "= nan", "give a finite number"), id="nan-event-bias"),
    pytest.param((), '\n[[events]]\nwhen = { signal = "speed_mps", above = inf }\naction = "stop"\n', (),
                 ("events.0.when.above", "= inf", FINITE), id="inf-event-condition"),
    # unknown keys, with a did-you-mean
    pytest.param((('description = "', 'descripton = "'),), "", (),
                 ("descripton", "did you mean 'description'", "known keys here"), id="unknown-top-level-key"),
    pytest.param((("slope_deg = 11", "slop_deg = 11"),), "", (),
                 ("road.slop_deg", "did you mean 'slope_deg'", "known keys here"), id="unknown-key-in-section"),
    pytest.param((), BODY_OVERRIDE + "mas_kg = 13000\n", (),
                 ("vehicle.body.mas_kg", "did you mean 'mass_kg'"), id="unknown-key-in-vehicle-override"),
    pytest.param((), "\n[vehicle.bdy]\nmass_kg = 13000\n", (),
                 ("vehicle.bdy", "unknown subsystem", "did you mean 'body'"), id="unknown-vehicle-subsystem"),
    pytest.param((), "\n[sensors.engine_sped]\ndelay_s = 0.01\n", (),
                 ("sensors.engine_sped", "unknown sensor", "did you mean 'engine_speed'"), id="unknown-sensor"),
    pytest.param((('metric = "rollback_distance_m"', 'metric = "rollback_distanse_m"'),), "", (),
                 ("checks.0.metric", "'rollback_distanse_m'", "did you mean 'rollback_distance_m'"), id="unknown-check-metric"),
    pytest.param((('gear = ["1"]', 'gear = ["11"]'),), "", (),
                 ("driver.gear_lever.gear.0", "'11'", "did you mean '1'", "gears: N, C, 1"), id="unknown-gear"),
    pytest.param((), "", ("road.slop_deg=3",),
                 ("road.slop_deg", "did you mean 'slope_deg'"), id="unknown-key-set"),
    pytest.param((), "", ("vehicle.body.mas_kg=3",),
                 ("vehicle.body.mas_kg", "did you mean 'mass_kg'"), id="unknown-vehicle-key-set"),
    # missing base vehicle
    pytest.param(((BASE_LINE, 'base = "heavy_amt_truk_empty"'),), "", (),
                 ("vehicle.base", "'heavy_amt_truk_empty'", "did you mean 'heavy_amt_truck_empty'"), id="missing-base-name"),
    pytest.param(((BASE_LINE, 'base = "no_such_dir/truck.toml"'),), "", (),
                 ("vehicle.base", "no_such_dir/truck.toml", "file not found"), id="missing-base-file"),
    # non-monotonic, duplicate and mismatched tables
    pytest.param((("time_s = [0.0, 2.0, 2.5]", "time_s = [0.0, 2.5, 2.0]"),), "", (),
                 ("driver.accelerator.time_s", "2 follows 2.5", "strictly increasing"), id="driver-table-non-monotonic"),
    pytest.param((("time_s = [0.0, 1.0, 1.2], frac = [0.6", "time_s = [0.0, 1.0, 1.0], frac = [0.6"),), "", (),
                 ("driver.brake_pedal.time_s", "1 follows 1", "strictly increasing"), id="driver-table-duplicate"),
    pytest.param((("slope_deg = 11", "slope = { distance_m = [0, 20, 10], slope_deg = [11, 11, 5] }"),), "", (),
                 ("road.slope.distance_m", "10 follows 20", "strictly increasing"), id="road-table-non-monotonic"),
    pytest.param((("slope_deg = 11", "slope = { distance_m = [0, 10, 10], slope_deg = [11, 11, 5] }"),), "", (),
                 ("road.slope.distance_m", "10 follows 10", "strictly increasing"), id="road-table-duplicate"),
    pytest.param((("time_s = [0.0, 2.0, 2.5]", "time_s = [0.0, 2.0]"),), "", (),
                 ("driver.accelerator.time_s", "has 2 breakpoints but frac has 3 values", "one value per breakpoint"),
                 id="driver-table-length-mismatch"),
    pytest.param((("slope_deg = 11", "slope = { distance_m = [0, 10], slope_deg = [11, 11, 5] }"),), "", (),
                 ("road.slope.distance_m", "has 2 breakpoints but slope_deg has 3 values", "one value per breakpoint"),
                 id="road-table-length-mismatch"),
    # run settings and syntax
    pytest.param((("duration_s = 20", "duration_s = 20\nplant_step_s = 0.003"),), "", (),
                 ("run.controller_period_s", "= 0.01", "whole multiple of plant_step_s = 0.003"), id="run-period-mismatch"),
    pytest.param((("slope_deg = 11", "slope_deg = = 11"),), "", (),
                 ("not valid TOML", f"line {_line_of('truck_11deg_early_release', 'slope_deg = 11')}", "fix the syntax"),
                 id="invalid-toml"),
]


@pytest.mark.parametrize(("scenario_edits", "append", "sets", "fragments"), SCENARIO_CASES)
def test_bad_scenario_gives_one_line_naming_file_field_value_and_fix(tmp_path, scenario_edits, append, sets, fragments):
    """Requirement: a bad scenario file or --set override raises InputError with one line naming the
    scenario file, the dotted field, the bad value and the allowed range or fix (did-you-mean for keys)."""
    path, _ = write_case(tmp_path, scenario_edits, append=append)
    message = load_error(path, sets)
    assert_names(message, str(path), *fragments)


def test_negative_mass_by_shipped_name_and_set_names_the_shipped_file():
    """Requirement: `--set vehicle.body.mass_kg=-5` on a shipped scenario (by name) names that scenario's
    file, the field, the value and the allowed range."""
    message = load_error("truck_11deg_early_release", ["vehicle.body.mass_kg=-5"])
    assert_names(message, str(SCENARIO), "vehicle.body.mass_kg", "= -5", MASS_RANGE)


# ---------------------------------------------------------------------------------------------- vehicle
# (vehicle edits, fragments) -- the vehicle file is the scenario's base; the message must name the vehicle file
VEHICLE_CASES = [
    pytest.param((("mass_kg = 13000", "mass_kg = -5"),),
                 ("body.mass_kg", "= -5", MASS_RANGE), id="mass-negative"),
    pytest.param((("mass_kg = 13000", "mass_kg = nan"),),
                 ("body.mass_kg", "= nan", FINITE, MASS_RANGE), id="nan-scalar"),
    pytest.param((("torque_nm = [420,", "torque_nm = [inf,"),),
                 ("engine.full_load_torque.torque_nm.0", "= inf", FINITE, "allowed: 0 <= torque_nm <= 20000"), id="inf-in-table"),
    pytest.param((("speed_rpm = [600, 800,", "speed_rpm = [800, 600,"),),
                 ("engine.full_load_torque.speed_rpm", "600 follows 800", "strictly increasing"), id="table-non-monotonic"),
    pytest.param((('mass_kg = "paper 000 P9: empty mass 13 t"\n', ""),),
                 ("body.mass_kg", "has no source", "[body.source]"), id="number-without-source"),
    pytest.param((("mass_kg = 13000", "mas_kg = 13000"),),
                 ("body.mas_kg", "unknown key", "did you mean 'mass_kg'"), id="unknown-key"),
    pytest.param((("[body]", "[bdy]"), ("[body.source]", "[bdy.source]")),
                 ("bdy", "unknown key", "did you mean 'body'"), id="unknown-subsystem"),
    pytest.param((('layout = "truck_amt"', 'layout = "truck_amx"'),),
                 ("layout", "'truck_amx'", "did you mean 'truck_amt'"), id="unknown-layout"),
    pytest.param((("mass_kg = 13000", "mass_kg = "),),
                 ("not valid TOML", "line 7", "fix the syntax"), id="invalid-toml"),
]


@pytest.mark.parametrize(("vehicle_edits", "fragments"), VEHICLE_CASES)
def test_bad_vehicle_file_gives_one_line_naming_the_vehicle_file(tmp_path, vehicle_edits, fragments):
    """Requirement: a bad vehicle file (negative mass, NaN/inf, non-monotonic table, unknown key, a number
    without a source, bad syntax) raises InputError with one line naming the vehicle file, the field, the
    bad value and the range or fix."""
    scenario_path, vehicle_path = write_case(tmp_path, vehicle_edits=vehicle_edits)
    message = load_error(scenario_path)
    assert_names(message, str(vehicle_path), *fragments)


def test_override_error_names_the_scenario_not_the_vehicle_file(tmp_path):
    """Requirement (naming the file): a bad value set in the scenario's [vehicle.body] is reported
    against the scenario file with the full dotted path, not against the (correct) vehicle file."""
    scenario_path, vehicle_path = write_case(tmp_path, vehicle_edits=(), append=BODY_OVERRIDE + "mass_kg = -5\n")
    message = load_error(scenario_path)
    assert_names(message, str(scenario_path), "vehicle.body.mass_kg", "= -5", MASS_RANGE)
    assert str(vehicle_path) not in message


def test_vehicle_base_chain_names_the_file_holding_the_bad_base(tmp_path):
    """Requirement (missing file, did-you-mean): a vehicle file whose own `base` is misspelt names that
    vehicle file, its `base` key, the bad name and the likely intended one."""
    vehicle_path = tmp_path / "my_truck.toml"
    vehicle_path.write_text('name = "my_truck"\nbase = "heavy_amt_truk_empty"\n', encoding="utf-8")
    scenario_path = tmp_path / "my_scenario.toml"
    scenario_path.write_text(edit(SCENARIO.read_text(encoding="utf-8"), (BASE_LINE, f'base = "{vehicle_path}"')), encoding="utf-8")
    message = load_error(scenario_path)
    assert_names(message, str(scenario_path), str(vehicle_path), "base", "'heavy_amt_truk_empty'",
                 "did you mean 'heavy_amt_truck_empty'")


# ---------------------------------------------------------------------------------------------- files
def test_missing_scenario_file_names_the_path(tmp_path):
    """Requirement: a missing scenario file gives one line naming the path and what to give instead."""
    path = tmp_path / "nope.toml"
    message = load_error(path)
    assert_names(message, str(path), "file not found", "vehicle-assist list")


def test_unknown_scenario_name_suggests_the_near_miss():
    """Requirement: a misspelt shipped scenario name gets a did-you-mean."""
    message = load_error("truck_11deg_erly_release")
    assert_names(message, "'truck_11deg_erly_release'", "did you mean 'truck_11deg_early_release'")


def test_directory_instead_of_file_is_an_input_error(tmp_path):
    """Requirement (no traceback): a directory given as the scenario is a one-line InputError."""
    message = load_error(tmp_path)
    assert_names(message, str(tmp_path), "cannot read it")


def test_line_break_in_a_key_still_gives_one_line(tmp_path):
    """Requirement (one line): a quoted key holding a line break does not split the message."""
    path, _ = write_case(tmp_path, (("slope_deg = 11", '"slope\\ndeg" = 11'),))
    message = load_error(path)
    assert_names(message, str(path), "road.slope\\ndeg", "did you mean 'slope_deg'")


@pytest.mark.parametrize("name", sorted(shipped("scenarios")))
def test_shipped_scenarios_load(name):
    """Control: every shipped scenario loads without error (so the failures above come from the edits)."""
    assert load_scenario(name).name == name
