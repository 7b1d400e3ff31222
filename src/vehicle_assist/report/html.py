"""The "reproduce the papers" page: one self-contained HTML file with a pass/fail table and figures.

Each entry is one checked criterion of one paper (value, unit, bound, pass); figures are referenced by
paths relative to the page, so the page and its figures can be moved or published together. The page
has inline CSS only (no scripts, no network), and every text taken from an entry is HTML-escaped.
"""
from __future__ import annotations

import html
import math
import numbers
import os
from collections.abc import Sequence
from pathlib import Path
from urllib.parse import quote

from vehicle_assist.io.results import atomic_write_text

__all__ = ["write_reproduce_page", "ENTRY_KEYS"]

ENTRY_KEYS = ("paper", "scenario", "criterion", "value", "unit", "bound", "pass")

_CSS = """
body { font-family: system-ui, -apple-system, "Segoe UI", sans-serif; margin: 2em auto; max-width: 1100px;
       color: #222; line-height: 1.4; padding: 0 1em; }
h1 { font-size: 1.5em; margin-bottom: 0.2em; }
p.summary { color: #555; margin-top: 0; }
table { border-collapse: collapse; width: 100%; margin: 1em 0 2em; font-size: 0.92em; }
th, td { border: 1px solid #ccc; padding: 0.35em 0.6em; text-align: left; vertical-align: top; }
th { background: #f2f2f2; }
td.num { text-align: right; font-variant-numeric: tabular-nums; white-space: nowrap; }
td.pass { background: #2e7d32; color: #fff; font-weight: bold; text-align: center; }
td.fail { background: #c62828; color: #fff; font-weight: bold; text-align: center; }
td.unknown { background: #9e9e9e; color: #fff; text-align: center; }
figure { margin: 1.5em 0; }
figure img { max-width: 100%; border: 1px solid #ddd; }
figcaption { color: #444; font-size: 0.9em; margin-top: 0.3em; }
"""


def _format_value(value: object) -> str:
    if value is None:
        return ""
    if isinstance(value, bool):
        return str(value)
    if isinstance(value, numbers.Real):
        number = float(value)
        if math.isnan(number):
            return "NaN"
        return f"{number:.4g}"
    return str(value)


def _pass_cell(passed: object) -> str:
    if passed is None:
        return '<td class="unknown">n/a</td>'
    return '<td class="pass">PASS</td>' if bool(passed) else '<td class="fail">FAIL</td>'


def _relative_src(figure: Path, page_dir: Path) -> str:
    try:
        rel = os.path.relpath(Path(figure).resolve(), page_dir.resolve())
    except ValueError:  # another drive on Windows: no relative path exists
        return Path(figure).resolve().as_uri()
    return quote(Path(rel).as_posix())


def write_reproduce_page(
    entries: Sequence[dict],
    figures: Sequence[tuple[str, Path]],
    path: str | Path,
    title: str,
) -> Path:
    """Write the HTML page to ``path`` (atomically) and return it.

    ``entries``: dicts with keys ``paper, scenario, criterion, value, unit, bound, pass``
    (``pass`` True/False, or None for "not evaluated"). ``figures``: (caption, image path) pairs; the
    images are linked relative to the page's directory.
    """
    from vehicle_assist.scenarios.errors import plain

    target = Path(path)

    def esc(text: str) -> str:  # HTML-escaped, control characters shown as visible escapes
        return html.escape(plain(text))

    n_pass = sum(1 for e in entries if e.get("pass") is not None and bool(e.get("pass")))
    n_fail = sum(1 for e in entries if e.get("pass") is not None and not bool(e.get("pass")))
    rows = []
    for entry in entries:
        missing = [k for k in ENTRY_KEYS if k not in entry]
        if missing:
            raise ValueError(f"reproduce-page entry {entry!r} lacks key(s) {missing}")
        rows.append(
            "<tr>"
            f"<td>{esc(str(entry['paper']))}</td>"
            f"<td>{esc(str(entry['scenario']))}</td>"
            f"<td>{esc(str(entry['criterion']))}</td>"
            f'<td class="num">{esc(_format_value(entry["value"]))}</td>'
            f"<td>{esc(str(entry['unit']))}</td>"
            f'<td class="num">{esc(_format_value(entry["bound"]))}</td>'
            f"{_pass_cell(entry['pass'])}"
            "</tr>"
        )
    figure_html = [
        "<figure>"
        f'<img src="{esc(_relative_src(Path(fig_path), target.parent))}" alt="{esc(caption)}">'
        f"<figcaption>{esc(caption)}</figcaption>"
        "</figure>"
        for caption, fig_path in figures
    ]
    page = "\n".join(
        [
            "<!DOCTYPE html>",
            '<html lang="en">',
            "<head>",
            '<meta charset="utf-8">',
            '<meta name="viewport" content="width=device-width, initial-scale=1">',
            f"<title>{esc(title)}</title>",
            f"<style>{_CSS}</style>",
            "</head>",
            "<body>",
            f"<h1>{esc(title)}</h1>",
            f'<p class="summary">{n_pass} passed, {n_fail} failed, {len(entries)} criteria in total.</p>',
            "<table>",
            "<thead><tr><th>paper</th><th>scenario</th><th>criterion</th><th>value</th><th>unit</th>"
            "<th>bound</th><th>result</th></tr></thead>",
            "<tbody>",
            *rows,
            "</tbody>",
            "</table>",
            *figure_html,
            "</body>",
            "</html>",
            "",
        ]
    )
    return atomic_write_text(target, page)
