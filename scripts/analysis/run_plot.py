"""The command line of scripts/plot-run: one run folder of `ratchet run` as two figures
(.run_figures: the results and the solver diagnostics) and a one-line summary.

The results figure goes to --out (default RUN_DIR/run.png), the solver figure beside it
as <name>-solver<extension> (RUN_DIR/run-solver.png); the extension sets the format
(.png, .pdf, .svg), and another one is refused before anything is read.

Exit status: 0 figures written; 2 bad arguments (an --out that is not .png, .pdf or
.svg, or a folder), an unreadable run folder or an unwritable output (nothing written
then).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Sequence

from common import paths  # noqa: F401  (puts the package `ratchet` on sys.path)
from common.fsutil import figure_format, save_figure_atomic

from ratchet.run_folder import Run, RunInputError, load_run, thermal_phases

from .run_figures import results_figure, solver_figure

PROG = "plot-run"
#: Default figure name in RUN_DIR; the solver figure adds SOLVER_SUFFIX to the stem.
DEFAULT_NAME = "run.png"
SOLVER_SUFFIX = "-solver"


def solver_path(results: Path) -> Path:
    """The solver figure beside the results figure: run.png -> run-solver.png."""
    return results.with_name(results.stem + SOLVER_SUFFIX + results.suffix)


def summary_line(run: Run, results: Path, solver: Path) -> str:
    if run.cap is None:
        capped = "capped n/a (no run.json)"
    else:
        capped = f"{run.capped} capped (of the {len(run.ts)} timeseries rows, those at the cap of {run.cap} sweeps"
        unconverged = ((run.run or {}).get("counters") or {}).get("unconverged_steps")
        capped += f"; run.json: {unconverged} steps unconverged)" if unconverged is not None else ")"
    p_max = "n/a" if run.p_max is None else f"{run.p_max:.4g}"
    state = "completed" if run.complete else "INCOMPLETE"
    return (f"{PROG}: {run.name} {state}: {run.steps} steps, {capped}, "
            f"max residual {run.max_residual:.3g}, P_max {p_max} -> {results} and {solver}")


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog=PROG, description="Plots one run folder of `ratchet run` as two figures: the results "
                               "(wall pressure with the cycle peaks and P_max, and V/V0, from the start "
                               "of cycling, over the thermal phases) and the solver diagnostics (kinetic "
                               "energy, contacts, sweeps, residual, overlap and wall time per step over "
                               "the whole run); prints a one-line summary.",
        epilog="Exit status: 0 figures written; 2 bad arguments, an unreadable run folder "
               "(missing folder, timeseries.csv or column) or an unwritable output.")
    parser.add_argument("run_dir", metavar="RUN_DIR", type=Path, help="folder written by `ratchet run --out`")
    parser.add_argument("--out", metavar="FILE", type=Path,
                        help="the results figure; its extension sets the format: .png, .pdf or .svg "
                             f"(default: RUN_DIR/{DEFAULT_NAME}); the solver figure goes beside it as "
                             f"NAME{SOLVER_SUFFIX}.EXT (default: RUN_DIR/run{SOLVER_SUFFIX}.png)")
    args = parser.parse_args(argv)
    out = args.out or args.run_dir / DEFAULT_NAME
    try:
        figure_format(out)
    except ValueError as e:
        parser.error(f"argument --out: {e}")
    for path in (out, solver_path(out)):
        if path.is_dir():
            parser.error(f"argument --out: {path} is a folder")
    try:
        run = load_run(args.run_dir)
    except RunInputError as e:
        print(f"{PROG}: error: {e}", file=sys.stderr)
        return 2
    phases = thermal_phases(run)
    figures = ((out, results_figure(run, phases)), (solver_path(out), solver_figure(run, phases)))
    for path, fig in figures:
        try:
            save_figure_atomic(fig, path, dpi=120)
        except OSError as e:
            print(f"{PROG}: error: cannot write {path}: {e}", file=sys.stderr)
            return 2
    print(summary_line(run, out, solver_path(out)))
    return 0
