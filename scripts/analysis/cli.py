"""Command line of scripts/trends (docs/trends.md).

scripts/trends SWEEP_OUT_DIR [SWEEP_OUT_DIR ...] --out OUT [--checks DIR]
               [--tier quick|standard|paper] [--no-plots]
scripts/trends --list-checks

Exit status: 0 no check failed (skipped, not-resolved and checks contradicted at a reduced
scale do not fail); 1 a check failed (a contradiction at the paper tier, or a value that is
not a number); 2 usage error, a sweep folder that cannot be read, or an unwritable output.
"""

from __future__ import annotations

import argparse
import datetime as _dt
import os
import sys
import traceback
from pathlib import Path
from typing import Sequence

from common.fsutil import write_atomic
from common.jsonsafe import dumps

from common.gitinfo import git_commit
from common.paths import REPO_ROOT

from . import headline, output, plots, trends
from .inputs import InputError, load_sweep


def _parse(argv: Sequence[str] | None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(
        prog="trends",
        description="Fits and checks the paper's trends on sweep outputs (angle sweeps vary "
                    "container.opening_angle_deg, ratio sweeps thermal.alpha_c), draws the "
                    "figures and writes OUT/trends.json, OUT/trends.md and one JSON line per "
                    "check for scripts/report.py.",
        epilog="Exit status: 0 no check failed (skipped, not-resolved and checks contradicted at a "
               "reduced scale do not fail); 1 a check failed (a contradiction at the paper tier, or "
               "a value that is not a number); 2 usage error, unreadable sweep or unwritable output.")
    parser.add_argument("sweeps", nargs="*", metavar="SWEEP_OUT_DIR",
                        help="sweep output folder holding summary.csv (and runs/<run>/)")
    parser.add_argument("--out", metavar="OUT", help="folder for trends.json, trends.md and "
                        "figures/ (the validation report embeds OUT/figures/*.png)")
    parser.add_argument("--checks", metavar="DIR",
                        help="folder for the check lines (default: $RATCHET_CHECKS_DIR, "
                             "else OUT/checks)")
    parser.add_argument("--tier", choices=trends.TIERS, default="quick",
                        help="tier of the sweeps; sets the tolerances (default: quick)")
    parser.add_argument("--scale", metavar="TEXT",
                        help="what the sweeps' beds are, shown with the headline (default: the "
                             "tier's description); the tier still sets the tolerances")
    parser.add_argument("--out-of-scale", metavar="ID=REASON", action="append", default=[],
                        help="a check whose paper statement does not cover these beds (e.g. the "
                             "paper's 10-cycle vorticity windows against a 3-cycle sweep): a pass "
                             "becomes not resolved, a resolved contradiction stays contradicted "
                             "(never a failure, never a pass), with REASON; the measured value and "
                             "the rule's status stay in the record; repeatable; ids: --list-checks")
    parser.add_argument("--no-plots", action="store_true", help="skip the figures")
    parser.add_argument("--list-checks", action="store_true",
                        help="print the check definitions (rules, tolerances, reasons) and exit")
    store = parser.add_argument_group("storing the headline (docs/trends.md, 'Stored results')")
    store.add_argument("--store", metavar="FILE",
                       help="also write the headline record of this analysis to FILE (e.g. "
                            "validation/results/standard.json), shown by every validation report")
    store.add_argument("--engine-commit", metavar="COMMIT",
                       help="commit of the engine that ran the sweeps (default: this checkout's HEAD)")
    store.add_argument("--command", dest="store_command", metavar="TEXT",
                       help="the command that ran the sweeps (default: scripts/validate --tier TIER)")
    args = parser.parse_args(argv)
    if args.list_checks:
        return args
    if not args.sweeps:
        parser.error("give at least one SWEEP_OUT_DIR")
    if not args.out:
        parser.error("--out OUT is required")
    args.out_of_scale_reasons = {}
    for item in args.out_of_scale:
        check_id, sep, reason = item.partition("=")
        if not sep or not reason.strip() or check_id not in trends.CHECKS:
            parser.error(f"--out-of-scale {item!r}: expected ID=REASON with ID one of "
                         f"{', '.join(sorted(trends.CHECKS))}")
        args.out_of_scale_reasons[check_id] = reason.strip()
    return args


def main(argv: Sequence[str] | None = None) -> int:
    args = _parse(argv)
    if args.list_checks:
        sys.stdout.write(trends.describe_checks())
        return 0

    def error(message: str) -> int:
        print(f"trends: error: {message}", file=sys.stderr)
        return 2

    sweeps = []
    try:
        for folder in args.sweeps:
            sweeps.append(load_sweep(folder))
    except InputError as problem:
        return error(str(problem))
    names = [s.name for s in sweeps]
    for i, sweep in enumerate(sweeps):
        if names.count(sweep.name) > 1:
            sweep.name = f"{sweep.name}-{i + 1}"

    out_dir = Path(args.out)
    checks_dir = Path(args.checks or os.environ.get("RATCHET_CHECKS_DIR") or out_dir / "checks")
    try:
        out_dir.mkdir(parents=True, exist_ok=True)
    except OSError as problem:
        return error(f"cannot create {out_dir}: {problem}")

    analyses, results, notes, figures = [], [], [], []
    for sweep in sweeps:
        notes += [f"{sweep.name}: {n}" for n in sweep.notes]
        if not sweep.kinds:
            notes.append(f"{sweep.name}: neither container.opening_angle_deg nor thermal.alpha_c "
                         f"is a column of summary.csv: not an angle or ratio sweep, no check run "
                         f"(columns: {', '.join(sweep.parameters) or 'none'})")
        for kind in sweep.kinds:
            a = trends.analyse(sweep, kind, args.tier)
            analyses.append(a)
            results += [trends.out_of_scale(r, args.out_of_scale_reasons.get(r.check_id))
                        for r in a.results]
            notes += [f"{a.case}: {n}" for n in a.notes]
            if args.no_plots:
                continue
            plots.remove_stale(a, out_dir)
            for make in plots.ALL:
                try:
                    made, why = make(a, out_dir)
                except Exception as problem:  # a broken figure must not hide the checks
                    made, why = [], [f"{a.case}: figure {make.__name__} failed: "
                                     f"{type(problem).__name__}: {problem}"]
                    traceback.print_exc(file=sys.stderr)
                figures += made
                notes += why

    meta = {
        "Date": _dt.datetime.now(_dt.timezone.utc).strftime("%Y-%m-%d %H:%M:%S UTC"),
        "Tier": f"{args.tier} ({args.scale or trends.TIER_SCALE[args.tier]})",
        "Sweeps": ", ".join(f"{s.folder} ({'+'.join(s.kinds) or 'not recognized'}, "
                            f"{len(s.completed)}/{len(s.summary)} runs completed)" for s in sweeps),
    }
    total = output.counts(results)
    document = {
        "tier": args.tier,
        "tier_scale": args.scale or trends.TIER_SCALE[args.tier],
        "generated": meta["Date"],
        "sweeps": [{"folder": str(s.folder), "name": s.name, "kinds": s.kinds,
                    "parameters": s.parameters, "runs": len(s.summary),
                    "completed": len(s.completed), "failed_runs": s.failed_runs,
                    "windows": [w.column for w in s.windows]} for s in sweeps],
        "analyses": [output.analysis_json(a) for a in analyses],
        "checks": [r.to_dict() for r in results],
        "counts": total,
        "check_definitions": {k: {"sweep": d.sweep, "check": d.check, "figure": d.figure,
                                  "rule": d.rule, "tolerance": dict(d.params(args.tier)),
                                  "reason": d.reason_for(args.tier)}
                              for k, d in trends.CHECKS.items()},
        "figures": [str(f) for f in figures],
        "notes": notes,
    }
    try:
        checks_path = output.write_checks(checks_dir,
                                          output.checks_file_name(s.folder for s in sweeps),
                                          results)
        write_atomic(out_dir / "trends.json", dumps(document))
        if args.store:
            commit = args.engine_commit or git_commit(REPO_ROOT, short=12)[0] or "unknown"
            runs = ", ".join(f"{s.name}: {len(s.completed)} runs" for s in sweeps)
            record = headline.from_trends(
                document, engine_commit=commit,
                command=args.store_command or f"scripts/validate --tier {args.tier}",
                scale=f"{runs} ({trends.TIER_SCALE[args.tier]})")
            Path(args.store).parent.mkdir(parents=True, exist_ok=True)
            write_atomic(Path(args.store), dumps(record))
        write_atomic(out_dir / "trends.md",
                     output.render_markdown(meta, analyses, results, figures, notes, out_dir))
    except OSError as problem:
        return error(f"cannot write the results: {problem}")

    print(f"trends: tier {args.tier}: {args.scale or trends.TIER_SCALE[args.tier]}")
    if results:
        print(output.terminal_table(results))
    for r in results:
        if r.status == "failed":
            print(f"FAILED {r.case} / {r.check}: {r.reason}")
    for r in results:
        if r.status == "contradicted":
            print(f"CONTRADICTED {r.case} / {r.check}: {r.reason.split('. ')[0]}")
    for r in results:
        if r.status == "unresolved":
            print(f"NOT RESOLVED {r.case} / {r.check}: {r.reason.split('. ')[0]}")
    for r in results:
        if r.status == "skipped":
            print(f"SKIPPED {r.case} / {r.check}: {r.reason.removeprefix('skipped: ')}")
    for note in notes:
        print(f"note: {note}")
    written = f"{checks_path}" if checks_path else "no check line (every check skipped)"
    print(f"trends: wrote {out_dir / 'trends.json'}, {out_dir / 'trends.md'}, "
          f"{len(figures)} figure(s), {written}")
    print(f"trends: {total['passed']} passed, {total['failed']} failed, "
          f"{total['unresolved']} not resolved, {total['contradicted']} contradicted at reduced scale, "
          f"{total['skipped']} skipped")
    return 1 if total["failed"] else 0
