"""The figure of one or more sweep folders and its command line (scripts/plot-sweep).

P_max and W_rms against the swept parameter, in the style of the paper's Figs. 3b/3d and
7a/7b: every realization a small grey marker, the mean of each point with an error bar
of one standard error (std / sqrt(n)). One row of two panels per study (an angle sweep,
a ratio sweep; a sweep over both gives both, each cut where the paper fixes the other,
as scripts/trends does). Sweep folders are read by .inputs.load_sweep (summary.csv as
`ratchet sweep` writes it, docs/sweeps.md); a run's run.json gives the bed and the
averaging of P_max for the caption.

Exit status: 0 figure written; 2 bad arguments (an --out that is not .png, .pdf or .svg,
refused before anything is read), an unreadable sweep folder, a folder whose
summary.csv has neither swept parameter, no finite P_max, or an unwritable output
(nothing written then).
"""

from __future__ import annotations

import argparse
import os
import sys
from dataclasses import dataclass, field
from pathlib import Path
from typing import Sequence

os.environ.setdefault("MPLBACKEND", "Agg")

import matplotlib  # noqa: E402

matplotlib.use("Agg")

import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

from common.fsutil import figure_format, save_figure_atomic  # noqa: E402

from . import fits  # noqa: E402
from .inputs import ANGLE, ALPHA_C, InputError, Sweep, load_sweep, read_run_json, run_dir  # noqa: E402
from .run_figures import describe  # noqa: E402
from .trends import X_COLUMNS, study_runs  # noqa: E402

PROG = "plot-sweep"
DEFAULT_NAME = "sweep.png"
X_LABELS = {"angle": "cone opening angle θ_c (deg)", "ratio": "expansion ratio α_c / α_p"}
#: The paper's figures these mirror.
PAPER = {"angle": ("Fig. 3b", "Fig. 7a"), "ratio": ("Fig. 3d", "Fig. 7b")}
P_MAX_LABEL = "P_max / (ρ g r_max)"
W_RMS_LABEL = "W_rms (dimensionless)"
#: Means of several W_rms windows at one x are drawn this fraction of the x range apart.
WINDOW_OFFSET = 0.012


class SweepPlotError(Exception):
    """A sweep that cannot be drawn; the message names the folder or file."""


@dataclass
class Study:
    """One sweep along one parameter: the completed runs of the slice and what they mean."""

    sweep: Sweep
    kind: str                   # "angle" or "ratio"
    data: pd.DataFrame
    scene: dict                 # a run's scene, for the caption ({} without run.json)
    summary: dict               # that run's summary (steady_cycles)
    notes: list[str] = field(default_factory=list)

    @property
    def x(self) -> str:
        return X_COLUMNS[self.kind]

    @property
    def windows(self):
        """The W_rms windows with a finite value in this slice."""
        return [w for w in self.sweep.windows if w.column in self.data.columns
                and np.isfinite(pd.to_numeric(self.data[w.column], errors="coerce")).any()]

    def stats(self, metric: str) -> pd.DataFrame:
        """x, n, mean, std, sem of `metric` per point (fits.group_stats)."""
        return fits.group_stats(self.data[[self.x, metric]], self.x, metric)


def load_studies(folder: str | os.PathLike) -> list[Study]:
    """The studies of one sweep folder; SweepPlotError naming the folder when there is none."""
    try:
        sweep = load_sweep(folder)
    except InputError as e:
        raise SweepPlotError(str(e)) from None
    if not sweep.kinds:
        raise SweepPlotError(f"{sweep.folder / 'summary.csv'}: neither {ANGLE} nor {ALPHA_C} is a column "
                             f"(columns: {', '.join(sweep.summary.columns)}): not an angle or ratio sweep "
                             "(docs/sweeps.md)")
    studies = []
    for kind in sweep.kinds:
        notes = list(sweep.notes)
        data = study_runs(sweep, kind, notes)
        if not np.isfinite(pd.to_numeric(data["P_max"], errors="coerce")).any():
            # Say why: the runs left out (not completed, or at the solver's cap) are in the notes.
            raise SweepPlotError(f"{sweep.folder / 'summary.csv'}: no completed run with a finite P_max "
                                 f"along {X_COLUMNS[kind]}" + "".join(f"; {n}" for n in notes))
        first = data.sort_values("run").iloc[0]
        run = read_run_json(run_dir(sweep.folder, int(first["run"]))) or {}
        if not run:
            notes.append(f"no run.json in runs/{int(first['run'])}: the caption does not describe the bed")
        studies.append(Study(sweep, kind, data, run.get("scene") or {}, run.get("summary") or {}, notes))
    return studies


def _points(ax, study: Study, metric: str, color, label: str, offset: float = 0.0) -> pd.DataFrame:
    """Every realization as a small marker, the means with standard-error bars; the stats."""
    values = study.data[[study.x, metric]].apply(pd.to_numeric, errors="coerce").dropna()
    ax.plot(values[study.x] + offset, values[metric], "o", ms=4, color=color, alpha=0.45, mew=0,
            label=f"{label}: each realization")
    stats = study.stats(metric)
    ax.errorbar(stats["x"] + offset, stats["mean"], yerr=stats["sem"].fillna(0.0), fmt="o", ms=6,
                color=color, mec="black", mew=0.6, capsize=4, elinewidth=1.2,
                label=f"{label}: mean ± standard error")
    return stats


def _p_max_caption(study: Study) -> str:
    """How this study's P_max was averaged, as far as its run.json says."""
    steady = study.summary.get("steady_cycles")
    window = (study.scene.get("outputs") or {}).get("pressure_window")
    parts = []
    if window is not None:
        parts.append(f"peaks of P averaged over blocks of Δt = {window:g}")
    if isinstance(steady, list) and len(steady) == 2:
        parts.append(f"steady cycles {steady[0]}–{steady[1]}")
    return f"; P_max from {', '.join(parts)}" if parts else ""


def figure(studies: list[Study]) -> Figure:
    rows = len(studies)
    fig = Figure(figsize=(11, 3.9 * rows + 1.6))
    axes = fig.subplots(rows, 2, squeeze=False)
    captions = []
    for study, (ax_p, ax_w) in zip(studies, axes):
        name = study.sweep.name
        stats = _points(ax_p, study, "P_max", "C0", "P_max")
        ax_p.set_xlabel(X_LABELS[study.kind])
        ax_p.set_ylabel(P_MAX_LABEL)
        ax_p.set_title(f"{name}: mean peak pressure (as the paper's {PAPER[study.kind][0]})",
                       loc="left", fontsize=9)
        n = ", ".join(str(int(v)) for v in stats["n"])
        bed = describe(study.scene, leave_out=(study.kind,))
        captions.append(f"{name} ({study.kind} sweep{', ' + bed if bed else ''}): "
                        f"{len(study.data)} runs, realizations per point with a P_max {n}{_p_max_caption(study)}.")
        windows = study.windows
        span = float(np.ptp(stats["x"])) or 1.0
        for i, window in enumerate(windows):
            offset = WINDOW_OFFSET * span * (i - (len(windows) - 1) / 2)
            _points(ax_w, study, window.column, f"C{(i + 1) % 10}", f"W_rms, {window.label}", offset)
        if windows:
            ax_w.set_title(f"{name}: RMS vorticity (as the paper's {PAPER[study.kind][1]})",
                           loc="left", fontsize=9)
        else:
            ax_w.text(0.5, 0.5, "no finite W_rms_<a>_<b> in summary.csv\n(no window, or no interior "
                      "cell: a bed only a few cells tall)", transform=ax_w.transAxes, ha="center",
                      va="center", fontsize=8, color="0.3")
            ax_w.set_title(f"{name}: RMS vorticity", loc="left", fontsize=9)
        ax_w.set_xlabel(X_LABELS[study.kind])
        ax_w.set_ylabel(W_RMS_LABEL)
        for ax in (ax_p, ax_w):
            ax.grid(alpha=0.3)
            ax.set_xticks(stats["x"], labels=[f"{v:g}" for v in stats["x"]])
            if ax.get_legend_handles_labels()[0]:
                ax.legend(fontsize=7, loc="best")
            ax.margins(x=0.08)
    notes = [f"{s.sweep.name} ({s.kind}): {n}" for s in studies for n in s.notes]
    text = ("Small pale markers: every completed realization; large markers: the mean of each "
            "point with an error bar of one standard error (sample std / sqrt(n); none with n = 1). "
            "P_max: each run's mean of its cycles' peak pressure over the steady cycles; W_rms: RMS "
            "vorticity of the displacement field accumulated over the window's cycles "
            "(docs/output-format.md).\n" + "\n".join(captions))
    fig.suptitle("Sweep " + ", ".join(dict.fromkeys(s.sweep.name for s in studies))
                 + ": P_max and W_rms against the swept parameter", x=0.01, ha="left", fontsize=11)
    lines = text.count("\n") + 1 + len(notes)
    inch = 1.0 / fig.get_figheight()
    fig.text(0.01, 0.08 * inch, text + ("\n" + "\n".join(notes) if notes else ""), fontsize=7,
             va="bottom", wrap=True, color="0.2", linespacing=1.3)
    fig.tight_layout(rect=(0, (0.2 + 0.16 * (lines + 1)) * inch, 1, 1 - 0.1 * inch))
    return fig


def summary_line(study: Study, out: Path) -> str:
    stats = study.stats("P_max")
    windows = ", ".join(w.column for w in study.windows) or "no W_rms"
    return (f"{PROG}: {study.sweep.name} ({study.kind}): {len(study.data)} runs at {len(stats)} points "
            f"({int(stats['n'].min())}-{int(stats['n'].max())} realizations), P_max means "
            f"{stats['mean'].min():.4g} to {stats['mean'].max():.4g}, {windows} -> {out}")


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog=PROG, description="Plots P_max and W_rms of sweep output folders against the swept "
                               "parameter (opening angle, or alpha_c/alpha_p): every realization as a "
                               "small marker, the mean of each point with a standard-error bar.",
        epilog="Exit status: 0 figure written; 2 bad arguments, an unreadable sweep folder, no swept "
               "parameter or no finite P_max, or an unwritable output.")
    parser.add_argument("sweeps", nargs="+", metavar="SWEEP_DIR", type=Path,
                        help="folder written by `ratchet sweep --out` (summary.csv, runs/<id>/)")
    parser.add_argument("--out", metavar="FILE", type=Path,
                        help="the figure; its extension sets the format: .png, .pdf or .svg (default "
                             f"with one SWEEP_DIR: SWEEP_DIR/{DEFAULT_NAME}; required with several)")
    args = parser.parse_args(argv)
    if args.out is None and len(args.sweeps) > 1:
        parser.error("argument --out: required with several SWEEP_DIRs")
    out = args.out or args.sweeps[0] / DEFAULT_NAME
    try:
        figure_format(out)
    except ValueError as e:
        parser.error(f"argument --out: {e}")
    if out.is_dir():
        parser.error(f"argument --out: {out} is a folder")
    try:
        studies = [study for folder in args.sweeps for study in load_studies(folder)]
    except SweepPlotError as e:
        print(f"{PROG}: error: {e}", file=sys.stderr)
        return 2
    try:
        save_figure_atomic(figure(studies), out, dpi=120)
    except OSError as e:
        print(f"{PROG}: error: cannot write {out}: {e}", file=sys.stderr)
        return 2
    for study in studies:
        print(summary_line(study, out))
    return 0
