"""Envelope files: validation errors name the field; points map to the overrides they promise.

References: the envelope ranges of issue #7 (truck 13-40 t, 0-20 deg; EV 1300-2100 kg, 0-25 deg) read
back from the shipped files, and the pedal shape written out by hand."""
from pathlib import Path

import numpy as np
import pytest

from vehicle_assist.scenarios.errors import InputError
from vehicle_assist.verification.envelope import load_envelope, pedal_table, shipped_envelopes

GOOD = """
name = "t"
function = "hill_start_amt"
base = "hsa_truck_full_14deg_8p0bar"
baseline = ["vehicle.hill_start_assist.enabled_flag=0"]
baseline_source = "issue #7"
[ranges.mass]
path = "vehicle.body.mass_kg"
min = 13000
max = 40000
source = "issue #7 item 1"
"""


def _write(tmp_path: Path, text: str) -> Path:
    p = tmp_path / "env.toml"
    p.write_text(text)
    return p


def test_shipped_envelopes_carry_issue_7_ranges():
    assert {"hill_start_amt", "hill_start_ehb"} <= set(shipped_envelopes())
    truck = load_envelope("hill_start_amt")
    assert (truck.dim("mass").lo, truck.dim("mass").hi) == (13000, 40000)
    assert (truck.dim("slope").lo, truck.dim("slope").hi) == (0, 20)
    assert set(truck.dim("start_gear").options) == {"crawler", "first", "second"}
    assert set(truck.dim("surface").options) == {"gravel", "asphalt", "wet"}
    ev = load_envelope("hill_start_ehb")
    assert (ev.dim("mass").lo, ev.dim("mass").hi) == (1300, 2100)
    assert (ev.dim("accelerator.rate_per_s").lo, ev.dim("accelerator.rate_per_s").hi) == (0.01, 0.5)
    for env in (truck, ev):
        assert all(len(d.source) > 3 for d in env.dims)


def test_point_becomes_scenario_with_its_overrides():
    env = load_envelope("hill_start_amt")
    point = dict(env.center(), mass=20000.0, slope=12.0, surface="wet", start_gear="second")
    sc = env.scenario(point)
    assert sc.vehicle.model.body.mass_kg == 20000.0
    assert sc.model.road.slope_deg == 12.0
    assert sc.model.road.friction_mu == 0.5 and sc.model.road.rolling_resistance_coeff == 0.015
    assert sc.model.driver.gear_lever.gear == ["2"]
    assert sc.vehicle.model.hill_start_assist.enabled_flag == 1
    twin = env.scenario(point, baseline=True)
    assert twin.vehicle.model.hill_start_assist.enabled_flag == 0
    assert twin.model.road.slope_deg == 12.0


def test_unit_cube_maps_discrete_cells_and_ends():
    env = load_envelope("hill_start_amt")
    p = env.unit_to_point(np.zeros(len(env.dims)))
    assert p["mass"] == 13000 and p["start_gear"] == "crawler"
    p = env.unit_to_point(np.ones(len(env.dims)))
    assert p["mass"] == 40000 and p["start_gear"] == "second"
    g = env.grid({d.name: 2 for d in env.dims})
    assert len(g) == 2 ** 7 * 3 * 3


def test_pedal_profile_by_hand():
    # ramp 0 -> 0.5 at 0.0225 /s from 2 s ends at 2 + 0.5 / 0.0225 = 24.222 s (hill_start_ehb.md 4 S1)
    t = pedal_table(2.0, 0.5, rate_per_s=0.0225)
    assert t["time_s"] == [2.0, pytest.approx(24.222222, abs=1e-5)] and t["frac"] == [0.0, 0.5]
    # hesitating (S4): at 0.3 (0.6 of 0.5) the pedal falls to 0.1 and is held
    t = pedal_table(2.0, 0.5, rate_per_s=0.0225, dip_at_frac=0.6, dip_depth_frac=2 / 3, dip_hold_s=0.67)
    assert t["frac"][1] == pytest.approx(0.3) and t["frac"][2] == pytest.approx(0.1)
    assert t["time_s"][1] == pytest.approx(2 + 0.3 / 0.0225, abs=1e-5)


def test_ev_run_lasts_past_the_slowest_pedal():
    env = load_envelope("hill_start_ehb")
    sc = env.scenario(dict(env.center(), **{"accelerator.rate_per_s": 0.01, "accelerator.level_frac": 0.5, "driver": "steady"}))
    assert sc.model.run.duration_s == pytest.approx(2.0 + 50.0 + 6.0)
    sc = env.scenario(dict(env.center(), **{"accelerator.rate_per_s": 0.01, "accelerator.level_frac": 1.0, "driver": "steady"}))
    assert sc.model.run.duration_s == pytest.approx(60.0)  # max_duration_s of the envelope file


@pytest.mark.parametrize("edit, field", [
    (("min = 13000", "min = 50000"), "ranges.mass"),
    (('path = "vehicle.body.mass_kg"', 'path = "vehicle.body.masss_kg"'), "mass"),
    (('source = "issue #7 item 1"\n', ''), "ranges.mass.source"),
    (('base = "hsa_truck_full_14deg_8p0bar"', 'base = "nope"'), "base"),
    (("[ranges.mass]", "[ranges.mass]\nstep = 3"), "ranges.mass"),
])
def test_bad_envelope_one_line_error_names_field(tmp_path, edit, field):
    text = GOOD.replace(*edit)
    with pytest.raises(InputError) as exc:
        load_envelope(_write(tmp_path, text))
    msg = str(exc.value)
    assert "\n" not in msg and field in msg and "env.toml" in msg


def test_unknown_shipped_envelope():
    with pytest.raises(InputError, match="hill_start_amt"):
        load_envelope("hill_start_am")


def test_envelope_numbers_are_strict(tmp_path):
    """Reviewer (issues #8/#14): `max = "8.5"` in an envelope was coerced to 8.5 silently; scenarios refuse it."""
    from vehicle_assist.scenarios.errors import InputError
    from vehicle_assist.verification.envelope import load_envelope, shipped_envelopes

    text = shipped_envelopes()["hill_start_amt"].read_text(encoding="utf-8")
    assert "max = 8.5" in text
    bad = tmp_path / "e.toml"
    bad.write_text(text.replace("max = 8.5", 'max = "8.5"', 1), encoding="utf-8")
    with pytest.raises(InputError, match=r"ranges\.reservoir\.max = '8\.5': give a number, not a string"):
        load_envelope(bad)
