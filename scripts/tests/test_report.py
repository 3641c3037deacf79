"""Tests of scripts/report.py on synthetic check files.

Run with Debian's interpreter: /usr/bin/python3 -m pytest -q scripts/tests
"""

from __future__ import annotations

import base64
import importlib.util
import json
import math
import os
import shutil
import subprocess
import sys
from pathlib import Path

import jinja2
import pytest

SCRIPT = Path(__file__).resolve().parent.parent / "report.py"
PYTHON = "/usr/bin/python3"


def _load_module():
    spec = importlib.util.spec_from_file_location("ratchet_report", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    return module


report = _load_module()


def check(case="case_a", name="check_1", measured=1.0, expected="1", tolerance="abs 0.1",
          reason="because", passed=True):
    return {"case": case, "check": name, "measured": measured, "expected": expected,
            "tolerance": tolerance, "reason": reason, "passed": passed}


def write_checks(folder: Path, records, name="validation_case-123.jsonl") -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / name
    with open(path, "a", encoding="utf-8") as stream:
        for record in records:
            stream.write((record if isinstance(record, str) else json.dumps(record)) + "\n")
    return path


def run(checks: Path, out: Path, *extra: str):
    """report.main in-process; returns its exit status (output via capsys). The paper-scale
    section reads an empty folder unless --paper-results is given: these tests do not
    depend on what the campaign has stored."""
    if "--paper-results" not in extra:
        extra = (*extra, "--paper-results", str(out.parent / "no-paper-runs"))
    return report.main(["--checks", str(checks), "--out", str(out), "--no-color", *extra])


@pytest.fixture
def folders(tmp_path):
    return tmp_path / "checks", tmp_path / "out"


MIXED = [
    check("free_fall", "z(t=1)", 0.30000000000000004, "0.3", "abs 1e-12", "exact", True),
    check("wall_pressure", "P_max", 1.2, "1", "rel 0.05", "coarse bed", False),
    check("energy", "kinetic energy", 1e-9, "<= 1e-06", "upper bound", "at rest", True),
]


def test_table_contains_each_check(folders, capsys):
    checks, out = folders
    write_checks(checks, MIXED[:1])
    write_checks(checks, MIXED[1:], name="other-456.jsonl")
    status = run(checks, out)
    terminal = capsys.readouterr().out
    markdown = (out / "report.md").read_text(encoding="utf-8")
    page = (out / "report.html").read_text(encoding="utf-8")
    for record in MIXED:
        for text in (terminal, markdown, page):
            assert record["case"] in text
            assert record["check"] in text
            assert record["tolerance"] in text
        # Full precision in the terminal and in the HTML cell's title; 4 significant
        # digits in the reports' tables (the JSON lines keep every digit).
        assert repr(record["measured"]) in terminal
        assert f'title="{record["measured"]!r}"' in page
        assert f"| {record['measured']:.4g} |" in markdown
    assert "0.30000000000000004" in terminal and "| 0.3 |" in markdown
    assert "checks: 2 passed, 1 failed" in terminal.splitlines()[-1]
    assert status == 1


def test_terminal_table_is_aligned(folders, capsys):
    checks, out = folders
    write_checks(checks, MIXED)
    run(checks, out)
    lines = capsys.readouterr().out.splitlines()
    header, rule, rows = lines[0], lines[1], lines[2:5]
    for column in ("case", "check", "expected", "measured", "tolerance", "result"):
        assert column in header
    bars = [i for i, c in enumerate(rule) if c == "+"]
    assert len(bars) == 5
    for row in [header] + rows:
        assert [i for i, c in enumerate(row) if c == "|"] == bars


def test_all_passing_exits_zero(folders, capsys):
    checks, out = folders
    write_checks(checks, [MIXED[0], MIXED[2]])
    assert run(checks, out) == 0
    assert capsys.readouterr().out.splitlines()[-1] == "checks: 2 passed, 0 failed"
    assert "PASSED: all 2 checks passed" in (out / "report.md").read_text(encoding="utf-8")


def test_one_failure_makes_exit_one(folders, capsys):
    checks, out = folders
    write_checks(checks, [MIXED[0], MIXED[1]])
    assert run(checks, out) == 1
    captured = capsys.readouterr().out
    assert "FAIL" in captured
    assert "wall_pressure / P_max" in captured and "coarse bed" in captured
    markdown = (out / "report.md").read_text(encoding="utf-8")
    assert "FAILED: 1 of 2 checks failed" in markdown
    assert "**FAIL**" in markdown
    page = (out / "report.html").read_text(encoding="utf-8")
    assert '<tr class="fail">' in page and '<tr class="pass">' in page


def test_a_not_resolved_check_is_neither_a_pass_nor_a_failure(folders, capsys):
    checks, out = folders
    unresolved = dict(check("trends_angle:angle", "P_max(6 deg)/P_max(0 deg)", 0.61, "0.5",
                            "abs 0.497", "not resolved at this tier: 2 sigma_R = 0.497", True),
                      resolved=False)
    write_checks(checks, [MIXED[0], unresolved])
    assert run(checks, out) == 0
    captured = capsys.readouterr().out
    assert "NOT RESOLVED" in captured and "2 sigma_R = 0.497" in captured
    assert captured.splitlines()[-1] == "checks: 1 passed, 0 failed, 1 not resolved"
    markdown = (out / "report.md").read_text(encoding="utf-8")
    assert "*NOT RESOLVED*" in markdown and "PASSED with 1 of 2 checks not resolved" in markdown
    assert '<tr class="unresolved">' in (out / "report.html").read_text(encoding="utf-8")


CONTRADICTED = dict(check("trends_angle:headline", "W_rms[0-3] slope vs theta_c", -0.0145, "0",
                          "abs 2.5 SE = 0.0133", "contradicted at this scale (reduced): the slope resolves a "
                          "dependence on theta_c", False), resolved=True, contradicted=True)


def test_a_contradiction_at_reduced_scale_is_counted_apart_and_is_not_a_failure(folders, capsys):
    """docs/trends.md, "States": not a pass, not a failure (exit 0), its own column."""
    checks, out = folders
    write_checks(checks, [MIXED[0], CONTRADICTED])
    assert run(checks, out) == 0
    captured = capsys.readouterr().out
    assert captured.splitlines()[-1] == "checks: 1 passed, 0 failed, 1 contradicted at reduced scale"
    assert "Contradicted at a reduced scale" in captured and "CONTRADICTED" in captured
    markdown = (out / "report.md").read_text(encoding="utf-8")
    assert "**CONTRADICTED**" in markdown and "NO FAILURE, 1 of 2 checks CONTRADICTED" in markdown
    page = (out / "report.html").read_text(encoding="utf-8")
    assert '<tr class="contradicted">' in page and 'class="verdict contradicted"' in page
    frame = report.load_checks(checks)
    assert report.totals(frame) == (1, 0, 0, 1)


def test_a_contradiction_beside_a_failure_still_fails(folders):
    checks, out = folders
    write_checks(checks, [MIXED[1], CONTRADICTED])
    assert run(checks, out) == 1
    assert report.totals(report.load_checks(checks)) == (0, 1, 0, 1)


@pytest.mark.parametrize("line, message", [
    (dict(CONTRADICTED, passed=True), "a contradicted check must have"),
    (dict(CONTRADICTED, resolved=False), "a contradicted check must have"),
    (dict(CONTRADICTED, contradicted="yes"), "'contradicted' must be true or false"),
])
def test_a_contradicted_line_that_passes_or_is_unresolved_is_malformed(folders, capsys, line, message):
    checks, out = folders
    write_checks(checks, [line])
    assert run(checks, out) == 2
    assert message in capsys.readouterr().err


def test_a_contradicted_line_without_a_number_is_a_failure(folders):
    checks, out = folders
    write_checks(checks, [dict(CONTRADICTED, measured=None)])
    assert run(checks, out) == 1


def test_a_failed_check_stays_failed_whatever_resolved_says(folders, capsys):
    checks, out = folders
    write_checks(checks, [dict(MIXED[1], resolved=False)])
    assert run(checks, out) == 1
    assert capsys.readouterr().out.splitlines()[-1] == "checks: 0 passed, 1 failed"


def test_a_resolved_field_that_is_not_a_bool_is_malformed(folders, capsys):
    checks, out = folders
    write_checks(checks, [dict(MIXED[0], resolved="no")])
    assert run(checks, out) == 2
    assert "'resolved' must be true or false" in capsys.readouterr().err


def test_empty_folder_exits_one_with_a_message(folders, capsys):
    checks, out = folders
    checks.mkdir()
    (checks / "empty-1.jsonl").write_text("\n", encoding="utf-8")
    assert run(checks, out) == 1
    captured = capsys.readouterr()
    assert "no checks found" in captured.err
    assert not (out / "report.md").exists() and not (out / "report.html").exists()


def test_missing_folder_exits_one_with_a_message(folders, capsys):
    checks, out = folders
    assert run(checks, out) == 1
    assert "does not exist" in capsys.readouterr().err


def test_no_checks_removes_a_stale_report(folders, capsys):
    checks, out = folders
    write_checks(checks, MIXED[:1])
    assert run(checks, out) == 0
    assert (out / "report.md").exists()
    for path in checks.iterdir():
        path.unlink()
    assert run(checks, out) == 1
    assert not (out / "report.md").exists() and not (out / "report.html").exists()
    assert "removed the earlier report" in capsys.readouterr().err


def test_malformed_line_names_file_and_line(folders, capsys):
    checks, out = folders
    path = write_checks(checks, [MIXED[0], "{not json"])
    assert run(checks, out) == 2
    assert f"{path}:2" in capsys.readouterr().err
    assert not (out / "report.md").exists()


def test_missing_field_is_an_error(folders, capsys):
    checks, out = folders
    record = dict(MIXED[0])
    del record["tolerance"]
    write_checks(checks, [record])
    assert run(checks, out) == 2
    assert "missing field(s) tolerance" in capsys.readouterr().err


@pytest.mark.parametrize("written_passed", [False, True])
def test_nan_measured_is_shown_as_a_failure(folders, capsys, written_passed):
    checks, out = folders
    # The C++ writer stores NaN as null with passed false; even a writer that claims
    # success must not turn a non-number into a pass.
    write_checks(checks, [MIXED[0], check("blow_up", "energy", None, "0", "abs 1", "r", written_passed)])
    assert run(checks, out) == 1
    frame = report.load_checks(checks)
    row = frame[frame["case"] == "blow_up"].iloc[0]
    assert math.isnan(row["measured"]) and not row["passed"]
    terminal = capsys.readouterr().out
    nan_line = next(line for line in terminal.splitlines() if line.startswith("blow_up"))
    assert "non-finite" in nan_line and "FAIL" in nan_line
    markdown = (out / "report.md").read_text(encoding="utf-8")
    assert "| blow_up | energy | 0 | non-finite | abs 1 | **FAIL** |" in markdown


def test_atomic_write_leaves_no_temporary_files(folders):
    checks, out = folders
    write_checks(checks, MIXED)
    run(checks, out)
    run(checks, out)  # a second run replaces the reports
    assert sorted(p.name for p in out.iterdir()) == ["report.html", "report.md"]


def test_figures_are_embedded(folders):
    checks, out = folders
    write_checks(checks, MIXED[:1])
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    figure, axes = plt.subplots(figsize=(2, 2))
    axes.plot([0, 1], [0, 1])
    png = report.save_figure(figure, out, "wall pressure", caption="P(t) over two cycles")
    plt.close(figure)
    assert run(checks, out) == 0
    markdown = (out / "report.md").read_text(encoding="utf-8")
    assert "![P(t) over two cycles](figures/wall%20pressure.png)" in markdown
    page = (out / "report.html").read_text(encoding="utf-8")
    assert "data:image/png;base64," + base64.b64encode(png.read_bytes()).decode("ascii") in page
    assert "figures/" not in page  # self-contained
    assert sorted(p.name for p in (out / "figures").iterdir()) == ["wall pressure.png",
                                                                     "wall pressure.txt"]


def test_notes_are_appended(folders):
    checks, out = folders
    write_checks(checks, MIXED[:1])
    (out / "notes").mkdir(parents=True)
    (out / "notes" / "b.md").write_text("### Second\n\nplain <text> & more\n", encoding="utf-8")
    (out / "notes" / "a.md").write_text(
        "### Where the methods differ\n\n- soft contact\n  spans lines\n- damping\n\n"
        "| case | NSCD | DEM |\n|---|---|---|\n| 0 deg | 1.0 | 2.0 |\n", encoding="utf-8")
    assert run(checks, out) == 0
    markdown = (out / "report.md").read_text(encoding="utf-8")
    assert markdown.index("## Notes") < markdown.index("### Where the methods differ") < markdown.index("### Second")
    assert "| 0 deg | 1.0 | 2.0 |" in markdown
    page = (out / "report.html").read_text(encoding="utf-8")
    assert "<h3>Where the methods differ</h3>" in page
    assert "<li>soft contact spans lines</li><li>damping</li>" in page
    assert "<tr><th>case</th><th>NSCD</th><th>DEM</th></tr><tr><td>0 deg</td><td>1.0</td><td>2.0</td></tr>" in page
    assert "<p>plain &lt;text&gt; &amp; more</p>" in page


def test_html_escapes_text(folders):
    checks, out = folders
    write_checks(checks, [check("a<b>", "x & y", 1.0, "<= 2", "upper bound", "<script>", True)])
    assert run(checks, out) == 0
    page = (out / "report.html").read_text(encoding="utf-8")
    assert "<script>" not in page and "&lt;script&gt;" in page
    assert "a&lt;b&gt;" in page and "x &amp; y" in page


def test_markdown_escapes_pipes(folders):
    checks, out = folders
    write_checks(checks, [check("c", "a|b", 1.0, "1", "abs 0", "line\nbreak", True)])
    assert run(checks, out) == 0
    markdown = (out / "report.md").read_text(encoding="utf-8")
    assert "| c | a\\|b | 1 | 1 | abs 0 | PASS | line break |" in markdown


def test_header_has_date_and_tier(folders):
    checks, out = folders
    write_checks(checks, MIXED[:1])
    run(checks, out, "--tier", "quick")
    markdown = (out / "report.md").read_text(encoding="utf-8")
    assert "- Date: " in markdown and "- Tier: quick" in markdown


def test_command_line_with_debian_python(folders):
    checks, out = folders
    write_checks(checks, MIXED)
    done = subprocess.run([PYTHON, str(SCRIPT), "--checks", str(checks), "--out", str(out)],
                          capture_output=True, text=True, check=False,
                          env={**os.environ, "NO_COLOR": "1"})
    assert done.returncode == 1, done.stderr
    assert done.stdout.splitlines()[-1] == "checks: 2 passed, 1 failed"
    assert "\x1b[" not in done.stdout



# --------------------------------------------------------------------------- templates


def test_the_templates_fail_on_a_missing_variable(folders):
    checks, _ = folders
    write_checks(checks, MIXED)
    frame = report.load_checks(checks)
    assert report.template_environment().undefined is jinja2.StrictUndefined
    for name, make_context in ((report.MARKDOWN_TEMPLATE, report.markdown_context),
                               (report.HTML_TEMPLATE, report.html_context)):
        assert "wall_pressure" in report.render_template(name, make_context(frame))  # complete
        for key in ("verdict", "rows", "sections", "meta"):
            context = {k: v for k, v in make_context(frame).items() if k != key}
            with pytest.raises(jinja2.UndefinedError, match=f"'{key}' is undefined"):
                report.render_template(name, context)
        context = make_context(frame)
        del context["rows"][0]["reason"]  # a field of one row
        with pytest.raises(jinja2.UndefinedError, match="reason"):
            report.render_template(name, context)


def _templates_copy(tmp_path, monkeypatch) -> Path:
    """A copy of scripts/templates that report.py then uses."""
    templates = tmp_path / "templates"
    shutil.copytree(report.TEMPLATES_DIR, templates)
    monkeypatch.setattr(report, "TEMPLATES_DIR", templates)
    return templates


@pytest.mark.parametrize("name", ["report.md.j2", "report.html.j2", "report.css", "headline.md.j2",
                                  "headline.html.j2", "paper_repro.md.j2", "paper_repro.html.j2"])
def test_a_missing_template_is_named_and_no_report_is_written(folders, tmp_path, monkeypatch, capsys,
                                                              name):
    checks, out = folders
    write_checks(checks, MIXED[:1])
    assert run(checks, out) == 0  # an earlier report, which must not stay
    (_templates_copy(tmp_path, monkeypatch) / name).unlink()
    capsys.readouterr()
    assert run(checks, out) == 2
    err = capsys.readouterr().err
    assert f"report template not found: {tmp_path / 'templates' / name}" in err
    assert "no report written" in err
    assert not (out / "report.md").exists() and not (out / "report.html").exists()


@pytest.mark.parametrize("name, text, message", [
    ("headline.html.j2", "{{ nope }}\n", "headline.html.j2, line 1: 'nope' is undefined"),
    ("report.md.j2", "# Report\n{% if %}\n", "report.md.j2, line 2: Expected an expression"),
])
def test_a_broken_template_is_named(folders, tmp_path, monkeypatch, capsys, name, text, message):
    checks, out = folders
    write_checks(checks, MIXED[:1])
    (_templates_copy(tmp_path, monkeypatch) / name).write_text(text, encoding="utf-8")
    assert run(checks, out) == 2
    assert message in capsys.readouterr().err
    assert not (out / "report.md").exists() and not (out / "report.html").exists()


def test_the_html_autoescapes_a_script_in_a_check(folders):
    checks, out = folders
    script = "<script>alert('x')</script>"
    write_checks(checks, [check(script, "check " + script, 1.0, script, script, script, False)])
    assert run(checks, out, "--tier", script) == 1
    page = (out / "report.html").read_text(encoding="utf-8")
    assert "<script" not in page.lower()
    # case, check, expected, tolerance, reason and the tier of the header
    assert page.count("&lt;script&gt;alert(&#39;x&#39;)&lt;/script&gt;") == 6


# --------------------------------------------------------------------------- headline

STORED = Path(__file__).resolve().parents[2] / "validation" / "results"


def test_the_report_leads_with_the_stored_headline(folders):
    checks, out = folders
    write_checks(checks, [MIXED[0]])
    assert run(checks, out) == 0
    markdown = (out / "report.md").read_text(encoding="utf-8")
    head, _, table = markdown.partition("## Checks of this run")
    assert "## The paper's headline trends" in head and "This run ran no sweep" in head
    # Every stored record appears with its tier, date and engine commit, before the table.
    for path in sorted(STORED.glob("*.json")):
        record = json.loads(path.read_text(encoding="utf-8"))
        assert (f"Stored: {record['tier']} tier, {record['generated']}, engine commit "
                f"{record['engine_commit']}") in head
    assert "z(t=1)" in table and "z(t=1)" not in head


def test_a_sweep_of_this_run_comes_first(folders, tmp_path):
    checks, out = folders
    write_checks(checks, [MIXED[0]])
    out.mkdir(parents=True)
    document = {"tier": "quick", "tier_scale": "CI scale", "generated": "2026-01-01 00:00:00 UTC",
                "analyses": [], "counts": {},
                "checks": [{"id": "pmax_ratio_6_0", "check": "P_max(6 deg)/P_max(0 deg)",
                            "status": "unresolved", "measured": 0.8, "tolerance": "abs 0.35",
                            "reason": "not resolved at this scale: one realization at 0 or 6 deg. paper: x",
                            "detail": {"sigma": None}}]}
    (out / "trends.json").write_text(json.dumps(document), encoding="utf-8")
    assert run(checks, out, "--results", str(tmp_path / "none")) == 0
    markdown = (out / "report.md").read_text(encoding="utf-8")
    assert "This run ran no sweep" not in markdown
    assert "### This run: quick tier" in markdown
    assert "**NOT RESOLVED**: one realization at 0 or 6 deg" in markdown
    assert "| P_max falls with the opening angle (Fig. 3b) |   | - |   | **not measured** |" in markdown


def test_a_malformed_stored_record_names_the_file_and_field(folders, tmp_path, capsys):
    checks, out = folders
    write_checks(checks, [MIXED[0]])
    results = tmp_path / "results"
    results.mkdir()
    (results / "standard.json").write_text(json.dumps({"version": 1, "tier": "standard"}), encoding="utf-8")
    assert run(checks, out, "--results", str(results)) == 2
    err = capsys.readouterr().err
    assert f"{results / 'standard.json'}: field 'generated' must be a str" in err
    assert not (out / "report.md").exists()


def test_the_report_shows_what_accuracy_costs(folders):
    checks, out = folders
    write_checks(checks, [MIXED[0]])
    assert run(checks, out) == 0
    markdown = (out / "report.md").read_text(encoding="utf-8")
    figures = sorted((STORED / "accuracy").glob("*.png"))
    assert figures, "validation/results/accuracy holds the stored accuracy-cost figures"
    # Each stored figure has its own caption: the report's images are told apart by it.
    captions = {}
    for figure in figures:
        captions.setdefault(report.figure_caption(figure), []).append(figure.name)
    assert not [names for names in captions.values() if len(names) > 1]
    section = markdown.split("## What accuracy costs", 1)[1].split("## Checks of this run", 1)[0]
    for figure in figures:
        caption = figure.with_suffix(".txt").read_text(encoding="utf-8").strip()
        assert caption in section
        assert os.path.relpath(figure, out).replace(os.sep, "/") in section
    # The overview (every knob in one figure) leads the section.
    first = section.index("](")
    assert os.path.relpath(STORED / "accuracy" / "pareto.png", out).replace(os.sep, "/") in section[first:].split(")", 1)[0]
    page = (out / "report.html").read_text(encoding="utf-8")
    assert page.count("data:image/png;base64,") >= len(figures)


def test_the_summary_counts_checks_per_area_and_the_contents_link_every_section(folders):
    checks, out = folders
    records = [check("free fall, theta = 1", "z", 1.0, passed=True),
               check("box on box (aligned)", "points", 4.0, passed=False),
               check("trends_angle:angle", "P_max slope", -0.8, passed=True),
               dict(check("trends_angle:angle", "P_max(6 deg)/P_max(0 deg)", 0.61, passed=True), resolved=False),
               dict(check("trends_angle:angle", "W_rms[0-3] slope vs theta_c", -0.017, passed=False),
                    resolved=True, contradicted=True),
               check("something new", "x", 2.0, passed=True)]
    write_checks(checks, records)
    assert run(checks, out) == 1
    markdown = (out / "report.md").read_text(encoding="utf-8")
    summary = markdown.split("## Summary", 1)[1].split("## The paper's headline trends", 1)[0]
    assert "| area | passed | failed | not resolved | contradicted | checks |" in summary
    assert "| The paper's trends | 1 | 0 | 1 | 1 | 3 |" in summary
    assert "| Polyhedron contact | 0 | 1 | 0 | 0 | 1 |" in summary
    assert "| Analytic cases | 1 | 0 | 0 | 0 | 1 |" in summary
    assert "| Other checks | 1 | 0 | 0 | 0 | 1 |" in summary
    assert markdown.index("## Summary") < markdown.index("## Checks of this run")
    page = (out / "report.html").read_text(encoding="utf-8")
    for anchor in ("summary", "headline", "checks"):
        assert f'href="#{anchor}"' in page and f'id="{anchor}"' in page


# --------------------------------------------------------------------------- the paper, figure by figure

sys.path.insert(0, str(Path(__file__).resolve().parent))
import paper_runs  # noqa: E402  (synthetic stored runs of the paper campaign)


def _section(markdown: str) -> str:
    return markdown.split("## The paper, figure by figure", 1)[1].split("## The paper's headline", 1)[0]


def test_with_no_paper_run_every_statement_says_not_yet_run_and_the_headline_says_reduced_scale(folders):
    checks, out = folders
    write_checks(checks, [MIXED[0]])
    assert run(checks, out) == 0
    markdown = (out / "report.md").read_text(encoding="utf-8")
    assert markdown.index("## Summary") < markdown.index("## The paper, figure by figure") \
        < markdown.index("## The paper's headline trends, reduced scale")
    section = _section(markdown)
    statements = len(report.paper_repro.STATEMENTS)
    # The overview and each statement say it, Table 1 (the plan's scene) aside.
    assert section.count("**NOT YET RUN at the paper's scale**") == 2 * (statements - 1)
    assert "**0 of 45** runs" in section and "Still to run: 45 run(s)" in section
    assert "REDUCED SCALE, not the paper's verdict" in section  # the stored standard tier, beside
    headline = markdown.split("## The paper's headline trends, reduced scale", 1)[1]
    assert report.HEADLINE_SCALE_TEXT in headline
    page = (out / "report.html").read_text(encoding="utf-8")
    assert '<a href="#paper">The paper, figure by figure</a>' in page and '<h2 id="paper">' in page
    assert page.count('<tr class="notrun">') == 2 * (statements - 1)


def test_the_paper_section_shows_the_stored_runs_verdicts_and_figures(folders, tmp_path):
    checks, out = folders
    write_checks(checks, [MIXED[0]])
    results = tmp_path / "paper-runs"
    paper_runs.store_halving(results)
    assert run(checks, out, "--paper-results", str(results)) == 0  # the run's own checks decide
    section = _section((out / "report.md").read_text(encoding="utf-8"))
    assert "**PASSED (1 passed; provisional: 4 of 10 runs)**" in section
    link = "paper-repro/figures/paper_halving_halving.png"
    assert f"]({link})" in section and (out / link).is_file()
    page = (out / "report.html").read_text(encoding="utf-8")
    assert base64.b64encode((out / link).read_bytes()).decode("ascii") in page
    # The paper's figures stay out of the report's Figures section (OUT/figures).
    assert not (out / "figures").exists()


def test_a_paper_scale_contradiction_is_shown_as_one(folders, tmp_path):
    checks, out = folders
    write_checks(checks, [MIXED[0]])
    results = tmp_path / "paper-runs"
    paper_runs.store_halving(results, p6=(0.9, 0.91))
    assert run(checks, out, "--paper-results", str(results)) == 0
    halving = _section((out / "report.md").read_text(encoding="utf-8")).split("### Results text")[1]
    halving = halving.split("### ")[0]
    assert "**CONTRADICTED (1 contradicted; provisional: 4 of 10 runs)**" in halving
    assert "PASS" not in halving


def test_a_bad_paper_plan_names_the_file_and_no_report_is_written(folders, tmp_path, capsys):
    checks, out = folders
    write_checks(checks, [MIXED[0]])
    plan = tmp_path / "paper.json"
    plan.write_text('{"scene": "none.json"}', encoding="utf-8")
    assert run(checks, out, "--paper-plan", str(plan)) == 2
    err = capsys.readouterr().err
    assert f"{plan}: field 'seeds': missing" in err and "no report written" in err
    assert not (out / "report.md").exists()
