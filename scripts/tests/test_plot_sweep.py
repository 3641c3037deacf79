"""scripts/plot-sweep on sweep folders in the format `ratchet sweep` writes (docs/sweeps.md):
synthetic ones whose means and standard errors are known, and one tiny real sweep. Every
realization must be drawn, each point's mean with an error bar of one standard error,
axes in the scaled units; the figure's format follows --out's extension, and bad input
exits 2 naming the option or the file, with nothing written."""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

SCRIPTS = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(SCRIPTS))
from analysis import sweep_plot  # noqa: E402
from common.paths import REPO_ROOT, engine_binary  # noqa: E402

TOOL = REPO_ROOT / "scripts" / "plot-sweep"
ALPHA_P = 1e-4
#: P_max per point and realization: the means and standard errors follow by hand.
ANGLE_P_MAX = {0.0: [0.30, 0.34, 0.32], 4.0: [0.20, 0.26], 8.0: [0.12, 0.18, 0.15, 0.11]}
W_RMS = {(0, 1): 0.05, (1, 3): 0.08}


def summary_frame(kind: str, values: dict[float, list[float]], missing=()) -> pd.DataFrame:
    """summary.csv as the engine writes it: run, the grid key, thermal.alpha_p (unless it
    is swept), seed, packing, the summary keys in byte order, status."""
    rows = []
    for x, p_max in values.items():
        for seed, value in enumerate(p_max, start=1):
            run = len(rows)
            row = {"run": run}
            if kind == "angle":
                row["container.opening_angle_deg"] = x
            else:
                row["thermal.alpha_c"] = x * ALPHA_P
            row.update({"thermal.alpha_p": ALPHA_P, "seed": seed, "packing": f"{run:016x}",
                        "P_max": value, "P_max_std": 0.01, "V_over_V0_end": 0.95})
            for (a, b), w in W_RMS.items():
                row[f"W_rms_{a}_{b}"] = w * (1 + 0.1 * seed) * (1 + x / 10)
            row.update({"cycles_completed": 3, "unconverged_fraction": 0.0, "unconverged_steps": 0,
                        "status": "completed"})
            if run in missing:
                row.update({k: math.nan for k in row if k not in ("run", "container.opening_angle_deg",
                                                                  "thermal.alpha_c", "thermal.alpha_p",
                                                                  "seed")})
                row["packing"], row["status"] = "", "missing"
            rows.append(row)
    return pd.DataFrame(rows)


def write_sweep(folder: Path, kind="angle", values=None, missing=()) -> Path:
    frame = summary_frame(kind, values or ANGLE_P_MAX, missing)
    folder.mkdir(parents=True, exist_ok=True)
    frame.to_csv(folder / "summary.csv", index=False, float_format="%.17g")
    for run in frame["run"]:
        if run in missing:
            continue
        (folder / "runs" / str(run)).mkdir(parents=True)
        scene = {"name": "bed_quick", "particles": {"generate": {"count": 45, "shape": "polyhedron"}},
                 "container": {"type": "cone", "opening_angle_deg": 0},
                 "thermal": {"cycles": 3, "alpha_p": ALPHA_P, "alpha_c": 1e-3},
                 "outputs": {"pressure_window": 0.25, "steady_cycles": [1, 2]}}
        (folder / "runs" / str(run) / "run.json").write_text(json.dumps(
            {"status": "completed", "scene": scene, "summary": {"steady_cycles": [1, 2]}}))
    return folder


def plot(*args, cwd) -> subprocess.CompletedProcess:
    return subprocess.run([str(TOOL), *map(str, args)], capture_output=True, text=True, cwd=cwd)


def _expected(values: dict[float, list[float]]):
    xs = sorted(values)
    means = [np.mean(values[x]) for x in xs]
    sems = [np.std(values[x], ddof=1) / np.sqrt(len(values[x])) for x in xs]
    return xs, means, sems


def _errorbars(ax):
    """(x, mean, half-length of the bar) of every errorbar container of the axes."""
    found = []
    for container in ax.containers:
        line, _, (bars,) = container
        segments = bars.get_segments()
        found.append((np.asarray(line.get_xdata(), dtype=float), np.asarray(line.get_ydata(), dtype=float),
                      np.array([abs(s[1][1] - s[0][1]) / 2 for s in segments]),
                      np.array([s[0][0] for s in segments])))
    return found


def test_every_point_has_its_mean_with_a_standard_error_bar(tmp_path):
    folder = write_sweep(tmp_path / "angle")
    (study,) = sweep_plot.load_studies(folder)
    fig = sweep_plot.figure([study])
    ax_p, ax_w = fig.axes[:2]
    xs, means, sems = _expected(ANGLE_P_MAX)
    ((x, mean, half, bar_x),) = _errorbars(ax_p)
    assert list(x) == xs and mean == pytest.approx(means, rel=1e-12)
    assert list(bar_x) == xs and half == pytest.approx(sems, rel=1e-9)  # one bar per point
    # Every realization is a marker of its own.
    (each,) = [line for line in ax_p.get_lines() if line.get_label().endswith("each realization")]
    runs = sum(len(v) for v in ANGLE_P_MAX.values())
    assert len(each.get_ydata()) == runs
    assert sorted(each.get_ydata()) == pytest.approx(sorted(v for vs in ANGLE_P_MAX.values() for v in vs))
    # One set of bars per W_rms window, a bar at every point, the windows side by side.
    bars = _errorbars(ax_w)
    assert len(bars) == len(W_RMS)
    assert all(len(b[2]) == len(xs) and (b[2] > 0).all() for b in bars)
    assert not np.allclose(bars[0][0], bars[1][0])


def test_axes_carry_units_and_the_title_names_the_sweep(tmp_path):
    angle = write_sweep(tmp_path / "angle_quick")
    ratio = write_sweep(tmp_path / "ratio_quick", "ratio", {1.0: [0.1, 0.12], 5.0: [0.2, 0.25], 10.0: [0.4, 0.3]})
    studies = sweep_plot.load_studies(angle) + sweep_plot.load_studies(ratio)
    fig = sweep_plot.figure(studies)
    axes = fig.axes
    assert [ax.get_ylabel() for ax in axes] == ["P_max / (ρ g r_max)", "W_rms (dimensionless)"] * 2
    assert [ax.get_xlabel() for ax in axes] == ["cone opening angle θ_c (deg)"] * 2 + ["expansion ratio α_c / α_p"] * 2
    # The ratio is alpha_c / alpha_p, not alpha_c.
    assert list(_errorbars(axes[2])[0][0]) == pytest.approx([1.0, 5.0, 10.0])
    title = fig._suptitle.get_text()
    assert "angle_quick" in title and "ratio_quick" in title and str(tmp_path) not in title
    caption = " ".join(t.get_text() for t in fig.texts)
    assert "standard error" in caption and "Δt = 0.25" in caption and "steady cycles 1–2" in caption


def test_runs_that_did_not_complete_are_left_out(tmp_path):
    folder = write_sweep(tmp_path / "angle", missing=(1,))
    (study,) = sweep_plot.load_studies(folder)
    values = {x: list(v) for x, v in ANGLE_P_MAX.items()}
    values[0.0].pop(1)
    xs, means, sems = _expected(values)
    ((x, mean, half, _),) = _errorbars(sweep_plot.figure([study]).axes[0])
    assert mean == pytest.approx(means, rel=1e-12) and half == pytest.approx(sems, rel=1e-9)
    assert any("did not complete" in note for note in study.notes)


@pytest.mark.parametrize("name, magic", [(None, b"\x89PNG"), ("f.pdf", b"%PDF-"), ("f.svg", b"<?xml")])
def test_the_figure_is_written_in_the_format_of_its_extension(tmp_path, name, magic):
    folder = write_sweep(tmp_path / "angle")
    args = [folder] + (["--out", tmp_path / "out" / name] if name else [])
    r = plot(*args, cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    out = tmp_path / "out" / name if name else folder / "sweep.png"
    assert out.read_bytes().startswith(magic)
    assert sorted(p.name for p in out.parent.iterdir() if p.is_file()) == sorted(
        [out.name] + (["summary.csv"] if name is None else []))  # no temporary file left
    (line,) = r.stdout.splitlines()
    assert line.startswith("plot-sweep: angle (angle): 9 runs at 3 points (2-4 realizations)")
    assert line.endswith(f"W_rms_0_1, W_rms_1_3 -> {out}")
    if name == "f.svg":
        text = out.read_text(encoding="utf-8")
        assert "P_max / (ρ g r_max)" in text and "cone opening angle θ_c (deg)" in text


@pytest.mark.parametrize("args, words", [
    (["{sweep}", "--out", "{tmp}/f.jpg"], ["--out", "f.jpg", ".png, .pdf, .svg"]),
    (["{sweep}", "{sweep}"], ["--out", "required with several"]),
    (["{tmp}/nothing"], ["nothing/summary.csv", "not found"]),
])
def test_bad_arguments_exit_2_naming_the_option_or_file_with_nothing_written(tmp_path, args, words):
    sweep = write_sweep(tmp_path / "angle")
    before = sorted(tmp_path.rglob("*"))
    args = [a.format(sweep=sweep, tmp=tmp_path) for a in args]
    r = plot(*args, cwd=tmp_path)
    assert r.returncode == 2
    assert all(w in r.stderr for w in words), r.stderr
    assert "Traceback" not in r.stderr and r.stdout == ""
    assert sorted(tmp_path.rglob("*")) == before


def test_a_sweep_of_another_parameter_is_refused_naming_the_columns(tmp_path):
    folder = tmp_path / "theta"
    folder.mkdir()
    pd.DataFrame({"run": [0, 1], "solver.theta": [1.0, 0.5], "seed": [1, 1], "P_max": [0.1, 0.2],
                  "status": ["completed"] * 2}).to_csv(folder / "summary.csv", index=False)
    r = plot(folder, cwd=tmp_path)
    assert r.returncode == 2
    assert str(folder / "summary.csv") in r.stderr and "container.opening_angle_deg" in r.stderr
    assert "solver.theta" in r.stderr and not (folder / "sweep.png").exists()


def test_a_sweep_whose_runs_are_all_left_out_says_why(tmp_path):
    folder = write_sweep(tmp_path / "capped")
    frame = pd.read_csv(folder / "summary.csv")
    frame["unconverged_fraction"] = 0.2  # every run above the 5 % that load_sweep accepts
    frame.to_csv(folder / "summary.csv", index=False)
    r = plot(folder, cwd=tmp_path)
    assert r.returncode == 2
    assert "no completed run with a finite P_max" in r.stderr and "solver's iteration cap" in r.stderr
    assert not (folder / "sweep.png").exists()


RATCHET = engine_binary()


@pytest.mark.skipif(not RATCHET.is_file(), reason=f"engine not built ({RATCHET})")
def test_a_real_sweep_of_the_engine(tmp_path):
    # 2 angles x 2 seeds of 20 polyhedra, one cycle: about 10 s of CPU.
    plan = {"scene": str(REPO_ROOT / "validation" / "sweeps" / "bed_quick.json"),
            "set": {"particles.generate.count": 20, "thermal.cycles": 1, "outputs.steady_cycles": [0, 0],
                    "outputs.displacement": {"cell": 1.0, "windows": [[0, 1]]}},
            "grid": {"container.opening_angle_deg": [0, 6]}, "realizations": 2}
    (tmp_path / "plan.json").write_text(json.dumps(plan))
    subprocess.run([str(RATCHET), "sweep", tmp_path / "plan.json", "--out", tmp_path / "sweep", "--jobs", "1"],
                   check=True, capture_output=True)
    r = plot(tmp_path / "sweep", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "sweep" / "sweep.png").read_bytes()[:4] == b"\x89PNG"
    (study,) = sweep_plot.load_studies(tmp_path / "sweep")
    summary = pd.read_csv(tmp_path / "sweep" / "summary.csv")
    ((x, mean, half, _),) = _errorbars(sweep_plot.figure([study]).axes[0])
    groups = summary.groupby("container.opening_angle_deg")["P_max"]
    assert list(x) == [0.0, 6.0]
    assert mean == pytest.approx(groups.mean().to_numpy(), rel=1e-12)
    assert half == pytest.approx((groups.std(ddof=1) / np.sqrt(2)).to_numpy(), rel=1e-9)
    assert "20 polyhedra" in " ".join(t.get_text() for t in sweep_plot.figure([study]).texts)
