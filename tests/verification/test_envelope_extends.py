"""Envelope ``extends`` (session m): a variant states only what differs from its base envelope.

References: the base file itself (read with tomllib, not through the loader) - every dimension not replaced must be
the base's, in the base's order; the replaced one must be the variant's own table; the right-curve variants (M4) carry
the base's curve radii with the sign flipped (signed lane radius, + left, - right)."""

from __future__ import annotations

import tomllib
from pathlib import Path

import pytest

from vehicle_assist.scenarios.errors import InputError
from vehicle_assist.verification.envelope import load_envelope, shipped_envelopes


@pytest.mark.parametrize("variant, base", [("tire_blowout_right", "tire_blowout"),
                                           ("tire_blowout_false_alarm_right", "tire_blowout_false_alarm"),
                                           ("tire_blowout_faults_right", "tire_blowout_faults")])
def test_right_curve_variant_is_its_base_with_the_curve_mirrored(variant, base):
    raw_base = tomllib.loads(shipped_envelopes()[base].read_text(encoding="utf-8"))
    env = load_envelope(variant, validate=False)
    assert env.model.name == variant
    assert env.model.base == raw_base["base"] and env.model.requirements == raw_base["requirements"]
    assert list(env.model.ranges) == list(raw_base["ranges"])  # the base's order: same sampled coordinates
    assert list(env.model.choices) == list(raw_base["choices"])
    for name, table in raw_base["ranges"].items():
        assert env.model.ranges[name].model_dump(exclude_unset=True) == table, name
    for name, table in raw_base["choices"].items():
        if name != "curve":
            assert env.model.choices[name].options == table["options"], name
    radii_base = {o["vehicle.lane_keeper.lane_radius_m"] for o in raw_base["choices"]["curve"]["options"].values()}
    radii = {o["vehicle.lane_keeper.lane_radius_m"] for o in env.model.choices["curve"].options.values()}
    assert radii == {-r for r in radii_base if r > 0}  # every left curve of the base, turned right; no straight


def _write(path: Path, text: str) -> Path:
    path.write_text(text, encoding="utf-8")
    return path


def test_user_variant_replaces_one_dimension_keeps_the_rest(tmp_path):
    f = _write(tmp_path / "slow.toml", 'name = "slow"\nextends = "tire_blowout"\n[ranges.speed]\npath = '
               '"run.initial_speed_kph"\nmin = 40\nmax = 60\nsource = "test: the slow end only"\n')
    env = load_envelope(f, validate=False)
    base = load_envelope("tire_blowout", validate=False)
    assert (env.model.ranges["speed"].min, env.model.ranges["speed"].max) == (40, 60)
    assert [d.name for d in env.dims] == [d.name for d in base.dims]
    assert env.model.ranges["mu"] == base.model.ranges["mu"]


@pytest.mark.parametrize("body, needle", [
    ('extends = "no_such_envelope"', "extends = 'no_such_envelope': no shipped envelope named 'no_such_envelope'"),
    ("extends = 3", "give the base envelope"),
    ('extends = ""', "give the base envelope"),
    ('extends = "self.toml"', "cycle"),
])
def test_bad_extends_is_one_line(tmp_path, body, needle):
    f = _write(tmp_path / "self.toml", f'name = "x"\n{body}\n')
    with pytest.raises(InputError) as err:
        load_envelope(f)
    assert needle in str(err.value) and "\n" not in str(err.value)


def test_cycle_of_two(tmp_path):
    _write(tmp_path / "a.toml", 'name = "a"\nextends = "b.toml"\n')
    _write(tmp_path / "b.toml", 'name = "b"\nextends = "a.toml"\n')
    with pytest.raises(InputError, match="cycle"):
        load_envelope(tmp_path / "a.toml")


def test_a_choice_replaced_by_a_range_of_the_same_name(tmp_path):
    """final read (session m): a dimension given in another table replaces the base's too (no choice and range both named curve)."""
    f = _write(tmp_path / "radius.toml", 'name = "radius"\nextends = "tire_blowout"\n[ranges.curve]\npath = '
               '"vehicle.lane_keeper.lane_radius_m"\nmin = 650\nmax = 1000\nsource = "test: left radii as a range"\n')
    env = load_envelope(f)
    assert "curve" not in env.model.choices and (env.model.ranges["curve"].min, env.model.ranges["curve"].max) == (650, 1000)
    assert sum(d.name == "curve" for d in env.dims) == 1
