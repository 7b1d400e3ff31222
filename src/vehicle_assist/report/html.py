"""The "reproduce the papers" page: one self-contained HTML file, a section per paper and per study, figures,
negative controls marked "must fail" with their reason, and the provenance of the run.

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
td.why { font-size: 0.85em; color: #444; }
span.must { color: #8e24aa; font-weight: bold; white-space: nowrap; }
section.paper { border-top: 3px solid #555; margin-top: 2em; }
table.prov { width: auto; }
h3 { margin-bottom: 0.2em; }
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


def _pass_cell(passed: object, negative: bool = False) -> str:
    """A negative control that fails its bound is what the spec asks: "fails as required", never a bare PASS
    next to a bound it breaks; one that meets its bound is a FAIL that says it should have failed."""
    if passed is None:
        return '<td class="unknown">n/a</td>'
    if negative:
        return ('<td class="pass">fails as required</td>' if bool(passed)
                else '<td class="fail">FAIL (should fail)</td>')
    return '<td class="pass">PASS</td>' if bool(passed) else '<td class="fail">FAIL</td>'


def _relative_src(figure: Path, page_dir: Path) -> str:
    try:
        rel = os.path.relpath(Path(figure).resolve(), page_dir.resolve())
    except ValueError:  # another drive on Windows: no relative path exists
        return Path(figure).resolve().as_uri()
    return quote(Path(rel).as_posix())


STANDARD_KEYS = set(ENTRY_KEYS) | {"negative_control", "why", "section"}


def _anchor(text: str) -> str:
    return "".join(c if c.isalnum() else "-" for c in text).strip("-").lower() or "x"


def provenance() -> dict[str, str]:
    """Package version, git commit (and whether the tree had changes) if the package runs from a checkout,
    date (UTC), Python and platform."""
    import datetime
    import platform
    import subprocess

    import vehicle_assist

    out = {"package_version": vehicle_assist.__version__,
           "date_utc": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
           "python": platform.python_version(), "platform": platform.platform(terse=True)}
    root = Path(vehicle_assist.__file__).resolve().parent
    try:
        commit = subprocess.run(["git", "rev-parse", "HEAD"], cwd=root, capture_output=True, text=True, timeout=5)
        if commit.returncode == 0:
            dirty = subprocess.run(["git", "status", "--porcelain", "--untracked-files=no"], cwd=root,
                                   capture_output=True, text=True, timeout=5)
            out["git_commit"] = commit.stdout.strip() + (" (with uncommitted changes)" if dirty.stdout.strip() else "")
    except (OSError, subprocess.SubprocessError):
        pass
    out.setdefault("git_commit", "none (not a git checkout)")
    return out


def write_reproduce_page(
    entries: Sequence[dict],
    figures: Sequence[tuple[str, Path]],
    path: str | Path,
    title: str,
    papers: dict[str, str] | None = None,
    scenario_hashes: dict[str, dict[str, str]] | None = None,
    info: dict[str, str] | None = None,
) -> Path:
    """Write the HTML page to ``path`` (atomically) and return it.

    ``entries``: dicts with keys ``paper, scenario, criterion, value, unit, bound, pass`` (``pass`` True when
    the outcome is the expected one, False, or None for "not evaluated"), optionally ``negative_control``
    (the criterion must fail: shown as "must fail" with ``why``), ``why``, ``section`` (a study name: its own
    section; default: the paper's scenario criteria) and any further keys (e.g. requirement robustness),
    which are shown in a "details" column. ``figures``: (caption, image path) pairs; a caption starting with
    "paper NNN" goes to that paper's section. ``papers``: paper -> title. ``scenario_hashes``: scenario ->
    {scenario_hash, parameter_hash}. ``info``: provenance (default :func:`provenance`).
    """
    from vehicle_assist.scenarios.errors import plain

    target = Path(path)

    def esc(text: str) -> str:  # HTML-escaped, control characters shown as visible escapes
        return html.escape(plain(text))

    for entry in entries:
        missing = [k for k in ENTRY_KEYS if k not in entry]
        if missing:
            raise ValueError(f"reproduce-page entry {entry!r} lacks key(s) {missing}")
    n_pass = sum(1 for e in entries if e.get("pass") is not None and bool(e.get("pass")))
    n_fail = sum(1 for e in entries if e.get("pass") is not None and not bool(e.get("pass")))
    n_neg = sum(1 for e in entries if e.get("negative_control"))
    papers = dict(papers or {})
    for e in entries:
        papers.setdefault(str(e["paper"]), "")
    info = dict(info if info is not None else provenance())

    def row(entry: dict) -> str:
        negative = bool(entry.get("negative_control"))
        bound = esc(_format_value(entry["bound"]))
        if negative:
            bound = f'<span class="must">must fail:</span> {bound}'
        extra = {k: v for k, v in entry.items() if k not in STANDARD_KEYS}
        details = "; ".join(f"{esc(str(k))} = {esc(_format_value(v) if not isinstance(v, (list, dict)) else str(v))}"
                            for k, v in extra.items())
        return ("<tr>"
                f"<td>{esc(str(entry['scenario']))}</td>"
                f"<td>{esc(str(entry['criterion']))}</td>"
                f'<td class="num">{esc(_format_value(entry["value"]))}</td>'
                f"<td>{esc(str(entry['unit']))}</td>"
                f'<td class="num">{bound}</td>'
                f"{_pass_cell(entry['pass'], negative)}"
                f'<td class="why">{esc(str(entry.get("why", "")))}</td>'
                + (f'<td class="why">{details}</td>' if details else "<td></td>")
                + "</tr>")

    def table(rows: list[dict]) -> list[str]:
        return ["<table>",
                "<thead><tr><th>scenario</th><th>criterion</th><th>value</th><th>unit</th><th>bound</th>"
                "<th>result</th><th>why (clause)</th><th>details</th></tr></thead>", "<tbody>",
                *(row(e) for e in rows), "</tbody>", "</table>"]

    def figure(caption: str, fig_path) -> str:
        return ("<figure>"
                f'<img src="{esc(_relative_src(Path(fig_path), target.parent))}" alt="{esc(caption)}" loading="lazy">'
                f"<figcaption>{esc(caption)}</figcaption></figure>")

    body: list[str] = []
    toc: list[str] = []
    placed: set[int] = set()
    for paper, paper_title in papers.items():
        mine = [e for e in entries if str(e["paper"]) == paper]
        aid = f"paper-{_anchor(paper)}"
        bad = sum(1 for e in mine if e.get("pass") is not None and not e.get("pass"))
        toc.append(f'<li><a href="#{aid}">paper {esc(paper)}</a> {esc(paper_title)} '
                   f'({len(mine)} criteria, {bad} failed)</li>')
        body.append(f'<section class="paper" id="{aid}"><h2>Paper {esc(paper)}: {esc(paper_title)}</h2>')
        sections: dict[str, list[dict]] = {}
        for e in mine:
            sections.setdefault(str(e.get("section") or "scenario criteria"), []).append(e)
        for name, rows in sections.items():
            body.append(f'<section class="study" id="{aid}-{_anchor(name)}"><h3>{esc(name)}</h3>')
            body.extend(table(rows))
            body.append("</section>")
        figs = [(i, c, p) for i, (c, p) in enumerate(figures) if str(c).startswith(f"paper {paper}")]
        if figs:
            body.append(f"<details class='figures'><summary>{len(figs)} figures of paper {esc(paper)}</summary>")
            body.extend(figure(c, p) for _, c, p in figs)
            body.append("</details>")
            placed.update(i for i, _, _ in figs)
        body.append("</section>")
    rest = [(c, p) for i, (c, p) in enumerate(figures) if i not in placed]
    if rest:
        body.append('<section id="other-figures"><h2>Other figures</h2>')
        body.extend(figure(c, p) for c, p in rest)
        body.append("</section>")
    prov = ["<section id=\"provenance\"><h2>Provenance</h2><table class=\"prov\">",
            *(f"<tr><th>{esc(k)}</th><td>{esc(str(v))}</td></tr>" for k, v in info.items()), "</table>"]
    if scenario_hashes:
        prov += ["<details><summary>scenario and parameter hashes</summary><table class=\"prov\">",
                 "<tr><th>scenario</th><th>scenario hash</th><th>parameter hash</th></tr>",
                 *(f"<tr><td>{esc(n)}</td><td><code>{esc(h.get('scenario_hash', ''))}</code></td>"
                   f"<td><code>{esc(h.get('parameter_hash', ''))}</code></td></tr>" for n, h in scenario_hashes.items()),
                 "</table></details>"]
    prov.append("</section>")
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
            f'<p class="summary">{n_pass} as expected, {n_fail} failed, {len(entries)} criteria in total '
            f"({n_neg} negative controls, which must fail and are shown as \u201cfails as required\u201d). "
            f"vehicle-assist {esc(info.get('package_version', ''))}, commit {esc(info.get('git_commit', ''))}, "
            f"{esc(info.get('date_utc', ''))}.</p>",
            f'<nav><ul class="toc">{"".join(toc)}<li><a href="#provenance">provenance</a></li></ul></nav>',
            *body,
            *prov,
            "</body>",
            "</html>",
            "",
        ]
    )
    return atomic_write_text(target, page)
