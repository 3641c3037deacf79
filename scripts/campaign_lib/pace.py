"""A running run's pace between progress reports: steps a minute and the time it still
needs at that pace; and the cores its engine got, with a warning when other work takes
them (docs/campaign.md, "Working beside a run": a run on two threads slows about four
times beside a job of the same priority)."""

from __future__ import annotations

import os
from dataclasses import dataclass, field

import psutil

from .state import hours

#: Below this share of the cores an engine asks for, the report warns that other work
#: takes them. Alone a run gets 0.96-0.99 of them (its threads spin at barriers rather
#: than sleep: 1.93 of 2 cores over a minute of the bed of 20,000's cooling, 1.96 in a
#: paper run's heating); beside a job of the same priority, three or four threads share
#: two cores and it gets 0.5-0.67 (1.2 of 2 measured, docs/campaign.md). The pace itself
#: cannot tell: a cycle of the bed of 20,000 lasts longer than a report, and its hold
#: runs three times faster than its ramps (a warning "the pace fell to 0.33" on a quiet
#: machine, 2026-12-07).
LOW_CPU_SHARE = 0.8


def seen_at(now: float, step_time: float | None, wall_now: float) -> float:
    """When (on the clock of `now`) a step read from the growing timeseries was reached: at
    the file's last write (`step_time`, on the wall clock `wall_now` reads), not at the
    report. The rows reach the disk at the engine's checkpoints, so a report may see a step
    written minutes ago (a resumed run's first checkpoint, 73 steps after its start, read
    ten minutes later, once gave a pace of 7 steps a minute for 150)."""
    if step_time is None:
        return now
    return now - max(0.0, wall_now - step_time)


@dataclass
class Pace:
    """(seconds, step) at each report of one run that saw a step beyond the last."""
    marks: list = field(default_factory=list)
    # The last report saw no step beyond the last mark's. The engine's growing timeseries
    # reaches the disk at its checkpoints (io/atomic_file flush_size), so a run slower than
    # a checkpoint per report shows the same step twice: no window ends there (it would
    # give a pace of 0), the next step seen ends a longer one.
    unchanged: bool = False
    # The first mark is a resumed run's checkpoint at its start, not a report's step.
    resumed: bool = False

    def resume(self, seconds: float, checkpoint: int | None) -> None:
        """The first mark of a run resumed at `checkpoint`: its first window counts from there."""
        self.add(seconds, checkpoint)
        self.resumed = bool(self.marks)

    def add(self, seconds: float, step: int | None) -> None:
        if step is None:
            return
        self.unchanged = bool(self.marks) and step <= self.marks[-1][1]
        if not self.unchanged:
            self.marks.append((seconds, step))

    def rates(self) -> list:
        """Steps a second between successive marks that both have a step and a gap."""
        return [(b - a) / (t1 - t0) for (t0, a), (t1, b) in zip(self.marks, self.marks[1:]) if t1 > t0]

    def text(self, total: int | None, left_seconds: float) -> str:
        """'' before two marks; else the last window's pace and what it implies for the
        run's end against the budget left."""
        if self.unchanged:
            since = "it started" if self.resumed and len(self.marks) == 1 else "the last report"
            return (f"; no step written since {since} (the engine writes its timeseries at its "
                    "checkpoints): the pace when the next one is seen")
        rates = self.rates()
        if not rates:
            return ""
        rate = rates[-1]
        out = f"; {60.0 * rate:.0f} steps a minute since the last report"
        step = self.marks[-1][1]
        if total and rate > 0.0:
            need = (total - step) / rate
            verdict = "within the budget" if need <= left_seconds else \
                "not within the budget: it stops at a checkpoint"
            out += f", about {hours(need)} to go at that pace ({verdict})"
        return out


def process_cpu_seconds(pid: int) -> float | None:
    """User and system CPU seconds of a running process and its live descendants (a
    launcher's ranks on this host run as its children); None once it is gone."""
    try:
        root = psutil.Process(pid)
        processes = [root, *root.children(recursive=True)]
    except psutil.Error:
        return None
    total = 0.0
    for process in processes:
        try:
            times = process.cpu_times()
        except psutil.Error:
            continue   # a descendant that ended between the listing and the reading
        total += times.user + times.system
    return total


def available_cores() -> int:
    return len(os.sched_getaffinity(0))


@dataclass
class CpuShare:
    """(seconds, CPU seconds) of one engine at each report: the cores it got in between.
    The first mark is the first report's, not the start's: an engine's first minutes load
    its hulls and packing on one thread."""
    marks: list = field(default_factory=list)

    def add(self, seconds: float, cpu: float | None) -> None:
        if cpu is not None:
            self.marks.append((seconds, cpu))

    def cores(self) -> float | None:
        """Cores the engine used over the last window; None before two marks."""
        if len(self.marks) < 2:
            return None
        (t0, c0), (t1, c1) = self.marks[-2:]
        return (c1 - c0) / (t1 - t0) if t1 > t0 else None

    def text(self, asks: float) -> str:
        """'' before two marks; else the cores it got against the `asks` it could have
        (its threads, or its fair part of the cores when the campaign's own engines ask
        for more than there are), with the warning below LOW_CPU_SHARE of them."""
        got = self.cores()
        if got is None:
            return ""
        out = f"; {got:.2f} of {asks:g} core(s) to it"
        if got < LOW_CPU_SHARE * asks:
            out += ("; WARNING: other work takes its cores (it slows far more than its share: its threads "
                    "wait for each other). Run that work at nice -n 19 from the campaign's session, or lower its "
                    "own session's share (docs/campaign.md, Working beside a run)")
        return out


def fair_cores(threads: int, engines_threads: int, cores: int) -> float:
    """The cores an engine of `threads` threads can have when the campaign's engines ask
    for `engines_threads` in all on `cores` cores."""
    return threads * min(1.0, cores / engines_threads) if engines_threads > 0 else float(threads)
