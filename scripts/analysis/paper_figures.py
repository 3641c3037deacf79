"""The figures of "The paper, figure by figure" that scripts/trends does not draw from
the campaign's stored results (analysis/paper_repro.py; the others are plots.py's): the
peak pressure cycle by cycle, for Fig. 3a / 3c (the stored runs keep cycles.csv, not the
time series that plots.pressure_vs_time needs), the peak pressure against the packing
density cycle by cycle (Fig. 3a / 3c's "pressure increases as the total packing density
increases"), and the 6 deg halving with the band its check accepts.

Each function takes an Analysis (trends.analyse), saves one PNG with its caption
through common.figures.save_figure and returns (paths, notes), as plots.py's do.
"""

from __future__ import annotations

import math
import os
from pathlib import Path

os.environ.setdefault("MPLBACKEND", "Agg")

import matplotlib  # noqa: E402

matplotlib.use("Agg")

import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402
from matplotlib import colormaps  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402
from matplotlib.ticker import MaxNLocator  # noqa: E402

from common.figures import save_figure  # noqa: E402

from .inputs import read_cycles, run_dir, steady_peaks  # noqa: E402
from .plots import PAPER_FIGURE  # noqa: E402
from .trends import CHECKS, HALVING_ANGLES  # noqa: E402
from .verdict_text import result_text  # noqa: E402


def _name(a, what: str) -> str:
    return f"paper_{a.sweep.name}_{what}"


def peaks_per_cycle(a, out_dir: Path):
    """Per point: each cycle's peak pressure, mean over the realizations with one
    standard deviation shaded; the steady cycles P_max averages marked."""
    fig = Figure(figsize=(8, 4.5))
    ax = fig.add_subplot()
    points = sorted(a.data[a.x].dropna().unique())
    window, drawn, missing = None, 0, []
    colors = colormaps["viridis"](np.linspace(0.0, 0.9, max(len(points), 1)))
    for color, value in zip(colors, points):
        curves = []
        for run in a.data.loc[np.isclose(a.data[a.x], value), "run"]:
            folder = run_dir(a.sweep.folder, int(run))
            cycles = read_cycles(folder) if folder else None
            if cycles is None or not {"cycle", "peak_pressure"}.issubset(cycles.columns):
                missing.append(f"run {int(run)}")
                continue
            curves.append(cycles.set_index("cycle")["peak_pressure"].rename(int(run)))
            if window is None:
                steady, _ = steady_peaks(folder)
                window = steady["window"] if steady else None
        if not curves:
            continue
        table = pd.concat(curves, axis=1).sort_index()
        mean, std = table.mean(axis=1), table.std(axis=1, ddof=1)
        ax.plot(table.index, mean, "o-", color=color, ms=3, lw=1,
                label=f"{a.point_label(value)} ({table.shape[1]} realization"
                      f"{'s' if table.shape[1] > 1 else ''})")
        if table.shape[1] > 1:
            ax.fill_between(table.index, mean - std, mean + std, color=color, alpha=0.2, lw=0)
        drawn += 1
    notes = [f"{a.case}: peak figure: no cycles.csv with cycle and peak_pressure for "
             f"{', '.join(missing)}"] if missing else []
    if not drawn:
        return [], notes
    if window:
        ax.axvspan(window[0] - 0.5, window[1] + 0.5, color="0.93", zorder=0,
                   label=f"steady cycles {window[0]}-{window[1]}")
    ax.xaxis.set_major_locator(MaxNLocator(integer=True))
    ax.set_xlabel("cycle")
    ax.set_ylabel("peak wall pressure of the cycle")
    ax.legend(fontsize=7, loc="best")
    paper = PAPER_FIGURE[(a.kind, "pressure")]
    path = save_figure(fig, out_dir, _name(a, "peaks"),
                       f"Peak wall pressure of each cycle (cycles.csv) for each {a.x_label}: mean "
                       f"over the realizations, one standard deviation shaded; grey: the steady "
                       f"cycles that P_max averages. Mirrors the paper's {paper}, which shows "
                       f"P(t) with each cycle's peak as a dot: the stored runs keep the peaks, "
                       f"not the time series. Sweep {a.sweep.name}, {a.tier} tier.")
    return [path], notes


def pressure_density(a, out_dir: Path):
    """One panel per point: each realization's cycles as (V/V0 at the end of the cooling,
    peak pressure), joined in cycle order with the first cycle ringed, and the point's
    verdict of pmax_follows_density in the title. Panels have their own axes: the
    pressure and the compaction differ by orders of magnitude between the points."""
    points = sorted(a.data[a.x].dropna().unique())
    verdicts = {r.check: r for r in a.results if r.check_id == "pmax_follows_density"}
    columns = min(len(points), 3) or 1
    rows = max(math.ceil(len(points) / columns), 1)
    fig = Figure(figsize=(4.0 * columns, 3.4 * rows))
    axes = np.atleast_1d(fig.subplots(rows, columns, squeeze=False)).ravel()
    drawn, missing = 0, []
    for ax, value in zip(axes, points):
        runs = a.data.loc[np.isclose(a.data[a.x], value), "run"]
        colors = colormaps["tab10"](np.arange(len(runs)) % 10)
        for color, run in zip(colors, runs):
            folder = run_dir(a.sweep.folder, int(run))
            cycles = read_cycles(folder) if folder else None
            if cycles is None or not {"peak_pressure", "V_over_V0_end_cooling"}.issubset(cycles.columns):
                missing.append(f"run {int(run)}")
                continue
            v, p = cycles["V_over_V0_end_cooling"].to_numpy(float), cycles["peak_pressure"].to_numpy(float)
            ax.plot(v, p, ".-", color=color, ms=4, lw=0.7, label=f"run {int(run)}")
            ax.plot(v[:1], p[:1], "o", mfc="none", color=color, ms=8)
            drawn += 1
        result = verdicts.get(CHECKS["pmax_follows_density"].check.format(point=a.point_label(value)))
        shown = result_text(result.status, result.measured).lower() if result else "not evaluated"
        rho = f"rho {result.measured:+.2f}, {shown}" if result and result.measured is not None else shown
        ax.set_title(f"{a.point_label(value)}: {rho}", fontsize=8)
        ax.set_xlabel("V/V0 at the end of the cooling (denser to the right)", fontsize=7)
        ax.set_ylabel("peak wall pressure of the cycle", fontsize=7)
        ax.tick_params(labelsize=7)
        ax.invert_xaxis()  # denser to the right: "pressure rises with density" reads upward
        ax.xaxis.get_offset_text().set_fontsize(7)
    for ax in axes[len(points):]:
        ax.set_visible(False)
    notes = [f"{a.case}: pressure-density figure: no cycles.csv with peak_pressure and "
             f"V_over_V0_end_cooling for {', '.join(missing)}"] if missing else []
    if not drawn:
        return [], notes
    axes[0].legend(fontsize=6, loc="best")
    fig.tight_layout()
    paper = PAPER_FIGURE[(a.kind, "pressure")]
    path = save_figure(fig, out_dir, _name(a, "density"),
                       f"Peak wall pressure of each cycle against V/V0 at the end of its cooling "
                       f"(cycles.csv; the x axis runs from loose to dense), one line per "
                       f"realization in cycle order, the first cycle ringed; one panel per "
                       f"{a.x_label}, each with its own axes. The title gives check "
                       f"pmax_follows_density's mean rank correlation and status. The paper "
                       f"({paper}): 'the first regime is due to compaction of the granular "
                       f"material, since pressure increases as the total packing density "
                       f"increases'. Sweep {a.sweep.name}, {a.tier} tier.")
    return [path], notes


def halving(a, out_dir: Path):
    """P_max of each realization at 0 and 6 deg, and their ratio with its interval
    against the band that check pmax_ratio_6_0 accepts."""
    low_angle, high_angle = HALVING_ANGLES
    data = a.data[[a.x, "P_max"]].apply(pd.to_numeric, errors="coerce").dropna()
    at = {angle: data.loc[np.isclose(data[a.x], angle), "P_max"].to_numpy(float)
          for angle in HALVING_ANGLES}
    if not all(len(v) for v in at.values()):
        return [], []  # the check says skipped, and why
    result = next((r for r in a.results if r.check_id == "pmax_ratio_6_0"), None)
    fig = Figure(figsize=(9, 4))
    left, right = fig.subplots(1, 2, gridspec_kw={"width_ratios": [3, 2]})
    for i, angle in enumerate(HALVING_ANGLES):
        values = at[angle]
        left.plot(np.full(len(values), i), values, "o", color="0.45", ms=5,
                  label="realizations" if i == 0 else None)
        std = float(np.std(values, ddof=1)) if len(values) > 1 else 0.0
        left.errorbar([i + 0.15], [values.mean()], yerr=[std], fmt="s", color="C0", capsize=5,
                      label="mean +- 1 std" if i == 0 else None)
    left.axhline(0.5 * at[low_angle].mean(), color="C3", ls="--", lw=1,
                 label=f"half of P_max({low_angle:g} deg)")
    left.set_xticks([0, 1], [f"theta_c = {low_angle:g} deg", f"theta_c = {high_angle:g} deg"])
    left.set_xlim(-0.5, 1.6)
    left.set_ylabel("P_max (steady-state mean peak)")
    left.legend(fontsize=7)
    band = CHECKS["pmax_ratio_6_0"].params(a.tier)
    right.axhspan(band["target"] - band["half_width"], band["target"] + band["half_width"],
                  color="#d8f0d8", label="accepted band")
    right.axhline(band["target"], color="C2", lw=1)
    ratio = a.halving or {}
    value = ratio.get("ratio", math.nan)
    interval = (result.detail.get("interval") if result else None) or [math.nan, math.nan]
    if all(math.isfinite(v) for v in interval):
        right.errorbar([0], [value], yerr=[[value - interval[0]], [interval[1] - value]], fmt="o",
                       color="black", capsize=6, label=f"R, {band['level']:.0%} interval")
    else:
        right.plot([0], [value], "o", color="black", label="R (no interval: one realization)")
    right.set_xticks([])
    right.set_xlim(-1, 1)
    right.set_ylabel(f"R = P_max({high_angle:g}) / P_max({low_angle:g})")
    right.legend(fontsize=7)
    status = result.status if result else "not evaluated"
    n_low, n_high = len(at[low_angle]), len(at[high_angle])
    path = save_figure(fig, out_dir, _name(a, "halving"),
                       f"Left: P_max of each realization at theta_c = {low_angle:g} and "
                       f"{high_angle:g} deg ({n_low} and {n_high} realizations) with their means; "
                       f"right: R = P_max({high_angle:g})/P_max({low_angle:g}) with its "
                       f"{band['level']:.0%} interval (Student t, Welch-Satterthwaite dof) against "
                       f"the band {band['target'] - band['half_width']:g}-"
                       f"{band['target'] + band['half_width']:g} that check pmax_ratio_6_0 accepts "
                       f"(status: {status}). The paper: 'an opening angle of only 6 deg halves the "
                       f"peak pressure'. Sweep {a.sweep.name}, {a.tier} tier.")
    return [path], []
