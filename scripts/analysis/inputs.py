"""Reading a sweep folder: summary.csv, and the optional per-run files in runs/<run>/.

The contract (docs/trends.md, "Input files"):

- SWEEP/summary.csv: one row per run. Required columns: ``run``, ``P_max``.
  Used when present: ``status`` ("completed" or "failed"; absent: every row counts
  as completed), ``unconverged_fraction`` (runs above CAPPED_REFUSE are left out,
  others with capped steps flagged), ``seed``, ``P_max_std``, ``V_over_V0_end``, ``thermal.alpha_p``,
  the swept parameter columns ``container.opening_angle_deg`` and
  ``thermal.alpha_c``, and ``W_rms_<a>_<b>`` (vorticity window of cycles a..b).
- SWEEP/runs/<run>/timeseries.csv: ``t`` with ``pressure``, ``T``, ``V_over_V0``.
- SWEEP/runs/<run>/volume.csv (a campaign's stored run, in place of timeseries.csv):
  ``step``, ``t``, ``T``, ``V_over_V0``.
- SWEEP/runs/<run>/cycles.csv: ``cycle``, ``peak_pressure``, ``t_peak``,
  ``V_over_V0_end_cooling``, ``V_over_V0_end_heating``.
- SWEEP/runs/<run>/displacement_<a>_<b>.csv: ir, iz, r, z, ur, uz, count, w.
- SWEEP/runs/<run>/run.json: ``summary.steady_cycles`` (the cycles P_max averages); the
  scene (scripts/plot-sweep describes the bed with it).

Every per-run file is optional; readers return None and the caller notes why.
"""

from __future__ import annotations

import json
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from common import paths  # noqa: F401  (puts the package `ratchet` on sys.path)
from ratchet.csv_columns import read_csv_columns  # noqa: E402

ANGLE = "container.opening_angle_deg"
ALPHA_C = "thermal.alpha_c"
ALPHA_P = "thermal.alpha_p"
#: Name of the derived column alpha_c / alpha_p.
RATIO = "alpha_c/alpha_p"
REQUIRED = ("run", "P_max")
METRICS = {"run", "seed", "P_max", "P_max_std", "V_over_V0_end", "cycles", "wall_seconds",
           "status", "packing", RATIO, "unconverged_steps", "unconverged_fraction"}
#: A run with more of its steps stopped at the solver's iteration cap than this is left
#: out: its observables are read from unconverged impulses, not from the contact law.
#: Below it, the run is kept and flagged (a few capped steps at jams barely move a peak;
#: docs/performance.md measured the rigid standard bed at 8 of 12000 steps).
CAPPED_REFUSE = 0.05
#: Text columns of summary.csv (``packing``: the key of the settled packing a run started from).
TEXT_COLUMNS = ("status", "packing")
W_RMS = re.compile(r"^W_rms_(\d+)_(\d+)$")
DISPLACEMENT = re.compile(r"^displacement_(\d+)_(\d+)\.csv$")
#: Parameter values are grouped after rounding to this many decimals, so that
#: 1e-3/1e-4 = 9.999999999999998 and 10 are one point.
GROUP_DECIMALS = 9


class InputError(Exception):
    """A sweep folder that cannot be read under the contract."""


@dataclass(frozen=True)
class Window:
    """A vorticity window of cycles first..last, with its summary.csv column."""

    first: int
    last: int
    column: str

    @property
    def label(self) -> str:
        return f"cycles {self.first}-{self.last}"

    @property
    def tag(self) -> str:
        return f"{self.first}_{self.last}"


@dataclass
class Sweep:
    folder: Path
    name: str
    summary: pd.DataFrame          # every row, with the derived RATIO column when possible
    completed: pd.DataFrame        # rows with status == "completed"
    kinds: list[str]               # "angle" and/or "ratio"
    parameters: list[str]          # swept parameter columns (dotted scene paths)
    windows: list[Window]
    notes: list[str] = field(default_factory=list)
    capped: dict = field(default_factory=dict)   # kept run -> fraction of steps at the cap (> 0)

    @property
    def failed_runs(self) -> list[int]:
        return [int(r) for r in self.summary.loc[~self.summary.index.isin(self.completed.index), "run"]]


def _numeric(frame: pd.DataFrame, column: str) -> None:
    if column in frame.columns:
        frame[column] = pd.to_numeric(frame[column], errors="coerce")


def load_sweep(folder: str | Path) -> Sweep:
    """Reads SWEEP/summary.csv and recognizes the kind of sweep.

    An angle sweep has a ``container.opening_angle_deg`` column, a ratio sweep a
    ``thermal.alpha_c`` column (summary.csv has a column only for swept parameters);
    a grid has both, each with more than one value (with both columns and one of
    them single-valued, that one is a fixed parameter of the other sweep). Raises InputError for a missing or unreadable summary, or a
    missing required column.
    """
    folder = Path(folder)
    path = folder / "summary.csv"
    if not path.is_file():
        raise InputError(f"{path}: not found (expected the summary.csv of a sweep)")
    try:
        summary = pd.read_csv(path, dtype={c: str for c in TEXT_COLUMNS})
    except (OSError, ValueError, pd.errors.ParserError) as error:
        raise InputError(f"{path}: cannot be read as CSV ({error})") from None
    missing = [c for c in REQUIRED if c not in summary.columns]
    if missing:
        raise InputError(f"{path}: missing column(s) {', '.join(missing)}")
    notes: list[str] = []
    for column in summary.columns:
        if column not in TEXT_COLUMNS:
            _numeric(summary, column)
    if summary["run"].isna().any():
        raise InputError(f"{path}: column 'run' has a value that is not an integer")
    summary["run"] = summary["run"].astype(int)
    if ANGLE in summary.columns:
        summary[ANGLE] = summary[ANGLE].round(GROUP_DECIMALS)
    if ALPHA_C in summary.columns:
        if ALPHA_P in summary.columns:
            summary[RATIO] = (summary[ALPHA_C] / summary[ALPHA_P]).round(GROUP_DECIMALS)
        else:
            notes.append(f"{ALPHA_C} is swept but {ALPHA_P} is missing: the ratio "
                         "alpha_c/alpha_p cannot be formed")
    if "status" in summary.columns:
        status = summary["status"].astype(str).str.strip().str.lower()
        completed = summary[status == "completed"].copy()
    else:
        notes.append("summary.csv has no 'status' column: every run is taken as completed")
        completed = summary.copy()
    if "seed" not in summary.columns:
        notes.append("summary.csv has no 'seed' column: the first realization is the lowest run id")
    failed = len(summary) - len(completed)
    if failed:
        runs = ", ".join(str(r) for r in summary.loc[~summary.index.isin(completed.index), "run"])
        notes.append(f"{failed} of {len(summary)} runs did not complete and are left out (run {runs})")
    capped = {}
    if "unconverged_fraction" in completed.columns:
        fraction = completed["unconverged_fraction"].fillna(0.0)
        refused = completed[fraction > CAPPED_REFUSE]
        if len(refused):
            listed = ", ".join(f"{int(r.run)} ({r.unconverged_fraction:.1%})" for r in refused.itertuples())
            notes.append(f"{len(refused)} run(s) had more than {CAPPED_REFUSE:.0%} of their steps at the "
                         f"solver's iteration cap and are left out (run {listed})")
            completed = completed[fraction <= CAPPED_REFUSE].copy()
            fraction = fraction[fraction <= CAPPED_REFUSE]
        capped = {int(r): float(f) for r, f in zip(completed["run"], fraction) if f > 0}
        if capped:
            notes.append(f"{len(capped)} run(s) kept with steps at the iteration cap (at most "
                         f"{max(capped.values()):.2%} of their steps; run "
                         f"{', '.join(str(r) for r in sorted(capped))})")

    kinds = []
    if ANGLE in summary.columns:
        kinds.append("angle")
    if ALPHA_C in summary.columns and RATIO in summary.columns:
        kinds.append("ratio")
    if len(kinds) == 2:
        # Both columns, but one holds a single value: a fixed parameter of the other sweep.
        single = [k for k, c in (("angle", ANGLE), ("ratio", RATIO))
                  if summary[c].dropna().nunique() < 2]
        if len(single) == 1:
            kinds.remove(single[0])
    parameters = [c for c in summary.columns if c not in METRICS and not W_RMS.match(c)]
    windows = []
    for column in summary.columns:
        match = W_RMS.match(column)
        if match:
            windows.append(Window(int(match.group(1)), int(match.group(2)), column))
    windows.sort(key=lambda w: (w.first, w.last))
    return Sweep(folder=folder, name=folder.resolve().name or "sweep", summary=summary,
                 completed=completed, kinds=kinds, parameters=parameters, windows=windows,
                 notes=notes, capped=capped)


# --------------------------------------------------------------------------- per run


def run_dir(sweep_folder: Path, run: int) -> Path | None:
    """SWEEP/runs/<run>, or a folder there whose name is the run id zero-padded."""
    runs = Path(sweep_folder) / "runs"
    direct = runs / str(int(run))
    if direct.is_dir():
        return direct
    if runs.is_dir():
        for candidate in sorted(runs.iterdir()):
            if candidate.is_dir() and candidate.name.isdigit() and int(candidate.name) == int(run):
                return candidate
    return None


def read_run_json(folder: Path | None) -> dict | None:
    """A run's run.json as a dict; None when missing or unreadable (the caller notes why)."""
    if folder is None:
        return None
    try:
        value = json.loads((Path(folder) / "run.json").read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    return value if isinstance(value, dict) else None


def read_timeseries(folder: Path) -> pd.DataFrame | None:
    return read_csv_columns(folder / "timeseries.csv", ("t", "T", "pressure", "bed_height", "V_over_V0"))


#: The V/V0 series a campaign stores in place of timeseries.csv (docs/campaign.md,
#: "Stored results"): timeseries.csv's columns step, t, T, V_over_V0, its rows as written.
VOLUME_SERIES = "volume.csv"
VOLUME_COLUMNS = ("step", "t", "T", "V_over_V0")


def read_volume_series(folder: Path | None) -> tuple[pd.DataFrame | None, str]:
    """The bed's V/V0 against time and temperature: (frame with t, T, V_over_V0 and no
    missing value, source), or (None, why not). Source: volume.csv, else timeseries.csv."""
    if folder is None:
        return None, "no run folder"
    for name in (VOLUME_SERIES, "timeseries.csv"):
        path = Path(folder) / name
        if not path.is_file():
            continue
        frame = read_csv_columns(path, VOLUME_COLUMNS)
        if frame is None or not {"t", "T", "V_over_V0"}.issubset(frame.columns):
            return None, f"{name} has no columns t, T and V_over_V0 (outputs.volume)"
        frame = frame.dropna(subset=["t", "T", "V_over_V0"])
        if frame.empty:
            return None, f"{name} has no finite V_over_V0"
        return frame.sort_values("t", kind="stable").reset_index(drop=True), name
    return None, f"no {VOLUME_SERIES} or timeseries.csv (the V/V0 series)"


def read_cycles(folder: Path) -> pd.DataFrame | None:
    return read_csv_columns(folder / "cycles.csv", ("cycle", "peak_pressure", "t_peak",
                                                   "V_over_V0_end_heating", "V_over_V0_end_cooling"))


def displacement_files(folder: Path) -> list[tuple[int, int, Path]]:
    """(first, last, path) of every displacement_<a>_<b>.csv, sorted by window."""
    if folder is None or not folder.is_dir():
        return []
    found = []
    for path in folder.iterdir():
        match = DISPLACEMENT.match(path.name)
        if match and path.is_file():
            found.append((int(match.group(1)), int(match.group(2)), path))
    return sorted(found)


def read_displacement(path: Path) -> pd.DataFrame | None:
    frame = read_csv_columns(path, ("ir", "iz", "r", "z", "ur", "uz", "count", "w"))
    if frame is None or not {"r", "z", "ur", "uz"}.issubset(frame.columns):
        return None
    return frame


def end_of_cycle_volumes(folder: Path | None) -> tuple[np.ndarray | None, str]:
    """V/V0 before cycling (1 by definition) and at the end of each cycle.

    Source, in this order: cycles.csv ``V_over_V0_end_cooling`` (the bed back at T0,
    comparable with V0); else timeseries.csv ``V_over_V0`` and ``T``: the last value
    of each cold hold (T within 1 % of the temperature range above its minimum)
    after the first. Returns (values, source) or (None, why not).
    """
    if folder is None:
        return None, "no run folder"
    cycles = read_cycles(folder)
    if cycles is not None and "V_over_V0_end_cooling" in cycles.columns:
        order = cycles.sort_values("cycle") if "cycle" in cycles.columns else cycles
        values = order["V_over_V0_end_cooling"].to_numpy(dtype=float)
        values = values[np.isfinite(values)]
        if values.size:
            return np.concatenate([[1.0], values]), "cycles.csv V_over_V0_end_cooling"
    series = read_timeseries(folder)
    if series is None:
        return None, "no cycles.csv with V_over_V0_end_cooling and no timeseries.csv"
    if not {"V_over_V0", "T"}.issubset(series.columns):
        return None, "no V_over_V0_end_cooling in cycles.csv and no V_over_V0 and T in timeseries.csv"
    series = series.dropna(subset=["V_over_V0", "T"])
    if series.empty:
        return None, "timeseries.csv has no finite V_over_V0"
    temperature = series["T"].to_numpy(dtype=float)
    span = float(temperature.max() - temperature.min())
    if span <= 0:
        return None, "timeseries.csv: the temperature never changes (no thermal cycle)"
    cold = temperature <= temperature.min() + 0.01 * span
    volume = series["V_over_V0"].to_numpy(dtype=float)
    ends = []
    block_start = None
    for i, is_cold in enumerate(cold):
        if is_cold and block_start is None:
            block_start = i
        if block_start is not None and (not is_cold or i == len(cold) - 1):
            last = i if is_cold else i - 1
            ends.append((block_start, last))
            block_start = None
    if not ends:
        return None, "timeseries.csv: no cold hold found"
    values = [volume[0]] + [volume[last] for first, last in ends if first > 0]
    return np.asarray(values, dtype=float), "timeseries.csv V_over_V0 at the end of each cold hold"


def steady_peaks(folder: Path | None) -> tuple[dict | None, str]:
    """The peak pressures of the cycles that P_max averages, for the steady-state check.

    The window is run.json's ``summary.steady_cycles`` [a, b] (inclusive, cycle numbers
    from 0); without it, the engine's default, the second half [floor(N/2), N - 1] of
    the N rows of cycles.csv. Cut at the cycles reached. Returns ({"cycles", "peaks",
    "window", "window_source"}, "") or (None, why not)."""
    if folder is None:
        return None, "no run folder"
    cycles = read_cycles(folder)
    if cycles is None or not {"cycle", "peak_pressure"}.issubset(cycles.columns):
        return None, "no cycles.csv with cycle and peak_pressure"
    cycles = cycles.sort_values("cycle")
    window, source = None, "the default second half of the cycles (no steady_cycles in run.json)"
    try:
        summary = json.loads((folder / "run.json").read_text(encoding="utf-8")).get("summary") or {}
        value = summary.get("steady_cycles")
        if isinstance(value, list) and len(value) == 2 and all(isinstance(v, int) for v in value):
            window, source = (int(value[0]), int(value[1])), "run.json summary.steady_cycles"
    except (OSError, ValueError, AttributeError):
        pass
    if window is None:
        count = len(cycles)
        window = (count // 2, count - 1)
    keep = (cycles["cycle"] >= window[0]) & (cycles["cycle"] <= window[1])
    chosen = cycles[keep & np.isfinite(cycles["peak_pressure"])]
    return ({"cycles": chosen["cycle"].to_numpy(dtype=float),
             "peaks": chosen["peak_pressure"].to_numpy(dtype=float),
             "window": [int(window[0]), int(window[1])], "window_source": source}, "")


def first_realizations(frame: pd.DataFrame, column: str) -> pd.DataFrame:
    """One row per value of `column`: the completed run with the lowest seed (then run)."""
    keys = [k for k in ("seed", "run") if k in frame.columns]
    ordered = frame.sort_values([column] + keys, kind="stable")
    return ordered.groupby(column, sort=True).head(1).reset_index(drop=True)

