"""Envelope ranges that drive several scenario paths with one value (``paths = [...]``).

Reference: the overrides written by hand (one value to each listed path) and the scenario the loader
builds from them (the sensors' noise vector read back per channel)."""
from pathlib import Path

import numpy as np
import pytest

from vehicle_assist.scenarios.errors import InputError
from vehicle_assist.verification.envelope import load_envelope

WHEELS = ("fl", "fr", "rl", "rr")
HEAD = """
name = "t"
function = "tire_blowout"
base = "blowout_lf_60kph_paper"
baseline = ["vehicle.blowout_compensation.enabled_flag=0"]
baseline_source = "issue #10"
"""
NOISE = HEAD + """
[ranges.noise]
paths = [{paths}]
min = 0.0
max = 0.4
source = "test"
"""


def _env(tmp_path: Path, text: str):
    p = tmp_path / "env.toml"
    p.write_text(text)
    return load_envelope(p)


def _noise_paths():
    return ", ".join(f'"sensors.wheel_speed_{w}.noise_std_radps"' for w in WHEELS)


def test_one_value_sets_every_listed_path(tmp_path):
    env = _env(tmp_path, NOISE.format(paths=_noise_paths()))
    sets = env.sets({"noise": 0.25})
    assert sets == [f"sensors.wheel_speed_{w}.noise_std_radps=0.25" for w in WHEELS]
    sc = env.scenario({"noise": 0.25})
    from vehicle_assist.vehicles import sedan_esp as lay

    names = [s.rsplit("_", 1)[0] for s in lay.SENSORS]
    noise = sc.flat["sensor_noise_std"]
    for w in WHEELS:
        assert noise[names.index(f"wheel_speed_{w}")] == 0.25
    # every other sensor stays noise-free
    others = [i for i, n in enumerate(names) if not n.startswith("wheel_speed_")]
    assert np.all(noise[others] == 0.0)


def test_single_path_form_unchanged(tmp_path):
    env = _env(tmp_path, HEAD + '[ranges.speed]\npath = "run.initial_speed_kph"\nmin = 40\nmax = 120\nsource = "test"\n')
    assert env.sets({"speed": 80.0}) == ["run.initial_speed_kph=80.0"]


@pytest.mark.parametrize("body, needle", [
    ('path = "run.initial_speed_kph"\npaths = ["run.initial_speed_kph"]\n', "exactly one of path"),
    ("", "exactly one of path"),
    ('paths = []\n', "paths"),
    ('paths = ["run.initial_speed_kph", "run.initial_speed_kph"]\n', "listed twice"),
])
def test_path_and_paths_are_exclusive(tmp_path, body, needle):
    text = HEAD + "[ranges.x]\n" + body + "min = 40\nmax = 120\nsource = \"test\"\n"
    with pytest.raises(InputError) as err:
        _env(tmp_path, text)
    assert needle in str(err.value)
    assert "\n" not in str(err.value).strip()


def test_bad_path_in_list_reported_by_validation(tmp_path):
    text = NOISE.format(paths='"sensors.wheel_speed_fl.noise_std_radps", "sensors.wheel_speed_xx.noise_std_radps"')
    with pytest.raises(InputError) as err:
        _env(tmp_path, text)
    assert "wheel_speed_xx" in str(err.value)


def test_integer_range_writes_a_whole_number(tmp_path):
    """An ``integer = true`` range (the noise seed) writes 12, not 12.0 (the scenario schema takes only whole seeds)."""
    env = _env(tmp_path, HEAD + '[ranges.seed]\npath = "run.seed"\nmin = 0\nmax = 9999\ninteger = true\nsource = "test"\n')
    point = env.unit_to_point([12.2 / 9999])
    assert env.sets(point) == ["run.seed=12"]
    assert env.scenario(point).model.run.seed == 12
