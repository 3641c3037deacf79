#!/usr/bin/python3
"""Validation report: the table of physics checks recorded by the validation cases.

Reads every *.jsonl file of a checks folder (one JSON object per line, written by
validation/support/check_record.cpp; format in scripts/README.md), prints an aligned
pass/fail table with totals, and writes OUT/report.md and OUT/report.html atomically,
with every PNG of OUT/figures embedded (relative links in Markdown, base64 in HTML)
and every OUT/notes/*.md (plain-language findings of the validation scripts) appended.

Usage: /usr/bin/python3 scripts/report.py --checks DIR --out DIR [--tier NAME] [--build-dir DIR]

Exit status: 0 all checks passed; 1 a check failed or no check was found (empty
or missing checks folder); 2 unreadable or malformed input, an unwritable OUT, or a
usage error. When no report can be made, an earlier OUT/report.* is removed.

Importable: load_checks, collect_metadata, find_figures, render_terminal,
render_markdown, render_html, write_atomic, save_figure, main.
"""

from __future__ import annotations

import argparse
import base64
import datetime as _dt
import html
import json
import math
import os
import sys
import urllib.parse
from pathlib import Path
from typing import Iterable, Sequence

# Plots are written to files only, never shown: no display needed.
os.environ.setdefault("MPLBACKEND", "Agg")

import pandas as pd  # noqa: E402  (after the backend choice, as later plot code needs)

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))  # scripts/, for common
from common.figures import figure_caption, save_figure  # noqa: E402,F401  (part of this module's interface)
from common.fsutil import write_atomic  # noqa: E402
from common.gitinfo import git_commit  # noqa: E402
from common.paths import REPO_ROOT, build_dir as default_build_dir  # noqa: E402
from analysis import headline  # noqa: E402

#: Stored results of the larger tiers (scripts/trends --store), shown in every report.
RESULTS_DIR = REPO_ROOT / "validation" / "results"
NO_SWEEP_TEXT = (
    "This run ran no sweep, so it measures none of the paper's trends itself: the quick "
    "tier's sweeps (45 particles, one realization per point, `scripts/validate --sweeps`) "
    "do not resolve the 6 deg halving or the quadratic fits (docs/trends.md). The stored "
    "results of larger tiers follow, with their date and engine commit; a not-resolved row "
    "says what it would take.")

#: Fields of one JSON line, in the order the writer emits them.
FIELDS = ("case", "check", "measured", "expected", "tolerance", "reason", "passed")
#: Columns of the table, terminal and reports alike (reports add "reason").
TABLE_COLUMNS = ("case", "check", "expected", "measured", "tolerance", "result")
REPORT_NAMES = ("report.md", "report.html")
NON_FINITE = "non-finite"
NOT_RESOLVED = "NOT RESOLVED"


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
        "source": where,
    }


def load_checks(checks_dir: str | os.PathLike) -> pd.DataFrame:
    """All checks of every *.jsonl file in checks_dir, sorted by case and check.

    Columns: case, check, expected, measured (float, NaN when not finite), tolerance,
    reason, passed (bool), source ("file:line"). Raises CheckFileError on a missing
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
               "source"]
    frame = pd.DataFrame(rows, columns=columns)
    frame["passed"] = frame["passed"].astype(bool)
    frame["resolved"] = frame["resolved"].astype(bool)
    frame["measured"] = frame["measured"].astype(float)
    return frame.sort_values(["case", "check"], kind="stable").reset_index(drop=True)


def format_measured(value: float) -> str:
    """Shortest text that reads back to the value; 'non-finite' for NaN/Inf (null)."""
    return repr(float(value)) if math.isfinite(value) else NON_FINITE


def table_rows(checks: pd.DataFrame) -> list[dict]:
    """The checks as display strings: TABLE_COLUMNS plus reason."""
    return [
        {
            "case": row.case,
            "check": row.check,
            "expected": row.expected,
            "measured": format_measured(row.measured),
            "tolerance": row.tolerance,
            "result": result_text(row.passed, row.resolved),
            "reason": row.reason,
        }
        for row in checks.itertuples(index=False)
    ]


def result_text(passed: bool, resolved: bool) -> str:
    if not passed:
        return "FAIL"
    return "PASS" if resolved else NOT_RESOLVED


def totals(checks: pd.DataFrame) -> tuple[int, int, int]:
    """(passed, failed, not resolved): a not-resolved check neither passes nor fails."""
    failed = int((~checks["passed"]).sum())
    unresolved = int((checks["passed"] & ~checks["resolved"]).sum())
    return len(checks) - failed - unresolved, failed, unresolved


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


def note_html(text: str) -> str:
    """The small Markdown subset of a note as HTML: '#' headings (as h3), '- ' lists,
    '|' tables and paragraphs; all text escaped."""
    esc = html.escape
    out = []
    for block in _note_blocks(text):
        if block[0].startswith("#"):
            out.append(f"<h3>{esc(block[0].lstrip('#').strip())}</h3>")
            block = block[1:]
            if not block:
                continue
        if all(line.startswith("|") for line in block):
            rows = [[c.strip() for c in line.strip("|").split("|")] for line in block
                    if not set(line.replace("|", "").strip()) <= set("-: ")]
            out.append("<table>" + "".join(
                "<tr>" + "".join(f"<{'th' if i == 0 else 'td'}>{esc(c)}</{'th' if i == 0 else 'td'}>" for c in row)
                + "</tr>" for i, row in enumerate(rows)) + "</table>")
        elif block[0].startswith("- "):
            items, item = [], []
            for line in block:
                if line.startswith("- ") and item:
                    items.append(" ".join(item))
                    item = []
                item.append(line[2:] if line.startswith("- ") else line.strip())
            items.append(" ".join(item))
            out.append("<ul>" + "".join(f"<li>{esc(i)}</li>" for i in items) + "</ul>")
        else:
            out.append(f"<p>{esc(' '.join(line.strip() for line in block))}</p>")
    return "\n".join(out)


# --------------------------------------------------------------------------- rendering


def render_terminal(checks: pd.DataFrame, color: bool = False) -> str:
    """Aligned table, the failed checks with their reasons, and the totals line."""
    rows = table_rows(checks)
    widths = {c: max([len(c)] + [len(r[c]) for r in rows]) for c in TABLE_COLUMNS}

    def line(values: dict, paint: bool) -> str:
        cells = [values[c].ljust(widths[c]) for c in TABLE_COLUMNS]
        if paint:
            code = {"PASS": "32", NOT_RESOLVED: "33"}.get(values["result"], "31;1")
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
    unresolved_rows = [r for r in rows if r["result"] == NOT_RESOLVED]
    if unresolved_rows:
        out.append("")
        out.append("Not resolved (within tolerance, but not showing the paper's statement):")
        for r in unresolved_rows:
            out.append(f"  {r['case']} / {r['check']}: measured {r['measured']}; {r['reason']}")
    out.append("")
    out.append(f"checks: {_counts_text(*totals(checks))}")
    return "\n".join(out) + "\n"


def _md_cell(text: str) -> str:
    return " ".join(text.split()).replace("\\", "\\\\").replace("|", "\\|") or " "


def _md_link(path: str) -> str:
    return urllib.parse.quote(path, safe="/._-")


def _counts_text(passed: int, failed: int, unresolved: int) -> str:
    return f"{passed} passed, {failed} failed" + (f", {unresolved} not resolved" if unresolved else "")


def _verdict(passed: int, failed: int, unresolved: int = 0) -> str:
    total = passed + failed + unresolved
    if failed:
        return f"FAILED: {failed} of {total} checks failed"
    if unresolved:
        return (f"PASSED with {unresolved} of {total} checks not resolved: no check failed, but "
                f"{unresolved} cannot show the paper's statement at this scale")
    return f"PASSED: all {total} checks passed"


def accuracy_figures(results_dir: Path) -> list[Path]:
    """Stored accuracy-cost figures (results_dir/accuracy/*.png, docs/accuracy-cost.md)."""
    folder = Path(results_dir) / "accuracy"
    return sorted(folder.glob("*.png")) if folder.is_dir() else []


ACCURACY_TEXT = ("What each accuracy knob changes in the observables against what it costs, "
                 "as ensembles over seeds (scripts/compare-settings); the study, its commands "
                 "and the tier defaults chosen from it: docs/accuracy-cost.md.")


def headline_sources(current: dict | None, stored: Sequence[dict]) -> list[tuple[str, dict]]:
    return ([("This run", current)] if current else []) + [("Stored", r) for r in stored]


def render_markdown(checks: pd.DataFrame, meta: dict[str, str] | None = None,
                    figures: Iterable[Path] = (), out_dir: str | os.PathLike = ".",
                    notes: Iterable[Path] = (), current: dict | None = None,
                    stored: Sequence[dict] = (), accuracy: Sequence[Path] = ()) -> str:
    """Markdown report; figures are linked relative to out_dir (where report.md goes)."""
    counts = totals(checks)
    columns = list(TABLE_COLUMNS) + ["reason"]
    out = ["# Validation report", ""]
    for key, value in (meta or {}).items():
        out.append(f"- {key}: {value}")
    out.append(f"- Checks: {_counts_text(*counts)}, {sum(counts)} total")
    out += ["", f"**{_verdict(*counts)}**", "", "## The paper's headline trends"]
    if not current:
        out += ["", NO_SWEEP_TEXT]
    out += headline.render_markdown(headline_sources(current, stored))
    if not current and not stored:
        out += ["", "No stored result (validation/results/ is empty)."]
    if accuracy:
        out += ["", "## What accuracy costs", "", ACCURACY_TEXT]
        for figure in accuracy:
            link = os.path.relpath(figure, out_dir).replace(os.sep, "/")
            caption = figure_caption(figure)
            out += ["", f"![{_md_cell(caption)}]({_md_link(link)})", "", caption]
    out += ["", "## Checks of this run", "",
            "| " + " | ".join(columns) + " |",
            "|" + "|".join("---" for _ in columns) + "|"]
    for r in table_rows(checks):
        cells = dict(r)
        cells["result"] = {"PASS": "PASS", NOT_RESOLVED: f"*{NOT_RESOLVED}*"}.get(r["result"], "**FAIL**")
        out.append("| " + " | ".join(_md_cell(cells[c]) for c in columns) + " |")
    figures = list(figures)
    if figures:
        out += ["", "## Figures"]
        for figure in figures:
            link = os.path.relpath(figure, out_dir).replace(os.sep, "/")
            caption = figure_caption(figure)
            out += ["", f"### {caption}", "", f"![{_md_cell(caption)}]({_md_link(link)})"]
    notes = list(notes)
    if notes:
        out += ["", "## Notes"]
        for note in notes:
            out += ["", note.read_text(encoding="utf-8", errors="replace").strip()]
    return "\n".join(out) + "\n"


_CSS = """
body { font-family: system-ui, sans-serif; margin: 2em; color: #222; }
table { border-collapse: collapse; font-size: 0.92em; }
th, td { border: 1px solid #ccc; padding: 0.3em 0.6em; text-align: left; vertical-align: top; }
th { background: #eee; }
td.num { font-family: monospace; }
tr.pass td.result { background: #d8f0d8; color: #185c18; font-weight: bold; }
tr.fail td { background: #fbe3e3; }
tr.unresolved td.result { background: #fff1c2; color: #6b5200; font-weight: bold; }
tr.fail td.result { background: #f3b7b7; color: #8a1010; font-weight: bold; }
.verdict { padding: 0.5em 1em; display: inline-block; font-weight: bold; border-radius: 4px; }
.verdict.pass { background: #d8f0d8; color: #185c18; }
.verdict.fail { background: #f3b7b7; color: #8a1010; }
figure { margin: 1.5em 0; }
figure img { max-width: 100%; border: 1px solid #ddd; }
"""


def render_html(checks: pd.DataFrame, meta: dict[str, str] | None = None,
                figures: Iterable[Path] = (), notes: Iterable[Path] = (),
                current: dict | None = None, stored: Sequence[dict] = (),
                accuracy: Sequence[Path] = ()) -> str:
    """Self-contained HTML report (inline CSS, figures embedded as base64)."""
    esc = html.escape
    counts = totals(checks)
    passed, failed, unresolved = counts
    columns = list(TABLE_COLUMNS) + ["reason"]
    out = ["<!DOCTYPE html>", '<html lang="en">', "<head>", '<meta charset="utf-8">',
           "<title>Validation report</title>", f"<style>{_CSS}</style>", "</head>", "<body>",
           "<h1>Validation report</h1>", "<ul>"]
    for key, value in (meta or {}).items():
        out.append(f"<li>{esc(key)}: {esc(value)}</li>")
    out.append(f"<li>Checks: {esc(_counts_text(*counts))}, {sum(counts)} total</li>")
    out.append("</ul>")
    verdict_class = "fail" if failed else "pass"
    out.append(f'<p class="verdict {verdict_class}">{esc(_verdict(*counts))}</p>')
    out.append("<h2>The paper's headline trends</h2>")
    if not current:
        out.append(f"<p>{esc(NO_SWEEP_TEXT)}</p>")
    out += headline.render_html(headline_sources(current, stored))
    if accuracy:
        out += ["<h2>What accuracy costs</h2>", f"<p>{esc(ACCURACY_TEXT)}</p>"]
        for figure in accuracy:
            data = base64.b64encode(figure.read_bytes()).decode("ascii")
            caption = esc(figure_caption(figure))
            out.append(f'<figure><img src="data:image/png;base64,{data}" alt="{caption}">'
                       f"<figcaption>{caption}</figcaption></figure>")
    out.append("<h2>Checks of this run</h2>")
    out.append("<table>")
    out.append("<thead><tr>" + "".join(f"<th>{esc(c)}</th>" for c in columns) + "</tr></thead>")
    out.append("<tbody>")
    for r in table_rows(checks):
        row_class = {"PASS": "pass", NOT_RESOLVED: "unresolved"}.get(r["result"], "fail")
        cells = []
        for c in columns:
            css = {"measured": "num", "expected": "num", "tolerance": "num", "result": "result"}.get(c)
            attr = f' class="{css}"' if css else ""
            cells.append(f"<td{attr}>{esc(r[c])}</td>")
        out.append(f'<tr class="{row_class}">' + "".join(cells) + "</tr>")
    out += ["</tbody>", "</table>"]
    figures = list(figures)
    if figures:
        out.append("<h2>Figures</h2>")
        for figure in figures:
            data = base64.b64encode(figure.read_bytes()).decode("ascii")
            caption = esc(figure_caption(figure))
            out.append(f'<figure><img src="data:image/png;base64,{data}" alt="{caption}">'
                       f"<figcaption>{caption}</figcaption></figure>")
    notes = list(notes)
    if notes:
        out.append("<h2>Notes</h2>")
        for note in notes:
            out.append(note_html(note.read_text(encoding="utf-8", errors="replace")))
    out += ["</body>", "</html>"]
    return "\n".join(out) + "\n"


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
        epilog="Exit status: 0 all checks passed; 1 a check failed or none was found; "
               "2 malformed input, unwritable OUT or usage error.")
    parser.add_argument("--checks", required=True, metavar="DIR",
                        help="folder of *.jsonl check files (RATCHET_CHECKS_DIR of the run)")
    parser.add_argument("--out", required=True, metavar="DIR",
                        help="folder for report.md and report.html; PNGs in DIR/figures are embedded")
    parser.add_argument("--tier", metavar="NAME", help="validation tier, shown in the report header")
    parser.add_argument("--results", metavar="DIR", default=str(RESULTS_DIR),
                        help="stored headline results of larger tiers (default: validation/results); "
                             "OUT/trends.json, when a sweep of this run wrote it, comes first")
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

    try:
        out_dir.mkdir(parents=True, exist_ok=True)
        accuracy = accuracy_figures(Path(args.results))
        write_atomic(out_dir / "report.md", render_markdown(checks, meta, figures, out_dir, notes,
                                                            current, stored, accuracy))
        write_atomic(out_dir / "report.html", render_html(checks, meta, figures, notes, current, stored,
                                                          accuracy))
    except OSError as error:
        return no_report(f"cannot write the report in {out_dir}: {error}", 2)

    table = render_terminal(checks, color=color)
    body, _, last = table.rstrip("\n").rpartition("\n")
    sys.stdout.write(body + "\n")
    print(f"report: wrote {out_dir / 'report.md'} and {out_dir / 'report.html'}")
    print(last)
    _, failed, _ = totals(checks)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
