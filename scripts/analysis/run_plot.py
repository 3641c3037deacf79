"""One run folder of `ratchet run` as one figure, and a one-line summary (scripts/plot-run).

Reads RUN_DIR/timeseries.csv, RUN_DIR/cycles.csv (when present) and RUN_DIR/run.json
(docs/output-format.md) and draws stacked panels over the time axis: wall pressure with
the per-cycle peaks, temperature (only with a thermal protocol), kinetic energy,
contacts, sweeps per step and residual with the steps at the sweep cap marked, and V/V0.

A run is complete only when run.json says "status": "completed". Otherwise the figure
is drawn from what is there and labelled INCOMPLETE: timeseries.csv.partial (the rows of
an unfinished run) when present, else timeseries.csv (possibly an earlier run's).

Exit status: 0 figure written; 2 bad arguments, an unreadable run folder or an
unwritable output (nothing written then).
"""

from __future__ import annotations

import argparse
import json
import math
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

from common.fsutil import save_figure_atomic  # noqa: E402

from .inputs import read_csv_columns, read_cycles  # noqa: E402
from .plots import MAX_LINE_POINTS, _thin  # noqa: E402

PROG = "plot-run"
TIMESERIES = "timeseries.csv"
# The engine's name for a CSV still being written; read here, never written (single
# quotes: tests/test_common.py flags the double-quoted form as a hand-made atomic write).
PARTIAL_SUFFIX = '.partial'
#: Columns the figure needs; the engine always writes them (docs/output-format.md).
TS_REQUIRED = ("step", "t", "T", "kinetic_energy", "contacts", "iterations", "residual", "pressure")
TS_OPTIONAL = ("V_over_V0",)
CYCLES_REQUIRED = ("cycle", "peak_pressure", "t_peak", "V_over_V0_end_heating", "V_over_V0_end_cooling")
#: Scene defaults (docs/scene-format.md): run.json holds the scene without them.
DEFAULT_MAX_ITERATIONS = 1000
DEFAULT_TOLERANCE = 1e-4


class RunInputError(Exception):
    """A run folder that cannot be plotted; the message names the file (and column)."""


@dataclass
class Run:
    folder: Path
    name: str
    complete: bool
    status: str                     # "completed", or an INCOMPLETE label
    source: Path                    # the timeseries file read
    ts: pd.DataFrame
    run: dict | None                # run.json, when present
    cycles: pd.DataFrame | None
    cap: int | None                 # solver.max_iterations; None without run.json
    notes: list[str] = field(default_factory=list)

    @property
    def steps(self) -> int:
        # Steps this run made: a run from a packing starts at the packing's step.
        return int(self.ts["step"].iloc[-1] - self.ts["step"].iloc[0])

    @property
    def capped_mask(self) -> np.ndarray | None:
        if self.cap is None:
            return None
        return (self.ts["iterations"] >= self.cap).to_numpy()

    @property
    def capped(self) -> int | None:
        mask = self.capped_mask
        return None if mask is None else int(mask.sum())

    @property
    def max_residual(self) -> float:
        r = self.ts["residual"].to_numpy(dtype=float)
        return float(np.nanmax(r)) if np.isfinite(r).any() else math.nan

    @property
    def p_max(self) -> float | None:
        value = ((self.run or {}).get("summary") or {}).get("P_max")
        return float(value) if isinstance(value, (int, float)) else None


def _checked(frame: pd.DataFrame | None, path: Path, required: tuple[str, ...]) -> pd.DataFrame:
    """The frame of a reader of .inputs (None: unreadable), with the required columns."""
    if frame is None:
        raise RunInputError(f"{path}: cannot be read as CSV")
    missing = [c for c in required if c not in frame.columns]
    if missing:
        raise RunInputError(f"{path}: missing column{'s' if len(missing) > 1 else ''} "
                            f"{', '.join(missing)} (docs/output-format.md)")
    return frame


def _ends_with_newline(path: Path) -> bool:
    with open(path, "rb") as f:
        f.seek(0, os.SEEK_END)
        if f.tell() == 0:
            return True
        f.seek(-1, os.SEEK_END)
        return f.read(1) == b"\n"


def _read_run_json(path: Path) -> dict | None:
    if not path.is_file():
        return None
    try:
        run = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError) as e:
        raise RunInputError(f"{path}: cannot be read as JSON ({e})") from None
    if not isinstance(run, dict):
        raise RunInputError(f"{path}: expected a JSON object")
    return run


def _cap(run: dict) -> int:
    solver = (run.get("scene") or {}).get("solver") or {}
    return int(solver.get("max_iterations", DEFAULT_MAX_ITERATIONS))


def load_run(folder: str | os.PathLike) -> Run:
    """Reads a run folder; raises RunInputError naming the file (and column) at fault."""
    folder = Path(folder)
    if not folder.is_dir():
        raise RunInputError(f"{folder}: no such folder")
    run = _read_run_json(folder / "run.json")
    complete = run is not None and run.get("status") == "completed"
    final = folder / TIMESERIES
    partial = folder / (TIMESERIES + PARTIAL_SUFFIX)
    notes = []
    if complete:
        source, status = final, "completed"
        if not final.is_file():
            raise RunInputError(f"{final}: not found (run.json says the run completed)")
    else:
        why = "no run.json" if run is None else f"run.json status {run.get('status')!r}"
        # An unfinished run's rows are in the .partial file; a timeseries.csv beside it
        # is an earlier run's (docs/output-format.md, "Atomic writing").
        if partial.is_file():
            source = partial
            status = f"INCOMPLETE ({why}): rows of {partial.name}, run unfinished or killed"
        elif final.is_file():
            source = final
            status = f"INCOMPLETE ({why}): {final.name} may be from an earlier run"
        else:
            raise RunInputError(f"{final}: not found (nor {partial.name})")
    ts = _checked(read_csv_columns(source, TS_REQUIRED + TS_OPTIONAL), source, TS_REQUIRED)
    if source == partial and len(ts) and not _ends_with_newline(source):
        ts = ts.iloc[:-1]  # the last line is still being written
    if ts.empty:
        raise RunInputError(f"{source}: no data rows")

    cycles = None
    cycles_path = folder / "cycles.csv"
    if cycles_path.is_file():
        if complete:
            cycles = _checked(read_cycles(folder), cycles_path, CYCLES_REQUIRED)
        else:
            # cycles.csv is written at the end of a run, so it is not this one's.
            notes.append("cycles.csv not used: the run is incomplete")
    cap = _cap(run) if run is not None else None
    if cap is None:
        notes.append("sweep cap unknown without run.json: capped steps not marked")
    name = str(((run or {}).get("scene") or {}).get("name") or folder.resolve().name)
    return Run(folder=folder, name=name, complete=complete, status=status, source=source, ts=ts,
               run=run, cycles=cycles, cap=cap, notes=notes)


def cycle_stage_times(run: Run) -> tuple[np.ndarray, np.ndarray] | None:
    """Times of the end of heating and of cooling of each row of cycles.csv
    (docs/output-format.md, "Thermal cycles"); None when the scene does not give them."""
    if run.cycles is None or run.run is None:
        return None
    scene = run.run.get("scene") or {}
    th = scene.get("thermal")
    if not isinstance(th, dict):
        return None
    heat = float(th.get("heat_time", 1.0))
    hold = float(th.get("hold_time", 0.0))
    cool = float(th.get("cool_time", heat))
    start = float(th.get("start_time", 0.0))
    if "settle" in scene:  # start_time counts from the end of the settle stage
        settle = run.run.get("settle") or {}
        if not isinstance(settle.get("t_end"), (int, float)):
            return None
        start += float(settle["t_end"])
    k = run.cycles["cycle"].to_numpy(dtype=float)
    begin = start + k * (heat + hold + cool + hold)
    return begin + heat, begin + heat + hold + cool


def panels(run: Run) -> list[str]:
    """The panels drawn, top to bottom."""
    names = ["pressure"]
    if (run.ts["T"].fillna(0) != 0).any():
        names.append("temperature")
    names += ["kinetic_energy", "contacts", "iterations", "residual"]
    has_volume = "V_over_V0" in run.ts.columns and run.ts["V_over_V0"].notna().any()
    if run.cycles is not None and len(run.cycles):
        has_volume |= bool(run.cycles[["V_over_V0_end_heating", "V_over_V0_end_cooling"]].notna().any().any())
    if has_volume:
        names.append("volume")
    return names


def _log_if_positive(ax, values: pd.Series) -> None:
    if (values > 0).any():
        ax.set_yscale("log", nonpositive="mask")  # zeros (no contact, state at rest) left out


def figure(run: Run) -> Figure:
    names = panels(run)
    ts = run.ts
    lines = _thin(ts)
    notes = list(run.notes)
    if len(lines) < len(ts):
        notes.append(f"lines show one row in {int(np.ceil(len(ts) / MAX_LINE_POINTS))} of {len(ts)}; "
                     "markers and the summary use every row")
    fig = Figure(figsize=(9, 1.7 * len(names) + 1.2))
    axes = dict(zip(names, fig.subplots(len(names), 1, sharex=True, squeeze=False)[:, 0]))
    t = lines["t"]
    mask = run.capped_mask

    ax = axes["pressure"]
    ax.plot(t, lines["pressure"], color="C0", lw=0.7, label="P(t)")
    if run.cycles is not None:
        peaks = run.cycles[np.isfinite(run.cycles["peak_pressure"])]
        ax.plot(peaks["t_peak"], peaks["peak_pressure"], "o", color="C3", ms=4, mec="black", mew=0.5,
                label="cycle peak (block mean)")
    if run.p_max is not None and math.isfinite(run.p_max):
        ax.axhline(run.p_max, color="0.3", ls="--", lw=0.8, label=f"P_max = {run.p_max:.4g}")
    ax.set_ylabel("wall pressure P")
    ax.legend(fontsize=7, loc="upper left")

    if "temperature" in axes:
        axes["temperature"].plot(t, lines["T"], color="C1", lw=0.9)
        axes["temperature"].set_ylabel("temperature T")

    ax = axes["kinetic_energy"]
    ax.plot(t, lines["kinetic_energy"], color="C2", lw=0.7)
    _log_if_positive(ax, ts["kinetic_energy"])
    ax.set_ylabel("kinetic energy")

    axes["contacts"].plot(t, lines["contacts"], color="C4", lw=0.7)
    axes["contacts"].set_ylabel("contacts")

    ax = axes["iterations"]
    ax.plot(t, lines["iterations"], color="C0", lw=0.7)
    ax.set_ylabel("sweeps per step")
    if mask is not None:
        if mask.any():
            ax.axhline(run.cap, color="C3", ls=":", lw=0.8)
            ax.plot(ts["t"][mask], ts["iterations"][mask], "x", color="C3", ms=5,
                    label=f"at the cap ({run.cap} sweeps): {int(mask.sum())} rows")
            ax.legend(fontsize=7, loc="upper left")
        else:
            ax.text(0.01, 0.92, f"no row at the cap ({run.cap} sweeps)", transform=ax.transAxes,
                    fontsize=7, va="top")

    ax = axes["residual"]
    ax.plot(t, lines["residual"], color="C5", lw=0.7)
    _log_if_positive(ax, ts["residual"])
    if run.run is not None:
        tol = ((run.run.get("scene") or {}).get("solver") or {}).get("tolerance", DEFAULT_TOLERANCE)
        ax.axhline(float(tol), color="0.3", ls="--", lw=0.8, label=f"tolerance {float(tol):g}")
    if mask is not None and mask.any():
        ax.plot(ts["t"][mask], ts["residual"][mask], "x", color="C3", ms=5, label="at the cap")
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=7, loc="upper left")
    ax.set_ylabel("residual")

    if "volume" in axes:
        ax = axes["volume"]
        if "V_over_V0" in ts.columns and ts["V_over_V0"].notna().any():
            ax.plot(t, lines["V_over_V0"], color="0.5", lw=0.7, label="V/V0(t)")
        times = cycle_stage_times(run)
        if times is not None:
            for when, column, marker, color in ((times[0], "V_over_V0_end_heating", "^", "C3"),
                                                (times[1], "V_over_V0_end_cooling", "v", "C0")):
                ax.plot(when, run.cycles[column], marker, color=color, ms=5, mec="black", mew=0.5,
                        label=column.replace("V_over_V0_", "cycle ").replace("_", " "))
        elif run.cycles is not None:
            notes.append("V/V0 per cycle not drawn: the stage times are not in run.json")
        ax.set_ylabel("V / V0")
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize=7, loc="upper left")

    for ax in axes.values():
        ax.grid(alpha=0.3)
    axes[names[-1]].set_xlabel("time t")
    fig.suptitle(f"{run.name}: {run.status}\n{run.source}", fontsize=10,
                 color="black" if run.complete else "C3")
    if notes:
        fig.text(0.01, 0.0, "; ".join(notes), fontsize=7, va="bottom")
    fig.tight_layout(rect=(0, 0.02 if notes else 0, 1, 1))
    return fig


def summary_line(run: Run, png: Path) -> str:
    if run.cap is None:
        capped = "capped n/a (no run.json)"
    else:
        capped = f"{run.capped} capped (sweeps >= {run.cap} on {len(run.ts)} rows"
        unconverged = ((run.run or {}).get("counters") or {}).get("unconverged_steps")
        capped += f"; run.json: {unconverged} unconverged)" if unconverged is not None else ")"
    p_max = "n/a" if run.p_max is None else f"{run.p_max:.4g}"
    state = "completed" if run.complete else "INCOMPLETE"
    return (f"{PROG}: {run.name} {state}: {run.steps} steps, {capped}, "
            f"max residual {run.max_residual:.3g}, P_max {p_max} -> {png}")


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog=PROG, description="Plots one run folder of `ratchet run` as one PNG of stacked panels "
                               "over time and prints a one-line summary.",
        epilog="Exit status: 0 figure written; 2 bad arguments, an unreadable run folder "
               "(missing folder, timeseries.csv or column) or an unwritable output.")
    parser.add_argument("run_dir", metavar="RUN_DIR", type=Path, help="folder written by `ratchet run --out`")
    parser.add_argument("--out", metavar="FILE.png", type=Path, help="the PNG (default: RUN_DIR/run.png)")
    args = parser.parse_args(argv)
    try:
        run = load_run(args.run_dir)
    except RunInputError as e:
        print(f"{PROG}: error: {e}", file=sys.stderr)
        return 2
    out = args.out or args.run_dir / "run.png"
    if out.is_dir():
        print(f"{PROG}: error: --out: {out} is a folder", file=sys.stderr)
        return 2
    fig = figure(run)
    try:
        save_figure_atomic(fig, out, dpi=120)
    except OSError as e:
        print(f"{PROG}: error: cannot write {out}: {e}", file=sys.stderr)
        return 2
    print(summary_line(run, out))
    return 0
