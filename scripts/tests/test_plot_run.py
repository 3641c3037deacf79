"""scripts/plot-run on small real runs of a cycled bed: both figures (results and solver)
must be real images in the format of --out's extension, with units on the axes, V/V0 only
from the start of cycling, the cycle peaks and the thermal phases drawn; the printed
summary must agree with the run's own timeseries.csv and run.json (also with a forced low
sweep cap and from a packing), an unfinished run must be labelled, and bad input (an
unknown extension, a missing file or column) must exit 2 naming the option or the file
and column, with no figure written."""

import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
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
SUMMARY = re.compile(r"^plot-run: \S+ (completed|INCOMPLETE): (\d+) steps, (?:(\d+) capped \(of the \d+ timeseries rows, those at the cap of (\d+) sweeps"
                     r"|capped n/a).*max residual (\S+), P_max (\S+) -> (.+) and (.+)$")

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


def test_both_figures_and_summary_agree_with_the_run(run_dir, tmp_path):
    import matplotlib.image as mpimg

    before = set(os.listdir(run_dir))
    r = plot(run_dir, cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    results, solver = run_dir / "run.png", run_dir / "run-solver.png"
    assert set(os.listdir(run_dir)) == before | {"run.png", "run-solver.png"}  # no temporary file left
    for png in (results, solver):
        assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
        img = mpimg.imread(png)
        assert img.ndim == 3 and img.shape[2] in (3, 4)
        assert img.shape[1] > 1000 and img.shape[0] > 500
        assert img.std() > 0.05  # something was drawn
    # Two panels against six: the results figure is the shorter one.
    assert mpimg.imread(results).shape[0] < mpimg.imread(solver).shape[0]

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
    assert (Path(m.group(7)), Path(m.group(8))) == (results, solver)


def test_phases_follow_the_scene_and_the_temperature(run_dir):
    from ratchet import run_folder

    run = run_folder.load_run(run_dir)
    phases = run_folder.thermal_phases(run)
    th = run.run["scene"]["thermal"]
    assert [p.kind for p in phases] == ["heating", "hot hold", "cooling", "cold hold"] * th["cycles"]
    assert phases[0].start == pytest.approx(run.run["settle"]["t_end"])  # cycling starts at the settle end
    ts = run.ts
    at = lambda time: ts.loc[(ts["t"] - time).abs().idxmin(), "T"]  # noqa: E731
    # The stage ends of the cycles fall on the temperature ramp's ends.
    heating, cooling = run_folder.cycle_stage_times(run)
    assert at(heating[0]) == pytest.approx(th["T1"]) and at(cooling[0]) == pytest.approx(0, abs=1e-9)
    # Without run.json the phases are read off T(t): the same, to a row (one step here).
    h = run.run["scene"]["time"]["dt"]
    from_t = run_folder._phases_from_temperature(ts)
    assert [(p.cycle, p.kind) for p in from_t] == [(p.cycle, p.kind) for p in phases]
    for a, b in zip(from_t, phases):
        assert a.start == pytest.approx(b.start, abs=1.01 * h) and a.end == pytest.approx(b.end, abs=1.01 * h)
    # Without a thermal protocol T is all 0: no phase.
    assert run_folder._phases_from_temperature(ts.assign(T=0.0)) == []


def _figures(run_dir):
    from analysis import run_figures
    from ratchet import run_folder

    run = run_folder.load_run(run_dir)
    return run, run_figures.results_figure(run), run_figures.solver_figure(run)


def _texts(fig) -> list[str]:
    return [t.get_text() for t in fig.findobj(lambda a: hasattr(a, "get_text"))]


def test_axes_carry_the_scaled_units_and_the_title_names_the_scene(run_dir):
    run, results, solver = _figures(run_dir)
    pressure, volume = results.axes[:2]
    assert pressure.get_ylabel() == "P / (ρ g r_max)"
    assert volume.get_ylabel() == "V / V0"
    assert volume.get_xlabel() == "time t / sqrt(r_max / g)"
    labels = {ax.get_ylabel() for ax in solver.axes}
    assert {"E_kin / (ρ g r_max⁴)", "contacts (count)", "sweeps per step", "residual", "overlap / r_max",
            "wall time (ms)"} <= labels
    assert solver.axes[-1].get_xlabel() == "time t / sqrt(r_max / g)"
    for fig in (results, solver):
        title = fig._suptitle.get_text()
        assert title.startswith(f"{run.name}: ") and str(run_dir) not in title and "/" not in title
        assert not any(str(run_dir) in text for text in _texts(fig))  # no file path anywhere


def test_results_start_at_cycling_with_peaks_phases_and_cycle_numbers(run_dir):
    from analysis import run_figures
    from ratchet import run_folder

    run, results, _ = _figures(run_dir)
    start = run_folder.thermal_phases(run)[0].start
    ts = run.ts
    assert (ts["t"] < start).sum() > 100  # the pour is in the timeseries, so leaving it out is tested
    pressure, volume = results.axes[:2]
    (v_line,) = [line for line in volume.get_lines() if line.get_label() == "V/V0(t)"]
    x, y = v_line.get_xdata(), v_line.get_ydata()
    assert x.min() >= start - 1e-9 and x[0] == pytest.approx(start, abs=1e-9)
    assert y[0] == pytest.approx(1.0, abs=1e-12)  # V0 is the settled bed: 1 at the start of cycling
    assert len(x) == (ts["t"] >= start - 1e-9).sum()  # every row from the start of cycling, none before
    assert pressure.get_xlim() == pytest.approx((start, ts["t"].iloc[-1]))
    # The cycle peaks of cycles.csv, with the averaging window stated in their legend entry.
    (peaks,) = [line for line in pressure.get_lines() if line.get_label().startswith("cycle peak")]
    cycles = pd.read_csv(run_dir / "cycles.csv")
    assert list(peaks.get_ydata()) == pytest.approx(list(cycles["peak_pressure"]))
    window = run.run["scene"]["outputs"]["pressure_window"]
    assert f"Δt = {window:g}" in peaks.get_label()
    # With a row per step the block means drawn are the engine's: their largest in each
    # cycle is its peak, at the block's middle.
    blocks = run_folder.block_means(run, run_folder.thermal_phases(run))
    assert blocks and all(b - a >= window - 1e-9 for a, b, _ in blocks)
    for cycle, (first, last) in run_folder.cycle_spans(run_folder.thermal_phases(run)).items():
        block_start, block_end, mean = max((b for b in blocks if first <= b[0] < last), key=lambda b: b[2])
        row = cycles[cycles["cycle"] == cycle].iloc[0]
        assert mean == pytest.approx(row["peak_pressure"], rel=1e-12)
        assert (block_start + block_end) / 2 == pytest.approx(row["t_peak"], abs=1e-9)
    (block_line,) = [line for line in pressure.get_lines() if line.get_label().startswith("P averaged")]
    assert f"Δt = {window:g}" in block_line.get_label()
    assert np.nanmax(block_line.get_ydata()) == pytest.approx(cycles["peak_pressure"].max(), rel=1e-12)
    # The axis shows every averaged value; single-step spikes above it are said to be cut.
    top = pressure.get_ylim()[1]
    assert top >= cycles["peak_pressure"].max() and top >= run.p_max
    cycling = ts.loc[ts["t"] >= start - 1e-9, "pressure"]
    said = [t.get_text() for t in pressure.texts if t.get_text().startswith("single steps reach")]
    if cycling.max() > top:
        assert said == [f"single steps reach P = {cycling.max():.3g} (off scale; {(cycling > top).sum()} rows)"]
    else:
        assert said == []
    legend = [t.get_text() for t in pressure.get_legend().get_texts()]
    assert any(text.startswith(f"P_max = {run.p_max:.4g}") for text in legend)
    # Heating, hot hold and cooling shaded in their colours, once per cycle and panel.
    colors = {matplotlib_rgba(c) for c in run_figures.PHASE_COLORS.values() if c}
    spans = [p for p in pressure.patches if matplotlib_rgba(p.get_facecolor()[:3]) in colors]
    assert len(spans) == 3 * run.run["scene"]["thermal"]["cycles"]
    # Cycle numbers on a time axis above the pressure panel.
    (top,) = pressure.child_axes
    assert [t.get_text() for t in top.get_xticklabels()] == [f"cycle {k}" for k in cycles["cycle"]]


def matplotlib_rgba(color) -> tuple:
    from matplotlib.colors import to_rgb

    return tuple(round(v, 3) for v in to_rgb(color))


@pytest.mark.parametrize("name, magic", [("run.pdf", b"%PDF-"), ("run.svg", b"<?xml"), ("RUN.PNG", b"\x89PNG")])
def test_the_extension_of_out_sets_the_format_of_both_figures(run_dir, tmp_path, name, magic):
    out = tmp_path / "figs" / name
    r = plot(run_dir, "--out", out, cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    solver = out.with_name(out.stem + "-solver" + out.suffix)
    assert sorted(p.name for p in out.parent.iterdir()) == sorted([out.name, solver.name])
    for path in (out, solver):
        data = path.read_bytes()
        assert data.startswith(magic)
        if name.endswith(".svg"):
            assert b"<svg" in data[:1000]
    if name.endswith(".svg"):
        # matplotlib writes each text as a comment beside its glyphs: the labels are there.
        text = out.read_text(encoding="utf-8")
        assert "P / (ρ g r_max)" in text and "time t / sqrt(r_max / g)" in text


@pytest.mark.parametrize("name", ["run.jpg", "run", "run.png.bak"])
def test_an_unknown_extension_is_refused_naming_out_before_any_work(run_dir, tmp_path, name):
    out = tmp_path / name
    r = plot(tmp_path / "no such run", "--out", out, cwd=tmp_path)  # refused before the folder is read
    assert r.returncode == 2
    assert "--out" in r.stderr and ".png, .pdf, .svg" in r.stderr and name in r.stderr
    assert "Traceback" not in r.stderr and r.stdout == ""
    assert list(tmp_path.iterdir()) == []


def test_low_cap_from_a_packing_reports_capped_steps(low_cap_dir, tmp_path):
    out = tmp_path / "elsewhere" / "low.png"
    r = plot(low_cap_dir, "--out", out, cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert out.stat().st_size > 1000 and (out.parent / "low-solver.png").stat().st_size > 1000
    assert not list(low_cap_dir.glob("*.png"))
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
    assert (folder / "run.png").stat().st_size > 1000 and (folder / "run-solver.png").stat().st_size > 1000


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
