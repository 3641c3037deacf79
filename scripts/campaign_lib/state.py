"""Where each run of the plan stands: done (a current stored result), stale (a stored
result the reuse rule refuses), in progress (work in the work folder), or missing; and
the cost estimate of a run."""

from __future__ import annotations

import statistics
from dataclasses import dataclass
from pathlib import Path

from . import store
from .engine import Engine, same_engine
from .plan import Plan, Run
from .workdir import Progress, RunFolder


@dataclass
class RunState:
    run: Run
    folder: RunFolder
    stored: store.Stored | None
    verdict: store.Verdict | None
    progress: Progress
    busy: bool

    @property
    def done(self) -> bool:
        return self.verdict is not None and self.verdict.current

    @property
    def stale(self) -> bool:
        return self.verdict is not None and not self.verdict.current

    @property
    def started(self) -> bool:
        return self.progress.stage not in ("not started", "completed")


def survey(plan: Plan, work: Path, results: Path, engine: Engine, golden_now: dict | None) -> list:
    states = []
    record = engine.record()
    for run in plan.runs:
        stored = store.read(results, run)
        verdict = store.judge(stored, plan.scene_for(run), record, golden_now) if stored else None
        folder = RunFolder(work, run)
        states.append(RunState(run=run, folder=folder, stored=stored, verdict=verdict,
                               progress=folder.progress(), busy=folder.busy()))
    return states


@dataclass
class Estimate:
    seconds: float
    source: str


def estimate(plan: Plan, states: list, engine: Engine, override_hours: float | None) -> Estimate:
    """Wall seconds of one run (what --budget schedules by, not CPU time): --run-hours,
    else the median of the stored runs' measured wall times (those of the current engine
    when there are any), else the plan's run_cost_hours."""
    if override_hours is not None:
        return Estimate(override_hours * 3600.0, "--run-hours")
    measured = [(s.stored.provenance.get("wall_seconds"), s.stored.provenance.get("engine", {}))
                for s in states if s.stored]
    measured = [(w, e) for w, e in measured if isinstance(w, (int, float)) and w > 0]
    mine = [w for w, e in measured if same_engine(e, engine.record())]
    use = mine or [w for w, _ in measured]
    if use:
        which = "current engine's" if mine else "stored"
        return Estimate(float(statistics.median(use)), f"median of {len(use)} {which} run(s)")
    return Estimate(plan.run_cost_hours * 3600.0, f"the plan's run_cost_hours ({plan.run_cost_hours:g})")


def todo(states: list) -> list:
    """What is left, in the order it is run: runs already under way first (their work is
    sunk), then the plan's order; stale results are rerun like missing ones."""
    left = [s for s in states if not s.done]
    return [s for s in left if s.started] + [s for s in left if not s.started]


def hours(seconds: float) -> str:
    seconds = max(0.0, seconds)
    if seconds < 120:
        return f"{seconds:.1f} s"
    if seconds < 3600:
        return f"{seconds / 60:.1f} min"
    return f"{seconds / 3600:.2f} h"
