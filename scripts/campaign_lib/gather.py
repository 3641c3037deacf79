"""--finish-one: near the budget's end, one run on every thread rather than several that
all stop at a checkpoint (docs/campaign.md, "Finishing one run at the budget's end").

Only a stored run is sure to outlive a session; a checkpoint is not. Side by side the
runs carry more work, so they stay side by side as long as they can, and the rule acts
only at the last moment: when the most advanced run would still finish alone on every
thread, but would not if it waited one more check. The results are the same bits on any
number of threads, so a run may change its thread count at a checkpoint."""

from __future__ import annotations

from dataclasses import dataclass, replace

from .state import thread_factor

#: Seconds between two looks at the runs under way.
CHECK_SECONDS = 60.0
#: Kept free of the alone estimate: a share of it, because the pace of a run moves by about
#: a sixth between progress windows (999-1399 steps a minute alone on two threads,
#: 2026-12-05/06), and the seconds a stop and a resume take (a checkpoint written and read,
#: the hulls built again: under 20 s on the paper bed) with room to spare.
SAFETY_SHARE = 0.15
RESTART_SECONDS = 60.0


@dataclass
class Running:
    """A run under way as the rule sees it."""
    label: str
    steps_left: int
    rate: float      # steps a second over the last progress window, on `threads`
    threads: int

    def alone_seconds(self, all_threads: int) -> float:
        """Its time to the end on `all_threads` threads with no run beside it, by the
        thread model (state.thread_factor). The model leaves out what sharing the cores
        costs a run side by side (1.87 of one run's speed for two, not 2), so it errs on
        the long side."""
        return self.steps_left / (self.rate * thread_factor(self.threads) / thread_factor(all_threads))


def needs_with_safety(seconds: float) -> float:
    return seconds * (1.0 + SAFETY_SHARE) + RESTART_SECONDS


def lead_to_finish(running: list, all_threads: int, left: float, nothing_else_starts: bool,
                   check_every: float = CHECK_SECONDS) -> int | None:
    """Which run (its index in `running`) gets every thread now, or None.

    Several runs: none while one of them finishes at its own pace within `left` seconds
    (nothing is lost by waiting); else the run with the least time alone, when that time
    with its safety fits in `left` but would not after one more check. One run on fewer
    threads than there are: it gets them at once when no other run will start and it has
    more than a restart's worth of work left."""
    if not running or any(r.rate <= 0.0 for r in running):
        return None
    if len(running) == 1:
        r = running[0]
        worth = r.threads < all_threads and r.steps_left / r.rate > 2.0 * RESTART_SECONDS
        return 0 if nothing_else_starts and worth else None
    if any(r.steps_left / r.rate <= left for r in running):
        return None
    lead = min(range(len(running)), key=lambda i: running[i].alone_seconds(all_threads))
    r = running[lead]
    need = needs_with_safety(r.alone_seconds(all_threads))
    if need > left:
        return None     # too late even alone: every run stops at a checkpoint
    after_check = replace(r, steps_left=max(0.0, r.steps_left - r.rate * check_every))
    later = needs_with_safety(after_check.alone_seconds(all_threads))
    return lead if check_every + later > left else None
