"""scripts/campaign: the command line (docs/campaign.md)."""

from __future__ import annotations

import argparse
import json
import math
import os
import shlex
import subprocess
import sys
import time
from pathlib import Path

from common.paths import REPO_ROOT, shown
from ratchet import command

from . import golden, state
from .assemble import assemble
from .engine import EngineError, identify
from .plan import PlanError, load_plan, resolve
from .recheck import recheck
from .runner import Runner

USAGE_EXAMPLES = """
examples:
  scripts/campaign paper --status
  scripts/campaign paper --dry-run --budget 3 --jobs 2
  scripts/campaign paper --budget 2.5 --jobs 2 --commit
  scripts/campaign paper --budget 2.5 --threads 2 --commit   # one run at a time on two cores
  scripts/campaign paper --budget 2.6 --jobs 2 --min-slice 20 --finish-one --commit   # a kept machine
  scripts/campaign paper --budget 23 --jobs 64 --mpirun          # a cluster allocation
  scripts/campaign paper --assemble out/campaign/paper-sweeps
  scripts/campaign paper --recheck-golden OLD/ratchet --commit   # golden/ moved on, the engine did not
exit status: 0 nothing failed (whether or not the plan is finished); 1 a run failed
(--recheck-golden: the check failed); 2 bad plan, option or engine (--recheck-golden: no
stored run of that binary); 130/143 stopped by SIGINT/SIGTERM (runs resumable).
"""


def say(message: str) -> None:
    try:
        print(f"campaign: {message}", flush=True)
    except (BrokenPipeError, OSError):
        pass   # a closed output must not leave the engines running unattended


class UsageError(Exception):
    pass


def number_at_least(name, low, strict):
    """argparse type: a finite number > low (strict) or >= low, else an error naming the option."""
    expected = f"a number {'>' if strict else '>='} {low:g}"

    def parse(text):
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{name}: expected {expected}, got '{text}'") from None
        if not math.isfinite(value) or value < low or (strict and value == low):
            raise argparse.ArgumentTypeError(f"{name}: expected {expected}, got '{text}'")
        return value
    return parse


def positive(name):
    return number_at_least(name, 0.0, strict=True)


def non_negative(name):
    return number_at_least(name, 0.0, strict=False)


def whole(name, what):
    def parse(text):
        if not text.isdigit() or int(text) < 1:
            raise argparse.ArgumentTypeError(f"{name}: expected a whole number >= 1 ({what}), got '{text}'")
        return int(text)
    return parse


def parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="scripts/campaign",
        description="Runs a campaign plan (validation/campaigns/<PLAN>.json) in installments within a time "
                    "budget, on the resumable sweep machinery; stores each finished run's small results with "
                    "their provenance (docs/campaign.md).",
        epilog=USAGE_EXAMPLES, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("plan", help="a plan name (validation/campaigns/NAME.json) or a plan file")
    mode = p.add_mutually_exclusive_group()
    mode.add_argument("--status", action="store_true", help="print the plan, what is stored, stale, in progress, "
                      "and the CPU hours left; run nothing")
    mode.add_argument("--dry-run", action="store_true", help="print what would run (within --budget if given)")
    mode.add_argument("--assemble", metavar="OUTDIR", help="write the stored results as sweep folders "
                      "OUTDIR/<part>/ (summary.csv, runs/<id>/) for scripts/trends; run nothing")
    mode.add_argument("--recheck-golden", metavar="BIN", help="the bit-for-bit golden check of an earlier "
                      "engine binary on today's golden data; if it passes, the stored runs that binary made "
                      "(same SHA-256) record it, and stay reusable by an engine that passes it too; run nothing "
                      "else")
    p.add_argument("--budget", type=positive("--budget"), metavar="HOURS",
                   help="wall-clock hours this invocation may take (required to run)")
    p.add_argument("--jobs", type=whole("--jobs", "runs at a time"), default=1, help="runs at a time (default 1)")
    p.add_argument("--threads", type=whole("--threads", "threads per run"), default=1,
                   help="OpenMP threads of each run (default 1; the results are the same bits for any "
                        "count): a run then takes about 0.48 + 0.52/THREADS of its one-thread time; keep "
                        "jobs x threads within the cores")
    p.add_argument("--mpirun", nargs="?", const="mpirun -n 1", metavar="LAUNCHER",
                   help="put LAUNCHER before each engine command (default 'mpirun -n 1'; as root "
                        "--allow-run-as-root is added); e.g. 'srun -n 1 --exclusive'")
    p.add_argument("--out", metavar="WORKDIR", help="work folder, outside git (default out/campaign/<plan>)")
    p.add_argument("--results", metavar="DIR", help="stored results (default validation/results/<plan>)")
    p.add_argument("--ratchet", metavar="BIN", help="engine binary (default $RATCHET_BIN, else "
                   "build/reference_engine/ratchet)")
    p.add_argument("--commit", action="store_true", help="git-commit each newly stored run's folder (that "
                   "folder only)")
    p.add_argument("--golden-check", choices=("run", "skip"), default="run",
                   help="run: the bit-for-bit golden check of this engine (regression/run --all --tol-scale 0, "
                        "about a minute, cached per engine) before the first run; skip: record none, so results "
                        "of this engine are never reused by another (default run)")
    p.add_argument("--run-hours", type=positive("--run-hours"), metavar="H",
                   help="the estimated wall hours of one run (default: measured from stored runs, else the "
                        "plan's run_cost_hours)")
    p.add_argument("--min-slice", type=non_negative("--min-slice"), default=0.0, metavar="MINUTES",
                   help="a run that will not finish within the budget still starts while this much of it is "
                        "left, and stops at a checkpoint for the next invocation: only where the work folder "
                        "outlives the session (default 0: only runs that fit start)")
    p.add_argument("--stop-margin", type=positive("--stop-margin"), metavar="SECONDS",
                   help="stop the engines this long before the budget ends (default 60, at most a tenth of "
                        "the budget)")
    p.add_argument("--finish-one", action="store_true",
                   help="near the budget's end, when none of the runs under way would finish at its pace but the "
                        "most advanced would on all JOBS x THREADS threads, stop the others at a checkpoint and "
                        "resume it on all of them (the same bits on any thread count); a last run alone gets the "
                        "idle threads too. For machines whose work folder may not outlive the session")
    p.add_argument("--progress-every", type=positive("--progress-every"), default=600.0, metavar="SECONDS",
                   help="print each running run's progress this often (default 600)")
    return p


def launcher_words(text: str | None) -> list:
    if not text:
        return []
    words = shlex.split(text)
    if words and os.path.basename(words[0]) == "mpirun" and os.geteuid() == 0 \
            and "--allow-run-as-root" not in words:
        words.insert(1, "--allow-run-as-root")
    return words


def check_scenes(plan, states, engine) -> None:
    """Every point still to run is built by the engine (`run --explain`) before any work,
    so a bad value stops the campaign here, naming the plan file and the point."""
    checked = set()
    for s in states:
        if s.done or s.run.point.name in checked:
            continue
        checked.add(s.run.point.name)
        sets = [f"{k}={json.dumps(v)}" for k, v in sorted(plan.set.items())]
        sets += [f"{k}={json.dumps(v)}" for k, v in sorted(s.run.point.set.items())]
        sets.append(f"seed={s.run.seed}")
        line = command("run", "--explain", plan.scene_path, *(a for item in sets for a in ("--set", item)),
                       ratchet=engine.binary)
        done = subprocess.run(line, capture_output=True, text=True)
        if done.returncode != 0:
            message = done.stderr.strip().splitlines()[-1] if done.stderr.strip() else f"exit {done.returncode}"
            raise PlanError(f"{plan.path}: field '{blamed_field(plan, s.run.point, message)}' (point "
                            f"'{s.run.point.name}'): the engine refuses its scene: {message}")


def blamed_field(plan, point, message: str) -> str:
    """The plan field behind an engine error about a --set (else the base scene's)."""
    index = list(plan.points).index(point.name)
    for key in sorted(point.set, key=len, reverse=True):
        if f"--set {key}=" in message:
            return f"points[{index}].set.{key}"
    for key in sorted(plan.set, key=len, reverse=True):
        if f"--set {key}=" in message:
            return f"set.{key}"
    return "scene"


def print_status(plan, states, estimate, engine, golden_now, work, results) -> None:
    say(f"plan {shown(plan.path)}: {len(plan.runs)} runs ({len(plan.points)} points), scene "
        f"{shown(plan.scene_path)}")
    say(f"engine {engine.short} ({engine.version}); golden check: "
        + ("not run for this engine" if golden_now is None else
           ("passed" if golden_now.get("passed") else "FAILED") + f" ({golden_now.get('date')})"))
    say(f"results {shown(results)}, work folder {shown(work)}")
    by_label = {s.run.label: s for s in states}
    for part in plan.parts:
        say(f"part {part.name}: {part.description}")
        for run in plan.part_runs(part):
            s = by_label[run.label]
            if s.done:
                p = s.stored.provenance
                what = (f"stored (engine {str(p.get('engine', {}).get('engine_commit'))[:10]}, "
                        f"{p.get('date')}, {float(p.get('cpu_seconds') or 0) / 3600:.2f} CPU h; {s.verdict.reason})")
            elif s.stale:
                what = f"STALE: {s.verdict.reason}; {s.progress.text()}"
            else:
                what = s.progress.text()
            if s.busy:
                what += " [running now in another process]"
            say(f"  {run.label:28s} {what}")
    left = state.todo(states)
    seconds = sum(estimate.for_run(s.run) * (1.0 - s.progress.fraction) for s in left)
    done = sum(1 for s in states if s.done)
    stale = sum(1 for s in states if s.stale)
    going = sum(1 for s in states if not s.done and s.started)
    say(f"{done} of {len(states)} runs stored and current, {stale} stale, {going} in progress, "
        f"{len(left)} to run: about {state.hours(seconds)} of run time left, the runs' estimated wall times summed "
        f"(a run: {state.hours(estimate.seconds)}, {estimate.source}{per_point(estimate)})")


def per_point(estimate) -> str:
    """The points whose own stored runs set their estimate, for the lines that give the
    estimate of 'a run'."""
    if not estimate.by_point:
        return ""
    return "; by a point's own stored runs: " + ", ".join(
        f"{name} {state.hours(seconds)}" for name, (seconds, _) in estimate.by_point.items())


def print_dry_run(states, estimate, budget, jobs, min_slice) -> None:
    queue = state.todo(states)
    if not queue:
        say("dry run: nothing to run, every run of the plan is stored and current")
        return
    say(f"dry run: {len(queue)} run(s) to do, in this order (a run: {state.hours(estimate.seconds)}, "
        f"{estimate.source}{per_point(estimate)})")
    slots = [0.0] * jobs   # when each slot is free, in seconds from now
    fitting = partial = 0
    left = list(queue)
    order = []   # (state, start seconds or None, fits), in the order they would start
    while left:
        slot = min(range(jobs), key=lambda i: slots[i])
        begin = slots[slot]
        needs = [estimate.for_run(s.run) * (1.0 - s.progress.fraction) for s in left]
        if budget is None:
            index, fits = 0, True
        else:   # as Runner._next_fitting
            index, fits = state.choose(needs, budget - begin, min_slice)
        if index is None:
            order += [(s, None, False) for s in left]
            break
        order.append((left[index], begin, fits))
        slots[slot] = begin + needs[index] if fits else budget
        fitting, partial = fitting + fits, partial + (not fits)
        left.pop(index)
        if min_slice == 0.0 and budget is not None:
            # Runs before the chosen one did not fit and never will (Runner drops them).
            order += [(s, None, False) for s in left[:index]]
            del left[:index]
    for s, begin, fits in order:
        why = f"; rerun of a stale result ({s.verdict.reason})" if s.stale else ""
        when = f", would start at +{state.hours(begin)}" if begin is not None and budget is not None else ""
        mark = "" if fits else (" [stops at a checkpoint when the budget ends]" if begin is not None else
                                " [not within the budget]")
        say(f"  {s.run.label:28s} {s.progress.text()}{why}{when}{mark}")
    if budget is not None:
        say(f"dry run: {fitting} of {len(queue)} run(s) fit in {state.hours(budget)} with {jobs} at a time, "
            f"{partial} more start and stop at a checkpoint (at the estimate; the real start of each is "
            "decided when a slot frees)")


def main(argv=None) -> int:
    args = parser().parse_args(argv)
    try:
        plan = load_plan(resolve(args.plan))
        engine = identify(args.ratchet)  # --ratchet, else the build's
        work = Path(args.out) if args.out else REPO_ROOT / "out" / "campaign" / plan.name
        results = Path(args.results) if args.results else REPO_ROOT / "validation" / "results" / plan.name
        work = work.resolve()
        results = results.resolve()
        if REPO_ROOT in work.parents and not (REPO_ROOT / "out") in [work, *work.parents]:
            raise UsageError(f"--out {work}: the work folder holds large files; put it under out/ or outside "
                             "the repository")
        running = not (args.status or args.dry_run or args.assemble or args.recheck_golden)
        if running and args.budget is None:
            raise UsageError("--budget HOURS is required to run (or give --status, --dry-run or --assemble)")
    except (PlanError, EngineError, UsageError) as error:
        print(f"campaign: error: {error}", file=sys.stderr, flush=True)
        return 2

    if args.recheck_golden:
        try:
            return recheck(plan, work, results, Path(args.recheck_golden).resolve(), args.commit, say)
        except EngineError as error:
            print(f"campaign: error: {error}", file=sys.stderr, flush=True)
            return 2
    if engine.built_elsewhere:
        why = (f"its source hash {engine.source_hash} is not that of the engine sources here ({engine.sources_hash})"
               if engine.source_hash else f"{len(engine.stale)} engine source file(s) are newer than it (e.g. "
               f"{shown(engine.stale[0])})")
        if engine.built_at:
            say(f"note: {shown(engine.binary)} was not built from this checkout's engine sources ({why}) but at commit "
                f"{engine.built_at[:10]}, whose engine sources give its source hash: the engine is named by them "
                f"(engine_commit {engine.short}, built_at)")
        else:
            say(f"warning: {shown(engine.binary)} was not built from this checkout's engine sources: {why}; the engine "
                "is named by the binary's SHA-256, not by its sources' commit (engine_dirty); rebuild unless that is "
                "meant")
    golden_now = golden.cached(work, engine)
    states = state.survey(plan, work, results, engine, golden_now)
    estimate = state.estimate(plan, states, engine, args.run_hours, args.threads)

    if args.status:
        print_status(plan, states, estimate, engine, golden_now, work, results)
        return 0
    if args.assemble:
        assemble(plan, states, Path(args.assemble), say)
        return 0
    budget = args.budget * 3600.0 if args.budget else None
    if args.dry_run:
        print_dry_run(states, estimate, budget, args.jobs, 60.0 * args.min_slice)
        return 0

    queue = state.todo(states)
    if not queue:
        say(f"all {len(states)} runs of plan {plan.name} are stored and current; nothing to run")
        return 0
    try:
        check_scenes(plan, states, engine)
    except PlanError as error:
        print(f"campaign: error: {error}", file=sys.stderr, flush=True)
        return 2
    work.mkdir(parents=True, exist_ok=True)
    if args.golden_check == "run" and golden_now is None:
        golden_now = golden.run_check(work, engine, say)
        states = state.survey(plan, work, results, engine, golden_now)
        queue = state.todo(states)
        if not queue:
            say("every run is current after the golden check; nothing to run")
            return 0
    cores = os.cpu_count() or 1
    if args.jobs * args.threads > cores:
        say(f"warning: {args.jobs} run(s) of {args.threads} thread(s) each on {cores} core(s): more threads than "
            "cores slows every run far more than in proportion (OpenMP's threads wait busy at each barrier)")
    if args.finish_one and args.jobs * args.threads == 1:
        say("note: --finish-one has no threads to give with --jobs 1 --threads 1")
    margin = args.stop_margin if args.stop_margin else min(60.0, 0.1 * budget)
    say(f"plan {plan.name}: {len(states) - len(queue)} of {len(states)} runs stored and current, {len(queue)} to "
        f"run; budget {state.hours(budget)}, {args.jobs} at a time on {args.threads} thread(s) each; a run is estimated at "
        f"{state.hours(estimate.seconds)} ({estimate.source}{per_point(estimate)}); engine {engine.short}")
    runner = Runner(plan, work, results, engine, golden_now, launcher_words(args.mpirun), args.jobs,
                    estimate, budget, margin, args.progress_every, args.commit, say,
                    min_slice=60.0 * args.min_slice, threads=args.threads, finish_one=args.finish_one)
    started = time.monotonic()
    outcome = runner.run(queue)
    states = state.survey(plan, work, results, engine, golden_now)
    left = state.todo(states)
    seconds = sum(estimate.for_run(s.run) * (1.0 - s.progress.fraction) for s in left)
    say(f"session over after {state.hours(time.monotonic() - started)}: {len(outcome.stored)} stored, "
        f"{len(outcome.stopped)} stopped at a checkpoint, {len(outcome.failed)} failed; "
        f"{len(states) - len(left)} of {len(states)} runs done, about {state.hours(seconds)} of run time left"
        + ("; run the same command again to go on" if left else ""))
    if outcome.signal is not None:
        return 128 + outcome.signal
    return 1 if outcome.failed else 0
