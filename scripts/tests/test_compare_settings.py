"""scripts/compare-settings on a small cycled bed: its table must agree with the runs'
own run.json files, a second call must resume instead of rerunning, and a bad plan must
stop before any work with the file and field named."""

import json
import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from scipy import stats

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from analysis import fields  # noqa: E402
from common.flock import try_lock  # noqa: E402
from common.paths import REPO_ROOT, engine_binary  # noqa: E402

RATCHET = engine_binary()
TOOL = REPO_ROOT / "scripts" / "compare-settings"
SCENE = REPO_ROOT / "validation" / "sweeps" / "bed_quick.json"

pytestmark = pytest.mark.skipif(not RATCHET.is_file(), reason=f"engine not built ({RATCHET})")


def write_plan(folder: Path, **fields) -> Path:
    plan = {"scene": str(SCENE), "seeds": [1, 2],
            "set": {"particles.generate.count": 20, "thermal.cycles": 1, "outputs.steady_cycles": [0, 0],
                    "outputs.displacement": {"cell": 2.0, "windows": [[0, 1]]}},
            "pack_set": {"solver.acceleration": "anderson", "solver.max_iterations": 5000},
            "reference": "rigid",
            "settings": {"rigid": {"solver.acceleration": "anderson", "solver.max_iterations": 5000},
                         "soft": {"solver.acceleration": "anderson", "solver.max_iterations": 5000,
                                  "solver.compliance": 0.1}}}
    plan.update(fields)
    path = folder / "plan.json"
    path.write_text(json.dumps(plan))
    return path


def load_tool():
    """The tool as a module, for its runner's functions."""
    import importlib.machinery
    import importlib.util
    loader = importlib.machinery.SourceFileLoader("compare_settings", str(TOOL))
    spec = importlib.util.spec_from_loader("compare_settings", loader)
    tool = importlib.util.module_from_spec(spec)
    loader.exec_module(tool)
    return tool


def call(*args) -> subprocess.CompletedProcess:
    return subprocess.run(["/usr/bin/python3", str(TOOL), *map(str, args)], capture_output=True, text=True)


@pytest.fixture(scope="module")
def done(tmp_path_factory):
    folder = tmp_path_factory.mktemp("compare")
    plan = write_plan(folder)
    out = folder / "out"
    r = call(plan, "--out", out, "--jobs", "2")
    assert r.returncode == 0, r.stderr
    return plan, out


def test_table_agrees_with_the_runs(done):
    plan, out = done
    res = json.loads((out / "comparison.json").read_text())
    assert res["settings"] == ["rigid", "soft"]
    p_max = {n: [json.loads((out / "runs" / f"{n}-s{s}" / "run.json").read_text())["summary"]["P_max"]
                 for s in (1, 2)] for n in ("rigid", "soft")}
    # rel 1e-12: the same numbers averaged in another order (numpy here, pandas there).
    for n in ("rigid", "soft"):
        e = res["observables"]["P_max"][n]
        assert e["n"] == 2
        assert e["mean"] == pytest.approx(np.mean(p_max[n]), rel=1e-12)
        assert e["se"] == pytest.approx(np.std(p_max[n], ddof=1) / np.sqrt(2), rel=1e-12)
    soft = res["observables"]["P_max"]["soft"]
    assert soft["shift"] == pytest.approx(np.mean(p_max["soft"]) - np.mean(p_max["rigid"]), rel=1e-12)
    assert soft["p"] == pytest.approx(stats.ttest_ind(p_max["soft"], p_max["rigid"], equal_var=False).pvalue)
    assert soft["bias"] == (soft["p"] < 0.05)
    # The compliant runs really ran compliant, from the same packings as the rigid ones.
    for s in (1, 2):
        run = json.loads((out / "runs" / f"soft-s{s}" / "run.json").read_text())
        assert run["scene"]["solver"]["compliance"] == 0.1
        assert run["packing"]["file"].endswith(f"s{s}.state")
    # The overlaps come from the sampled steps after the packing's row; the stiffer law
    # (rigid here) must not overlap more deeply than the compliant one at its worst.
    for n in ("rigid", "soft"):
        depth = [pd.read_csv(out / "runs" / f"{n}-s{s}" / "timeseries.csv")["max_overlap"].iloc[1:].max()
                 for s in (1, 2)]
        assert res["observables"]["max_overlap_max"][n]["mean"] == pytest.approx(np.mean(depth), rel=1e-12)
    assert (res["observables"]["max_overlap_max"]["rigid"]["mean"]
            <= res["observables"]["max_overlap_max"]["soft"]["mean"])
    # The cost is the step's phases (timed over every installment of a resumed run).
    run = json.loads((out / "runs" / "soft-s1" / "run.json").read_text())
    assert res["observables"]["step_seconds"]["soft"]["n"] == 2
    assert 0 < sum(ph["seconds"] for ph in run["phases"]) <= run["wall_seconds"]
    assert (out / "comparison.md").read_text().count("|") > 10
    assert (out / "figures" / "compare_settings.png").stat().st_size > 1000
    # The caption names the plan and its settings (a report tells its figures apart by caption).
    caption = (out / "figures" / "compare_settings.txt").read_text()
    assert caption.startswith(f"Plan {plan.stem}: settings rigid, soft (reference rigid), 2 seeds each;")


def test_the_stage_fields_give_the_still_zone_and_the_circulation(done, tmp_path):
    tool = load_tool()
    run = done[1] / "runs" / "rigid-s1"
    assert not (run / "stage_fields.csv").exists() and "still_zone_f" not in tool.observe(run)
    # The same bed with the stage fields written: the observables are the checks' measures.
    staged_set = {"particles.generate.count": 20, "thermal.cycles": 1, "outputs.steady_cycles": [0, 0],
                  "outputs.displacement": {"cell": 2.0, "windows": [[0, 1]], "stages": True}}
    plan = write_plan(tmp_path, set=staged_set)
    r = call(plan, "--out", tmp_path / "out", "--jobs", "2")
    assert r.returncode == 0, r.stderr
    staged = tmp_path / "out" / "runs" / "rigid-s1"
    row = tool.observe(staged)
    stage = fields.read_stage_fields(staged)
    assert row["still_zone_f"] == pytest.approx(fields.still_zone_ratio(stage).value, nan_ok=True)
    assert row["circulation_per_cycle"] == pytest.approx(fields.circulation(stage).per_cycle.value, nan_ok=True)
    assert "still_zone_f" in json.loads((tmp_path / "out" / "comparison.json").read_text())["observables"]


def test_second_call_resumes(done):
    plan, out = done
    before = {p: p.stat().st_mtime_ns for p in (out / "runs").glob("*/run.json")}
    r = call(plan, "--out", out)
    assert r.returncode == 0, r.stderr
    assert {p: p.stat().st_mtime_ns for p in (out / "runs").glob("*/run.json")} == before


def test_runs_carried_over_without_their_beds_are_not_poured_again(done, tmp_path):
    # An earlier machine's completed runs, copied into a new folder without packs/ (a plan
    # resumed on a fresh machine): nothing is poured or run, and the table is written.
    plan, ref = done
    out = tmp_path / "out"
    shutil.copytree(ref / "runs", out / "runs", ignore=shutil.ignore_patterns("*.log"))
    r = call(plan, "--out", out)
    assert r.returncode == 0, r.stderr
    assert not list((out / "packs").glob("*.state"))
    assert json.loads((out / "comparison.json").read_text())["complete"] is True


def test_a_knob_that_shapes_the_bed_pours_a_bed_per_setting(tmp_path):
    """pack_each_setting: the particle count varies, so each setting runs from its own
    beds, poured with its fields; the plain plan would be refused by `ratchet run`."""
    settings = {"n20": {}, "n12": {"particles.generate.count": 12}}
    plan = write_plan(tmp_path, reference="n20", settings=settings, seeds=[1, 2], pack_each_setting=True)
    r = call(plan, "--out", tmp_path / "out", "--jobs", "2")
    assert r.returncode == 0, r.stderr
    for n, count in (("n20", 20), ("n12", 12)):
        for s in (1, 2):
            run = json.loads((tmp_path / "out" / "runs" / f"{n}-s{s}" / "run.json").read_text())
            assert run["bodies"] == count
            assert run["packing"]["file"].endswith(f"{n}-s{s}.state")
    (tmp_path / "shared_plan").mkdir()
    shared = write_plan(tmp_path / "shared_plan", reference="n20", settings=settings, seeds=[1, 2])
    r = call(shared, "--out", tmp_path / "shared")
    assert r.returncode == 1  # a shared bed of 20 cannot start a run of 12
    assert "failed" in r.stderr


def stored_results(done, folder: Path) -> Path:
    """The fixture's `rigid` runs laid out as a campaign stores them: seed<s>/, without
    the timeseries (docs/campaign.md, Stored results)."""
    for s in (1, 2):
        shutil.copytree(done[1] / "runs" / f"rigid-s{s}", folder / f"seed{s}",
                        ignore=shutil.ignore_patterns("timeseries.csv", "*.state", "*.vtk", "*.vtu"))
    return folder


def test_stored_runs_are_read_not_run(done, tmp_path):
    stored = stored_results(done, tmp_path / "results")
    plan = write_plan(tmp_path, stored={"rigid": "results"})
    out = tmp_path / "out"
    r = call(plan, "--out", out, "--jobs", "2")
    assert r.returncode == 0, r.stderr
    assert not list((out / "runs").glob("rigid-s*")) and len(list((out / "runs").glob("soft-s*/run.json"))) == 2
    res = json.loads((out / "comparison.json").read_text())
    assert res["stored"] == {"rigid": str(stored)}
    ref = json.loads((done[1] / "comparison.json").read_text())["observables"]
    for obs in ("P_max", "V_over_V0_end", "peak_cycle0"):
        # The stored runs are the fixture's rigid runs, so their figures are the fixture's; the
        # soft runs are the same scene, seed and binary from beds poured again: the same bits.
        for n in ("rigid", "soft"):
            assert res["observables"][obs][n]["mean"] == ref[obs][n]["mean"], (obs, n)
    # No timeseries: the stored runs' sweeps are their cycles' means, and no overlap is claimed.
    # rel 1e-12: the same numbers averaged in another order (numpy here, pandas there).
    cycles = [pd.read_csv(stored / f"seed{s}" / "cycles.csv")["iterations_mean"].mean() for s in (1, 2)]
    assert res["observables"]["sweeps_mean"]["rigid"]["mean"] == pytest.approx(np.mean(cycles), rel=1e-12)
    assert res["observables"]["max_overlap_max"]["rigid"]["n"] == 0
    assert "the stored runs of" in (out / "comparison.md").read_text()


@pytest.mark.parametrize("fields, expected", [
    ({"settings": {"rigid": {"solver.acceleration": "anderson", "solver.max_iterations": 4000}, "soft": {}}},
     "field 'scene_hash': expected"),
    ({"seeds": [1, 2, 3]}, "expected the completed run of seed 3"),
    ({"stored": {"hard": "results"}}, "field 'stored': 'hard' is not one of the settings"),
    ({"stored": {"rigid": "results", "soft": "results"}}, "every setting is stored"),
])
def test_a_stored_run_that_is_not_the_plans_stops_before_any_work(done, tmp_path, fields, expected):
    stored_results(done, tmp_path / "results")
    plan = write_plan(tmp_path, **{"stored": {"rigid": "results"}, **fields})
    r = call(plan, "--out", tmp_path / "out")
    assert r.returncode == 2, r.stderr
    assert str(plan) in r.stderr and expected in r.stderr
    assert not (tmp_path / "out").exists()


def git_checkout(folder: Path) -> Path:
    for args in (["init", "-q"], ["config", "user.email", "t@example.org"], ["config", "user.name", "t"]):
        subprocess.run(["git", "-C", str(folder), *args], check=True)
    return folder


def test_runs_are_kept_and_committed_as_they_complete_and_read_back(done, tmp_path):
    """A plan with "keep": the runs completed before (the fixture's, copied in) are kept
    at the start, the one made here as it completes, each committed alone; a fresh
    machine with only the kept folder reads them all and pours and runs nothing."""
    repo = git_checkout(tmp_path)
    plan = write_plan(tmp_path, keep="kept")
    out = tmp_path / "out"
    shutil.copytree(done[1] / "runs", out / "runs", ignore=shutil.ignore_patterns("soft-s2*"))
    shutil.copytree(done[1] / "packs", out / "packs", ignore=shutil.ignore_patterns("*.lock", "*.log"))
    r = call(plan, "--out", out, "--commit")
    assert r.returncode == 0, r.stderr
    for n in ("rigid", "soft"):
        for s in (1, 2):
            kept = tmp_path / "kept" / f"{n}-s{s}"
            record = json.loads((kept / "kept.json").read_text())
            assert (record["setting"], record["seed"]) == (n, s)
            assert record["engine"] == json.loads((out / "runs" / f"{n}-s{s}" / "run.json").read_text())["engine"]
            # What was kept is the run's files byte for byte, of the timeseries the three
            # columns the table reads with their text unchanged; bodies and shapes are not kept.
            made = out / "runs" / f"{n}-s{s}"
            assert set(record["files"]) >= {"run.json", "cycles.csv", "solver_steps.csv"}
            for name, entry in record["files"].items():
                if name != "solver_steps.csv":
                    assert (kept / name).read_bytes() == (made / name).read_bytes()
            series = pd.read_csv(made / "timeseries.csv", dtype=str, keep_default_na=False)
            steps = pd.read_csv(kept / "solver_steps.csv", dtype=str, keep_default_na=False)
            assert list(steps.columns) == ["step", "iterations", "max_overlap"]
            assert steps.equals(series[["step", "iterations", "max_overlap"]])
            assert not (kept / "timeseries.csv").exists() and not (kept / "bodies.csv").exists()
            assert (made / "bodies.csv").exists()
    log = subprocess.run(["git", "-C", str(repo), "log", "--format=%s"], capture_output=True, text=True).stdout
    assert log.count("kept (engine ") == 4 and "soft-s2 kept" in log.splitlines()[0]  # the run made here, last
    # The engine is named as the campaign names it: the last commit of its sources when the
    # build is theirs (a clean clone), else the build's HEAD, said so.
    from campaign_lib.engine import identify
    engine = identify(RATCHET)
    named = engine.commit[:10] if not engine.dirty else json.loads(
        (out / "runs" / "soft-s2" / "run.json").read_text())["engine"]["commit"][:10] + " (build HEAD)"
    assert f"soft-s2 kept (engine {named})" in log.splitlines()[0], (named, log)
    assert subprocess.run(["git", "-C", str(repo), "status", "--porcelain", "kept"], capture_output=True,
                          text=True).stdout == ""
    first = json.loads((out / "comparison.json").read_text())
    # A fresh machine: the kept folder alone.
    fresh = tmp_path / "fresh"
    r = call(plan, "--out", fresh)
    assert r.returncode == 0, r.stderr
    assert not list((fresh / "packs").glob("*.state")) and not list((fresh / "runs").iterdir())
    again = json.loads((fresh / "comparison.json").read_text())
    assert sorted(again["kept"]["runs"]) == ["rigid-s1", "rigid-s2", "soft-s1", "soft-s2"]
    for obs in ("P_max", "V_over_V0_end", "sweeps_mean", "max_overlap_max"):
        for n in ("rigid", "soft"):
            assert again["observables"][obs][n] == first["observables"][obs][n], (obs, n)
    assert "Read from the kept runs of" in (fresh / "comparison.md").read_text()


def test_a_half_kept_run_is_not_read(done, tmp_path):
    tool = load_tool()
    folder = tmp_path / "kept" / "rigid-s1"
    tool.keep_run(done[1] / "runs" / "rigid-s1", folder, {"setting": "rigid", "seed": 1})
    assert tool.is_kept(folder)
    (folder / "kept.json").unlink()  # the call stopped before its marker
    assert not tool.is_kept(folder)


def test_a_kept_run_of_another_scene_stops_before_any_work(done, tmp_path):
    tool = load_tool()
    tool.keep_run(done[1] / "runs" / "soft-s1", tmp_path / "kept" / "soft-s1", {"setting": "soft", "seed": 1})
    settings = {"rigid": {"solver.acceleration": "anderson", "solver.max_iterations": 5000},
                "soft": {"solver.acceleration": "anderson", "solver.max_iterations": 5000, "solver.compliance": 0.2}}
    plan = write_plan(tmp_path, keep="kept", settings=settings)
    r = call(plan, "--out", tmp_path / "out")
    assert r.returncode == 2, r.stderr
    assert str(plan) in r.stderr and "field 'keep'" in r.stderr and "the kept run is of another scene" in r.stderr
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("fields, args, expected", [
    ({}, ["--commit"], "has no field 'keep'"),
    ({"keep": ""}, [], "field 'keep': expected the path of a folder"),
    ({"keep": "kept"}, ["--commit", "--report"], "--report keeps and commits nothing"),
])
def test_bad_keep_stops_before_any_work(tmp_path, fields, args, expected):
    plan = write_plan(tmp_path, **fields)
    r = call(plan, "--out", tmp_path / "out", *args)
    assert r.returncode == 2
    assert expected in r.stderr
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("fields, expected", [
    ({"setings": {}}, "field 'setings': unknown field"),
    ({"pack_each_setting": "yes"}, "field 'pack_each_setting': expected true or false"),
    ({"reference": "none"}, "field 'reference': expected one of the settings"),
    ({"seeds": [1]}, "at least 2 seeds"),
    ({"scene": "missing.json"}, "no such file"),
])
def test_bad_plan_stops_before_any_work(tmp_path, fields, expected):
    plan = write_plan(tmp_path, **fields)
    r = call(plan, "--out", tmp_path / "out")
    assert r.returncode == 2
    assert str(plan) in r.stderr and expected in r.stderr
    assert not (tmp_path / "out").exists()


def test_engine_option_runs_that_setting_with_the_other_binary(tmp_path):
    # The other binary is a wrapper that logs each call and runs the engine: only the
    # named setting's runs go through it, from the packings of the default engine.
    log = tmp_path / "calls.log"
    wrapper = tmp_path / "other-engine"
    wrapper.write_text(f'#!/bin/sh\necho "$@" >> "{log}"\nexec "{RATCHET}" "$@"\n')
    wrapper.chmod(0o755)
    plan = write_plan(tmp_path, seeds=[1, 2])
    r = call(plan, "--out", tmp_path / "out", "--jobs", "2", "--engine", f"soft={wrapper}")
    assert r.returncode == 0, r.stderr
    calls = log.read_text().splitlines()
    assert len(calls) == 2 and all(c.startswith("run ") and "/runs/soft-s" in c for c in calls)


@pytest.mark.parametrize("engine, expected", [
    ("hard=/bin/true", "--engine: expected SETTING=BIN with SETTING one of rigid, soft"),
    ("soft", "--engine: expected SETTING=BIN"),
    ("soft=/no/such/engine", "--engine: /no/such/engine: no such file"),
])
def test_bad_engine_option_stops_before_any_work(tmp_path, engine, expected):
    plan = write_plan(tmp_path)
    r = call(plan, "--out", tmp_path / "out", "--engine", engine)
    assert r.returncode == 2
    assert expected in r.stderr
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("held", ["runs/soft-s2.lock", "packs/s2.lock"])
def test_a_second_instance_skips_what_another_process_holds(tmp_path, held):
    """A run (or a bed being poured) whose lock another process holds, as an instance started
    earlier on the same folder does while its engine runs, is not started: the rest of the
    plan runs, the skip is named, no table is written and the exit status is 3; once the
    lock is free the same command finishes the plan. A lock that could not be taken would
    leave the run started twice, and this test red."""
    plan = write_plan(tmp_path)
    out = tmp_path / "out"
    for sub in ("runs", "packs"):
        (out / sub).mkdir(parents=True)
    fd = try_lock(out / held)  # the lock compare-settings takes, held here as by another instance
    assert fd is not None
    try:
        r = call(plan, "--out", out, "--jobs", "2")
    finally:
        os.close(fd)
    assert r.returncode == 3, r.stderr
    assert f"lock {out / held}" in r.stderr
    skipped = ["soft-s2"] if held.startswith("runs") else ["rigid-s2", "soft-s2"]
    for name in ("rigid-s1", "soft-s1", "rigid-s2", "soft-s2"):
        run = out / "runs" / name / "run.json"
        assert run.is_file() != (name in skipped), name
    assert not (out / "comparison.json").exists()
    r = call(plan, "--out", out)
    assert r.returncode == 0, r.stderr
    assert json.loads((out / "comparison.json").read_text())["complete"] is True


def test_a_stopped_plan_goes_on_from_the_checkpoints(done, tmp_path):
    """SIGTERM to the tool stops its runs at a checkpoint (exit 3); the same command then
    resumes them, and each run's timeseries is byte for byte that of the plan never
    stopped (the `done` fixture; the wall-clock time_* columns aside)."""
    _, ref = done
    plan = write_plan(tmp_path)
    fields = json.loads(plan.read_text())
    fields["set"]["outputs.checkpoint_every"] = 20  # no effect on the results, only on where a run can resume
    plan.write_text(json.dumps(fields))
    out = tmp_path / "out"
    (out / "packs").mkdir(parents=True)
    for p in (ref / "packs").glob("*.state"):  # the same beds, not poured again
        (out / "packs" / p.name).write_bytes(p.read_bytes())
    proc = subprocess.Popen(["/usr/bin/python3", str(TOOL), str(plan), "--out", str(out)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 120
    while not list((out / "runs").glob("*/checkpoint.state")) and proc.poll() is None and time.monotonic() < deadline:
        time.sleep(0.01)
    assert proc.poll() is None, "the plan ended before it could be stopped: lengthen its runs"
    proc.send_signal(signal.SIGTERM)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 3, err
    assert "run the same command again" in err
    # Stopped cleanly, at its next step and with a checkpoint of it: one SIGTERM, not two
    # (a second one ends the engine at once).
    stopped = [d for d in (out / "runs").iterdir() if d.is_dir() and (d / "run.json").is_file()
               and json.loads((d / "run.json").read_text())["status"] == "interrupted"]
    assert stopped, [p.name for p in (out / "runs").iterdir()]
    assert all((d / "checkpoint.state").is_file() for d in stopped)
    r = call(plan, "--out", out)
    assert r.returncode == 0, r.stderr
    # A resumed run's phase timers count its first installment's steps too: the
    # comparison's cost covers the whole run, not the last installment's wall time.
    for d in stopped:
        run = json.loads((d / "run.json").read_text())
        solve = next(ph for ph in run["phases"] if ph["name"] == "solve")
        steps = pd.read_csv(d / "timeseries.csv")["step"]
        assert solve["calls"] == steps.iloc[-1] - steps.iloc[0], solve  # from the packing's step to the end
    for name in ("rigid", "soft"):
        for s in (1, 2):
            a = pd.read_csv(out / "runs" / f"{name}-s{s}" / "timeseries.csv", dtype=str)
            b = pd.read_csv(ref / "runs" / f"{name}-s{s}" / "timeseries.csv", dtype=str)
            keep = [c for c in a.columns if not c.startswith("time_")]
            pd.testing.assert_frame_equal(a[keep], b[keep])


def test_threads_option_runs_every_packing_and_run_on_that_many_threads(done, tmp_path):
    """--threads 2: the engine is asked for two threads (the runs' scenes say so) and
    gives the bits of one (the done fixture's runs, wall-clock columns aside); the
    table says what each setting ran on, so its seconds are not read as one thread's."""
    _, ref = done
    plan = write_plan(tmp_path)
    out = tmp_path / "out"
    r = call(plan, "--out", out, "--threads", "2")
    assert r.returncode == 0, r.stderr
    for name in ("rigid", "soft"):
        for s in (1, 2):
            run = json.loads((out / "runs" / f"{name}-s{s}" / "run.json").read_text())
            assert run["effective_scene"]["solver"]["threads"] == 2
            a = pd.read_csv(out / "runs" / f"{name}-s{s}" / "timeseries.csv", dtype=str)
            b = pd.read_csv(ref / "runs" / f"{name}-s{s}" / "timeseries.csv", dtype=str)
            keep = [c for c in a.columns if not c.startswith("time_")]
            pd.testing.assert_frame_equal(a[keep], b[keep])
    threads = json.loads((out / "comparison.json").read_text())["observables"]["threads"]
    assert {n: e["mean"] for n, e in threads.items()} == {"rigid": 2.0, "soft": 2.0}
    assert "p" not in threads["soft"]  # a run's setting, not an observable to test
    ref_threads = json.loads((ref / "comparison.json").read_text())["observables"]["threads"]
    assert {n: e["mean"] for n, e in ref_threads.items()} == {"rigid": 1.0, "soft": 1.0}


@pytest.mark.parametrize("threads", ["0", "-2"])
def test_a_bad_thread_count_stops_before_any_work(tmp_path, threads):
    r = call(write_plan(tmp_path), "--out", tmp_path / "out", "--threads", threads)
    assert r.returncode == 2
    assert f"--threads: expected a positive integer (OpenMP threads per run), got {threads}" in r.stderr
    assert not (tmp_path / "out").exists()


def test_a_bad_budget_stops_before_any_work(tmp_path):
    r = call(write_plan(tmp_path), "--out", tmp_path / "out", "--budget", "0")
    assert r.returncode == 2
    assert "--budget: expected a positive number of hours, got 0.0" in r.stderr
    assert not (tmp_path / "out").exists()


def test_a_run_gets_one_sigterm_however_it_is_stopped(tmp_path):
    """The engine takes a second SIGTERM as "stop now" and ends without its checkpoint,
    so a run whose step outlasts the tool's poll (a rigid step of the paper bed takes
    minutes) must not get the signal's forward and the deadline's SIGTERM both. A stand-in
    process counts the SIGTERMs it gets over 3 s."""
    import threading
    tool = load_tool()
    count = tmp_path / "count"
    child = ("import signal, time, pathlib\n"
             "n = [0]\n"
             "def on(*_):\n"
             "    n[0] += 1\n"
             f"    pathlib.Path({str(count)!r}).write_text(str(n[0]))\n"
             "signal.signal(signal.SIGTERM, on)\n"
             f"pathlib.Path({str(count)!r}).write_text('0')\n"
             "end = time.monotonic() + 3\n"
             "while time.monotonic() < end: time.sleep(0.01)\n")
    stop = tool.Stopper(None)
    result = {}
    worker = threading.Thread(target=lambda: result.update(
        rc=tool.execute(["/usr/bin/python3", "-c", child], tmp_path / "log", stop)))
    worker.start()
    deadline = time.monotonic() + 30
    while not count.is_file() and time.monotonic() < deadline:
        time.sleep(0.01)
    stop.on_signal()  # as SIGINT/SIGTERM to the tool; the poll then finds the stop due too
    worker.join(timeout=30)
    assert result["rc"] == tool.STOPPED
    assert count.read_text() == "1"


def test_a_program_without_a_handler_stopped_by_the_tool_is_stopped_not_failed(tmp_path):
    """`ratchet pack` has no SIGTERM handler: stopped while it pours, it dies of the signal
    (return code -15). That is the tool's own stop, not a failure; a process killed by a
    SIGTERM from elsewhere still is one."""
    tool = load_tool()
    stop = tool.Stopper(None)
    result = {}
    import threading
    worker = threading.Thread(target=lambda: result.update(
        rc=tool.execute(["/usr/bin/python3", "-c", "import time; time.sleep(30)"], tmp_path / "log", stop)))
    worker.start()
    deadline = time.monotonic() + 30
    while not stop.running and time.monotonic() < deadline:
        time.sleep(0.01)
    stop.on_signal()
    worker.join(timeout=30)
    assert result["rc"] == tool.STOPPED

    other = tool.Stopper(None)
    rc = tool.execute(["/usr/bin/python3", "-c", "import os, signal; os.kill(os.getpid(), signal.SIGTERM)"],
                      tmp_path / "log2", other)
    assert rc == -signal.SIGTERM


def test_report_compares_the_completed_runs_and_starts_none(done, tmp_path):
    plan, out = done
    part = tmp_path / "out"
    shutil.copytree(out, part)
    for f in ("comparison.json", "comparison.md"):
        (part / f).unlink()
    shutil.rmtree(part / "figures")
    (part / "runs" / "soft-s2" / "run.json").unlink()  # a run not finished yet
    before = sorted(p.relative_to(part) for p in part.rglob("*"))
    r = call(plan, "--out", part, "--report", "--ratchet", tmp_path / "no-engine")
    assert r.returncode == 0, r.stderr
    res = json.loads((part / "comparison.json").read_text())
    assert res["complete"] is False
    assert res["runs"] == ["rigid-s1", "soft-s1", "rigid-s2"]
    assert res["observables"]["P_max"]["soft"]["n"] == 1
    assert res["observables"]["P_max"]["rigid"]["n"] == 2
    assert "**Partial**: 3 of 4 runs completed" in (part / "comparison.md").read_text()
    # Nothing was run or poured: only the three outputs are new.
    after = sorted(p.relative_to(part) for p in part.rglob("*"))
    assert {Path("comparison.json"), Path("comparison.md"), Path("figures/compare_settings.png")} <= set(after)
    assert all(p.parts[0] in ("comparison.json", "comparison.md", "figures") for p in set(after) - set(before))
    assert not (part / "runs" / "soft-s2" / "run.json").exists()
    # The complete plan's report is the plan's own comparison.
    r = call(plan, "--out", out, "--report")
    assert r.returncode == 0, r.stderr
    assert json.loads((out / "comparison.json").read_text())["complete"] is True


def test_report_with_no_completed_run_says_so(tmp_path):
    plan = write_plan(tmp_path)
    r = call(plan, "--out", tmp_path / "empty", "--report")
    assert r.returncode == 1
    assert "no completed run" in r.stderr and str(tmp_path / "empty" / "runs") in r.stderr
