"""scripts/campaign on the real engine with tiny stand-in plans (docs/campaign.md): the
quick bed cut to 12 polyhedra, a loose settle threshold and h = 0.005, 2 points x 2
seeds (about a second of CPU for all four runs). Checked: runs stored with their
provenance; a second invocation runs nothing; a budget that ends mid-run leaves a run
that the next invocation completes with the bytes of an uninterrupted run, and a run that
completed as its SIGTERM came is stored, not stopped; stale results
are rerun and results of an engine that passed the golden check are reused (also after a
recheck of its binary on newer golden data); bad plans
are refused naming the file and the field; the engine id ignores the engine's tests and
benchmarks and names a binary built from other sources (its source hash, or for
an older binary its age) by its SHA-256; the progress report
gives the pace and warns when it falls; the engine runs in the campaign's session in a
process group of its own; --assemble gives sweep folders that scripts/analysis/inputs.py
reads; --commit commits each stored run; --finish-one hands the lead of a pair every
thread at the last moment, and its run keeps the bytes of an uninterrupted one."""

from __future__ import annotations

import json
import os
import re
import shlex
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path
from types import SimpleNamespace

import pytest

SCRIPTS = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(SCRIPTS))

from analysis.inputs import load_sweep, read_cycles, displacement_files  # noqa: E402
from campaign_lib import golden  # noqa: E402
from campaign_lib.runner import exit_outcome  # noqa: E402
from campaign_lib.engine import ENGINE_SOURCES, file_sha256, identify, sources_state  # noqa: E402
from common.paths import REPO_ROOT, engine_binary  # noqa: E402

RATCHET = engine_binary()
pytestmark = pytest.mark.skipif(not RATCHET.is_file(), reason=f"engine not built ({RATCHET})")
CAMPAIGN = [sys.executable if sys.executable.endswith("python3") else "/usr/bin/python3",
            str(SCRIPTS / "campaign")]
TINY_SET = {"particles.generate.count": 12, "settle.ke_ratio": 1e-3, "thermal.cycles": 1, "time.dt": 0.005,
            "outputs.checkpoint_every": 200, "outputs.timeseries_every": 10}


def write_plan(folder: Path, name="tiny", seed_list=(1, 2), angles=(0, 6), **changes) -> Path:
    plan = {"description": "tiny stand-in of the paper plan (tests)",
            "scene": str(REPO_ROOT / "validation" / "sweeps" / "bed_quick.json"),
            "set": dict(TINY_SET), "seeds": list(seed_list), "run_cost_hours": 0.0001,
            "points": [{"name": f"theta{a}", "set": {"container.opening_angle_deg": a}} for a in angles],
            "parts": [{"name": "angle", "sweep": "container.opening_angle_deg",
                       "points": [f"theta{a}" for a in angles]}]}
    for key, value in changes.items():
        if value is None:
            plan.pop(key, None)
        else:
            plan[key] = value
    path = folder / f"{name}.json"
    path.write_text(json.dumps(plan, indent=1))
    return path


def campaign(plan: Path, work: Path, results: Path, *args, check=True) -> subprocess.CompletedProcess:
    done = subprocess.run([*CAMPAIGN, str(plan), "--out", str(work), "--results", str(results),
                           "--ratchet", str(RATCHET), *args], capture_output=True, text=True, timeout=300)
    if check:
        assert done.returncode == 0, done.stdout + done.stderr
    return done


def run_args(*extra):
    return ["--budget", "0.2", "--golden-check", "skip", *extra]


@pytest.fixture(scope="module")
def tiny(tmp_path_factory):
    root = tmp_path_factory.mktemp("campaign")
    plan = write_plan(root)
    first = campaign(plan, root / "work", root / "results", *run_args("--jobs", "2"))
    return root, plan, first


def provenance(results: Path, label: str) -> dict:
    return json.loads((results / label / "provenance.json").read_text())


def test_runs_are_stored_with_provenance_and_a_second_invocation_runs_nothing(tiny):
    root, plan, first = tiny
    results = root / "results"
    labels = ["theta0/seed1", "theta6/seed1", "theta0/seed2", "theta6/seed2"]
    for label in labels:
        assert f"start {label} (new)" in first.stdout and f"done {label}" in first.stdout
        folder = results / label
        names = sorted(p.name for p in folder.iterdir())
        assert names == ["cycles.csv", "displacement_0_1.csv", "provenance.json", "run.json", "volume.csv"], names
        p = provenance(results, label)
        run_json = json.loads((folder / "run.json").read_text())
        assert run_json["status"] == "completed"
        assert p["scene_hash"] == run_json["scene_hash"]
        assert p["engine"]["engine_commit"] and p["engine"]["version"].startswith("ratchet ")
        assert isinstance(p["engine"]["engine_dirty"], bool) and p["engine"]["binary_sha256"]
        assert p["cpu_seconds"] >= 0 and p["host"] and p["date"] and "sweep" in p["command"]
        assert p["golden_check"] is None and p["seed"] == int(label[-1])
        assert set(p["files"]) == {"cycles.csv", "displacement_0_1.csv", "run.json", "volume.csv"}
    before = {label: (results / label / "provenance.json").read_bytes() for label in labels}

    again = campaign(plan, root / "work", results, *run_args())
    assert "nothing to run" in again.stdout and "start " not in again.stdout
    assert before == {label: (results / label / "provenance.json").read_bytes() for label in labels}
    status = campaign(plan, root / "work", results, "--status")
    assert "4 of 4 runs stored and current, 0 stale" in status.stdout
    dry = campaign(plan, root / "work", results, "--dry-run")
    assert "nothing to run" in dry.stdout


def test_a_run_another_invocation_stored_meanwhile_is_not_run_again(tiny, tmp_path):
    # Two invocations share a plan (one per core): each made its queue at its start, and
    # the other one stored this run since. It is skipped, not started and stored again.
    from campaign_lib import state as campaign_state
    from campaign_lib.plan import load_plan
    from campaign_lib.runner import Runner
    root, plan_file, _ = tiny
    plan, engine = load_plan(plan_file), identify(RATCHET)
    results = tmp_path / "results"
    queue = campaign_state.todo(campaign_state.survey(plan, tmp_path / "work", results, engine, None))
    assert [s.run.label for s in queue][:1] == ["theta0/seed1"]
    shutil.copytree(root / "results" / "theta0", results / "theta0")  # the other invocation's result
    before = (results / "theta0" / "seed1" / "provenance.json").read_bytes()
    said = []
    runner = Runner(plan, tmp_path / "work", results, engine, None, [], 1, 1.0, 60.0, 5.0, 600.0, False,
                    said.append)
    outcome = runner.run(queue[:1])
    assert outcome.stored == [] and outcome.failed == []
    assert any(line.startswith("skip theta0/seed1: another process stored it") for line in said), said
    assert not any(line.startswith("start ") for line in said), said
    assert (results / "theta0" / "seed1" / "provenance.json").read_bytes() == before


def test_a_run_longer_than_the_budget_starts_while_the_minimum_slice_is_left(tmp_path):
    # A run estimated far beyond the budget (a paper-tier run on one core is longer than a
    # session): with a minimum slice it starts and stops at a checkpoint; without, it waits.
    # 400 cycles of 12 bodies take far more than the 2 s budget on any machine (20 cycles
    # took under 2 s on a fast one, and the run was stored instead of stopped).
    plan = write_plan(tmp_path, name="slice", seed_list=(3,), angles=(0,), set={**TINY_SET, "thermal.cycles": 400})
    budget = f"{2.0 / 3600:.8f}"   # 2 s: the pour, not the cycles
    waits = campaign(plan, tmp_path / "w0", tmp_path / "r0", "--budget", budget, "--stop-margin", "0.5",
                     "--golden-check", "skip", "--run-hours", "100", "--min-slice", "0")
    assert "budget: not starting theta0/seed3: " in waits.stdout, waits.stdout
    assert "--min-slice MINUTES would start them now" in waits.stdout, waits.stdout
    assert not (tmp_path / "w0" / "runs" / "theta0" / "seed3" / "out").exists()
    # Runs the budget leaves are said in one line, not one each (a paper plan has 45).
    two = write_plan(tmp_path, name="slice2", seed_list=(3, 4), angles=(0,),
                     set={**TINY_SET, "thermal.cycles": 400})
    both = campaign(two, tmp_path / "w2", tmp_path / "r2", "--budget", budget, "--stop-margin", "0.5",
                    "--golden-check", "skip", "--run-hours", "100")
    assert both.stdout.count("budget: not starting") == 1, both.stdout
    assert "budget: not starting theta0/seed3 and 1 more: " in both.stdout, both.stdout
    # By default only runs that fit start: a session's work folder may not outlive it.
    default = campaign(plan, tmp_path / "w1", tmp_path / "r1", "--dry-run", "--budget", "1", "--run-hours", "100")
    assert "[not within the budget]" in default.stdout, default.stdout
    assert "0 of 1 run(s) fit in 1.00 h with 1 at a time, 0 more start and stop at a checkpoint" in default.stdout
    dry = campaign(plan, tmp_path / "w1", tmp_path / "r1", "--dry-run", "--budget", "1", "--run-hours", "100",
                   "--min-slice", "15")
    assert "[stops at a checkpoint when the budget ends]" in dry.stdout, dry.stdout
    assert "0 of 1 run(s) fit in 1.00 h with 1 at a time, 1 more start and stop at a checkpoint" in dry.stdout
    starts = campaign(plan, tmp_path / "w1", tmp_path / "r1", "--budget", budget, "--stop-margin", "0.5",
                      "--golden-check", "skip", "--run-hours", "100", "--min-slice", "0.001")
    assert "theta0/seed3 needs about 100.00 h" in starts.stdout and "starts and stops at a checkpoint" in starts.stdout
    assert "stopped theta0/seed3" in starts.stdout, starts.stdout
    bad = campaign(plan, tmp_path / "w1", tmp_path / "r1", "--budget", budget, "--min-slice", "-1", check=False)
    assert bad.returncode == 2 and "--min-slice: expected a number >= 0, got '-1'" in bad.stderr


LONG_SET = {**TINY_SET, "thermal.cycles": 60}


@pytest.fixture(scope="module")
def long_reference(tmp_path_factory):
    """One run long enough to be stopped, uninterrupted on one thread: 60 cycles (about 6 s
    of CPU; with 20 cycles and the stop at half, a CI machine once finished the run before
    the SIGTERM came). Returns its stored folder."""
    root = tmp_path_factory.mktemp("long")
    plan = write_plan(root, name="long", seed_list=(3,), angles=(0,), set=LONG_SET)
    campaign(plan, root / "w_ref", root / "r_ref", *run_args())
    return root / "r_ref" / "theta0" / "seed3"


def same_stored_bytes(ours: Path, reference: Path) -> None:
    """Every stored result file, bit for bit (provenance.json and run.json hold times)."""
    names = sorted(f.name for f in reference.iterdir() if f.name not in ("provenance.json", "run.json"))
    assert "cycles.csv" in names and sorted(f.name for f in ours.iterdir()
                                            if f.name not in ("provenance.json", "run.json")) == names
    for name in names:
        assert (ours / name).read_bytes() == (reference / name).read_bytes(), name


def test_budget_ending_mid_run_leaves_a_run_the_next_invocation_completes_with_the_same_bytes(tmp_path,
                                                                                             long_reference):
    plan = write_plan(tmp_path, name="long", seed_list=(3,), angles=(0,), set=LONG_SET)
    reference = long_reference
    took = json.loads((reference / "provenance.json").read_text())["wall_seconds"]

    # The budget ends at about a third of the uninterrupted run's time (after the pour): a
    # margin of 3x for a machine whose load differs between the two invocations.
    stop_after = max(0.5, 0.33 * took)
    hours = (stop_after + 0.5) / 3600
    first = campaign(plan, tmp_path / "w", tmp_path / "r", "--budget", f"{hours:.8f}", "--stop-margin", "0.5",
                     "--golden-check", "skip", "--run-hours", "0.00001")
    assert "the budget ends: stopping 1 run(s) with SIGTERM" in first.stdout, first.stdout
    assert "stopped theta0/seed3" in first.stdout and "resumes it" in first.stdout
    run_dir = tmp_path / "w" / "runs" / "theta0" / "seed3" / "out" / "runs" / "0"
    assert json.loads((run_dir / "run.json").read_text())["status"] == "interrupted"
    assert (run_dir / "checkpoint.state").is_file()
    assert not (tmp_path / "r" / "theta0" / "seed3").exists()
    status = campaign(plan, tmp_path / "w", tmp_path / "r", "--status")
    assert "theta0/seed3" in status.stdout and "interrupted, step" in status.stdout and "1 in progress" in status.stdout

    second = campaign(plan, tmp_path / "w", tmp_path / "r", *run_args("--progress-every", "0.5"))
    assert "start theta0/seed3 (resumes: interrupted" in second.stdout
    # From the second report on, the cores the running engine got (its own /proc times).
    # At most 1.1 of its one thread: /proc counts in 10 ms ticks, up to 0.04 over a 0.5 s window.
    got = [float(x) for x in re.findall(r"; (\d+\.\d\d) of 1 core\(s\) to it", second.stdout)]
    assert got and all(0.0 < x <= 1.1 for x in got), second.stdout
    same_stored_bytes(tmp_path / "r" / "theta0" / "seed3", reference)
    assert provenance(tmp_path / "r", "theta0/seed3")["segments"] == 2
    log = (tmp_path / "w" / "runs" / "theta0" / "seed3" / "engine.log").read_text()
    assert "run 0 resumes at step" in log


POUR_SET = {**TINY_SET, "particles.generate.count": 60, "settle.ke_ratio": 1e-6, "outputs.checkpoint_every": 50}


def test_budget_ending_in_the_pour_leaves_its_checkpoint_and_the_next_invocation_goes_on_from_it(tmp_path):
    # A pour longer than the budget (a bed of 20,000 pours for over an hour): stopped at
    # its checkpoint, resumed by the next invocation, stored with the bytes of a run that
    # never stopped. 60 bodies settled to 1e-6 pour for seconds; the budget stops it
    # after about half a second (a checkpoint every 50 steps).
    plan = write_plan(tmp_path, name="pour", seed_list=(3,), angles=(0,), set=POUR_SET)
    campaign(plan, tmp_path / "w_ref", tmp_path / "r_ref", *run_args())
    first = campaign(plan, tmp_path / "w", tmp_path / "r", "--budget", f"{1.0 / 3600:.8f}", "--stop-margin", "0.5",
                     "--golden-check", "skip", "--run-hours", "0.00001")
    assert "stopping 1 run(s) with SIGTERM" in first.stdout, first.stdout
    out = tmp_path / "w" / "runs" / "theta0" / "seed3" / "out"
    assert len(list((out / "packings").glob("*.state.pour-checkpoint"))) == 1
    assert not list((out / "packings").glob("*.state")) and not (out / "runs").exists()
    status = campaign(plan, tmp_path / "w", tmp_path / "r", "--status")
    assert "theta0/seed3" in status.stdout and "pouring (its checkpoint at step " in status.stdout, status.stdout

    second = campaign(plan, tmp_path / "w", tmp_path / "r", *run_args())
    assert "start theta0/seed3 (resumes: pouring (its checkpoint at step " in second.stdout, second.stdout
    log = (tmp_path / "w" / "runs" / "theta0" / "seed3" / "engine.log").read_text()
    assert ": resumes the pour from " in log
    same_stored_bytes(tmp_path / "r" / "theta0" / "seed3", tmp_path / "r_ref" / "theta0" / "seed3")


def fake_other_engine(results: Path, label: str, golden_check):
    path = results / label / "provenance.json"
    p = json.loads(path.read_text())
    p["engine"].update(binary_sha256="0" * 64, engine_tree="f" * 40, engine_commit="deadbeef" * 5,
                       engine_dirty=False)
    p["golden_check"] = golden_check
    path.write_text(json.dumps(p))


def test_stale_results_are_rerun_and_golden_checked_ones_reused(tiny, tmp_path):
    root, plan, _ = tiny
    results, work = tmp_path / "results", tmp_path / "work"
    shutil.copytree(root / "results", results)
    state = golden.golden_state()
    passed = {"passed": True, **state, "command": "regression/run --all --tol-scale 0"}
    fake_other_engine(results, "theta0/seed1", None)          # no golden pass recorded: stale
    fake_other_engine(results, "theta6/seed1", passed)        # golden pass on both: reused
    # The current engine's golden check, as if run (the cache regression/run would fill).
    engine = identify(RATCHET)
    cache = golden.cache_file(work, engine, state)
    cache.parent.mkdir(parents=True)
    cache.write_text(json.dumps({**passed, "engine": engine.record()}))

    status = campaign(plan, work, results, "--status")
    line = next(l for l in status.stdout.splitlines() if "theta0/seed1" in l)
    assert "STALE" in line and "no golden pass recorded" in line and "deadbeef" in line
    line = next(l for l in status.stdout.splitlines() if "theta6/seed1" in l)
    assert "stored" in line and "bit-for-bit golden check" in line, line
    assert "3 of 4 runs stored and current, 1 stale" in status.stdout

    rerun = campaign(plan, work, results, *run_args())
    assert "start theta0/seed1 (new; rerun of a stale result" in rerun.stdout
    assert "start theta6/seed1" not in rerun.stdout and "start theta0/seed2" not in rerun.stdout
    p = provenance(results, "theta0/seed1")
    assert p["engine"]["binary_sha256"] == engine.binary_sha256
    assert p["golden_check"]["passed"] is True          # the current engine's record
    assert (results / "theta0/seed1/cycles.csv").read_bytes() == \
        (root / "results" / "theta0/seed1/cycles.csv").read_bytes()


def test_an_earlier_engine_rechecked_on_newer_golden_data_keeps_its_runs(tiny, tmp_path):
    # The stored runs' engine: the same program with a byte appended (another SHA-256,
    # the same arithmetic), checked when stored on golden data that has since moved on.
    root, plan, _ = tiny
    results, work = tmp_path / "results", tmp_path / "work"
    shutil.copytree(root / "results", results)
    old_binary = tmp_path / "old" / "ratchet"
    old_binary.parent.mkdir()
    old_binary.write_bytes(RATCHET.read_bytes() + b"\0")
    old_binary.chmod(0o755)
    state = golden.golden_state()
    earlier = {"passed": True, "golden_tree": "0" * 40, "golden_dirty": False}
    for label in ("theta6/seed1", "theta6/seed2"):
        fake_other_engine(results, label, earlier)
        path = results / label / "provenance.json"
        p = json.loads(path.read_text())
        p["engine"]["binary_sha256"] = file_sha256(old_binary)
        path.write_text(json.dumps(p))
    engine = identify(RATCHET)
    cache = golden.cache_file(work, engine, state)
    cache.parent.mkdir(parents=True)
    cache.write_text(json.dumps({"passed": True, **state, "engine": engine.record()}))
    line = next(l for l in campaign(plan, work, results, "--status").stdout.splitlines() if "theta6/seed1" in l)
    assert "STALE" in line and "different golden data (--recheck-golden" in line, line

    # A binary no stored run names: nothing to check. One that fails the check: nothing written.
    failing = tmp_path / "failing" / "ratchet"
    failing.parent.mkdir()
    failing.write_text(f"#!/bin/sh\n[ \"$1\" = --version ] && exec {RATCHET} --version\nexit 3\n")
    failing.chmod(0o755)
    none = campaign(plan, work, results, "--recheck-golden", str(failing), check=False)
    assert none.returncode == 2 and "no stored run of plan tiny" in none.stdout
    for label in ("theta6/seed1", "theta6/seed2"):
        p = json.loads((results / label / "provenance.json").read_text())
        p["engine"]["binary_sha256"] = file_sha256(failing)
        (results / label / "provenance.json").write_text(json.dumps(p))
    failed = campaign(plan, work / "f", results, "--recheck-golden", str(failing), check=False)
    assert failed.returncode == 1 and "failed" in failed.stdout, failed.stdout + failed.stderr
    assert golden.RECHECKS not in provenance(results, "theta6/seed1")

    for label in ("theta6/seed1", "theta6/seed2"):
        p = json.loads((results / label / "provenance.json").read_text())
        p["engine"]["binary_sha256"] = file_sha256(old_binary)
        (results / label / "provenance.json").write_text(json.dumps(p))
    done = campaign(plan, work, results, "--recheck-golden", str(old_binary))
    assert "passed; recorded in 2 of its 2 stored run(s)" in done.stdout, done.stdout
    p = provenance(results, "theta6/seed1")
    assert [c["golden_tree"] for c in p[golden.RECHECKS]] == [state["golden_tree"]]
    assert p["golden_check"] == earlier   # the record made when it was stored stays
    status = campaign(plan, work, results, "--status").stdout
    assert "4 of 4 runs stored and current, 0 stale" in status, status
    again = campaign(plan, work, results, "--recheck-golden", str(old_binary))
    assert "recorded in 0 of its 2 stored run(s) (all had it)" in again.stdout


@pytest.mark.parametrize("change, field", [
    ({"seeds": None}, "field 'seeds': missing"),
    ({"seeds": [1, "2"]}, "field 'seeds': expected a non-empty list of integers >= 0"),
    ({"run_cost_hours": 0}, "field 'run_cost_hours': expected a number > 0"),
    ({"sedes": [1]}, "field 'sedes': unknown field"),
    ({"scene": "no/such/scene.json"}, "field 'scene': cannot read"),
    ({"points": [{"name": "a b", "set": {}}]}, "field 'points[0].name'"),
    ({"parts": [{"name": "angle", "sweep": "container.opening_angle_deg", "points": ["theta9"]}]},
     "field 'parts[0].points[0]': no point named 'theta9'"),
    ({"points": [{"name": "theta0", "set": {"solver.p_gap": -1, "container.opening_angle_deg": 0}},
                 {"name": "theta6", "set": {"container.opening_angle_deg": 6}}]},
     "field 'points[0].set.solver.p_gap' (point 'theta0'): the engine refuses its scene"),
], ids=["no-seeds", "seed-type", "run-cost", "unknown", "scene", "point-name", "part-point", "engine-refuses"])
def test_bad_plan_files_are_refused_naming_the_file_and_the_field(tmp_path, change, field):
    plan = write_plan(tmp_path, name="bad", **change)
    done = campaign(plan, tmp_path / "work", tmp_path / "results", *run_args(), check=False)
    assert done.returncode == 2, done.stdout + done.stderr
    assert str(plan) in done.stderr and field in done.stderr, done.stderr
    assert "Traceback" not in done.stderr
    assert not (tmp_path / "results").exists() and not (tmp_path / "work" / "runs").exists()


def test_assembled_sweep_folders_read_as_sweeps(tiny, tmp_path):
    root, plan, _ = tiny
    campaign(plan, root / "work", root / "results", "--assemble", str(tmp_path / "sweeps"))
    sweep = load_sweep(tmp_path / "sweeps" / "angle")
    assert sweep.kinds == ["angle"] and len(sweep.completed) == 4 and not sweep.failed_runs
    assert sorted(sweep.completed["seed"]) == [1, 1, 2, 2]
    assert sorted(sweep.completed["container.opening_angle_deg"]) == [0, 0, 6, 6]
    for run in sweep.completed["run"]:
        folder = tmp_path / "sweeps" / "angle" / "runs" / str(run)
        assert read_cycles(folder) is not None and displacement_files(folder)
    assert not list((tmp_path / "sweeps").glob(".*"))      # no half-built folder left


def test_commit_makes_one_commit_per_stored_run(tmp_path):
    repo = tmp_path / "repo"
    repo.mkdir()
    for args in (["init", "-q"], ["config", "user.email", "t@example.org"], ["config", "user.name", "t"]):
        subprocess.run(["git", "-C", str(repo), *args], check=True)
    (repo / "other.txt").write_text("staged, not to be committed\n")
    subprocess.run(["git", "-C", str(repo), "add", "other.txt"], check=True)
    plan = write_plan(tmp_path, name="one", seed_list=(1,), angles=(0, 6))
    done = campaign(plan, tmp_path / "work", repo / "results", *run_args("--commit"))
    assert done.stdout.count("committed ") == 2
    log = subprocess.run(["git", "-C", str(repo), "log", "--format=%s", "--name-only"], capture_output=True,
                         text=True, check=True).stdout
    assert "campaign one: store theta0/seed1 (engine " in log and "campaign one: store theta6/seed1" in log
    assert "other.txt" not in log
    assert "results/theta0/seed1/provenance.json" in log


def test_the_stage_fields_of_figs_5_and_6_are_kept_and_the_bulky_files_are_not():
    from campaign_lib import store
    kept = ["run.json", "cycles.csv", "wall_profile.csv", "stage_fields.csv", "displacement_10_20.csv"]
    assert all(store.KEEP.match(name) for name in kept)
    assert not any(store.KEEP.match(name) for name in ["timeseries.csv", "bodies.csv", "bodies_shapes.json",
                                                       "checkpoint.state", "stage_fields.csv.partial"])


def test_threads_reach_each_engine_and_are_recorded_with_the_same_results(tiny, tmp_path):
    # The sweep runs each run on the threads it is given (it set one per run before, so
    # OMP_NUM_THREADS alone never reached a run), and says so in its log.
    root, _, _ = tiny
    plan = write_plan(tmp_path, name="threads", seed_list=(1,), angles=(0,))
    done = campaign(plan, tmp_path / "w", tmp_path / "r", *run_args("--threads", "2"))
    assert "1 at a time on 2 thread(s) each" in done.stdout, done.stdout
    log = (tmp_path / "w" / "runs" / "theta0" / "seed1" / "engine.log").read_text()
    assert "1 job(s) per rank, 2 thread(s) per run" in log and "--threads 2" in log, log
    p = provenance(tmp_path / "r", "theta0/seed1")
    assert p["threads"] == 2
    # abs 0.1: both are rounded to 0.1 s when stored.
    assert p["one_thread_seconds"] == pytest.approx(p["cpu_seconds"] / 2 / 0.74, abs=0.1)
    ledger = json.loads((tmp_path / "w" / "runs" / "theta0" / "seed1" / "ledger.json").read_text())
    assert [s["threads"] for s in ledger["segments"]] == [2]
    # The same scene and seed as the one-thread run of the fixture: the same bytes.
    ours, theirs = tmp_path / "r" / "theta0" / "seed1", root / "results" / "theta0" / "seed1"
    assert (ours / "cycles.csv").read_bytes() == (theirs / "cycles.csv").read_bytes()
    summary = [json.loads((d / "run.json").read_text())["summary"] for d in (ours, theirs)]
    assert summary[0] == summary[1]
    bad = campaign(plan, tmp_path / "w", tmp_path / "r", "--budget", "1", "--threads", "0", check=False)
    assert bad.returncode == 2 and "--threads: expected a whole number >= 1 (threads per run), got '0'" in bad.stderr


class _Stored:
    def __init__(self, provenance):
        self.provenance = provenance


class _State:
    def __init__(self, provenance, point="p"):
        self.stored = _Stored(provenance)
        self.run = SimpleNamespace(point=SimpleNamespace(name=point))


def test_the_estimate_is_the_stored_runs_cpu_time_scaled_by_the_thread_factor():
    from campaign_lib import state

    class _Engine:
        def record(self):
            return {"engine_tree": "t", "binary_sha256": "b"}

    engine = {"engine_tree": "old", "binary_sha256": "x"}
    # Two one-thread runs that took 3.0 h of wall beside other work for 2.5 h and 2.4 h
    # of CPU, and one two-thread run: CPU 2 x 1.8 h of wall, whose one-thread cost is
    # 1.8 h / 0.74 = 2.43 h.
    factor = state.thread_factor(2)
    assert factor == pytest.approx(0.74)
    states = [_State({"cpu_seconds": 2.5 * 3600, "wall_seconds": 3.0 * 3600, "engine": engine}),
              _State({"cpu_seconds": 2.4 * 3600, "wall_seconds": 3.0 * 3600, "engine": engine}),
              _State({"cpu_seconds": 3.6 * 3600, "wall_seconds": 1.8 * 3600, "threads": 2, "engine": engine})]

    class _Plan:
        run_cost_hours = 2.0
    one = state.estimate(_Plan(), states, _Engine(), None)
    assert one.seconds == pytest.approx(1.8 * 3600 / 0.74) and "median CPU time of 3 stored run(s)" in one.source
    two = state.estimate(_Plan(), states, _Engine(), None, threads=2)
    assert two.seconds == pytest.approx(1.8 * 3600) and "x 0.74 on 2 threads" in two.source
    assert state.one_thread_seconds(states[2].stored.provenance) == pytest.approx(1.8 * 3600 / 0.74)
    assert state.estimate(_Plan(), [], _Engine(), None, threads=2).seconds == pytest.approx(2.0 * 3600 * 0.74)
    assert state.estimate(_Plan(), states, _Engine(), 1.5, threads=2).seconds == 1.5 * 3600
    # The current engine's runs count alone from MIN_OWN_RUNS on: one fast run of it is no median.
    current = {"engine_tree": "t", "binary_sha256": "b"}
    own = [_State({"cpu_seconds": 1.0 * 3600, "engine": current})]
    assert state.estimate(_Plan(), states + own, _Engine(), None).seconds == pytest.approx((2.4 + 1.8 / 0.74) / 2 * 3600)
    own = [_State({"cpu_seconds": h * 3600, "engine": current}) for h in (1.0, 1.1, 1.2)]
    mine = state.estimate(_Plan(), states + own, _Engine(), None)
    assert mine.seconds == pytest.approx(1.1 * 3600) and "3 current engine's run(s)" in mine.source
    # A point with stored runs of its own is estimated by them (the paper bed's cost depends
    # on the point); the others by the median over all.
    cheap = [_State({"cpu_seconds": h * 3600, "engine": current}, point="ratio1") for h in (0.4, 0.5)]
    both = state.estimate(_Plan(), states + own + cheap, _Engine(), None, threads=2)
    ratio1, other = SimpleNamespace(point=SimpleNamespace(name="ratio1")), SimpleNamespace(point=SimpleNamespace(name="q"))
    assert both.for_run(ratio1) == pytest.approx(0.45 * 3600 * 0.74)
    assert "2 stored run(s) of ratio1" in both.source_for(ratio1)
    assert both.for_run(other) == both.seconds == pytest.approx(1.0 * 3600 * 0.74)  # the 5 current runs' median
    assert state.estimate(_Plan(), states + cheap, _Engine(), 1.5).for_run(ratio1) == 1.5 * 3600  # --run-hours: every run
    # A run of one- and two-thread segments stores its one-thread cost summed by segment.
    assert state.one_thread_seconds({"cpu_seconds": 9.0, "threads": 2, "one_thread_seconds": 7.0}) == 7.0
    assert state.thread_factor(1) == 1.0 and state.thread_factor(16) == pytest.approx(0.48 + 0.52 / 16)


def test_with_a_minimum_slice_a_run_that_fits_starts_before_one_that_would_stop_at_a_checkpoint(capsys):
    # Only a finished run is stored whatever becomes of the work folder, so a slice comes
    # after the runs that fit (the paper plan's ratio-5 runs, 3.6 h, came first in its order
    # and took a session's budget from a 2.2 h run at ratio 2.5, 2026-12-02).
    from campaign_lib import cli, state
    from campaign_lib.runner import Runner
    assert state.choose([3.6, 2.2, 2.0], 2.8, 0.0) == (1, True)
    assert state.choose([3.6, 3.8], 2.8, 0.3) == (0, False)
    assert state.choose([3.6, 3.8], 0.2, 0.3) == (None, False)
    assert state.choose([3.6, 3.8], 2.8, 0.0) == (None, False)
    assert state.choose([], 2.8, 0.3) == (None, False)

    class _Progress:
        fraction = 0.0

        def text(self):
            return "not started"

    def queued(label, hours):
        run = SimpleNamespace(label=label, point=SimpleNamespace(name=label), hours=hours)
        return SimpleNamespace(run=run, progress=_Progress(), stale=False, done=False, started=False,
                               verdict=None, folder=SimpleNamespace(progress=_Progress))

    def queue():
        return [queued("ratio5/seed2", 3.6), queued("ratio2.5/seed3", 2.2), queued("ratio7.5/seed2", 3.8)]
    estimate = SimpleNamespace(seconds=3600.0, source="test",
                               for_run=lambda run: run.hours * 3600.0, by_point={})
    runner = Runner.__new__(Runner)
    runner.estimate, runner.binary_changed, runner.say = estimate.for_run, False, lambda text: None
    runner.left = lambda: 2.8 * 3600.0
    runner.min_slice = 1200.0
    q = queue()
    assert runner._next_fitting(q).run.label == "ratio2.5/seed3"
    assert [s.run.label for s in q] == ["ratio5/seed2", "ratio7.5/seed2"]   # kept for a slice
    runner.left = lambda: 0.6 * 3600.0
    assert runner._next_fitting(q).run.label == "ratio5/seed2"             # the plan's order
    runner.min_slice, q = 0.0, queue()
    runner.left = lambda: 2.8 * 3600.0
    assert runner._next_fitting(q).run.label == "ratio2.5/seed3" and [s.run.label for s in q] == ["ratio7.5/seed2"]
    assert runner._next_fitting(q) is None and q == []
    # The dry run says the same order.
    cli.print_dry_run(queue(), estimate, 2.8 * 3600.0, 1, 1200.0)
    lines = [line for line in capsys.readouterr().out.splitlines() if "/seed" in line]
    assert "ratio2.5/seed3" in lines[0] and "+0.0 s" in lines[0] and "[" not in lines[0], lines
    assert "ratio5/seed2" in lines[1] and "+2.20 h" in lines[1] and "[stops at a checkpoint" in lines[1], lines
    assert "ratio7.5/seed2" in lines[2] and "[not within the budget]" in lines[2], lines


def test_the_engine_id_follows_the_binary_sources_not_its_tests_or_benchmarks(tmp_path):
    def commit(path, text):
        (tmp_path / path).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / path).write_text(text)
        subprocess.run(["git", "-C", str(tmp_path), "add", "-A"], check=True)
        subprocess.run(["git", "-C", str(tmp_path), "-c", "user.name=t", "-c", "user.email=t@t", "commit",
                        "-qm", path], check=True)
        return sources_state(ENGINE_SOURCES, repo=tmp_path)

    subprocess.run(["git", "init", "-q", str(tmp_path)], check=True)
    for path in ENGINE_SOURCES:
        file = tmp_path / (path if path.endswith(".txt") else f"{path}/a.cpp")
        file.parent.mkdir(parents=True, exist_ok=True)
        file.write_text("# engine\n")
    first = commit("reference_engine/tests/t.cpp", "// test\n")
    assert first["commit"] and first["tree"] and not first["dirty"]
    assert commit("reference_engine/bench/b.cpp", "// bench\n") == first
    assert commit("reference_engine/tests/t.cpp", "// test, changed\n") == first
    (tmp_path / "reference_engine/bench/b.cpp").write_text("// uncommitted\n")
    assert sources_state(ENGINE_SOURCES, repo=tmp_path) == first
    changed = commit("reference_engine/src/a.cpp", "// engine, changed\n")
    assert changed["tree"] != first["tree"] and changed["commit"] != first["commit"]
    (tmp_path / "reference_engine/app/new.cpp").write_text("// untracked\n")
    assert sources_state(ENGINE_SOURCES, repo=tmp_path)["dirty"]


def stand_in_engine(folder: Path, version: str) -> Path:
    """A program that answers --version with `version` and otherwise runs the real engine."""
    folder.mkdir(parents=True, exist_ok=True)
    binary = folder / "ratchet"
    binary.write_text(f"#!/bin/sh\n[ \"$1\" = --version ] && {{ printf '%s\\n' {shlex.quote(version)}; exit 0; }}\n"
                      f"exec {RATCHET} \"$@\"\n")
    binary.chmod(0o755)
    return binary


def test_the_campaign_computes_the_source_hash_the_build_printed():
    # engine.py recomputes what reference_engine/cmake/build_info.cmake hashed; the two
    # must agree, or every current build would be taken for one of other sources.
    engine = identify(RATCHET)
    assert engine.source_hash and len(engine.source_hash) == 16
    assert engine.sources_hash == engine.source_hash and not engine.built_elsewhere


def test_a_binary_built_from_other_sources_is_named_by_its_sha256(tmp_path):
    # The sources' commit names a binary only if it was built from them (a run's record
    # once named the wrong commit so): its source hash says whether it was, whatever
    # its age; a binary too old to say is judged by its age.
    real = identify(RATCHET)
    copy = tmp_path / "copy" / "ratchet"
    copy.parent.mkdir()
    shutil.copy2(RATCHET, copy)
    os.utime(copy, (1, 1))                          # 1970: older than every source file
    old_copy = identify(copy)
    assert not old_copy.built_elsewhere and old_copy.dirty == real.dirty and old_copy.source_hash == real.source_hash

    lines = real.version.splitlines() + version_lines(RATCHET)
    other = "\n".join(l if not l.startswith("source hash: ") else "source hash: 0123456789abcdef" for l in lines)
    elsewhere = identify(stand_in_engine(tmp_path / "other", other))
    assert elsewhere.built_elsewhere and elsewhere.dirty and elsewhere.key == f"bin-{elsewhere.binary_sha256[:16]}"
    assert elsewhere.record()["engine_dirty"] and elsewhere.record()["source_hash"] == "0123456789abcdef"
    assert elsewhere.version == real.version == lines[0] and elsewhere.tree == real.tree

    mute = stand_in_engine(tmp_path / "mute", lines[0])    # the first line only: built before 2026-12-06
    os.utime(mute, (1, 1))
    old = identify(mute)
    assert old.source_hash is None and old.stale and old.built_elsewhere and old.dirty
    os.utime(mute, None)                            # now: newer than every source file
    new = identify(mute)
    assert not new.stale and not new.built_elsewhere and new.dirty == real.dirty


def test_a_binary_built_at_an_earlier_commit_is_named_by_that_commits_sources(tmp_path):
    # A binary kept from an earlier build (out/bin/ratchet-<commit>) says the commit it was
    # built at; when that commit's engine sources give the binary's source hash it is that
    # commit's engine, not a "+dirty" HEAD (a stored run once named the checkout's later
    # commit so), and its work-folder key is the same tree key it had when it was current.
    from campaign_lib.engine import source_hash, source_hash_at
    repo = tmp_path / "repo"

    def commit(files: dict) -> str:
        for path, text in files.items():
            (repo / path).parent.mkdir(parents=True, exist_ok=True)
            (repo / path).write_text(text)
        subprocess.run(["git", "-C", str(repo), "add", "-A"], check=True)
        subprocess.run(["git", "-C", str(repo), "-c", "user.name=t", "-c", "user.email=t@t", "commit", "-qm", "c"],
                       check=True)
        return subprocess.run(["git", "-C", str(repo), "rev-parse", "HEAD"], capture_output=True, text=True,
                              check=True).stdout.strip()

    subprocess.run(["git", "init", "-q", str(repo)], check=True)
    first = commit({"CMakeLists.txt": "project(x)\n", "reference_engine/CMakeLists.txt": "add_library(r)\n",
                    "reference_engine/src/r/a.cpp": "int a;\n", "reference_engine/src/r/a.hpp": "int a();\n",
                    "reference_engine/app/main.cpp": "int main(){}\n", "reference_engine/src/notes.md": "not hashed\n"})
    real = identify(RATCHET)
    facts = dict(line.split(": ", 1) for line in version_lines(RATCHET))
    build_type, compiler = real.version[real.version.rindex("(") + 1:-1], facts["compiler"]
    first_hash = source_hash(build_type, compiler, repo)
    assert source_hash_at(first, build_type, compiler, repo) == first_hash   # git's blobs hash as the files do
    first_tree = sources_state(ENGINE_SOURCES, repo=repo)["tree"]
    later = commit({"reference_engine/src/r/a.cpp": "int a = 1;\n"})
    assert source_hash_at(later, build_type, compiler, repo) == source_hash(build_type, compiler, repo) != first_hash

    def stand_in(name: str, commit_line: str, hash_: str) -> Path:
        return stand_in_engine(tmp_path / name, f"{real.version}\ncommit: {commit_line}\nsource hash: {hash_}\n"
                                                f"compiler: {compiler}")

    kept = identify(stand_in("kept", first, first_hash), repo=repo)
    assert kept.built_elsewhere and kept.built_at == first and kept.commit == first and not kept.dirty
    assert kept.tree == first_tree and kept.key == f"tree-{first_tree[:16]}" and kept.short == first[:10]
    assert kept.record()["built_at"] == first and not kept.record()["engine_dirty"]
    # Built while some tracked file was modified: the hash says whether the engine's were.
    docs_only = identify(stand_in("docs", first + "+modified", first_hash), repo=repo)
    assert docs_only.built_at == first and docs_only.key == kept.key and not docs_only.dirty
    # Not named by the commit: engine files modified (a hash the commit does not give, with
    # or without "+modified"), a commit this repository does not have.
    for name, line, hash_ in (("modified", first + "+modified", "0123456789abcdef"),
                              ("other", first, "0123456789abcdef"), ("unknown", "f" * 40, first_hash)):
        engine = identify(stand_in(name, line, hash_), repo=repo)
        assert engine.built_at is None and engine.dirty and engine.key == f"bin-{engine.binary_sha256[:16]}", name
        assert engine.commit == later and "built_at" not in engine.record(), name


def version_lines(binary: Path) -> list:
    """The lines of `binary --version` after the first."""
    done = subprocess.run([str(binary), "--version"], capture_output=True, text=True, check=True)
    return done.stdout.splitlines()[1:]


def test_the_progress_report_gives_the_pace_and_the_time_to_go():
    from campaign_lib.pace import Pace
    pace = Pace()
    pace.add(0.0, 1000)
    assert pace.text(total=100_000, left_seconds=3600.0) == ""        # one mark: no pace yet
    pace.add(600.0, 13_000)                                             # 1200 steps a minute
    first = pace.text(total=100_000, left_seconds=7200.0)
    assert "1200 steps a minute" in first and "about 1.21 h to go" in first and "(within the budget)" in first
    assert "not within the budget" in pace.text(total=100_000, left_seconds=3600.0)
    pace.add(1200.0, 13_400)            # 40 a minute: a ramp of the bed of 20,000 after its hold, on a quiet machine
    slow = pace.text(total=100_000, left_seconds=7200.0)
    assert "40 steps a minute" in slow and "WARNING" not in slow   # the pace alone is no sign of other work
    pace.add(2400.0, None)              # no step read (the engine between files): no mark
    assert len(pace.marks) == 3


def test_the_report_warns_when_other_work_takes_the_engines_cores():
    # Alone a two-thread run got 1.93 of 2 cores (the bed of 20,000 cooling, 2026-12-07);
    # beside a job of the same priority 1.2 of 2 (docs/campaign.md).
    from campaign_lib.pace import CpuShare, fair_cores
    share = CpuShare()
    share.add(0.0, None)                # the engine gone: no mark
    share.add(600.0, 5000.0)
    assert share.text(2) == ""          # one mark: no window yet
    share.add(1200.0, 5000.0 + 1.93 * 600)
    quiet = share.text(2)
    assert "1.93 of 2 core(s) to it" in quiet and "WARNING" not in quiet
    share.add(1800.0, 5000.0 + 1.93 * 600 + 1.2 * 600)
    crowded = share.text(2)
    assert "1.20 of 2 core(s)" in crowded and "WARNING: other work takes its cores" in crowded
    assert "nice -n 19" in crowded
    assert "WARNING" not in share.text(1)   # one thread's worth: 1.2 of 1 is no crowding
    # Two two-thread engines of the campaign on two cores: each can have one core.
    assert fair_cores(2, 4, 2) == 1.0 and fair_cores(2, 2, 2) == 2.0 and fair_cores(1, 2, 8) == 1.0


def test_the_cpu_seconds_of_a_running_engine_and_its_children_are_read_while_it_runs():
    import psutil
    from campaign_lib.pace import process_cpu_seconds
    # A launcher (sh) whose child spins for half a second of CPU, then waits: the time is the
    # child's. The deadline is wall time for a loaded machine (a test run at nice 19 beside a
    # campaign gets a few per cent of a core).
    busy = "import time\nt = time.process_time()\nwhile time.process_time() - t < 0.5: pass\ntime.sleep(600)"
    proc = subprocess.Popen(["sh", "-c", f"{sys.executable} -c '{busy}'"])
    try:
        cpu, deadline = 0.0, time.monotonic() + 300.0
        while cpu < 0.45 and time.monotonic() < deadline:
            time.sleep(0.2)
            cpu = process_cpu_seconds(proc.pid)
        # 0.45: the half second less /proc's 10 ms ticks; below 1.5: not counted twice (1.0
        # and more), with room for the interpreter's start on a slow machine.
        assert 0.45 <= cpu < 1.5, cpu
    finally:
        for child in psutil.Process(proc.pid).children(recursive=True):
            child.kill()
        proc.kill()
        proc.wait()
    assert process_cpu_seconds(proc.pid) is None   # reaped: gone


def test_a_report_that_sees_no_new_step_gives_no_pace_and_no_warning():
    # The growing timeseries reaches the disk at the engine's checkpoints: a run slower than
    # a checkpoint per report (the bed of 8000 at 200 steps a minute, checkpoints every 2000
    # steps, reports every 10 minutes) shows the same step twice. That window is no pace of
    # 0 and no warning; the next step seen ends a window over both reports.
    from campaign_lib.pace import Pace
    new = Pace()
    new.add(600.0, 8000)                                                # a new run's first report
    new.add(1200.0, 8000)                                               # none since: not since its start
    assert "no step written since the last report" in new.text(total=29_389, left_seconds=7200.0)
    pace = Pace()
    pace.resume(0.0, 8000)
    pace.add(600.0, 8000)                                               # resumed at 8000, none since
    assert "no step written since it started" in pace.text(total=14_570, left_seconds=7200.0)
    pace.add(600.0, 10_000)                                             # 200 steps a minute
    assert "200 steps a minute" in pace.text(total=14_570, left_seconds=7200.0)
    pace.add(1200.0, 10_000)                                            # no checkpoint since
    same = pace.text(total=14_570, left_seconds=7200.0)
    assert "no step written since the last report" in same and "WARNING" not in same and "0 steps" not in same
    assert len(pace.marks) == 2
    pace.add(1800.0, 14_000)                                            # 4000 steps over 20 minutes
    after = pace.text(total=14_570, left_seconds=7200.0)
    assert "200 steps a minute" in after and "WARNING" not in after


def test_the_pace_counts_a_step_from_when_it_reached_the_disk_not_from_the_report(tmp_path):
    # A resumed run of the bed of 20,000 wrote its first checkpoint 73 steps after its start;
    # the report ten minutes later read that step and gave 7 steps a minute for about 150.
    from campaign_lib.pace import Pace, seen_at
    from campaign_lib.workdir import GROWING, RunFolder
    folder = RunFolder(tmp_path, SimpleNamespace(point=SimpleNamespace(name="p"), seed=1))
    folder.run_dir.mkdir(parents=True)
    growing = folder.run_dir / f"timeseries.csv.{GROWING}"
    growing.write_text("step,t\n9950,1.0\n10000,1.2\n10001,1.")       # the last row cut mid-write
    os.utime(growing, (1_000_035.0, 1_000_035.0))
    progress = folder.progress()
    assert progress.step == 10000 and progress.step_time == 1_000_035.0

    pace = Pace()
    pace.resume(0.0, 9927)                                              # resumed at its checkpoint
    pace.add(seen_at(600.0, progress.step_time, wall_now=1_000_600.0), progress.step)
    assert pace.marks[-1] == (35.0, 10000)
    assert "125 steps a minute" in pace.text(total=14_389, left_seconds=3000.0)
    assert seen_at(600.0, None, 1e6) == 600.0                           # no file time: the report's
    assert seen_at(600.0, 1_000_700.0, wall_now=1_000_600.0) == 600.0   # a file time ahead of the clock


def test_the_engine_runs_in_the_campaigns_session_in_a_process_group_of_its_own():
    # An engine in a session of its own ran at about a ninth of its pace beside a nice-19
    # job (docs/performance.md, nineteenth installment).
    from campaign_lib.runner import ENGINE_PROCESS
    child = subprocess.Popen(["sleep", "30"], **ENGINE_PROCESS)
    try:
        assert os.getpgid(child.pid) == child.pid != os.getpgid(0)
        assert os.getsid(child.pid) == os.getsid(0)
        ours, theirs = Path("/proc/self/autogroup"), Path(f"/proc/{child.pid}/autogroup")
        if ours.is_file():   # kernels built with CONFIG_SCHED_AUTOGROUP
            # Empty for both when the tasks sit in a cgroup (containers): no autogroup then.
            assert theirs.read_text() == ours.read_text()
    finally:
        child.kill()
        child.wait()


def test_the_volume_series_is_kept_as_written_and_only_it(tmp_path):
    from campaign_lib import store
    from campaign_lib.plan import Point, Run
    run_dir = tmp_path / "run"
    run_dir.mkdir()
    (run_dir / "run.json").write_text('{"status": "completed"}')
    (run_dir / "timeseries.csv").write_text(
        "step,t,T,pressure,V_over_V0\n"
        "0,0,0,1.5,1\n"
        "100,0.40000000000000002,4,2.5,0.99901234567890123\n"
        "200,0.8,8,3")  # the cut last line of an interrupted write
    run = Run(Point("theta0", {}, (1,)), 1)
    folder = store.store(tmp_path / "results", run, run_dir, {"format": 1})
    assert (folder / "volume.csv").read_text() == (
        "step,t,T,V_over_V0\n0,0,0,1\n100,0.40000000000000002,4,0.99901234567890123\n")
    files = json.loads((folder / "provenance.json").read_text())["files"]
    assert set(files) == {"run.json", "volume.csv"} and files["volume.csv"]["bytes"] == 73
    # A scene without outputs.volume has no series to keep.
    (run_dir / "timeseries.csv").write_text("step,t,T,pressure\n0,0,0,1\n")
    folder = store.store(tmp_path / "results", run, run_dir, {"format": 1})
    assert not (folder / "volume.csv").exists()


@pytest.mark.parametrize("code, stage, stopping, expected", [
    (0, "completed", False, "store"),
    (0, "completed", True, "store"),
    # Completed as the SIGTERM came: the sweep winds down with a non-zero status, the run
    # itself is whole (run.json is written last).
    (143, "completed", True, "store"),
    (1, "interrupted", True, "stopped"),
    (0, "running", True, "stopped"),
    (1, "failed", True, "failed"),
    # Not stopped by the campaign: a non-zero exit is a failure whatever the folder says.
    (1, "completed", False, "failed"),
    (1, "interrupted", False, "failed"),
])
def test_a_finished_engine_is_judged_by_its_folder_then_by_its_exit(code, stage, stopping, expected):
    assert exit_outcome(code, stage, stopping) == expected


def test_finish_one_waits_while_the_pair_can_and_gives_the_lead_every_thread_at_the_last_moment():
    from campaign_lib.gather import Running, lead_to_finish
    # The paper bed near a session's end: a pair at 840 steps a minute each on one thread;
    # alone on two threads a run goes 1/0.74 = 1.35 times that by the thread model.
    pair = lambda left_a, left_b: [Running("a", left_a, 14.0, 1), Running("b", left_b, 14.0, 1)]
    hour = 3600.0
    # 50,000 steps left each: 1.0 h in the pair. With 1.5 h left the pair finishes: wait.
    assert lead_to_finish(pair(50_000, 50_000), 2, 1.5 * hour, nothing_else_starts=True) is None
    # 60,000 and 40,000 left: neither finishes in the pair (4286 s, 2857 s). b alone needs
    # 2114 s, 2491 s with its safety (x 1.15 + 60 s); after one more minute in the pair it
    # would need 2440 s, 2501 s with that minute. With 2600 s left: wait.
    assert lead_to_finish(pair(60_000, 40_000), 2, 2600.0, nothing_else_starts=True) is None
    # 2495 s left: b now or never (the lead is the run with the least time alone).
    assert lead_to_finish(pair(60_000, 40_000), 2, 2495.0, nothing_else_starts=True) == 1
    # 2400 s left: b cannot finish even alone: both stop at a checkpoint.
    assert lead_to_finish(pair(60_000, 40_000), 2, 2400.0, nothing_else_starts=True) is None
    # A pace not measured yet: no decision.
    assert lead_to_finish([Running("a", 100, 0.0, 1), Running("b", 100, 5.0, 1)], 2, 60.0, True) is None
    # A last run alone on one of two threads gets the idle one when no other run will start,
    # and not when one may still start, or when it is nearly done.
    assert lead_to_finish([Running("a", 50_000, 14.0, 1)], 2, 2 * hour, nothing_else_starts=True) == 0
    assert lead_to_finish([Running("a", 50_000, 14.0, 1)], 2, 2 * hour, nothing_else_starts=False) is None
    assert lead_to_finish([Running("a", 1000, 14.0, 1)], 2, 2 * hour, nothing_else_starts=True) is None
    assert lead_to_finish([Running("a", 50_000, 20.0, 2)], 2, 2 * hour, nothing_else_starts=True) is None


def finish_one_forced(tmp_path, monkeypatch, capsys) -> str:
    """A pair of 60-cycle runs under --finish-one with the rule's choice forced to
    theta0/seed3 at its first look; returns the campaign's output."""
    from campaign_lib import cli, gather
    plan = write_plan(tmp_path, name="gather", seed_list=(3, 4), angles=(0,), set=LONG_SET)
    seen = []

    def forced(running, all_threads, left, nothing_else_starts, check_every=gather.CHECK_SECONDS):
        seen.append([r.label for r in running])
        labels = [r.label for r in running]
        return labels.index("theta0/seed3") if len(running) == 2 and len(seen) == 1 else None
    monkeypatch.setattr(gather, "lead_to_finish", forced)
    monkeypatch.setattr(gather, "CHECK_SECONDS", 0.0)
    code = cli.main([str(plan), "--out", str(tmp_path / "w"), "--results", str(tmp_path / "r"), "--ratchet",
                     str(RATCHET), "--budget", "0.2", "--golden-check", "skip", "--jobs", "2", "--finish-one",
                     "--progress-every", "0.2"])
    out = capsys.readouterr().out
    assert code == 0, out
    assert "finish one: theta0/seed3 needs about" in out, out
    return out


def test_finish_one_stops_the_pair_and_finishes_the_lead_on_both_threads_with_the_same_bytes(
        tmp_path, monkeypatch, capsys, long_reference):
    # The real engines; the rule's choice is forced (its numbers are the test above), so the
    # stop and the resume on more threads are what is checked: the lead's stored files are
    # those of an uninterrupted one-thread run, its ledger has a segment on 1 and one on 2
    # threads, and the other run waits at its checkpoint for the next invocation.
    out = finish_one_forced(tmp_path, monkeypatch, capsys)
    assert "stopping theta0/seed4 at a checkpoint to give it their threads" in out, out
    assert "theta0/seed3 at a checkpoint (" in out and "it resumes now on 2 thread(s)" in out, out
    assert "stopped theta0/seed4" in out and "1 stored, 1 stopped at a checkpoint, 0 failed" in out, out
    ledger = json.loads((tmp_path / "w" / "runs" / "theta0" / "seed3" / "ledger.json").read_text())
    assert [s["threads"] for s in ledger["segments"]] == [1, 2]
    assert provenance(tmp_path / "r", "theta0/seed3")["threads"] == 2
    same_stored_bytes(tmp_path / "r" / "theta0" / "seed3", long_reference)
    assert not (tmp_path / "r" / "theta0" / "seed4").exists()
    assert (tmp_path / "w" / "runs" / "theta0" / "seed4" / "out" / "runs" / "0" / "checkpoint.state").is_file()


def test_finish_one_stores_a_lead_that_completes_as_it_is_stopped_and_starts_it_no_more(
        tmp_path, monkeypatch, capsys, long_reference):
    # The race the early return in Runner._finish_one is for: the chosen run ends on its own
    # just as the SIGTERMs go out, so _stop_all stores it. Made certain here: on the
    # hand-over the other run's process group is paused (SIGSTOP) while the lead runs to its
    # end (waited for without reaping it, so the runner's own wait4 judges it), then the
    # stop goes on as the runner wrote it. The lead must be stored once, from one segment,
    # and not started again on the idle threads.
    from campaign_lib.runner import Runner
    original = Runner._stop_all

    def stop_all(self, active, outcome):
        lead = [i for i in active.values() if i.handing_over]
        if lead:
            others = [i for i in active.values() if not i.handing_over]
            for o in others:
                os.killpg(o.proc.pid, signal.SIGSTOP)
            os.waitid(os.P_PID, lead[0].proc.pid, os.WEXITED | os.WNOWAIT)
            for o in others:
                os.killpg(o.proc.pid, signal.SIGCONT)
        original(self, active, outcome)
    monkeypatch.setattr(Runner, "_stop_all", stop_all)
    out = finish_one_forced(tmp_path, monkeypatch, capsys)
    assert "it resumes now" not in out and out.count("done theta0/seed3") == 1, out
    assert "stopped theta0/seed4" in out and "1 stored, 1 stopped at a checkpoint, 0 failed" in out, out
    ledger = json.loads((tmp_path / "w" / "runs" / "theta0" / "seed3" / "ledger.json").read_text())
    assert [s["threads"] for s in ledger["segments"]] == [1]
    same_stored_bytes(tmp_path / "r" / "theta0" / "seed3", long_reference)
    assert (tmp_path / "w" / "runs" / "theta0" / "seed4" / "out" / "runs" / "0" / "checkpoint.state").is_file()


@pytest.mark.parametrize("plan_file", sorted((REPO_ROOT / "validation" / "campaigns").glob("*.json")),
                         ids=lambda p: p.name)
def test_every_plan_of_the_repository_loads_and_the_engine_builds_each_point(plan_file, tmp_path):
    # What the campaign checks before any work (cli.check_scenes): a plan that a user
    # starts after hours of other runs must not stop at its first point.
    from campaign_lib import cli, state
    from campaign_lib.plan import load_plan
    plan = load_plan(plan_file)
    engine = identify(RATCHET)
    states = state.survey(plan, tmp_path / "work", tmp_path / "results", engine, None)
    assert states and all(not s.done for s in states)
    cli.check_scenes(plan, states, engine)
