"""ratchet.load_run: a run folder as run.json and pandas DataFrames with stage and cycle
columns. Read by the harness's reader (run_folder.load_run), so a folder that plot-run
refuses is refused here with the same message (RunInputError naming the file)."""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path

import pandas as pd

from . import run_folder
from .run_folder import RunInputError
from .stages import with_stages

BODIES = "bodies.csv"


@dataclass
class RunData:
    """A run folder (docs/output-format.md, docs/python.md).

    info:        run.json as a dict (None while the run has not finished)
    timeseries:  timeseries.csv, every column, plus stage and cycle
    bodies:      bodies.csv plus stage and cycle (read when first asked for)
    cycles:      cycles.csv (None when the run wrote none or is incomplete)
    """

    folder: Path
    info: dict | None
    timeseries: pd.DataFrame
    cycles: pd.DataFrame | None
    complete: bool
    status: str
    phases: list[run_folder.Phase] = field(repr=False)
    dt: float = field(repr=False)

    @property
    def summary(self) -> dict:
        """run.json's summary (P_max, V/V0 at the end, ...); empty when absent."""
        return (self.info or {}).get("summary") or {}

    @property
    def scene(self) -> dict:
        return (self.info or {}).get("scene") or {}

    @cached_property
    def bodies(self) -> pd.DataFrame:
        path = self.folder / BODIES
        if not self.complete and (self.folder / (BODIES + run_folder.PARTIAL_SUFFIX)).is_file():
            path = self.folder / (BODIES + run_folder.PARTIAL_SUFFIX)
        try:
            frame = pd.read_csv(path, float_precision="round_trip")
        except (OSError, ValueError) as e:
            raise RunInputError(f"{path}: cannot be read as CSV ({e})") from None
        if "t" not in frame.columns:
            raise RunInputError(f"{path}: missing column t (docs/output-format.md)")
        return with_stages(frame, self.phases, self.dt)


def _dt(run: run_folder.Run) -> float:
    """The step, from the scene (time.dt) or else from the rows."""
    dt = (run.scene.get("time") or {}).get("dt")
    if isinstance(dt, (int, float)) and dt > 0:
        return float(dt)
    steps = run.ts["step"].diff().iloc[1:]
    times = run.ts["t"].diff().iloc[1:]
    return float((times / steps).median()) if len(steps) else 0.0


def load_run(folder: str | os.PathLike) -> RunData:
    """Reads a run folder of `ratchet run` (or of a sweep's runs/<id>/)."""
    run = run_folder.load_run(folder, all_columns=True)
    phases = run_folder.thermal_phases(run)
    dt = _dt(run)
    return RunData(folder=Path(folder), info=run.run, timeseries=with_stages(run.ts, phases, dt),
                   cycles=run.cycles, complete=run.complete, status=run.status, phases=phases, dt=dt)
