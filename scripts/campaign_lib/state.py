"""Where each run of the plan stands: done (a current stored result), stale (a stored
result the reuse rule refuses), in progress (work in the work folder), or missing; and
the cost estimate of a run."""

from __future__ import annotations

import statistics
from dataclasses import dataclass, field
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
    """Wall seconds of a run: `seconds` for a point with no stored run of its own, and
    `by_point` (point name -> (seconds, source)) for the points that have some. The paper
    bed's cost depends on the point: at alpha_c/alpha_p = 1 the container and the grains
    expand alike and a run took 0.6 CPU h (about 2 sweeps a step) where the ratio-10 runs
    take 2.7 (2026-11-29)."""
    seconds: float
    source: str
    by_point: dict = field(default_factory=dict)

    def for_run(self, run) -> float:
        own = self.by_point.get(run.point.name)
        return own[0] if own else self.seconds

    def source_for(self, run) -> str:
        own = self.by_point.get(run.point.name)
        return own[1] if own else self.source


# The serial share of the paper tier's step (the spring law at eps = 0.01): one thread
# T1, n threads about T1 (s + (1 - s) / n). Measured on a campaign run resumed on two
# threads, 0.74 T1 (docs/performance.md, sixteenth installment), so s = 0.48.
SERIAL_SHARE = 0.48


def thread_factor(threads: int) -> float:
    """A run's wall time on `threads` threads over its time on one (Amdahl's law with the
    measured serial share)."""
    return SERIAL_SHARE + (1.0 - SERIAL_SHARE) / max(1, threads)


def one_thread_cpu(cpu_seconds: float, threads: int) -> float:
    """What CPU time spent on `threads` threads would have been on one: a run on n threads
    spends about n times its wall in CPU (OpenMP's threads wait busy), so its one-thread
    cost is its CPU over n, over the thread factor."""
    threads = threads if isinstance(threads, int) and threads >= 1 else 1
    return float(cpu_seconds) / threads / thread_factor(threads)


def one_thread_seconds(provenance: dict) -> float | None:
    """What a stored run cost on one free core: its CPU seconds, which unlike its wall
    time do not grow when other work shares the machine (the first paper runs took
    3.0 h of wall for 2.5 h of CPU beside other runs); for runs on several threads the
    sum over its segments stored with it (one_thread_seconds), else one_thread_cpu of
    the whole."""
    stored = provenance.get("one_thread_seconds")
    if isinstance(stored, (int, float)) and stored > 0:
        return float(stored)
    cpu = provenance.get("cpu_seconds")
    if not isinstance(cpu, (int, float)) or cpu <= 0:
        return None
    return one_thread_cpu(cpu, provenance.get("threads", 1))


# The current engine's own runs make the estimate only from this many on: one run slowed
# by work beside it (its CPU time then undercounts a two-thread run's work) is no median.
# Seen 2026-11-28: one such run made the estimate 1.42 h against about 2 h.
MIN_OWN_RUNS = 3


def point_medians(costs) -> dict:
    """The median one-thread seconds of each point's stored runs, from (point, seconds)
    pairs: point -> (median, runs). The campaign's estimate and scripts/paper-repro's
    "still to run" both cost a point by its own runs with it."""
    per_point: dict = {}
    for point, seconds in costs:
        per_point.setdefault(point, []).append(seconds)
    return {point: (float(statistics.median(own)), len(own)) for point, own in per_point.items()}


def estimate(plan: Plan, states: list, engine: Engine, override_hours: float | None,
             threads: int = 1) -> Estimate:
    """Wall seconds of one run on `threads` threads and a free core each (what --budget
    schedules by): --run-hours for every run; else, for a point with stored runs of its
    own, the median of their one-thread cost times the thread factor; for the others the
    median over all stored runs (those of the current engine once there are MIN_OWN_RUNS)
    times the thread factor, else the plan's run_cost_hours times the thread factor."""
    if override_hours is not None:
        return Estimate(override_hours * 3600.0, "--run-hours")
    factor = thread_factor(threads)
    on = "" if threads == 1 else f", x {factor:.2f} on {threads} threads"
    measured = [(one_thread_seconds(s.stored.provenance), s.stored.provenance.get("engine", {}), s.run.point.name)
                for s in states if s.stored]
    measured = [(c, e, p) for c, e, p in measured if c is not None]
    by_point = {point: (median * factor, f"median CPU time of {runs} stored run(s) of {point}{on}")
                for point, (median, runs) in point_medians((p, c) for c, _, p in measured).items()}
    mine = [c for c, e, _ in measured if same_engine(e, engine.record())]
    if len(mine) < MIN_OWN_RUNS:
        mine = []
    use = mine or [c for c, _, _ in measured]
    if use:
        which = "current engine's" if mine else "stored"
        return Estimate(float(statistics.median(use)) * factor,
                        f"median CPU time of {len(use)} {which} run(s){on}", by_point)
    return Estimate(plan.run_cost_hours * 3600.0 * factor, f"the plan's run_cost_hours ({plan.run_cost_hours:g}){on}")


def todo(states: list) -> list:
    """What is left, in the order it is run: runs already under way first (their work is
    sunk), then the plan's order; stale results are rerun like missing ones."""
    left = [s for s in states if not s.done]
    return [s for s in left if s.started] + [s for s in left if not s.started]


def choose(needs: list, left: float, min_slice: float):
    """Which run of the queue starts next, given each one's remaining seconds (`needs`, in
    the queue's order) and the budget's seconds `left`: the first that fits, since only a
    finished run is stored and kept whatever becomes of the work folder; else, while at
    least `min_slice` is left, the first of the queue, to stop at a checkpoint when the
    budget ends. Returns (index, fits), or (None, False) when nothing starts."""
    for i, need in enumerate(needs):
        if need <= left:
            return i, True
    if needs and min_slice > 0.0 and left >= min_slice:
        return 0, False
    return None, False


def hours(seconds: float) -> str:
    seconds = max(0.0, seconds)
    if seconds < 120:
        return f"{seconds:.1f} s"
    if seconds < 3600:
        return f"{seconds / 60:.1f} min"
    return f"{seconds / 3600:.2f} h"
