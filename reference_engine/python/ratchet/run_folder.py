"""A run folder of `ratchet run` as the harness reads it (scripts/plot-run, and
ratchet.load_run): the timeseries, cycles.csv and run.json (docs/output-format.md), and
the thermal phases of its cycles.

A run is complete only when run.json says "status": "completed". Otherwise what is there
is read and labelled INCOMPLETE: timeseries.csv.partial (the rows of an unfinished run)
when present, else timeseries.csv (possibly an earlier run's); cycles.csv is not used.
"""

from __future__ import annotations

import json
import math
import os
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from .csv_columns import read_csv_columns

TIMESERIES = "timeseries.csv"
# The engine's name for a CSV still being written; read here, never written (single
# quotes: tests/test_common.py flags the double-quoted form as a hand-made atomic write).
PARTIAL_SUFFIX = '.partial'
#: Columns the figures need; the engine always writes them (docs/output-format.md).
TS_REQUIRED = ("step", "t", "T", "kinetic_energy", "contacts", "iterations", "residual", "pressure")
#: The wall-clock time of each phase of the row's step (docs/output-format.md).
TIME_COLUMNS = ("time_free_velocity", "time_thermal", "time_detect", "time_solve",
                "time_integrate", "time_keep_impulses", "time_observe")
TS_OPTIONAL = ("V_over_V0", "max_overlap") + TIME_COLUMNS
CYCLES_REQUIRED = ("cycle", "peak_pressure", "t_peak", "V_over_V0_end_heating", "V_over_V0_end_cooling")
#: Scene defaults (docs/scene-format.md): run.json holds the scene without them.
DEFAULT_MAX_ITERATIONS = 1000
DEFAULT_TOLERANCE = 1e-4
DEFAULT_PRESSURE_WINDOW = 0.5
THERMAL_DEFAULTS = {"T0": 0.0, "T1": 100.0, "start_time": 0.0, "heat_time": 1.0, "hold_time": 0.0,
                    "cycles": 1}

#: The thermal phases of a cycle, in order.
PHASES = ("heating", "hot hold", "cooling", "cold hold")


class RunInputError(Exception):
    """A run folder that cannot be plotted; the message names the file (and column)."""


@dataclass(frozen=True)
class Phase:
    """One thermal phase of one cycle, [start, end] in the run's time."""

    cycle: int
    kind: str           # one of PHASES
    start: float
    end: float


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
    def scene(self) -> dict:
        return (self.run or {}).get("scene") or {}

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
    def summary(self) -> dict:
        return (self.run or {}).get("summary") or {}

    @property
    def p_max(self) -> float | None:
        value = self.summary.get("P_max")
        return float(value) if isinstance(value, (int, float)) else None

    @property
    def row_steps(self) -> int:
        """Steps between rows (outputs.timeseries_every; the last row may come sooner)."""
        gaps = np.diff(self.ts["step"].to_numpy())
        return int(np.median(gaps)) if gaps.size else 1

    @property
    def every_step(self) -> bool:
        """Whether the rows hold every step (outputs.timeseries_every = 1)."""
        return bool((np.diff(self.ts["step"].to_numpy()) == 1).all())

    @property
    def pressure_window(self) -> float:
        """outputs.pressure_window: the blocks P is averaged over before a cycle's peak."""
        return float((self.scene.get("outputs") or {}).get("pressure_window", DEFAULT_PRESSURE_WINDOW))

    @property
    def steady_cycles(self) -> tuple[int, int] | None:
        """The cycles P_max averages: run.json's summary.steady_cycles, cut at the last
        cycle of cycles.csv; None when either is missing."""
        value = self.summary.get("steady_cycles")
        if not (isinstance(value, list) and len(value) == 2) or self.cycles is None or not len(self.cycles):
            return None
        first, last = int(value[0]), min(int(value[1]), int(self.cycles["cycle"].max()))
        return (first, last) if first <= last else None


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


def load_run(folder: str | os.PathLike, all_columns: bool = False) -> Run:
    """Reads a run folder; raises RunInputError naming the file (and column) at fault.
    The timeseries has the columns the figures use, or with all_columns every column."""
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
    ts = _checked(read_csv_columns(source, None if all_columns else TS_REQUIRED + TS_OPTIONAL), source, TS_REQUIRED)
    if source == partial and len(ts) and not _ends_with_newline(source):
        ts = ts.iloc[:-1]  # the last line is still being written
    if ts.empty:
        raise RunInputError(f"{source}: no data rows")

    cycles = None
    cycles_path = folder / "cycles.csv"
    if cycles_path.is_file():
        if complete:
            cycles = _checked(read_csv_columns(cycles_path, CYCLES_REQUIRED), cycles_path, CYCLES_REQUIRED)
        else:
            # cycles.csv is written at the end of a run, so it is not this one's.
            notes.append("cycles.csv not used: the run is incomplete")
    cap = _cap(run) if run is not None else None
    if cap is None:
        notes.append("sweep cap unknown without run.json: capped steps not marked")
    name = str(((run or {}).get("scene") or {}).get("name") or folder.resolve().name)
    return Run(folder=folder, name=name, complete=complete, status=status, source=source, ts=ts,
               run=run, cycles=cycles, cap=cap, notes=notes)


# --------------------------------------------------------------------------- thermal phases


def _scene_phases(run: Run) -> list[Phase] | None:
    """The phases of the scene's protocol (docs/output-format.md, "Thermal cycles");
    None when run.json does not give them (no run.json, or a settle stage without t_end)."""
    th = run.scene.get("thermal")
    if not isinstance(th, dict):
        return None
    p = {**THERMAL_DEFAULTS, **th}
    heat, hold, start = float(p["heat_time"]), float(p["hold_time"]), float(p["start_time"])
    cool = float(th.get("cool_time", heat))
    if "settle" in run.scene:  # start_time counts from the end of the settle stage
        t_end = (run.run.get("settle") or {}).get("t_end")
        if not isinstance(t_end, (int, float)):
            return None
        start += float(t_end)
    length = heat + hold + cool + hold
    t_last = float(run.ts["t"].iloc[-1])
    phases = []
    for k in range(int(p["cycles"])):
        begin = start + k * length
        for kind, duration in zip(PHASES, (heat, hold, cool, hold)):
            if duration > 0 and begin < t_last:
                phases.append(Phase(k, kind, begin, min(begin + duration, t_last)))
            begin += duration
    return phases


def _phases_from_temperature(ts: pd.DataFrame) -> list[Phase]:
    """The phases read off the recorded T(t) (no scene to read them from): rising is
    heating, falling cooling, flat at the top the hot hold, flat below after the first
    heating the cold hold; a cycle starts with each heating. Edges fall on recorded rows,
    except the start of a heating: the row before it is still at the base temperature."""
    t = ts["t"].to_numpy(dtype=float)
    temperature = ts["T"].to_numpy(dtype=float)
    if len(t) < 2 or not np.isfinite(temperature).all():
        return []
    span = float(temperature.max() - temperature.min())
    if span <= 0:
        return []
    eps = 1e-9 * span
    phases: list[Phase] = []
    cycle = -1
    for i in range(len(t) - 1):
        change = temperature[i + 1] - temperature[i]
        if change > eps:
            kind = "heating"
        elif change < -eps:
            kind = "cooling"
        elif temperature[i] >= temperature.max() - eps:
            kind = "hot hold"
        elif cycle >= 0:
            kind = "cold hold"
        else:
            continue  # before cycling
        if phases and phases[-1].kind == kind and phases[-1].end == t[i]:
            phases[-1] = Phase(phases[-1].cycle, kind, phases[-1].start, t[i + 1])
            continue
        begin = t[i]
        if kind == "heating":
            cycle += 1
            # Row i is still at the base temperature: the ramp starts within (t[i], t[i+1]),
            # where a line through the next rows of the ramp reaches T[i].
            if i + 2 < len(t) and temperature[i + 2] - temperature[i + 1] > eps:
                rate = (temperature[i + 2] - temperature[i + 1]) / (t[i + 2] - t[i + 1])
                begin = float(np.clip(t[i + 1] - change / rate, t[i], t[i + 1]))
            else:
                begin = t[i + 1]
            if phases and phases[-1].end == t[i]:
                phases[-1] = Phase(phases[-1].cycle, phases[-1].kind, phases[-1].start, begin)
        phases.append(Phase(cycle, kind, begin, t[i + 1]))
    return phases


def thermal_phases(run: Run) -> list[Phase]:
    """Heating, holds and cooling of every cycle the run reached (empty without a
    thermal protocol): from run.json's scene, else from the recorded T(t)."""
    phases = _scene_phases(run)
    if phases is None:
        phases = _phases_from_temperature(run.ts)
    return phases


def cycling_start(phases: list[Phase]) -> float | None:
    return phases[0].start if phases else None


def cycle_spans(phases: list[Phase]) -> dict[int, tuple[float, float]]:
    """cycle -> (start, end) of the phases of that cycle."""
    spans: dict[int, tuple[float, float]] = {}
    for p in phases:
        first, last = spans.get(p.cycle, (p.start, p.end))
        spans[p.cycle] = (min(first, p.start), max(last, p.end))
    return spans


def block_means(run: Run, phases: list[Phase]) -> list[tuple[float, float, float]]:
    """(start, end, mean P) of the blocks whose largest mean is a cycle's peak_pressure
    (docs/output-format.md, "Per-cycle peak pressure"), from the recorded rows: a block
    starts where the cycle or the previous block starts and closes at the first row at
    which its length reaches outputs.pressure_window; an unfinished block at the end of a
    cycle is dropped: the engine's computation over every step. Empty unless the rows
    hold every step (outputs.timeseries_every = 1: sparser rows give other means than the
    engine's), and for a window of 0 (every step its own block)."""
    window = run.pressure_window
    if window <= 0 or not run.every_step:
        return []
    t = run.ts["t"].to_numpy(dtype=float)
    pressure = run.ts["pressure"].to_numpy(dtype=float)
    tol = 1e-9 * max(1.0, window)  # t is a running sum of h: a few ulps off the grid
    blocks = []
    for first, last in cycle_spans(phases).values():
        inside = (t > first + tol) & (t <= last + tol)
        begin, values = first, []
        for time, value in zip(t[inside], pressure[inside]):
            values.append(value)
            if time - begin >= window - tol:
                blocks.append((begin, float(time), float(np.mean(values))))
                begin, values = float(time), []
    return blocks


def cycle_stage_times(run: Run) -> tuple[np.ndarray, np.ndarray] | None:
    """Times of the end of heating and of cooling of each row of cycles.csv
    (docs/output-format.md, "Thermal cycles"); None when the scene does not give them."""
    if run.cycles is None:
        return None
    phases = _scene_phases(run)
    if phases is None:
        return None
    ends = {(p.cycle, p.kind): p.end for p in phases}
    k = run.cycles["cycle"].astype(int)
    return (np.array([ends.get((c, "heating"), np.nan) for c in k]),
            np.array([ends.get((c, "cooling"), np.nan) for c in k]))
