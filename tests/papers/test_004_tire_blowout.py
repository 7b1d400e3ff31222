"""Paper 004 in reproduce (issue #10): registration, scenarios load, figure kind, and (slow) the studies."""
from __future__ import annotations

import pytest

import vehicle_assist as va
from vehicle_assist.procedures import reproduce
from vehicle_assist.procedures.blowout_study import SCENARIOS


def test_registered():
    """Paper 004 is a Reproduction with its extras and figure kind."""
    rep = [r for r in reproduce.REPRODUCTIONS if r.paper == "004"]
    assert len(rep) == 1
    assert set(rep[0].extras) <= set(reproduce.EXTRAS)
    from vehicle_assist.report.plots import FIGURES

    assert "tire_blowout" in FIGURES


def test_every_scenario_loads_with_sources():
    """Each shipped blowout scenario validates (every vehicle number has a source, checks cite a clause)."""
    for name in SCENARIOS:
        sc = va.load_scenario(name)
        for c in sc.model.checks:
            assert c.why


@pytest.mark.slow
def test_studies(tmp_path):
    """The Fig. 4 study and the sweep run and give their criteria (every wheel/speed reduces RMS by >= 30 %)."""
    figs, entries = reproduce.EXTRAS["blowout_fig4"](tmp_path)
    assert figs and all(e["pass"] for e in entries)
    figs, entries = reproduce.EXTRAS["blowout_sweep"](tmp_path)
    assert figs and entries


def test_envelope_and_requirements_load():
    """data/envelopes/tire_blowout.toml and data/requirements/tire_blowout.toml validate (sources, paths)."""
    from vehicle_assist.verification.envelope import load_envelope

    env = load_envelope("tire_blowout")
    assert env is not None


@pytest.mark.slow
def test_falsification_campaign(tmp_path):
    """The campaign runs and reports one entry per requirement and envelope (feed-forward, closed loop)."""
    figs, entries = reproduce.EXTRAS["falsify_004"](tmp_path)
    assert len(entries) == 4
