"""A running run's pace between progress reports: steps a minute, the time it still needs
at that pace, and a warning when the pace falls far below the run's best in this
invocation (docs/campaign.md, "Working beside a run": a run on two threads slows about
four times beside a job of the same priority)."""

from __future__ import annotations

from dataclasses import dataclass, field

from .state import hours

#: Below this share of the run's best pace in this invocation the report warns. A report
#: spans 10 minutes by default, more than one thermal cycle of the paper bed (6 minutes),
#: so the stages' own costs (a hold is about four times cheaper than a ramp) average out
#: and differ between windows by well under a half; the crowded case is a quarter.
SLOW_SHARE = 0.5


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
    # a checkpoint per report shows the same step twice: no window ends there (a pace of 0
    # and a false warning), the next step seen ends a longer one.
    unchanged: bool = False

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
        """'' before two marks; else the last window's pace, what it implies for the run's
        end against the budget left, and the warning when the pace fell."""
        if self.unchanged:
            since = "the last report" if len(self.marks) > 1 else "it started"
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
        best = max(rates)
        if len(rates) >= 2 and rate < SLOW_SHARE * best:
            out += (f"; WARNING: the pace fell to {rate / best:.2f} of its best in this invocation: other work "
                    "on the cores? Run it at nice -n 19 from the campaign's session, or lower its own session's "
                    "share (docs/campaign.md, Working beside a run)")
        return out
