"""The reproduce page in a real headless browser (Debian's chromium, installed by `make browser` when running as
root): it renders, has the expected sections, shows a negative control as "fails as required" and its figure
loads. Reference: the browser's own DOM after layout (--dump-dom) and its screenshot, independent of our HTML
writer. Skips, saying why, when no chromium is installed."""
from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

import vehicle_assist as va
from vehicle_assist.report.html import write_reproduce_page
from vehicle_assist.report.plots import overview_png

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
pytestmark = pytest.mark.skipif(CHROMIUM is None, reason="no chromium on PATH: run 'make browser' as root "
                                "(apt-get install chromium) to enable the headless-browser report test")
FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--disable-dev-shm-usage", "--hide-scrollbars"]


def chromium(tmp_path: Path, *args: str) -> subprocess.CompletedProcess:
    profile = tmp_path / f"profile-{len(list(tmp_path.glob('profile-*')))}"  # a fresh profile each call
    return subprocess.run([CHROMIUM, *FLAGS, f"--user-data-dir={profile}", *args], capture_output=True, text=True,
                          timeout=120)


def png_pixels(path: Path) -> np.ndarray:
    from PIL import Image  # matplotlib's own dependency

    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    with Image.open(path) as image:
        return np.asarray(image.convert("RGB"), dtype=np.int32)


@pytest.fixture(scope="module")
def page(tmp_path_factory) -> Path:
    site = tmp_path_factory.mktemp("site")
    name = "hsa_truck_full_14deg_no_assist_early_release"
    result = va.simulate(va.load_scenario(name, {"run.duration_s": 4.0}))
    figure = overview_png(result.trace, site / "figures" / f"{name}_overview.png", f"paper 000: {name}")
    entries = [{"paper": "000", "scenario": name, "criterion": c.metric, "negative_control": c.expect == "fail",
                "value": c.value, "unit": "m", "bound": c.bound, "pass": c.ok, "why": c.why} for c in result.checks]
    entries.append({"paper": "000", "scenario": "matrix", "criterion": "9.7", "value": 0.1, "unit": "1/s",
                    "bound": "> 0", "pass": True, "why": "hill_start_amt.md 9.7", "section": "study: load adaptation"})
    return write_reproduce_page(entries, [(f"paper 000, {name}: overview", figure)], site / "index.html",
                                "vehicle-assist: paper reproductions", papers={"000": "Heavy AMT truck hill start"},
                                scenario_hashes={name: {k: result.trace.meta[k] for k in ("scenario_hash", "parameter_hash")}})


def test_the_page_renders_with_its_sections(page, tmp_path):
    dom = chromium(tmp_path, "--dump-dom", page.as_uri())
    assert dom.returncode == 0, dom.stderr[-2000:]
    html = dom.stdout
    for needle in ('id="paper-000"', "Paper 000: Heavy AMT truck hill start", "<h3>scenario criteria</h3>",
                   "<h3>study: load adaptation</h3>", 'id="provenance"', "fails as required", "must fail:"):
        assert needle in html, needle
    assert 'class="pass">PASS</td><td class="why">hill_start_amt.md 9.2' not in html


def test_the_screenshot_is_a_rendered_page_not_blank(page, tmp_path):
    shot = tmp_path / "shot.png"
    res = chromium(tmp_path, f"--screenshot={shot}", "--window-size=1200,1600", page.as_uri())
    assert res.returncode == 0 and shot.exists(), res.stderr[-2000:]
    pixels = png_pixels(shot)[..., :3]
    assert pixels.shape[:2] == (1600, 1200)
    dark = (pixels.sum(axis=2) < 200).mean()  # text and table borders
    green = ((pixels[..., 1] > 100) & (pixels[..., 0] < 80) & (pixels[..., 2] < 80)).mean()  # result cells
    assert 0.001 < dark < 0.5, dark
    assert green > 1e-4, green  # the "fails as required" / PASS cells are drawn
