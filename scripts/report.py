#!/usr/bin/python3
"""Validation report: the table of physics checks recorded by the validation cases.

Reads every *.jsonl file of a checks folder (one JSON object per line, written by
validation/support/check_record.cpp; format in scripts/README.md), prints an aligned
pass/fail table with totals, and writes OUT/report.md and OUT/report.html atomically,
with every PNG of OUT/figures embedded (relative links in Markdown, base64 in HTML)
and every OUT/notes/*.md (plain-language findings of the validation scripts) appended.

A section "The paper, figure by figure" judges each checkable statement of the paper at
its scale from the campaign's stored runs (analysis/paper_repro.py,
docs/paper-reproduction.md); the headline that follows it is the reduced-scale check.

This module prepares the data (rows, totals, verdict, headline tables, captions, links,
base64 figures, note blocks) as plain dicts and lists; the layout is in the Jinja2
templates of scripts/templates/ (report.md.j2, report.html.j2 with report.css, and the
headline tables headline.md.j2 / headline.html.j2 they include). A missing or broken
template is an error with exit status 2, naming it.

Usage: /usr/bin/python3 scripts/report.py --checks DIR --out DIR [--tier NAME] [--build-dir DIR]

Exit status: 0 no check failed (passed, not resolved, or contradicted at a reduced
scale: docs/trends.md, "States"); 1 a check failed or no check was found (empty
or missing checks folder); 2 unreadable or malformed input, an unwritable OUT, or a
usage error, or a missing or broken report template. When no report can be made, an
earlier OUT/report.* is removed.

Importable: load_checks, collect_metadata, find_figures, render_terminal,
render_markdown, render_html (and their markdown_context, html_context, render_template,
template_environment), write_atomic, save_figure, main.
"""

from __future__ import annotations

import argparse
import base64
import datetime as _dt
import json
import math
import os
import sys
import traceback
import urllib.parse
from pathlib import Path
from typing import Iterable, Sequence

# Plots are written to files only, never shown: no display needed.
os.environ.setdefault("MPLBACKEND", "Agg")

import jinja2  # noqa: E402
import pandas as pd  # noqa: E402  (after the backend choice, as later plot code needs)

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))  # scripts/, for common
from common.figures import figure_caption, save_figure  # noqa: E402,F401  (part of this module's interface)
from common.fsutil import write_atomic  # noqa: E402
from common.gitinfo import git_commit  # noqa: E402
from common.paths import REPO_ROOT, build_dir as default_build_dir  # noqa: E402
from common import templates  # noqa: E402
from common.templates import md_cell  # noqa: E402,F401  (part of this module's interface)
from analysis import headline, paper_repro  # noqa: E402

#: The report templates (Jinja2): report.md.j2, report.html.j2 and what they include.
TEMPLATES_DIR = templates.TEMPLATES_DIR
MARKDOWN_TEMPLATE = "report.md.j2"
HTML_TEMPLATE = "report.html.j2"
#: Stored results of the larger tiers (scripts/trends --store), shown in every report.
RESULTS_DIR = REPO_ROOT / "validation" / "results"
NO_SWEEP_TEXT = (
    "This run ran no sweep, so it measures none of the paper's trends itself: the default "
    "scripts/validate runs the headline sweeps (400 and 200 polyhedra, about 8 minutes on "
    "2 cores, docs/accuracy-cost.md) unless --no-headline; the quick tier's own sweeps (45 "
    "particles, scripts/validate --sweeps) do not resolve the 6 deg halving or the quadratic "
    "fits (docs/trends.md). The stored results of larger tiers follow, with their date and "
    "engine commit; a not-resolved row says what it would take.")

#: The headline's scale, said where it is shown: its sweeps are smaller than the paper's.
HEADLINE_SCALE_TEXT = (
    "These are reduced-scale checks, not the paper's verdicts: the headline sweeps of "
    "scripts/validate (400 and 200 polyhedra, 3 cycles) and the stored results of the "
    "standard tier (200 polyhedra, 6 cycles, 1 or 2 realizations per point) run the "
    "paper's checks on smaller beds than the paper's 2000 polyhedra, 20 cycles and 5 "
    "realizations. The verdicts at the paper's scale are in \"The paper, figure by figure\".")
#: Where the paper-scale section's sweeps and figures go, inside OUT.
PAPER_DIR = "paper-repro"
PAPER_MISSING_TEXT = "not made for this report (scripts/report.py makes it from validation/results/paper/)."

#: Fields of one JSON line, in the order the writer emits them.
FIELDS = ("case", "check", "measured", "expected", "tolerance", "reason", "passed")
#: Columns of the table, terminal and reports alike (reports add "reason").
TABLE_COLUMNS = ("case", "check", "expected", "measured", "tolerance", "result")
REPORT_NAMES = ("report.md", "report.html")
NON_FINITE = "non-finite"
NOT_RESOLVED = "NOT RESOLVED"
#: The data resolve the opposite of the paper's statement at a reduced scale: counted
#: apart, not a failure (docs/trends.md, "States").
CONTRADICTED = "CONTRADICTED"


class CheckFileError(Exception):
    """A checks folder or file that cannot be read as recorded checks."""


# --------------------------------------------------------------------------- loading


def _text(value) -> str:
    return "" if value is None else str(value)


def _parse_line(line: str, where: str) -> dict:
    try:
        obj = json.loads(line)
    except json.JSONDecodeError as error:
        raise CheckFileError(f"{where}: not a JSON object ({error.msg})") from None
    if not isinstance(obj, dict):
        raise CheckFileError(f"{where}: expected a JSON object, got {type(obj).__name__}")
    missing = [field for field in FIELDS if field not in obj]
    if missing:
        raise CheckFileError(f"{where}: missing field(s) {', '.join(missing)}")
    measured = obj["measured"]
    if measured is not None and (isinstance(measured, bool) or not isinstance(measured, (int, float))):
        raise CheckFileError(f"{where}: 'measured' must be a number or null, got {measured!r}")
    if not isinstance(obj["passed"], bool):
        raise CheckFileError(f"{where}: 'passed' must be true or false, got {obj['passed']!r}")
    if not isinstance(obj.get("resolved", True), bool):
        raise CheckFileError(f"{where}: 'resolved' must be true or false, got {obj['resolved']!r}")
    if not isinstance(obj.get("contradicted", False), bool):
        raise CheckFileError(f"{where}: 'contradicted' must be true or false, got {obj['contradicted']!r}")
    if obj.get("contradicted", False) and (obj["passed"] or not obj.get("resolved", True)):
        raise CheckFileError(f"{where}: a contradicted check must have \"passed\": false and be "
                             "resolved")
    value = math.nan if measured is None else float(measured)
    finite = math.isfinite(value)
    return {
        "case": _text(obj["case"]),
        "check": _text(obj["check"]),
        "expected": _text(obj["expected"]),
        "measured": value,
        "tolerance": _text(obj["tolerance"]),
        "reason": _text(obj["reason"]),
        # A measurement that is not a number never passes, whatever the writer said.
        "passed": bool(obj["passed"]) and finite,
        # Within tolerance, yet too uncertain to show the paper's statement.
        "resolved": bool(obj.get("resolved", True)),
        # The opposite resolved at a reduced scale; a non-finite value stays a failure.
        "contradicted": bool(obj.get("contradicted", False)) and finite,
        "source": where,
    }


def load_checks(checks_dir: str | os.PathLike) -> pd.DataFrame:
    """All checks of every *.jsonl file in checks_dir, sorted by case and check.

    Columns: case, check, expected, measured (float, NaN when not finite), tolerance,
    reason, passed (bool), resolved (bool), contradicted (bool), source ("file:line"). Raises CheckFileError on a missing
    folder or a malformed line (naming the file and line).
    """
    folder = Path(checks_dir)
    if not folder.is_dir():
        raise CheckFileError(f"checks folder not found: {folder}")
    rows = []
    for path in sorted(folder.glob("*.jsonl")):
        try:
            with open(path, encoding="utf-8", errors="replace") as stream:
                for number, line in enumerate(stream, start=1):
                    if line.strip():
                        rows.append(_parse_line(line, f"{path}:{number}"))
        except OSError as error:
            raise CheckFileError(f"cannot read {path}: {error.strerror}") from None
    columns = ["case", "check", "expected", "measured", "tolerance", "reason", "passed", "resolved",
               "contradicted", "source"]
    frame = pd.DataFrame(rows, columns=columns)
    for flag in ("passed", "resolved", "contradicted"):
        frame[flag] = frame[flag].astype(bool)
    frame["measured"] = frame["measured"].astype(float)
    return frame.sort_values(["case", "check"], kind="stable").reset_index(drop=True)


def format_measured(value: float) -> str:
    """Shortest text that reads back to the value; 'non-finite' for NaN/Inf (null)."""
    return repr(float(value)) if math.isfinite(value) else NON_FINITE


def format_short(value: float) -> str:
    """4 significant digits for the reports' tables (full precision stays in the JSON
    lines, the terminal table and the HTML cell's title)."""
    return f"{float(value):.4g}" if math.isfinite(value) else NON_FINITE


def table_rows(checks: pd.DataFrame) -> list[dict]:
    """The checks as display strings: TABLE_COLUMNS plus reason (measured at full
    precision; measured_short with 4 significant digits, for the reports)."""
    return [
        {
            "case": row.case,
            "check": row.check,
            "expected": row.expected,
            "measured": format_measured(row.measured),
            "measured_short": format_short(row.measured),
            "tolerance": row.tolerance,
            "result": result_text(row.passed, row.resolved, row.contradicted),
            "reason": row.reason,
            "area": area_of(row.case),
        }
        for row in checks.itertuples(index=False)
    ]


#: Areas of the summary, by the start of a check's case name (first match wins).
AREAS = (
    ("The paper's trends", ("trends_",)),
    ("Cross-method (LIGGGHTS)", ("liggghts",)),
    ("Hard cases", ("deep_overlap",)),
    ("Polyhedron contact", ("box ", "polyhedra ")),
    ("Analytic cases", ("single particle", "jammed sphere", "free fall", "incline", "sphere column")),
)
OTHER_AREA = "Other checks"


def area_of(case: str) -> str:
    for area, prefixes in AREAS:
        if case.startswith(prefixes):
            return area
    return OTHER_AREA


def area_summary(rows: Sequence[dict]) -> list[dict]:
    """Per area (in AREAS order, then others): passed, failed, not resolved, contradicted,
    total."""
    order = [a for a, _ in AREAS] + [OTHER_AREA]
    out = []
    for area in order:
        mine = [r for r in rows if r["area"] == area]
        if mine:
            out.append({"area": area, "passed": sum(r["result"] == "PASS" for r in mine),
                        "failed": sum(r["result"] == "FAIL" for r in mine),
                        "unresolved": sum(r["result"] == NOT_RESOLVED for r in mine),
                        "contradicted": sum(r["result"] == CONTRADICTED for r in mine), "total": len(mine)})
    return out


def result_text(passed: bool, resolved: bool, contradicted: bool = False) -> str:
    if contradicted:
        return CONTRADICTED
    if not passed:
        return "FAIL"
    return "PASS" if resolved else NOT_RESOLVED


def totals(checks: pd.DataFrame) -> tuple[int, int, int, int]:
    """(passed, failed, not resolved, contradicted): a not-resolved check neither passes
    nor fails; a contradicted one (at a reduced scale) does not pass and is not a failure."""
    contradicted = int(checks["contradicted"].sum())
    failed = int((~checks["passed"]).sum()) - contradicted
    unresolved = int((checks["passed"] & ~checks["resolved"]).sum())
    return len(checks) - failed - unresolved - contradicted, failed, unresolved, contradicted


# --------------------------------------------------------------------------- metadata


def _cmake_cache(build_dir: Path) -> dict[str, str]:
    values = {}
    try:
        with open(build_dir / "CMakeCache.txt", encoding="utf-8", errors="replace") as stream:
            for line in stream:
                if line.startswith(("//", "#")) or "=" not in line or ":" not in line.split("=", 1)[0]:
                    continue
                key_type, value = line.rstrip("\n").split("=", 1)
                values[key_type.split(":", 1)[0]] = value
    except OSError:
        pass
    return values


def collect_metadata(build_dir: str | os.PathLike | None = None, tier: str | None = None,
                     checks_dir: str | os.PathLike | None = None) -> dict[str, str]:
    """Report header: date, tier, git commit and engine version where available."""
    meta = {"Date": _dt.datetime.now(_dt.timezone.utc).strftime("%Y-%m-%d %H:%M:%S UTC")}
    if tier:
        meta["Tier"] = tier
    commit, dirty = git_commit(REPO_ROOT, short=12)
    if commit:
        meta["Git commit"] = commit + (" (with uncommitted changes)" if dirty else "")
    if build_dir is not None:
        cache = _cmake_cache(Path(build_dir))
        version = cache.get("CMAKE_PROJECT_VERSION")
        if version:
            build_type = cache.get("CMAKE_BUILD_TYPE")
            meta["Engine version"] = version + (f" ({build_type} build)" if build_type else "")
    if checks_dir is not None:
        meta["Checks folder"] = str(checks_dir)
    return meta


# --------------------------------------------------------------------------- figures


def find_figures(out_dir: str | os.PathLike) -> list[Path]:
    """Every PNG in OUT/figures, sorted by name (a missing folder gives none)."""
    folder = Path(out_dir) / "figures"
    if not folder.is_dir():
        return []
    return sorted(p for p in folder.iterdir() if p.suffix.lower() == ".png" and p.is_file())


# --------------------------------------------------------------------------- notes


def find_notes(out_dir: str | os.PathLike) -> list[Path]:
    """Every OUT/notes/*.md, sorted by name: plain-language findings that validation
    scripts write next to their checks (e.g. where NSCD and DEM differ and why)."""
    folder = Path(out_dir) / "notes"
    if not folder.is_dir():
        return []
    return sorted(p for p in folder.iterdir() if p.suffix.lower() == ".md" and p.is_file())


def _note_blocks(text: str) -> list[list[str]]:
    """Paragraph blocks of a note (separated by blank lines)."""
    blocks, block = [], []
    for line in text.splitlines():
        if line.strip():
            block.append(line.rstrip())
        elif block:
            blocks.append(block)
            block = []
    if block:
        blocks.append(block)
    return blocks


def parse_note(text: str) -> list[dict]:
    """The small Markdown subset of a note as blocks for the HTML template: '#' headings
    ({"kind": "heading", "text"}, shown as h3), '|' tables ({"kind": "table", "rows"},
    the first row the header), '- ' lists ({"kind": "list", "entries"}) and paragraphs
    ({"kind": "paragraph", "text"}). Plain text: the template escapes it."""
    out = []
    for block in _note_blocks(text):
        if block[0].startswith("#"):
            out.append({"kind": "heading", "text": block[0].lstrip("#").strip()})
            block = block[1:]
            if not block:
                continue
        if all(line.startswith("|") for line in block):
            rows = [[c.strip() for c in line.strip("|").split("|")] for line in block
                    if not set(line.replace("|", "").strip()) <= set("-: ")]
            out.append({"kind": "table", "rows": rows})
        elif block[0].startswith("- "):
            entries, entry = [], []
            for line in block:
                if line.startswith("- ") and entry:
                    entries.append(" ".join(entry))
                    entry = []
                entry.append(line[2:] if line.startswith("- ") else line.strip())
            entries.append(" ".join(entry))
            out.append({"kind": "list", "entries": entries})
        else:
            out.append({"kind": "paragraph", "text": " ".join(line.strip() for line in block)})
    return out


# --------------------------------------------------------------------------- rendering


def render_terminal(checks: pd.DataFrame, color: bool = False) -> str:
    """Aligned table, the failed checks with their reasons, and the totals line."""
    rows = table_rows(checks)
    widths = {c: max([len(c)] + [len(r[c]) for r in rows]) for c in TABLE_COLUMNS}

    def line(values: dict, paint: bool) -> str:
        cells = [values[c].ljust(widths[c]) for c in TABLE_COLUMNS]
        if paint:
            code = {"PASS": "32", NOT_RESOLVED: "33", CONTRADICTED: "35;1"}.get(values["result"], "31;1")
            cells[-1] = f"\x1b[{code}m{cells[-1]}\x1b[0m"
        return " | ".join(cells).rstrip()

    out = [line({c: c for c in TABLE_COLUMNS}, False),
           "-+-".join("-" * widths[c] for c in TABLE_COLUMNS)]
    out += [line(r, color) for r in rows]
    failed_rows = [r for r in rows if r["result"] == "FAIL"]
    if failed_rows:
        out.append("")
        out.append("Failed checks:")
        for r in failed_rows:
            why = f" ({r['reason']})" if r["reason"] else ""
            out.append(f"  {r['case']} / {r['check']}: measured {r['measured']}, "
                       f"expected {r['expected']}, tolerance {r['tolerance']}{why}")
    contradicted_rows = [r for r in rows if r["result"] == CONTRADICTED]
    if contradicted_rows:
        out.append("")
        out.append("Contradicted at a reduced scale (the data resolve the opposite of the paper's "
                   "statement; not a failure):")
        for r in contradicted_rows:
            out.append(f"  {r['case']} / {r['check']}: measured {r['measured']}; {r['reason']}")
    unresolved_rows = [r for r in rows if r["result"] == NOT_RESOLVED]
    if unresolved_rows:
        out.append("")
        out.append("Not resolved (within tolerance, but not showing the paper's statement):")
        for r in unresolved_rows:
            out.append(f"  {r['case']} / {r['check']}: measured {r['measured']}; {r['reason']}")
    out.append("")
    out.append(f"checks: {_counts_text(*totals(checks))}")
    return "\n".join(out) + "\n"


def _md_link(path: str) -> str:
    return urllib.parse.quote(path, safe="/._-")


def _counts_text(passed: int, failed: int, unresolved: int, contradicted: int = 0) -> str:
    return (f"{passed} passed, {failed} failed" + (f", {unresolved} not resolved" if unresolved else "")
            + (f", {contradicted} contradicted at reduced scale" if contradicted else ""))


def _verdict(passed: int, failed: int, unresolved: int = 0, contradicted: int = 0) -> str:
    total = passed + failed + unresolved + contradicted
    if failed:
        return f"FAILED: {failed} of {total} checks failed"
    if contradicted:
        return (f"NO FAILURE, {contradicted} of {total} checks CONTRADICTED at a reduced scale: the "
                f"data resolve the opposite of the paper's statement there"
                + (f"; {unresolved} not resolved" if unresolved else ""))
    if unresolved:
        return (f"PASSED with {unresolved} of {total} checks not resolved: no check failed, but "
                f"{unresolved} cannot show the paper's statement at this scale")
    return f"PASSED: all {total} checks passed"


def accuracy_figures(results_dir: Path) -> list[Path]:
    """Stored accuracy-cost figures (results_dir/accuracy/*.png, docs/accuracy-cost.md):
    the overview (pareto.png, every knob in one figure) first, then the studies by name."""
    folder = Path(results_dir) / "accuracy"
    if not folder.is_dir():
        return []
    return sorted(folder.glob("*.png"), key=lambda f: (f.stem != "pareto", f.name))


ACCURACY_TEXT = ("What each accuracy knob changes in the observables against what it costs, "
                 "as ensembles over seeds (scripts/compare-settings); the study, its commands "
                 "and the tier defaults chosen from it: docs/accuracy-cost.md.")
NO_STORED_TEXT = "No stored result (validation/results/ is empty)."


def headline_sources(current: dict | None, stored: Sequence[dict]) -> list[tuple[str, dict]]:
    return ([("This run", current)] if current else []) + [("Stored", r) for r in stored]


def template_environment(folder: str | os.PathLike | None = None) -> jinja2.Environment:
    """The Jinja2 environment of the report templates (default TEMPLATES_DIR), that of
    common/templates.py: HTML templates (*.html.j2) autoescaped, the Markdown ones not;
    an undefined variable is an error; filter md_cell."""
    return templates.environment(folder if folder is not None else TEMPLATES_DIR)


def render_template(name: str, context: dict, folder: str | os.PathLike | None = None) -> str:
    """One template of the report with the context. Raises jinja2.TemplateNotFound (an
    OSError) naming a missing template, jinja2.UndefinedError for a missing variable."""
    return template_environment(folder).get_template(name).render(context)


def _template_frame(error: BaseException) -> str:
    """'FILE, line N' of the innermost template frame of a render error (Jinja2 puts
    the template's own lines into the traceback), else the templates folder."""
    frames = [f for f in traceback.extract_tb(error.__traceback__) if f.filename.endswith(".j2")]
    return f"{frames[-1].filename}, line {frames[-1].lineno}" if frames else str(TEMPLATES_DIR)


def _context(checks: pd.DataFrame, meta: dict[str, str] | None, current: dict | None,
             stored: Sequence[dict], paper: dict | None) -> dict:
    """What both reports show, as plain values (paper: the section of
    analysis/paper_repro.py with its figures made ready by the caller, or None)."""
    counts = totals(checks)
    rows = table_rows(checks)
    return {
        "meta": dict(meta or {}),
        "counts_text": _counts_text(*counts),
        "total": sum(counts),
        "failed": counts[1],
        "verdict": _verdict(*counts),
        "verdict_class": "fail" if counts[1] else ("contradicted" if counts[3] else "pass"),
        "ran_sweep": bool(current),
        "no_sweep_text": NO_SWEEP_TEXT,
        "headline_scale_text": HEADLINE_SCALE_TEXT,
        "paper": paper,
        "paper_missing": PAPER_MISSING_TEXT,
        "sections": headline.sections(headline_sources(current, stored)),
        "no_stored_text": NO_STORED_TEXT,
        "accuracy_text": ACCURACY_TEXT,
        "columns": list(TABLE_COLUMNS) + ["reason"],
        "rows": rows,
        "areas": area_summary(rows),
    }


def _read_note(path: Path) -> str:
    return path.read_text(encoding="utf-8", errors="replace")


def markdown_context(checks: pd.DataFrame, meta: dict[str, str] | None = None,
                     figures: Iterable[Path] = (), out_dir: str | os.PathLike = ".",
                     notes: Iterable[Path] = (), current: dict | None = None,
                     stored: Sequence[dict] = (), accuracy: Sequence[Path] = (),
                     paper: dict | None = None) -> dict:
    """The values of MARKDOWN_TEMPLATE; figures linked relative to out_dir (paper:
    paper_repro.build()'s values)."""

    def linked(figure: Path) -> dict:
        link = os.path.relpath(figure, out_dir).replace(os.sep, "/")
        return {"caption": figure_caption(figure), "link": _md_link(link)}

    section = paper_repro.with_figures(paper, lambda f: {"link": linked(f)["link"]}) if paper else None
    return {**_context(checks, meta, current, stored, section),
            "accuracy": [linked(f) for f in accuracy],
            "figures": [linked(f) for f in figures],
            "notes": [_read_note(n).strip() for n in notes]}


def html_context(checks: pd.DataFrame, meta: dict[str, str] | None = None,
                 figures: Iterable[Path] = (), notes: Iterable[Path] = (),
                 current: dict | None = None, stored: Sequence[dict] = (),
                 accuracy: Sequence[Path] = (), paper: dict | None = None) -> dict:
    """The values of HTML_TEMPLATE; figures as base64 (paper: paper_repro.build()'s
    values)."""

    def embedded(figure: Path) -> dict:
        return {"caption": figure_caption(figure),
                "data": base64.b64encode(figure.read_bytes()).decode("ascii")}

    section = paper_repro.with_figures(paper, lambda f: {"data": embedded(f)["data"]}) if paper else None
    return {**_context(checks, meta, current, stored, section),
            "accuracy": [embedded(f) for f in accuracy],
            "figures": [embedded(f) for f in figures],
            "notes": [parse_note(_read_note(n)) for n in notes]}


def render_markdown(checks: pd.DataFrame, meta: dict[str, str] | None = None,
                    figures: Iterable[Path] = (), out_dir: str | os.PathLike = ".",
                    notes: Iterable[Path] = (), current: dict | None = None,
                    stored: Sequence[dict] = (), accuracy: Sequence[Path] = (),
                    paper: dict | None = None) -> str:
    """Markdown report; figures are linked relative to out_dir (where report.md goes)."""
    return render_template(MARKDOWN_TEMPLATE, markdown_context(
        checks, meta, figures, out_dir, notes, current, stored, accuracy, paper))


def render_html(checks: pd.DataFrame, meta: dict[str, str] | None = None,
                figures: Iterable[Path] = (), notes: Iterable[Path] = (),
                current: dict | None = None, stored: Sequence[dict] = (),
                accuracy: Sequence[Path] = (), paper: dict | None = None) -> str:
    """Self-contained HTML report (inline CSS, figures embedded as base64)."""
    return render_template(HTML_TEMPLATE, html_context(
        checks, meta, figures, notes, current, stored, accuracy, paper))


# --------------------------------------------------------------------------- output


def _remove_stale_reports(out_dir: Path) -> list[Path]:
    removed = []
    for name in REPORT_NAMES:
        path = out_dir / name
        if path.exists():
            path.unlink()
            removed.append(path)
    return removed


def _parse_args(argv: Sequence[str] | None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(
        prog="report.py",
        description="Prints the table of recorded validation checks and writes "
                    "OUT/report.md and OUT/report.html.",
        epilog="Exit status: 0 no check failed (passed, not resolved or contradicted at a reduced "
               "scale); 1 a check failed or none was found; 2 malformed input, unwritable OUT or "
               "usage error.")
    parser.add_argument("--checks", required=True, metavar="DIR",
                        help="folder of *.jsonl check files (RATCHET_CHECKS_DIR of the run)")
    parser.add_argument("--out", required=True, metavar="DIR",
                        help="folder for report.md and report.html; PNGs in DIR/figures are embedded")
    parser.add_argument("--tier", metavar="NAME", help="validation tier, shown in the report header")
    parser.add_argument("--results", metavar="DIR", default=str(RESULTS_DIR),
                        help="stored headline results of larger tiers (default: validation/results); "
                             "OUT/trends.json, when a sweep of this run wrote it, comes first")
    parser.add_argument("--paper-plan", metavar="FILE", default=str(paper_repro.DEFAULT_PLAN),
                        help="the campaign plan of the paper's study (default: "
                             "validation/campaigns/paper.json), for 'The paper, figure by figure'")
    parser.add_argument("--paper-results", metavar="DIR",
                        help="its stored runs (default: RESULTS/<plan name>, validation/results/paper); "
                             "the section's sweeps and figures go to OUT/" + PAPER_DIR)
    parser.add_argument("--build-dir", metavar="DIR",
                        default=None,
                        help="build folder to read the engine version from, relative to the "
                             "repository root (default: $RATCHET_BUILD_DIR or build)")
    color = parser.add_mutually_exclusive_group()
    color.add_argument("--color", dest="color", action="store_true", default=None,
                       help="colour PASS/FAIL in the terminal table")
    color.add_argument("--no-color", dest="color", action="store_false",
                       help="never colour the terminal table")
    return parser.parse_args(argv)


def main(argv: Sequence[str] | None = None) -> int:
    args = _parse_args(argv)
    out_dir = Path(args.out)

    def no_report(message: str, status: int) -> int:
        print(f"report: error: {message}", file=sys.stderr)
        # An earlier report left in OUT would pass for the result of this run.
        for path in _remove_stale_reports(out_dir) if out_dir.is_dir() else []:
            print(f"report: removed the earlier report {path}, which does not describe this run",
                  file=sys.stderr)
        print("report: no report written", file=sys.stderr)
        return status

    if not Path(args.checks).is_dir():
        return no_report(f"no checks found: the checks folder {args.checks} does not exist", 1)
    try:
        checks = load_checks(args.checks)
    except CheckFileError as error:
        return no_report(str(error), 2)
    if checks.empty:
        return no_report(f"no checks found in {args.checks} (no *.jsonl file, or only empty "
                         "ones): did the validation tests run with RATCHET_CHECKS_DIR set to it?", 1)

    color = args.color
    if color is None:
        color = sys.stdout.isatty() and "NO_COLOR" not in os.environ
    build_dir = Path(args.build_dir) if args.build_dir else default_build_dir()
    if not build_dir.is_absolute():
        build_dir = REPO_ROOT / build_dir
    meta = collect_metadata(build_dir, args.tier, args.checks)
    figures = find_figures(out_dir)
    notes = find_notes(out_dir)
    try:
        stored = headline.load_records(Path(args.results))
        current = None
        if (out_dir / "trends.json").is_file():
            document = json.loads((out_dir / "trends.json").read_text(encoding="utf-8"))
            current = headline.from_trends(document, engine_commit=meta.get("Git commit", "unknown"),
                                           command="this run", scale=document.get("tier_scale", ""))
    except headline.RecordError as problem:
        return no_report(str(problem), 2)
    except (OSError, ValueError, KeyError) as problem:
        return no_report(f"cannot read {out_dir / 'trends.json'}: {problem}", 2)

    accuracy = accuracy_figures(Path(args.results))
    plan = Path(args.paper_plan)
    paper_results = Path(args.paper_results) if args.paper_results else Path(args.results) / plan.stem
    try:
        paper = paper_repro.build(plan, paper_results, out_dir / PAPER_DIR,
                                  headline_sources(current, stored))
    except paper_repro.PaperReproError as problem:
        return no_report(str(problem), 2)
    except OSError as error:
        return no_report(f"cannot write the paper-scale section in {out_dir / PAPER_DIR}: {error}", 2)
    try:  # both rendered before either is written
        markdown = render_markdown(checks, meta, figures, out_dir, notes, current, stored, accuracy,
                                   paper)
        page = render_html(checks, meta, figures, notes, current, stored, accuracy, paper)
    except jinja2.TemplateNotFound as missing:  # an OSError: before the OSError below
        return no_report(f"report template not found: {Path(TEMPLATES_DIR) / missing.name}", 2)
    except jinja2.TemplateSyntaxError as problem:
        return no_report(f"report template {problem.filename or problem.name}, line {problem.lineno}: "
                         f"{problem.message}", 2)
    except jinja2.TemplateError as problem:
        return no_report(f"report template {_template_frame(problem)}: {problem}", 2)
    except OSError as error:
        return no_report(f"cannot read a figure or note of {out_dir}: {error}", 2)
    try:
        out_dir.mkdir(parents=True, exist_ok=True)
        write_atomic(out_dir / "report.md", markdown)
        write_atomic(out_dir / "report.html", page)
    except OSError as error:
        return no_report(f"cannot write the report in {out_dir}: {error}", 2)

    table = render_terminal(checks, color=color)
    body, _, last = table.rstrip("\n").rpartition("\n")
    sys.stdout.write(body + "\n")
    print(f"report: wrote {out_dir / 'report.md'} and {out_dir / 'report.html'}")
    print(last)
    _, failed, _, _ = totals(checks)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
