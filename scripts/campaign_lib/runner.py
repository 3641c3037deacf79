"""Runs what is left of the plan within a time budget (docs/campaign.md, "Budget and
stopping"): a run starts when the budget's time left covers its estimated cost, or
when at least the minimum slice is left (it then stops at a checkpoint); when the budget ends (or on SIGTERM or SIGINT) every engine gets one SIGTERM, writes a
checkpoint and exits, and the next invocation resumes from there."""

from __future__ import annotations

import datetime
import json
import os
import signal
import socket
import subprocess
import time
from dataclasses import dataclass, field
from pathlib import Path

from common.paths import shown
from common.gitinfo import git_commit_folder

from . import gather, store
from .engine import Engine, file_sha256
from .pace import CpuShare, Pace, available_cores, fair_cores, process_cpu_seconds, seen_at
from .plan import Plan, same_json
from .state import RunState, choose, hours, one_thread_cpu
from .workdir import collect_packings, share_packings

POLL_SECONDS = 0.5
# The engine gets a process group of its own (os.killpg at the budget's end; a terminal's
# Ctrl-C reaches only the campaign) but stays in the campaign's session: the autogroup
# scheduler honours nice only within a session (docs/campaign.md, "Working beside a run").
ENGINE_PROCESS = {"process_group": 0}


def now_iso() -> str:
    return datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds")


def exit_outcome(code: int, stage: str, stopping: bool) -> str:
    """What a finished engine process leaves: "store", "stopped" or "failed".

    Judged by the folder first: run.json says "completed" only once every output is
    written, so a run that completed as its SIGTERM came (the sweep then exits non-zero
    while it winds down) is stored, not reported as stopped. A stopped run is judged by
    the folder, not the exit status: mpirun reports a rank stopped by SIGTERM as 1."""
    if stage == "completed" and (code == 0 or stopping):
        return "store"
    if stopping and stage != "failed":
        return "stopped"
    return "failed"


@dataclass
class Active:
    state: RunState
    proc: subprocess.Popen
    lock_fd: int
    command: list
    started: float
    started_iso: str
    threads: int = 1
    stopping: bool = False
    handing_over: bool = False   # stopped to resume at once on every thread (--finish-one)
    pace: Pace = field(default_factory=Pace)  # its step at each progress report
    cpu: CpuShare = field(default_factory=CpuShare)  # its CPU seconds at each progress report


@dataclass
class Outcome:
    stored: list = field(default_factory=list)
    stopped: list = field(default_factory=list)
    failed: list = field(default_factory=list)
    signal: int | None = None


class Runner:
    def __init__(self, plan: Plan, work: Path, results: Path, engine: Engine, golden_check: dict | None,
                 launcher: list, jobs: int, estimate, budget_seconds: float,
                 stop_margin: float, progress_every: float, commit: bool, say, min_slice: float = 0.0,
                 threads: int = 1, finish_one: bool = False):
        self.plan, self.work, self.results, self.engine = plan, work, results, engine
        self.golden_check, self.launcher, self.jobs = golden_check, launcher, jobs
        # Wall seconds of a run: a number for every run, or an Estimate (per point).
        self.estimate = estimate.for_run if hasattr(estimate, "for_run") else (lambda run, s=float(estimate): s)
        self.min_slice = min_slice  # seconds of budget worth starting a run that will not finish in it
        self.threads = threads      # OpenMP threads of each engine (the same bits for any count)
        self.finish_one = finish_one  # near the end, one run on every thread (gather.py)
        self.start = time.monotonic()
        self.stop_at = self.start + budget_seconds - stop_margin
        self.grace = max(stop_margin, 5.0)
        self.progress_every, self.commit, self.say = progress_every, commit, say
        self.pool = work / "packings" / engine.key
        self.signal = None
        self.binary_changed = False

    # ------------------------------------------------------------------ signals --
    def _on_signal(self, signum, _frame):
        self.signal = signum

    def left(self) -> float:
        return self.stop_at - time.monotonic()

    # -------------------------------------------------------------------- loop --
    def run(self, queue: list) -> Outcome:
        outcome = Outcome()
        old = {s: signal.signal(s, self._on_signal) for s in (signal.SIGTERM, signal.SIGINT)}
        active: dict = {}
        last_report = last_look = time.monotonic()
        try:
            queue = list(queue)
            while True:
                if self.signal is not None or self.left() <= 0:
                    if active:
                        why = (f"{signal.Signals(self.signal).name} received" if self.signal is not None
                               else "the budget ends")
                        self.say(f"{why}: stopping {len(active)} run(s) with SIGTERM (each writes a checkpoint)")
                        self._stop_all(active, outcome)
                    elif queue and self.signal is None:
                        self.say(f"budget: {len(queue)} run(s) left for the next invocation")
                    break
                while len(active) < self.jobs and queue:
                    state = self._next_fitting(queue)
                    if state is None:
                        break
                    started = self._start(state)
                    if started:
                        active[started.proc.pid] = started
                if not active:
                    if queue and not self.binary_changed:
                        self.say(f"budget: {hours(self.left())} left, less than the next run's estimate "
                                 f"and than the minimum slice; {len(queue)} run(s) left for the next invocation")
                    break
                self._reap(active, outcome, block=False)
                if time.monotonic() - last_report >= self.progress_every:
                    self._report(active)
                    last_report = time.monotonic()
                if self.finish_one and active and time.monotonic() - last_look >= gather.CHECK_SECONDS:
                    self._finish_one(active, queue, outcome)
                    last_look = time.monotonic()
                time.sleep(POLL_SECONDS)
        finally:
            if active:   # an exception: the engines still get their SIGTERM and checkpoint
                self._stop_all(active, outcome)
            for sig, handler in old.items():
                signal.signal(sig, handler)
        outcome.signal = self.signal
        return outcome

    def _next_fitting(self, queue: list):
        """The next run to start (state.choose): the first of the queue whose estimated
        remaining cost fits the time left, else the first while at least the minimum slice
        is left (a run longer than a session goes on in installments). Without a minimum
        slice, the runs that do not fit are dropped for this invocation (the time left only
        shrinks); with one, they wait for the fitting runs to have started."""
        if not queue or self.binary_changed:
            return None
        for s in queue:
            s.progress = s.folder.progress()
        needs = [self.estimate(s.run) * (1.0 - s.progress.fraction) for s in queue]
        index, fits = choose(needs, self.left(), self.min_slice)
        if index is None:
            self.say(self._not_starting([(s.run.label, n) for s, n in zip(queue, needs)]))
            queue.clear()
            return None
        if fits and index > 0 and self.min_slice == 0.0:
            self.say(self._not_starting([(s.run.label, n) for s, n in zip(queue[:index], needs[:index])]))
            del queue[:index]
            index = 0
        elif not fits:
            self.say(f"budget: {queue[index].run.label} needs about {hours(needs[index])}, {hours(self.left())} "
                     "left: it starts and stops at a checkpoint when the budget ends")
        return queue.pop(index)

    def _not_starting(self, waiting: list) -> str:
        """One line for the runs the budget leaves for the next invocation; without a
        minimum slice it says how to give them the idle cores."""
        label, need = waiting[0]
        if len(waiting) == 1:
            text = f"budget: not starting {label}: {hours(self.left())} left, it needs about {hours(need)}"
        else:
            least = min(n for _, n in waiting)
            text = (f"budget: not starting {label} and {len(waiting) - 1} more: {hours(self.left())} left, "
                    f"each needs at least {hours(least)}")
        if self.min_slice == 0.0:
            text += ("; --min-slice MINUTES would start them now, to stop at a checkpoint when the budget "
                     "ends (where the work folder outlives the session)")
        return text

    def _finish_one(self, active: dict, queue: list, outcome: Outcome) -> None:
        """gather.lead_to_finish on the runs under way; when it names one, every run stops at
        a checkpoint and that one resumes at once on all the threads, and from then on the
        invocation runs one run at a time on all of them."""
        everything = self.jobs * self.threads
        items = list(active.values())
        running = []
        for item in items:
            progress, rates = item.state.folder.progress(), item.pace.rates()
            if not rates or progress.total is None or progress.step is None:
                return   # no pace yet: wait for the next progress report
            running.append(gather.Running(item.state.run.label, progress.total - progress.step, rates[-1],
                                          item.threads))
        lead = gather.lead_to_finish(running, everything, self.left(), nothing_else_starts=not queue)
        if lead is None:
            return
        chosen = items[lead]
        alone = running[lead].alone_seconds(everything)
        others = [i.state.run.label for i in items if i is not chosen]
        self.say(f"finish one: {chosen.state.run.label} needs about {hours(alone)} alone on {everything} "
                 f"thread(s), {hours(self.left())} of the budget left"
                 + (f"; stopping {', '.join(others)} at a checkpoint to give it their threads" if others else
                    "; it resumes on the idle threads"))
        chosen.handing_over = True
        self._stop_all(active, outcome)
        self.jobs, self.threads = 1, everything
        if chosen.state.run.label in outcome.stored:
            return   # it completed as its SIGTERM came, and was stored
        started = self._start(chosen.state)
        if started:
            active[started.proc.pid] = started
        else:
            outcome.stopped.append(chosen.state.run.label)

    def _start(self, state: RunState) -> Active | None:
        folder = state.folder
        if file_sha256(self.engine.binary) != self.engine.binary_sha256:
            # Rebuilt under us: the provenance would name the wrong engine.
            self.say(f"the engine binary {self.engine.binary} changed since this invocation started; "
                     "no new run starts (run the command again to go on with the new engine)")
            self.binary_changed = True
            return None
        fd = folder.lock()
        if fd is None:
            self.say(f"skip {state.run.label}: another process is running it (lock {folder.lock_file})")
            return None
        if self._stored_meanwhile(state):
            os.close(fd)
            self.say(f"skip {state.run.label}: another process stored it since this invocation began "
                     f"({store.folder_of(self.results, state.run)})")
            return None
        if folder.forget_other_engine(self.engine):
            self.say(f"{state.run.label}: its work folder was of another engine; starting it over")
        folder.write_sweep(self.plan)
        share_packings(self.pool, folder.out)
        ledger = folder.ledger()
        ledger["engine"] = self.engine.record()
        folder.save_ledger(ledger)
        progress = folder.progress()
        command = [*self.launcher, str(self.engine.binary), "sweep", str(folder.sweep_file), "--out",
                   str(folder.out), "--jobs", "1"]
        if self.threads > 1:   # the sweep runs each run on one thread unless told (engines from 2026-11-28)
            command += ["--threads", str(self.threads)]
        with open(folder.log, "a") as log:
            log.write(f"\n=== {now_iso()} scripts/campaign: {' '.join(command)}\n")
            log.flush()
            env = dict(os.environ, OMP_NUM_THREADS="1")   # the sweep sets each run's threads (--threads)
            proc = subprocess.Popen(command, stdout=log, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL,
                                    pass_fds=(fd,), env=env, **ENGINE_PROCESS)
        fresh = progress.stage == "not started" or (progress.stage == "pouring" and progress.checkpoint is None)
        how = "new" if fresh else f"resumes: {progress.text()}"
        stale = f"; rerun of a stale result ({state.verdict.reason})" if state.stale else ""
        self.say(f"start {state.run.label} ({how}{stale}); {hours(self.left())} of the budget left; "
                 f"log {folder.log}")
        item = Active(state=state, proc=proc, lock_fd=fd, command=command, started=time.monotonic(),
                      started_iso=now_iso(), threads=self.threads)
        if how != "new":   # a resumed run goes on from its checkpoint: the first window's pace counts from there
            item.pace.resume(item.started, progress.checkpoint)
        return item

    def _stored_meanwhile(self, state: RunState) -> bool:
        """A current result of the run in the results folder now, though there was none when
        the queue was made: two invocations share the plan, and the other one finished it
        (its lock is gone by then). The queue holds no run that was current then."""
        stored = store.read(self.results, state.run)
        return stored is not None and store.judge(stored, self.plan.scene_for(state.run), self.engine.record(),
                                                  self.golden_check).current

    def _reap(self, active: dict, outcome: Outcome, block: bool) -> None:
        for pid in list(active):
            try:
                got, status, usage = os.wait4(pid, 0 if block else os.WNOHANG)
            except ChildProcessError:
                got, status, usage = pid, 0, None
            if got == 0:
                continue
            item = active.pop(pid)
            item.proc.returncode = os.waitstatus_to_exitcode(status)
            cpu = (usage.ru_utime + usage.ru_stime) if usage else 0.0
            self._finished(item, item.proc.returncode, cpu, outcome)

    def _finished(self, item: Active, code: int, cpu: float, outcome: Outcome) -> None:
        state, folder = item.state, item.state.folder
        wall = time.monotonic() - item.started
        ledger = folder.ledger()
        ledger["segments"].append({"start": item.started_iso, "end": now_iso(), "wall_seconds": round(wall, 1),
                                   "cpu_seconds": round(cpu, 1), "threads": item.threads, "exit_status": code,
                                   "host": socket.gethostname(), "command": [shown(c) if "/" in c else c
                                                                             for c in item.command]})
        folder.save_ledger(ledger)
        collect_packings(self.pool, folder.out)
        os.close(item.lock_fd)
        progress = folder.progress()
        label = state.run.label
        what = exit_outcome(code, progress.stage, item.stopping)
        if what == "store":
            try:
                where = self._store(state, ledger)
            except (OSError, ValueError, RuntimeError) as error:
                self.say(f"run {label} completed but was NOT stored: {error}")
                outcome.failed.append(label)
                return
            total_cpu = sum(s["cpu_seconds"] for s in ledger["segments"])
            self.say(f"done {label} in {hours(wall)} (this session), {hours(total_cpu)} CPU in all; "
                     f"stored in {shown(where)}")
            outcome.stored.append(label)
        elif what == "stopped" and item.handing_over:
            self.say(f"{label} at a checkpoint ({progress.text()}): it resumes now on {self.jobs * self.threads} "
                     "thread(s)")
        elif what == "stopped":
            self.say(f"stopped {label}: {progress.text()}; the next invocation resumes it")
            outcome.stopped.append(label)
        else:
            tail = ""
            try:
                tail = folder.log.read_text(errors="replace").strip().splitlines()[-1]
            except (OSError, IndexError):
                pass
            self.say(f"run {label} FAILED (exit {code}): {tail} (log {folder.log})")
            outcome.failed.append(label)

    def _store(self, state: RunState, ledger: dict) -> Path:
        folder, run = state.folder, state.run
        run_json = json.loads((folder.run_dir / "run.json").read_text())
        if not same_json(run_json.get("scene"), self.plan.scene_for(run)):
            raise ValueError(f"{folder.run_dir / 'run.json'}: its scene is not the plan's scene for {run.label} "
                             "(the campaign's composition of the scene disagrees with the engine's)")
        segments = ledger["segments"]
        sweep = folder.sweep(self.plan)
        sweep["scene"] = shown(self.plan.scene_path)
        provenance = {
            "format": 1,
            "campaign": self.plan.name, "plan_file": shown(self.plan.path),
            "point": run.point.name, "point_set": run.point.set, "seed": run.seed,
            "scene_file": shown(self.plan.scene_path), "scene_hash": run_json.get("scene_hash"),
            "sweep": sweep,
            "command": " ".join(segments[-1]["command"]),
            "engine": self.engine.record(),
            "golden_check": self.golden_check,
            "date": now_iso(), "host": socket.gethostname(),
            "started": segments[0]["start"] if segments else None,
            "segments": len(segments),
            "cpu_seconds": round(sum(s["cpu_seconds"] for s in segments), 1),
            "wall_seconds": round(sum(s["wall_seconds"] for s in segments), 1),
            "engine_wall_seconds": run_json.get("wall_seconds"),
            # The most threads a segment ran on (older segments did not say: one), and what
            # the run would have cost on one thread, segment by segment (state.py).
            "threads": max((s.get("threads", 1) for s in segments), default=1),
            "one_thread_seconds": round(sum(one_thread_cpu(s["cpu_seconds"], s.get("threads", 1))
                                            for s in segments), 1),
            "steps": run_json.get("steps"),
        }
        where = store.store(self.results, run, folder.run_dir, provenance)
        if self.commit:
            message = (f"campaign {self.plan.name}: store {run.label} (engine {self.engine.short}, "
                       f"{provenance['cpu_seconds'] / 3600:.2f} CPU h)")
            commit = git_commit_folder(where, message)
            self.say(f"committed {run.label} as {commit}")
        return where

    def _stop_all(self, active: dict, outcome: Outcome) -> None:
        for item in active.values():
            item.stopping = True
            try:
                item.proc.send_signal(signal.SIGTERM)   # once: a second SIGTERM ends the engine at once
            except ProcessLookupError:
                pass
        deadline = time.monotonic() + self.grace
        while active and time.monotonic() < deadline:
            self._reap(active, outcome, block=False)
            time.sleep(POLL_SECONDS)
        for item in active.values():
            self.say(f"{item.state.run.label}: no exit {self.grace:.0f} s after SIGTERM; SIGKILL "
                     "(its last periodic checkpoint remains)")
            try:
                os.killpg(item.proc.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
        self._reap(active, outcome, block=True)

    def _report(self, active: dict) -> None:
        asked = sum(item.threads for item in active.values())
        for item in active.values():
            progress = item.state.folder.progress()
            now, left = time.monotonic(), self.left()
            item.pace.add(seen_at(now, progress.step_time, time.time()), progress.step)
            cores = ""
            if not self.launcher:   # a launcher's ranks may run on other hosts: their CPU is not seen here
                item.cpu.add(now, process_cpu_seconds(item.proc.pid))
                cores = item.cpu.text(fair_cores(item.threads, asked, available_cores()))
            self.say(f"progress {item.state.run.label}: {progress.text()}, {hours(now - item.started)} "
                     f"so far; {hours(left)} of the budget left{item.pace.text(progress.total, left)}{cores}")
