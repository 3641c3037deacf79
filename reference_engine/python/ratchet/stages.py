"""Stage and cycle of each row of a run's CSVs, from its thermal phases
(run_folder.thermal_phases).

A row belongs to the phase whose end it reaches: start < t <= end, within 1e-4 h as the
engine counts a stage end (docs/output-format.md, "Thermal cycles"). Rows before the
first phase are the settle stage ("settle"), rows after the last one "after"; a scene
without a thermal protocol has stage "none" everywhere. cycle numbers from 0, -1 outside
the cycles.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from .run_folder import PHASES, Phase

#: Every stage a row can have, in the order of a run.
STAGES = ("settle", *PHASES, "after", "none")

#: The engine's tolerance on a stage end, in steps (run/time_marks.hpp, kStageMarkTol).
STAGE_MARK_TOL = 1e-4


def stage_columns(t: np.ndarray, phases: list[Phase], dt: float) -> tuple[np.ndarray, np.ndarray]:
    """(stage, cycle) arrays for the times t."""
    t = np.asarray(t, dtype=float)
    if not phases:
        return np.full(len(t), "none", dtype=object), np.full(len(t), -1, dtype=int)
    tol = STAGE_MARK_TOL * dt
    stage = np.where(t <= phases[0].start + tol, "settle", "after").astype(object)
    cycle = np.full(len(t), -1, dtype=int)
    for p in phases:
        inside = (t > p.start + tol) & (t <= p.end + tol)
        stage[inside] = p.kind
        cycle[inside] = p.cycle
    return stage, cycle


def with_stages(frame: pd.DataFrame, phases: list[Phase], dt: float) -> pd.DataFrame:
    """frame with the columns stage and cycle added after t."""
    stage, cycle = stage_columns(frame["t"].to_numpy(), phases, dt)
    out = frame.copy()
    at = list(out.columns).index("t") + 1
    out.insert(at, "stage", pd.Categorical(stage, categories=STAGES))
    out.insert(at + 1, "cycle", cycle)
    return out
