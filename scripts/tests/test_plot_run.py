"""scripts/plot-run on small real runs of a cycled bed: the PNG must be a real image, the
printed summary must agree with the run's own timeseries.csv and run.json (also with a
forced low sweep cap and from a packing), an unfinished run must be labelled, and bad
input must exit 2 naming the file and column, with no PNG written."""

import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pandas as pd
import pytest

SCRIPTS = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(SCRIPTS))
from common.paths import REPO_ROOT, engine_binary  # noqa: E402

RATCHET = engine_binary()
TOOL = REPO_ROOT / "scripts" / "plot-run"
SCENE = REPO_ROOT / "validation" / "sweeps" / "bed_quick.json"
# 20 polyhedra, one thermal cycle, a row per step: about 1 s of CPU.
SMALL = ["--set", "particles.generate.count=20", "--set", "thermal.cycles=1",
         "--set", "outputs.steady_cycles=[0,0]", "--set", "solver.threads=1"]
SUMMARY = re.compile(r"^plot-run: \S+ (completed|INCOMPLETE): (\d+) steps, (?:(\d+) capped \(sweeps >= (\d+)"
                     r"|capped n/a).*max residual (\S+), P_max (\S+) -> (.+)$")

pytestmark = pytest.mark.skipif(not RATCHET.is_file(), reason=f"engine not built ({RATCHET})")


def ratchet(*args) -> None:
    subprocess.run([str(RATCHET), *map(str, args), "--quiet"], check=True)


def plot(*args, cwd) -> subprocess.CompletedProcess:
    # From another folder: the entry point must find scripts/ itself.
    return subprocess.run([str(TOOL), *map(str, args)], capture_output=True, text=True, cwd=cwd)


def parse(stdout: str) -> re.Match:
    lines = stdout.splitlines()
    assert len(lines) == 1, stdout
    m = SUMMARY.match(lines[0])
    assert m, lines[0]
    return m


@pytest.fixture(scope="module")
def run_dir(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("plot") / "run"
    ratchet("run", SCENE, "--out", out, *SMALL, "--set", "outputs.timeseries_every=1")
    return out


@pytest.fixture(scope="module")
def low_cap_dir(tmp_path_factory) -> Path:
    # A cap of 2 sweeps would keep the bed from settling, so start from a packing.
    folder = tmp_path_factory.mktemp("lowcap")
    ratchet("pack", SCENE, "--out", folder / "bed.state", *SMALL)
    ratchet("run", SCENE, "--packing", folder / "bed.state", "--out", folder / "run", *SMALL,
            "--set", "solver.max_iterations=2", "--set", "outputs.timeseries_every=1")
    return folder / "run"


def copy_run(src: Path, dst: Path) -> Path:
    shutil.copytree(src, dst, ignore=shutil.ignore_patterns("*.png", "bodies.csv"))
    return dst


def test_png_and_summary_agree_with_the_run(run_dir, tmp_path):
    import matplotlib.image as mpimg

    before = set(os.listdir(run_dir))
    r = plot(run_dir, cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    png = run_dir / "run.png"
    assert set(os.listdir(run_dir)) == before | {"run.png"}  # no temporary file left behind
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    img = mpimg.imread(png)
    assert img.ndim == 3 and img.shape[2] in (3, 4)
    assert img.shape[0] > img.shape[1] > 500  # stacked panels: taller than wide
    assert img.std() > 0.05  # something was drawn

    m = parse(r.stdout)
    run = json.loads((run_dir / "run.json").read_text())
    ts = pd.read_csv(run_dir / "timeseries.csv")
    cap = run["scene"]["solver"]["max_iterations"]
    assert m.group(1) == "completed"
    assert int(m.group(2)) == ts["step"].iloc[-1] - ts["step"].iloc[0] == run["steps"]
    assert int(m.group(4)) == cap
    assert int(m.group(3)) == (ts["iterations"] >= cap).sum()
    assert float(m.group(5)) == pytest.approx(ts["residual"].max(), rel=1e-2)  # printed to 3 digits
    assert float(m.group(6)) == pytest.approx(run["summary"]["P_max"], rel=1e-3, abs=1e-12)
    assert Path(m.group(7)) == png


def test_panels_follow_the_data(run_dir):
    from analysis import run_plot

    run = run_plot.load_run(run_dir)
    names = run_plot.panels(run)
    assert names[:2] == ["pressure", "temperature"] and names[-1] == "volume"
    # The stage ends of the cycles fall on the temperature ramp's ends.
    heating, cooling = run_plot.cycle_stage_times(run)
    ts = run.ts
    at = lambda time: ts.loc[(ts["t"] - time).abs().idxmin(), "T"]  # noqa: E731
    t1 = run.run["scene"]["thermal"]["T1"]
    assert at(heating[0]) == pytest.approx(t1) and at(cooling[0]) == pytest.approx(0, abs=1e-9)
    # Without a thermal protocol T is all 0: no temperature panel.
    run.ts = ts.assign(T=0.0)
    assert "temperature" not in run_plot.panels(run)


def test_low_cap_from_a_packing_reports_capped_steps(low_cap_dir, tmp_path):
    out = tmp_path / "elsewhere" / "low.png"
    r = plot(low_cap_dir, "--out", out, cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert out.stat().st_size > 1000 and not (low_cap_dir / "run.png").exists()
    m = parse(r.stdout)
    run = json.loads((low_cap_dir / "run.json").read_text())
    ts = pd.read_csv(low_cap_dir / "timeseries.csv")
    assert int(m.group(4)) == 2
    capped = int(m.group(3))
    assert capped == (ts["iterations"] >= 2).sum() > 0
    # The engine counts only the capped steps that also missed the tolerance.
    assert 0 < run["counters"]["unconverged_steps"] <= capped
    # The run starts at the packing's step.
    assert int(m.group(2)) == run["steps"] - run["packing"]["step"] == len(ts) - 1


def test_unfinished_run_is_labelled_and_reads_the_partial_rows(run_dir, tmp_path):
    folder = copy_run(run_dir, tmp_path / "cut")
    (folder / "run.json").unlink()
    text = (folder / "timeseries.csv").read_text()
    (folder / "timeseries.csv").unlink()
    cut = text[: len(text) // 3]
    assert not cut.endswith("\n")
    (folder / "timeseries.csv.partial").write_text(cut)
    r = plot(folder, cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    m = parse(r.stdout)
    assert m.group(1) == "INCOMPLETE" and "capped n/a" in r.stdout
    whole_rows = cut.count("\n") - 1  # the header, and the cut line is left out
    assert int(m.group(2)) == whole_rows - 1
    assert (folder / "run.png").stat().st_size > 1000


def test_missing_folder(tmp_path):
    r = plot(tmp_path / "nothing", cwd=tmp_path)
    assert r.returncode == 2
    assert "nothing: no such folder" in r.stderr and r.stdout == ""


def test_folder_without_timeseries(run_dir, tmp_path):
    folder = copy_run(run_dir, tmp_path / "no_ts")
    (folder / "timeseries.csv").unlink()
    r = plot(folder, cwd=tmp_path)
    assert r.returncode == 2
    assert str(folder / "timeseries.csv") in r.stderr and "not found" in r.stderr
    assert not list(folder.glob("*.png"))


@pytest.mark.parametrize("file, column", [("timeseries.csv", "residual"), ("timeseries.csv", "iterations"),
                                          ("cycles.csv", "t_peak")])
def test_missing_column_is_named(run_dir, tmp_path, file, column):
    folder = copy_run(run_dir, tmp_path / "cols")
    frame = pd.read_csv(folder / file, dtype=str)
    frame.drop(columns=[column]).to_csv(folder / file, index=False)
    out = tmp_path / "x.png"
    r = plot(folder, "--out", out, cwd=tmp_path)
    assert r.returncode == 2
    assert str(folder / file) in r.stderr and f"missing column {column}" in r.stderr
    assert "Traceback" not in r.stderr
    assert not out.exists() and not list(folder.glob("*.png")) and not list(tmp_path.glob("*.png"))
