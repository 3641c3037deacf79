"""Tests of "The paper, figure by figure" (scripts/analysis/paper_repro.py, scripts/paper-repro)
on synthetic stored runs of the paper campaign, written in the campaign's format
(tests/paper_runs.py).

Run with Debian's interpreter: /usr/bin/python3 -m pytest -q scripts/tests/test_paper_repro.py
"""

from __future__ import annotations

import json
import re
import subprocess
import sys
from pathlib import Path

import pytest

TESTS = Path(__file__).resolve().parent
sys.path.insert(0, str(TESTS))
import paper_runs  # noqa: E402  (puts scripts/ on the path)

from analysis import paper_repro, paper_repro_cli, trends  # noqa: E402
from analysis.inputs import load_sweep  # noqa: E402
from campaign_lib import store  # noqa: E402
from common import templates  # noqa: E402
from common.paths import REPO_ROOT  # noqa: E402

PYTHON = "/usr/bin/python3"
ENTRY = REPO_ROOT / "scripts" / "paper-repro"
DOC = REPO_ROOT / "docs" / "paper-reproduction.md"
#: A stored headline record of a reduced scale, as validation/results/*.json hold them.
RECORD = {"version": 2, "tier": "standard", "generated": "2026-11-24 08:49:34 UTC",
          "engine_commit": "3c040d3", "command": "scripts/validate --tier standard",
          "scale": "200 polyhedra", "counts": {},
          "rows": [{"id": "pmax_ratio_6_0", "statement": "6 deg halves", "status": "passed",
                    "check": "P_max(6 deg)/P_max(0 deg)", "measured": 0.52, "detail": "",
                    "reason": "", "fit": None}]}


def statement(data: dict, sid: str) -> dict:
    return next(s for s in data["statements"] if s["id"] == sid)


def markdown(data: dict) -> str:
    return templates.render("paper_repro.md.j2", {
        "paper": paper_repro.with_figures(data, lambda path: {"link": path.name}), "paper_missing": ""})


def test_with_no_stored_run_every_statement_is_not_yet_run_and_names_what_is_left(tmp_path):
    data = paper_repro.build(results=tmp_path / "none", out=tmp_path / "out",
                             reduced=[("Stored", RECORD)])
    assert (data["stored"], data["planned"]) == (0, 45)
    hours = 45 * paper_runs.load_plan(paper_runs.PAPER_PLAN).run_cost_hours  # the plan's estimate
    assert data["todo"].startswith(f"45 run(s), about {hours:.1f} CPU h")
    for s in data["statements"]:
        assert s["figures"] == [] and s["checks"] == []
        if s["id"] == "table1":
            continue
        assert s["verdict"] == paper_repro.NOT_RUN, s["figure"]
        assert s["runs"].startswith("0 of ")
        assert "seeds 1-5" in s["missing"]
    assert statement(data, "halving")["missing"].startswith(
        "10 run(s): theta0_ratio10 seeds 1-5; theta6_ratio10 seeds 1-5")
    # The reduced-scale record is beside the verdict, labelled, never the verdict itself.
    halving = statement(data, "halving")
    assert halving["reduced"] and "REDUCED SCALE" in halving["reduced"][0]["label"]
    assert halving["reduced"][0]["result"] == "PASS" and halving["verdict"] == paper_repro.NOT_RUN
    text = markdown(data)
    assert text.count(f"**{paper_repro.NOT_RUN}**") == 2 * (len(paper_repro.STATEMENTS) - 1)
    assert not (tmp_path / "out" / "figures").exists() or not any((tmp_path / "out" / "figures").iterdir())


def test_table1_is_compared_with_the_scene_of_every_planned_run(tmp_path):
    data = paper_repro.build(results=tmp_path / "none", out=tmp_path / "out")
    table = statement(data, "table1")
    assert table["verdict"].startswith("MATCHES") and table["verdict_class"] == "pass"
    assert {p["symbol"]: p["ours"] for p in table["params"]}["N_p"] == "2000"
    # A plan whose bed differs from Table 1 is said to differ, by symbol.
    plan = json.loads(paper_runs.PAPER_PLAN.read_text())
    plan["scene"] = str(paper_runs.PAPER_PLAN.parent / plan["scene"])
    plan["set"] = {"particles.generate.count": 200}
    other = tmp_path / "small.json"
    other.write_text(json.dumps(plan))
    table = statement(paper_repro.build(other, tmp_path / "none", tmp_path / "out2"), "table1")
    assert table["verdict"] == "DIFFERS: N_p" and table["verdict_class"] == "fail"


def _halving_by_hand(results: Path, tmp_path: Path) -> trends.CheckResult:
    """The same runs as a plain sweep folder (summary.csv, runs/<id>/cycles.csv), judged by
    trends.analyse at the paper tier: what scripts/trends says of them."""
    sweep = tmp_path / "by_hand"
    lines = ["run,container.opening_angle_deg,seed,P_max,status"]
    run = 0
    for point, angle in (("theta0_ratio10", 0), ("theta6_ratio10", 6)):
        for folder in sorted((results / point).iterdir()):
            summary = json.loads((folder / "run.json").read_text())["summary"]
            lines.append(f"{run},{angle},{folder.name[4:]},{summary['P_max']!r},completed")
            (sweep / "runs" / str(run)).mkdir(parents=True)
            for name in ("cycles.csv", "run.json"):
                (sweep / "runs" / str(run) / name).write_bytes((folder / name).read_bytes())
            run += 1
    (sweep / "summary.csv").write_text("\n".join(lines) + "\n")
    a = trends.analyse(load_sweep(sweep), "angle", trends.PAPER_TIER)
    return next(r for r in a.results if r.check_id == "pmax_ratio_6_0")


def test_the_halving_shows_the_verdict_of_the_real_check(tmp_path):
    results = tmp_path / "results"
    paper_runs.store_halving(results)
    data = paper_repro.build(results=results, out=tmp_path / "out", reduced=[("Stored", RECORD)])
    halving = statement(data, "halving")
    expected = _halving_by_hand(results, tmp_path)
    assert expected.status == "passed"  # the synthetic cone halves the peak
    [row] = halving["checks"]
    assert row["id"] == "pmax_ratio_6_0" and row["result"] == "PASS"
    assert row["measured"] == f"{expected.measured:.4g}" and row["tolerance"] == expected.tolerance
    assert halving["verdict"] == "PASSED (1 passed; provisional: 4 of 10 runs)"
    assert halving["runs"] == "4 of 10"
    assert halving["missing"].startswith("6 run(s): theta0_ratio10 seeds 3-5; theta6_ratio10 seeds 3-5")
    assert "theta0_ratio10 2 of 5, theta6_ratio10 2 of 5" in halving["scale"]
    assert data["stored"] == 4 and data["engines"] == ["0123456789"]
    # Its figure, with its caption beside it.
    [figure] = halving["figures"]
    assert Path(figure).is_file() and Path(figure).with_suffix(".txt").is_file()
    assert "pmax_ratio_6_0" in Path(figure).with_suffix(".txt").read_text()


def test_every_statement_with_runs_has_its_figures(tmp_path, monkeypatch):
    results = tmp_path / "results"
    paper_runs.store_halving(results)
    data = paper_repro.build(results=results, out=tmp_path / "out")
    names = {s["id"]: [Path(f).name for f in s["figures"]] for s in data["statements"]}
    assert names["fig3a"] == ["paper_angle_peaks.png", "paper_angle_density.png"]
    caption = (tmp_path / "out" / "figures" / "paper_angle_density.txt").read_text()
    assert "pmax_follows_density" in caption and "loose to dense" in caption
    assert names["fig3b"] == ["trends_angle_angle_P_max.png"]
    assert names["fig6"] == ["trends_angle_angle_displacement.png"]
    assert names["fig7a"] == ["trends_angle_angle_W_rms.png"]
    assert names["fig5"] == []  # these synthetic runs hold no stage_fields.csv: nothing to draw
    # The campaign stores the stage fields, so no gap is named; a campaign that did not
    # would be said.
    assert store.KEEP.match("stage_fields.csv") and statement(data, "fig5")["gap"] == ""
    monkeypatch.setattr(store, "KEEP", re.compile(r"^(run\.json|cycles\.csv)$"))
    without = paper_repro.build(results=results, out=tmp_path / "out_without")
    assert "does not store stage_fields.csv" in statement(without, "fig5")["gap"]
    for figures in names.values():
        for name in figures:
            assert (tmp_path / "out" / "figures" / name).with_suffix(".txt").is_file()
    # A second build with no run removes the figures of the first.
    paper_repro.build(results=tmp_path / "none", out=tmp_path / "out")
    assert not list((tmp_path / "out" / "figures").glob("*.png"))


def test_the_papers_point_is_judged_once_though_both_studies_hold_it(tmp_path):
    # theta_c = 0 at alpha_c/alpha_p = 10 is a point of the angle and of the ratio study:
    # the same stored runs, so a per-point check of a statement read from both parts
    # (Fig. 6: wrms_early_larger) counts them once.
    results = tmp_path / "results"
    paper_runs.store_halving(results)
    data = paper_repro.build(results=results, out=tmp_path / "out")
    rows = [r for r in statement(data, "fig6")["checks"] if r["id"] == "wrms_early_larger"]
    assert [r["check"] for r in rows] == ["W_rms first window > last (theta_c=0 deg)",
                                          "W_rms first window > last (theta_c=6 deg)"]
    assert [r["case"] for r in rows] == ["trends_angle:angle"] * 2
    every = statement(data, "fig6")["checks"]
    assert not any("alpha_c/alpha_p=10" in r["check"] for r in every)  # nor the skipped toroidal rows
    assert statement(data, "fig6")["verdict"] == "PASSED (2 passed, 2 skipped; provisional: 4 of 45 runs)"


def test_what_is_left_is_costed_by_each_points_own_stored_runs(tmp_path):
    # The paper bed's cost depends on the point (a ratio-1 run took 0.6 CPU h where the
    # ratio-10 runs take 2.7): a point's missing runs cost the median of its own stored runs.
    results = tmp_path / "results"
    for seed in (1, 2):
        paper_runs.store_run(results, "theta0_ratio10", seed, 1.0, cpu_seconds=7200.0)
    paper_runs.store_run(results, "theta0_ratio1", 1, 0.2, cpu_seconds=1800.0)
    data = paper_repro.build(results=results, out=tmp_path / "out")
    # ratio 1: 4 x 0.5 h; 2.5, 5, 7.5 (no run of their own): 15 x the median 2 h; ratio 10: 3 x 2 h
    assert statement(data, "fig3d")["missing"].endswith(
        "(about 38.0 CPU h at the median of 3 stored run(s); theta0_ratio1, theta0_ratio10 at the median "
        "of their own)")
    assert data["todo"].startswith(f"42 run(s), about {(4 * 0.5 + 38 * 2):.1f} CPU h")


def test_a_reduced_records_per_point_rows_go_under_their_own_study(tmp_path):
    steady = [{"id": "pmax_steady", "statement": "steady", "status": "passed", "check": f"P_max steady ({p})",
               "measured": 0.1, "detail": "", "reason": "", "fit": None}
              for p in ("theta_c=0 deg", "alpha_c/alpha_p=1")]
    record = dict(RECORD, rows=RECORD["rows"] + steady)
    data = paper_repro.build(results=tmp_path / "none", out=tmp_path / "out", reduced=[("Stored", record)])
    assert [r["check"] for r in statement(data, "fig3a")["reduced"]] == ["P_max steady (theta_c=0 deg)"]
    assert [r["check"] for r in statement(data, "fig3c")["reduced"]] == ["P_max steady (alpha_c/alpha_p=1)"]


def test_a_contradiction_shows_contradicted_never_passed(tmp_path):
    results = tmp_path / "results"
    paper_runs.store_halving(results, p6=(0.9, 0.91))  # the cone lowers the peak by a tenth
    data = paper_repro.build(results=results, out=tmp_path / "out")
    halving = statement(data, "halving")
    assert _halving_by_hand(results, tmp_path).status == "failed"  # the paper tier's word for it
    [row] = halving["checks"]
    assert row["result"] == "CONTRADICTED" and row["result_class"] == "contradicted"
    assert "not by a half" in row["why"]
    assert halving["verdict"].startswith("CONTRADICTED") and halving["verdict_class"] == "contradicted"
    section = markdown(data).split("### Results text")[1].split("### Fig. 3c")[0]
    assert "**CONTRADICTED**" in section and "PASS" not in section


def test_a_value_that_is_not_a_number_is_a_failure_not_a_contradiction():
    assert paper_repro.result_text("failed", float("nan")) == "FAIL"
    assert paper_repro.result_text("failed", None) == "FAIL"
    assert paper_repro.result_text("failed", 0.9) == "CONTRADICTED"
    assert paper_repro.result_text("contradicted", 0.9) == "CONTRADICTED"
    assert paper_repro.result_text("unresolved", 0.9) == "NOT RESOLVED"


def test_a_stored_run_of_another_scene_is_not_used_and_is_named(tmp_path):
    results = tmp_path / "results"
    plan = paper_runs.load_plan(paper_runs.PAPER_PLAN)
    run = next(r for r in plan.runs if r.label == "theta0_ratio10/seed1")
    scene = plan.scene_for(run)
    scene["thermal"] = {**scene["thermal"], "cycles": 10}
    paper_runs.store_run(results, "theta0_ratio10", 1, 1.0, scene=scene)
    (results / "theta6_ratio10" / "seed1").mkdir(parents=True)
    (results / "theta6_ratio10" / "seed1" / "run.json").write_text("{}")  # no provenance yet
    data = paper_repro.build(results=results, out=tmp_path / "out")
    assert data["stored"] == 0
    assert statement(data, "halving")["verdict"] == paper_repro.NOT_RUN
    refused = "\n".join(data["refused"])
    assert "theta0_ratio10/seed1: field 'scene' of " in refused and "run.json" in refused
    assert "theta6_ratio10/seed1: no provenance.json" in refused


def test_a_plan_without_the_papers_parts_is_refused_naming_the_file(tmp_path):
    plan = json.loads(paper_runs.PAPER_PLAN.read_text())
    plan["scene"] = str(paper_runs.PAPER_PLAN.parent / plan["scene"])
    plan["parts"] = [p for p in plan["parts"] if p["name"] != "halving"]
    path = tmp_path / "cut.json"
    path.write_text(json.dumps(plan))
    with pytest.raises(paper_repro.PaperReproError, match=r"cut\.json: field 'parts': no part named 'halving'"):
        paper_repro.build(path, tmp_path / "none", tmp_path / "out")


# --------------------------------------------------------------------------- command line

DOC_TEXT = f"""# Hand-written title

Framing kept as it is.

{paper_repro_cli.BEGIN}
old block
{paper_repro_cli.END}

Hand-written end.
"""


def test_the_command_writes_its_files_and_rewrites_only_the_docs_block(tmp_path):
    results, out, doc = tmp_path / "results", tmp_path / "out", tmp_path / "doc.md"
    paper_runs.store_halving(results)
    doc.write_text(DOC_TEXT)
    done = subprocess.run([PYTHON, str(ENTRY), "--results", str(results), "--out", str(out),
                           "--records", str(tmp_path / "no-records"), "--doc", str(doc)],
                          capture_output=True, text=True, cwd=tmp_path, timeout=300)
    assert done.returncode == 0, done.stderr
    assert "Results text: PASSED (1 passed; provisional: 4 of 10 runs) [4 of 10 runs]" in done.stdout
    assert done.stdout.splitlines()[-1].startswith("paper-repro: 4 of 45 runs stored; still to run: 41 run(s)")
    text = doc.read_text()
    assert text.startswith("# Hand-written title\n\nFraming kept as it is.\n") and "Hand-written end." in text
    assert "old block" not in text and "### Results text: A 6 deg cone halves the peak pressure" in text
    # The doc names its figures (out/ is not in the repository); the standalone file links them.
    assert "](" not in text and "Figure (drawn from the stored runs by the report" in text
    standalone = (out / "paper-repro.md").read_text()
    assert "](figures/paper_halving_halving.png)" in standalone
    assert json.loads((out / "paper-repro.json").read_text())["stored"] == 4


def test_the_command_refuses_a_doc_without_its_block_and_a_bad_plan(tmp_path):
    doc = tmp_path / "doc.md"
    doc.write_text("# no block\n")
    done = subprocess.run([PYTHON, str(ENTRY), "--results", str(tmp_path / "none"), "--out",
                           str(tmp_path / "out"), "--doc", str(doc)], capture_output=True, text=True,
                          timeout=300)
    assert done.returncode == 2 and f"{doc}: no block" in done.stderr
    assert doc.read_text() == "# no block\n"
    bad = tmp_path / "bad.json"
    bad.write_text('{"scene": "x.json"}')
    done = subprocess.run([PYTHON, str(ENTRY), "--plan", str(bad), "--out", str(tmp_path / "out")],
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 2 and "bad.json: field 'seeds': missing" in done.stderr


# --------------------------------------------------------------------------- the doc


def test_the_doc_quotes_every_statement_and_has_the_generated_block():
    text = DOC.read_text(encoding="utf-8")
    block = text.split(paper_repro_cli.BEGIN, 1)[1].split(paper_repro_cli.END, 1)[0]
    for s in paper_repro.STATEMENTS:
        assert s.quote in block, s.id
        for check_id in s.checks:
            assert check_id in block and check_id in trends.CHECKS
    assert "scripts/paper-repro --doc docs/paper-reproduction.md" in text


def test_no_file_of_the_repository_points_outside_it():
    # The project stands alone: the paper's words are quoted, not linked. (The paths are
    # put together here so that this file does not name them itself.)
    outside = ("/".join(("", "work", "shared")), "/".join(("..", "shared")))
    files = subprocess.run(["git", "-C", str(REPO_ROOT), "ls-files", "--cached", "--others",
                            "--exclude-standard"], capture_output=True, text=True, check=True).stdout
    offenders = []
    for name in sorted(set(files.splitlines())):
        path = REPO_ROOT / name
        if not path.is_file() or path.stat().st_size > 2_000_000:
            continue
        text = path.read_bytes().decode("utf-8", errors="ignore")
        offenders += [f"{name}: {o}" for o in outside if o in text]
    assert offenders == []


def test_the_law_line_names_the_tangential_law_and_the_creep_only_where_it_is():
    from campaign_lib.plan import load_plan
    plan = load_plan(paper_repro.DEFAULT_PLAN)
    # The paper tier's scene: the spring law at 0.01, whose measured error the line names.
    line = paper_repro._law(plan)
    assert line.startswith("compliant, ε = 0.01 (solver.compliance), tangential law spring;")
    assert "The spring law at the paper's depth" in line and "creep" not in line
    plan.set = {**plan.set, "solver.tangential_law": "creep", "solver.compliance": 0.1}
    line = paper_repro._law(plan)
    assert "tangential law creep (sticking contacts creep" in line
    assert "the law moves the peak pressure and the halving ratio" in line


def test_the_contact_law_and_the_compliance_ladders_are_shown(tmp_path):
    def ladder(name, complete, p_max):
        path = tmp_path / name
        path.write_text(json.dumps({"complete": complete, "observables": {"P_max": {
            k: {"mean": m, "se": se, "n": n} for k, (m, se, n) in p_max.items()}}}))
        return path
    zero = ladder("l0.json", False, {"e0.01": (100.0, 10.0, 2), "e0.1": (50.0, None, 1)})
    six = ladder("l6.json", True, {"e0.01": (40.0, 2.0, 3), "e0.1": (28.0, 0.4, 3)})
    # The spring law's ladder: its settings are 's<eps>'; one with a suffix is not a rung.
    spring = ladder("s0.json", False, {"s0.003": (130.0, 8.0, 3), "s0.01": (150.0, 4.0, 3),
                                      "s0.01-ramp20": (1.0, 1.0, 3)})
    # The rigid law's comparison (the paper's law, setting 'rigid') beside its own s0.01 runs.
    rigid = ladder("r0.json", True, {"rigid": (170.0, 5.0, 3), "s0.01": (150.0, 4.0, 3)})
    data = paper_repro.build(results=tmp_path / "none", out=tmp_path / "out",
                             ladders=[(0.0, zero), (6.0, six), (8.0, tmp_path / "absent.json"), (0.0, spring),
                                      (0.0, rigid)])
    # The plan's scene is the paper tier's compliant law, not the paper's rigid one.
    assert data["law"].startswith("compliant, ε = 0.01 (")
    assert "the paper's law is rigid" in data["law"]
    assert "tangential law spring" in data["law"]
    # The absent file is left out; the state is per law and angle.
    assert data["ladder_state"] == "rigid 0° complete, spring 0° partial, creep 0° partial, creep 6° complete"
    rows = {(r["law"], r["eps"]): r for r in data["ladders"]}
    # The paper's rigid law first, then the spring law (the tier's), then the creep law;
    # each by decreasing compliance.
    assert list(rows) == [("rigid", "0"), ("spring", "0.01"), ("spring", "0.003"), ("creep", "0.1"),
                          ("creep", "0.01")]
    # 0.40 ± 0.40 hypot(0.1, 0.05) = 0.045; no SE where a point has one bed.
    assert rows[("creep", "0.01")]["ratio"] == "0.40 ± 0.04"
    assert rows[("creep", "0.1")]["ratio"] == "0.56"
    assert rows[("creep", "0.01")]["angles"] == {0.0: "100.0 ± 10.0 (2)", 6.0: "40.0 ± 2.0 (3)"}
    assert rows[("spring", "0.01")]["angles"] == {0.0: "150.0 ± 4.0 (3)"}
    assert rows[("spring", "0.01")]["ratio"] == "—"  # no 6° rung of that law
    text = markdown(data)
    assert "- Contact law: compliant, ε = 0.01" in text
    assert "| creep | 0.01 | 100.0 ± 10.0 (2) | 40.0 ± 2.0 (3) | 0.40 ± 0.04 |" in text
    assert "| spring | 0.01 | 150.0 ± 4.0 (3) | — | — |" in text
    assert "| rigid | 0 | 170.0 ± 5.0 (3) | — | — |" in text
    # Without ladders the table is left out.
    assert "| law | ε | 0° | 6° |" not in markdown(
        paper_repro.build(results=tmp_path / "none", out=tmp_path / "out2", ladders=[]))
    # A damaged comparison is an error naming the file, not a traceback.
    bad = tmp_path / "bad.json"
    bad.write_text('{"observables": {}}')
    with pytest.raises(paper_repro.PaperReproError, match=r"bad\.json: not a compare-settings comparison"):
        paper_repro.build(results=tmp_path / "none", out=tmp_path / "out3", ladders=[(0.0, bad)])


def test_the_stored_volume_series_reaches_the_steady_density_check(tmp_path):
    # Every synthetic stored run keeps its volume.csv as the campaign stores it, with the
    # same peak density at 0 and 6 deg: the check that needs it runs and passes.
    results = tmp_path / "results"
    paper_runs.store_halving(results)
    data = paper_repro.build(results=results, out=tmp_path / "out", reduced=[])
    rows = [row for row in statement(data, "fig4a")["checks"] if row["id"] == "steady_volume_flat"]
    assert [row["result"] for row in rows] == ["PASS"], rows
