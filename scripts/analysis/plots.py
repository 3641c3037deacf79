"""Figures mirroring the paper's (PNG in OUT/figures/ with a caption .txt beside each).

Each function takes an Analysis (trends.analyse) and the output folder, saves its
figure through common.figures.save_figure (Agg backend, atomic write) and
returns (paths, notes): a figure whose data are missing is skipped with a note.

| function             | paper figure |
|----------------------|--------------|
| pressure_vs_time     | Fig. 3a (angle), 3c (ratio): P(t), per-cycle peaks as dots |
| metric_vs_parameter  | Fig. 3b, 3d: mean P_max +- 1 std with linear and quadratic fits |
| volume_vs_time       | Fig. 4a (angle), 4b (ratio): V/V0(t) |
| wrms_vs_parameter    | Fig. 7a, 7b: W_rms +- 1 std per window with fits |
| displacement_fields  | Fig. 6 (and 5): accumulated displacement arrows, vorticity in colour |
| stage_fields_figure  | Fig. 5 and 6: heating, cooling and cumulative fields (stage_fields.csv) |
"""

from __future__ import annotations

import os
from pathlib import Path

os.environ.setdefault("MPLBACKEND", "Agg")

import matplotlib  # noqa: E402

matplotlib.use("Agg")

import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402
from matplotlib import colormaps  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

from common.figures import save_figure  # noqa: E402

from .inputs import (displacement_files, end_of_cycle_volumes, first_realizations,  # noqa: E402
                     read_cycles, read_displacement, read_timeseries, read_volume_series, run_dir)
from .output import slug  # noqa: E402
from .trends import PAPER_VALUE, TIER_SCALE  # noqa: E402

MAX_LINE_POINTS = 20000
PAPER_FIGURE = {("angle", "pressure"): "Fig. 3a", ("ratio", "pressure"): "Fig. 3c",
                ("angle", "P_max"): "Fig. 3b", ("ratio", "P_max"): "Fig. 3d",
                ("angle", "volume"): "Fig. 4a", ("ratio", "volume"): "Fig. 4b",
                ("angle", "wrms"): "Fig. 7a", ("ratio", "wrms"): "Fig. 7b"}


def prefix(a) -> str:
    return f"trends_{slug(a.sweep.name)}_{a.kind}_"


def remove_stale(a, out_dir: Path) -> None:
    """Removes this sweep's figures of an earlier run, so that none outlives its data."""
    folder = Path(out_dir) / "figures"
    if folder.is_dir():
        for path in folder.glob(prefix(a) + "*"):
            if path.suffix in (".png", ".txt") and path.is_file():
                path.unlink()


def _save(fig: Figure, a, out_dir: Path, what: str, caption: str) -> Path:
    caption = f"{caption} Sweep {a.sweep.name}, {a.tier} tier ({TIER_SCALE[a.tier]})."
    return save_figure(fig, out_dir, prefix(a) + what, caption)


def _colors(count: int):
    cmap = colormaps["viridis"]
    return [cmap(v) for v in np.linspace(0.0, 0.9, max(count, 1))]


def _thin(frame: pd.DataFrame) -> pd.DataFrame:
    if len(frame) > MAX_LINE_POINTS:
        return frame.iloc[:: int(np.ceil(len(frame) / MAX_LINE_POINTS))]
    return frame


def _first_runs(a) -> list[tuple[float, int, Path | None]]:
    rows = first_realizations(a.data, a.x)
    return [(float(r[a.x]), int(r["run"]), run_dir(a.sweep.folder, int(r["run"])))
            for _, r in rows.iterrows()]


# --------------------------------------------------------------------------- figures


def pressure_vs_time(a, out_dir: Path):
    runs = _first_runs(a)
    fig = Figure(figsize=(8, 4.5))
    ax = fig.add_subplot()
    drawn, missing = 0, []
    for color, (value, run, folder) in zip(_colors(len(runs)), runs):
        series = read_timeseries(folder) if folder else None
        if series is None or not {"t", "pressure"}.issubset(series.columns):
            missing.append(f"run {run}")
            continue
        series = _thin(series.dropna(subset=["t", "pressure"]))
        ax.plot(series["t"], series["pressure"], color=color, lw=0.7,
                label=a.point_label(value) + f" (run {run})")
        cycles = read_cycles(folder)
        if cycles is not None and {"t_peak", "peak_pressure"}.issubset(cycles.columns):
            ax.plot(cycles["t_peak"], cycles["peak_pressure"], "o", color=color, ms=4,
                    mec="black", mew=0.5)
        drawn += 1
    notes = []
    if missing:
        notes.append(f"{a.case}: pressure-time figure: no timeseries.csv with t and pressure "
                     f"for {', '.join(missing)}")
    if not drawn:
        return [], notes
    ax.set_xlabel("time t")
    ax.set_ylabel("wall pressure P")
    ax.legend(fontsize=7, loc="best")
    fig_name = PAPER_FIGURE[(a.kind, "pressure")]
    path = _save(fig, a, out_dir, "pressure_time",
                 f"Wall pressure against time for each {a.x_label}, first realization of each "
                 f"point; dots mark each cycle's peak pressure (mirrors the paper's {fig_name}).")
    return [path], notes


def _errorbar_points(ax, a, metric, groups, color, label, fallback_std=None):
    std = groups["std"].to_numpy(dtype=float).copy()
    used_fallback = False
    if fallback_std is not None:
        for i, (x, n) in enumerate(zip(groups["x"], groups["n"])):
            if n < 2 and x in fallback_std and np.isfinite(fallback_std[x]):
                std[i] = fallback_std[x]
                used_fallback = True
    std = np.where(np.isfinite(std), std, 0.0)
    ax.errorbar(groups["x"], groups["mean"], yerr=std, fmt="o", color=color, capsize=4,
                label=label)
    return used_fallback


_FIT_STYLES = (("linear", "--", "dashed"), ("quadratic", "-", "solid"))


def _fit_lines(ax, info, color, label_prefix=""):
    """Draws the fits through the means that exist (a quadratic needs 3 values)."""
    for name, style, _ in _FIT_STYLES:
        fit = info["means"][name]
        if fit is None:
            continue
        xs, ys = fit.curve()
        r2 = f", R^2 = {fit.r2:.3f}" if np.isfinite(fit.r2) else ""
        ax.plot(xs, ys, style, color=color, lw=1.2,
                label=f"{label_prefix}{name} fit{r2}")


def _fits_said(*infos) -> str:
    """The caption's words for the fit lines drawn, e.g. 'dashed: linear fit, solid:
    quadratic fit', or that none is drawn: only the fits that exist are named."""
    said = [f"{word}: {name} fit" for name, _, word in _FIT_STYLES
            if any(info["means"][name] is not None for info in infos)]
    return ", ".join(said) if said else "no fit (too few values)"


def metric_vs_parameter(a, out_dir: Path):
    info = a.metrics.get("P_max")
    if info is None or info["groups"].empty:
        return [], [f"{a.case}: P_max figure: no finite P_max"]
    fig = Figure(figsize=(6, 4.5))
    ax = fig.add_subplot()
    values = a.data[[a.x, "P_max"]].apply(pd.to_numeric, errors="coerce").dropna()
    ax.plot(values[a.x], values["P_max"], ".", color="0.6", ms=4, label="realizations")
    fallback = None
    if "P_max_std" in a.data.columns:
        fallback = {float(x): float(s) for x, s in
                    zip(a.data[a.x], pd.to_numeric(a.data["P_max_std"], errors="coerce"))}
    used = _errorbar_points(ax, a, "P_max", info["groups"], "C0", "mean P_max", fallback)
    _fit_lines(ax, info, "C3")
    ax.set_xlabel(a.x_label + (" (deg)" if a.kind == "angle" else ""))
    ax.set_ylabel("mean peak pressure P_max")
    ax.legend(fontsize=8)
    n = ", ".join(str(v) for v in info["groups"]["n"])
    bars = ("one standard deviation over the realizations, as in the paper"
            + ("; points with one realization show its cycle-to-cycle standard deviation "
               "of the peaks (P_max_std) instead" if used else ""))
    path = _save(fig, a, out_dir, "P_max",
                 f"Mean peak pressure P_max over the steady-state cycles against {a.x_label} "
                 f"(realizations per point: {n}); error bars: {bars}; {_fits_said(info)} "
                 f"(mirrors the paper's {PAPER_FIGURE[(a.kind, 'P_max')]}).")
    return [path], []


def wrms_vs_parameter(a, out_dir: Path):
    windows = [w for w in a.sweep.windows if w.column in a.metrics
               and not a.metrics[w.column]["groups"].empty]
    if not windows:
        return [], [f"{a.case}: W_rms figure: no W_rms_<a>_<b> column with finite values"]
    fig = Figure(figsize=(6, 4.5))
    ax = fig.add_subplot()
    for i, window in enumerate(windows):
        info = a.metrics[window.column]
        color = f"C{i % 10}"
        _errorbar_points(ax, a, window.column, info["groups"], color, f"W_rms, {window.label}")
        _fit_lines(ax, info, color, f"{window.label}: ")
    ax.set_xlabel(a.x_label + (" (deg)" if a.kind == "angle" else ""))
    ax.set_ylabel("RMS vorticity W_rms")
    ax.legend(fontsize=7)
    path = _save(fig, a, out_dir, "W_rms",
                 f"RMS vorticity W_rms of the accumulated displacement per window of cycles "
                 f"against {a.x_label}; error bars: one standard deviation over the "
                 f"realizations; {_fits_said(*(a.metrics[w.column] for w in windows))} (mirrors "
                 f"the paper's {PAPER_FIGURE[(a.kind, 'wrms')]}).")
    return [path], []


def volume_vs_time(a, out_dir: Path):
    runs = _first_runs(a)
    fig = Figure(figsize=(8, 4.5))
    ax = fig.add_subplot()
    drawn_time, drawn_cycles, missing = 0, 0, []
    for color, (value, run, folder) in zip(_colors(len(runs)), runs):
        series = read_volume_series(folder)[0]  # timeseries.csv, or a campaign run's volume.csv
        label = a.point_label(value) + f" (run {run})"
        if series is not None and {"t", "V_over_V0"}.issubset(series.columns) \
                and series["V_over_V0"].notna().any():
            series = _thin(series.dropna(subset=["t", "V_over_V0"]))
            ax.plot(series["t"], series["V_over_V0"], color=color, lw=0.8, label=label)
            drawn_time += 1
            continue
        missing.append(f"run {run}")
    notes = []
    if not drawn_time:
        # Fall back on V/V0 at the end of each cycle, against the cycle number.
        ax.clear()
        for color, (value, run, folder) in zip(_colors(len(runs)), runs):
            values, _ = end_of_cycle_volumes(folder)
            if values is not None:
                ax.plot(np.arange(len(values)), values, "o-", color=color, ms=3,
                        label=a.point_label(value) + f" (run {run})")
                drawn_cycles += 1
        if not drawn_cycles:
            return [], [f"{a.case}: V/V0 figure: no V_over_V0 in timeseries.csv or cycles.csv "
                        "of the first realizations"]
        notes.append(f"{a.case}: V/V0 figure drawn per cycle (no V_over_V0 in timeseries.csv)")
        ax.set_xlabel("cycle")
        what = "at the end of each cycle (cooling), against the cycle number"
    else:
        if missing:
            notes.append(f"{a.case}: V/V0 figure: no V_over_V0 in timeseries.csv for "
                         f"{', '.join(missing)}")
        ax.set_xlabel("time t")
        what = "against time"
    ax.set_ylabel("V / V0")
    ax.legend(fontsize=7)
    path = _save(fig, a, out_dir, "volume",
                 f"Bed volume V/V0 (convex hull of all vertices) {what} for each {a.x_label}, "
                 f"first realization of each point (mirrors the paper's "
                 f"{PAPER_FIGURE[(a.kind, 'volume')]}).")
    return [path], notes


def _grid(frame: pd.DataFrame, column: str):
    """(R, Z, values) on the (ir, iz) grid (or the distinct r, z), NaN where empty."""
    if {"ir", "iz"}.issubset(frame.columns):
        table = frame.pivot_table(index="iz", columns="ir", values=column, aggfunc="mean",
                                  dropna=False)
        r = frame.groupby("ir")["r"].mean().reindex(table.columns).to_numpy(dtype=float)
        z = frame.groupby("iz")["z"].mean().reindex(table.index).to_numpy(dtype=float)
    else:
        table = frame.pivot_table(index="z", columns="r", values=column, aggfunc="mean",
                                  dropna=False)
        r = table.columns.to_numpy(dtype=float)
        z = table.index.to_numpy(dtype=float)
    return r, z, table.to_numpy(dtype=float)


def displacement_fields(a, out_dir: Path):
    """Accumulated displacement of the reference run: theta_c nearest 0 (angle sweep),
    alpha_c/alpha_p nearest 10 (ratio sweep), first realization."""
    runs = _first_runs(a)
    if not runs:
        return [], []
    reference = PAPER_VALUE[a.kind]
    value, run, folder = min(runs, key=lambda item: abs(item[0] - reference))
    files = displacement_files(folder) if folder else []
    frames = [(first, last, read_displacement(path)) for first, last, path in files]
    frames = [(f, l, d) for f, l, d in frames if d is not None and not d.empty]
    if not frames:
        return [], [f"{a.case}: displacement figure: no displacement_<a>_<b>.csv in the run "
                    f"folder of run {run}"]
    fig = Figure(figsize=(4.2 * len(frames) + 1, 5))
    axes = fig.subplots(1, len(frames), squeeze=False)[0]
    w_max = 0.0
    for _, _, d in frames:
        if "w" in d.columns and np.isfinite(d["w"]).any():
            w_max = max(w_max, float(np.nanmax(np.abs(d["w"]))))
    mesh = None
    for ax, (first, last, d) in zip(axes, frames):
        if "w" in d.columns and w_max > 0:
            r, z, w = _grid(d, "w")
            if r.size and z.size:
                mesh = ax.pcolormesh(r, z, np.ma.masked_invalid(w), shading="nearest",
                                     cmap="RdBu_r", vmin=-w_max, vmax=w_max)
        cells = d
        if "count" in d.columns:
            cells = d[pd.to_numeric(d["count"], errors="coerce").fillna(0) > 0]
        cells = cells.dropna(subset=["r", "z", "ur", "uz"])
        ax.quiver(cells["r"], cells["z"], cells["ur"], cells["uz"], angles="xy", pivot="mid",
                  color="black", width=0.004)
        ax.set_title(f"cycles {first} to {last}")
        ax.set_xlabel("r")
        ax.set_aspect("equal", adjustable="box")
    axes[0].set_ylabel("z")
    if mesh is not None:
        fig.colorbar(mesh, ax=list(axes), label="vorticity w = du_z/dr - du_r/dz")
    path = _save(fig, a, out_dir, "displacement",
                 f"Accumulated displacement (u_r, u_z), averaged over the polar angle, as arrows "
                 f"with the vorticity w in colour (interior cells), per window of cycles; "
                 f"run {run} at {a.point_label(value)} (mirrors the paper's Fig. 6).")
    return [path], []


def draw_stage_fields(stage, title: str = "") -> Figure:
    """Three panels of a run's stage fields (fields.StageFields) over the second half of
    its cycles: the mean heating field, the mean cooling field (arrows), and their sum
    over those cycles, the cumulative field (arrows, vorticity in colour)."""
    from .fields import steady_cycles_of, vorticity  # fields imports trends, as this module
    cycles = steady_cycles_of(stage.cycles)
    pick = np.isin(stage.cycles, cycles)
    populated = (stage.count[pick] > 0).all(axis=0)
    r, z = np.meshgrid(stage.r, stage.z)
    fig = Figure(figsize=(13, 5))
    axes = fig.subplots(1, 3, sharey=True)
    for ax, name in zip(axes[:2], ("heating", "cooling")):
        with np.errstate(invalid="ignore"):  # cells empty in every cycle stay NaN, not drawn
            count = np.isfinite(getattr(stage, f"ur_{name}")[pick]).sum(axis=0)
            ur = np.nansum(getattr(stage, f"ur_{name}")[pick], axis=0) / count
            uz = np.nansum(getattr(stage, f"uz_{name}")[pick], axis=0) / count
        ax.quiver(r[populated], z[populated], ur[populated], uz[populated], angles="xy",
                  pivot="mid", color="black", width=0.004)
        ax.set_title(f"{name}, mean of cycles {cycles[0]}-{cycles[-1]}")
    ur, uz, both = stage.cumulative(cycles)
    w = vorticity(ur, uz, stage.cell)
    limit = float(np.nanmax(np.abs(w))) if np.isfinite(w).any() else 0.0
    if limit > 0:
        mesh = axes[2].pcolormesh(stage.r, stage.z, np.ma.masked_invalid(w), shading="nearest",
                                  cmap="RdBu_r", vmin=-limit, vmax=limit)
        fig.colorbar(mesh, ax=axes[2], label="vorticity w = du_z/dr - du_r/dz")
    axes[2].quiver(r[both], z[both], ur[both], uz[both], angles="xy", pivot="mid", color="black",
                   width=0.004)
    axes[2].set_title(f"cumulative, cycles {cycles[0]}-{cycles[-1]}")
    for ax in axes:
        ax.set_xlabel("r")
        ax.set_aspect("equal", adjustable="box")
        ax.set_xlim(0, stage.r[-1] + 0.5 * stage.cell)
        ax.set_ylim(0, stage.z[-1] + 0.5 * stage.cell)
    axes[0].set_ylabel("z")
    if title:
        fig.suptitle(title)
    return fig


def stage_fields_figure(a, out_dir: Path):
    """Heating, cooling and cumulative fields of the reference run (as
    displacement_fields): theta_c nearest 0 or alpha_c/alpha_p nearest 10, first
    realization."""
    from .fields import FieldsError, read_stage_fields
    runs = _first_runs(a)
    if not runs:
        return [], []
    reference = PAPER_VALUE[a.kind]
    value, run, folder = min(runs, key=lambda item: abs(item[0] - reference))
    try:
        stage = read_stage_fields(folder)
    except FieldsError as problem:
        return [], [f"{a.case}: stage-field figure: {problem}"]
    if stage is None:  # the scene did not ask for it: the field checks say so (skipped)
        return [], []
    fig = draw_stage_fields(stage, f"run {run}, {a.point_label(value)}")
    path = _save(fig, a, out_dir, "stage_fields",
                 f"Displacement over the heating and over the cooling (means over the second half "
                 f"of the cycles) and their sum over those cycles, the cumulative field, averaged "
                 f"over the polar angle on the (r, z) cells, vorticity in colour; run {run} at "
                 f"{a.point_label(value)} (mirrors the paper's Fig. 5 and Fig. 6).")
    return [path], []


ALL = (pressure_vs_time, metric_vs_parameter, volume_vs_time, wrms_vs_parameter,
       displacement_fields, stage_fields_figure)


def make_all(a, out_dir: Path):
    """Every figure of one analysis: (paths, notes)."""
    remove_stale(a, out_dir)
    paths, notes = [], []
    for make in ALL:
        made, why = make(a, out_dir)
        paths += made
        notes += why
    return paths, notes
