"""UN R139 brake-assist procedure (procedures/r139.py, ``vehicle-assist r139``).

References: brake_assist.md 6 derived reference values (F_ABS ~ 170 N, +-10 %); the friction limit for a_ABS
(a_ABS <= mu_peak*g + resistances, and >= 0.85*mu_peak*g for an ABS holding slip in [0.10, 0.20] around the dry
peak); the corridor [0.5, 0.7]*F_ABS (paper eqs. 2-3); spec S9: the test must fail without HBA.
"""
from __future__ import annotations

import pytest
from typer.testing import CliRunner

from vehicle_assist.cli import app
from vehicle_assist.procedures.r139 import run_r139


@pytest.fixture(scope="module")
def result():
    return run_r139()


def test_reference_values(result) -> None:
    assert result.f_abs_n == pytest.approx(170.0, rel=0.10)
    assert 0.85 * 1.17 * 9.81 <= result.a_abs_mps2 <= 1.17 * 9.81 + 0.4
    assert result.window["pedal_min_n"] >= 0.5 * result.f_abs_n and result.window["pedal_max_n"] <= 0.7 * result.f_abs_n


def test_verdict_and_negative_control(result) -> None:
    assert result.passed
    assert result.window["mean_decel_mps2"] >= 0.85 * result.a_abs_mps2
    assert result.baseline["mean_decel_mps2"] < 0.85 * result.a_abs_mps2  # spec S9: fails without HBA


def test_too_high_rate_threshold_fails_the_test() -> None:
    """Negative control through the calibration: with the rate threshold above what the manufacturer's pedal
    input produces (8000 N/s * 0.597 bar/N = 4776 bar/s), HBA never triggers and the verdict is FAIL."""
    res = run_r139(["vehicle.brake_assist.on_rate_bar_per_s=6000"])
    assert not res.passed
    assert not res.window["hba_activated"]


def test_cli_prints_the_verdict() -> None:
    out = CliRunner().invoke(app, ["r139"])
    assert out.exit_code == 0, out.output
    assert "verdict: PASS" in out.output and "[recollection]" in out.output
