"""Command line of scripts/convection-cells: the convection cells of runs' stage fields
(analysis/cells.py), as OUT/cells.md, OUT/cells.json and OUT/figures/cells.png.

Exit status: 0 written; 2 a bad option, a run folder without a readable stage_fields.csv
or a cycle it does not have (nothing is written then).
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path
from typing import Sequence

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from common.figures import save_figure  # noqa: E402
from common.fsutil import write_atomic  # noqa: E402
from common.jsonsafe import dumps  # noqa: E402

from . import cells, fields  # noqa: E402


def _parse(argv: Sequence[str] | None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(
        prog="convection-cells",
        description="Counts the convection cells of runs' stage fields (stage_fields.csv, "
                    "outputs.displacement.stages): the bands of one sign of the vorticity's "
                    "column circulation C(r) and each one's share, the grain-weighted u_z(r) "
                    "and its sign changes; a band is a cell from a share of "
                    f"{cells.CELL_SHARE:g} (analysis/cells.py says why). Writes OUT/cells.md, "
                    "OUT/cells.json and OUT/figures/cells.png.",
        epilog="Exit status: 0 written; 2 bad option, unreadable stage fields or a missing cycle.")
    parser.add_argument("runs", nargs="+", metavar="[LABEL=]DIR",
                        help="a run folder with stage_fields.csv (a stored campaign run's folder "
                             "will do), optionally labelled")
    parser.add_argument("--cycles", nargs="+", type=int, default=[0], metavar="K",
                        help="the cycles whose heating and cooling are summed (default: 0, the "
                             "first and strongest)")
    parser.add_argument("--each-cycle", action="store_true",
                        help="also count each of the --cycles alone: a second table in cells.md "
                             "and `each_cycle` in cells.json (whether a cell of the summed cycles "
                             "is in every one of them)")
    parser.add_argument("--out", required=True, metavar="OUT", help="output folder")
    return parser.parse_args(argv)


def _runs(specs: Sequence[str], cycles: list[int]) -> list[tuple[str, Path, fields.StageFields]]:
    out = []
    for spec in specs:
        label, _, folder = spec.rpartition("=")
        path = Path(folder)
        label = label or path.name
        try:
            f = fields.read_stage_fields(path)
        except fields.FieldsError as e:
            raise SystemExit(f"convection-cells: {e}")
        if f is None:
            raise SystemExit(f"convection-cells: {path / fields.STAGE_FILE}: no such file (a run with "
                             "outputs.displacement.stages writes it at each end of cooling)")
        missing = [k for k in cycles if k not in set(int(c) for c in f.cycles)]
        if missing:
            raise SystemExit(f"convection-cells: --cycles: {path / fields.STAGE_FILE} has cycles "
                             f"{[int(c) for c in f.cycles]}, not {missing}")
        out.append((label, path, f))
    return out


def _figure(runs, counts: list[cells.CellCount], cycles: list[int]):
    n = len(runs)
    widths = [max(c.radius, 1.0) for c in counts]
    width = min(4.0 + 0.35 * sum(widths), 22.0)
    # The maps keep r and z to scale, so the top row needs the tallest map's height at its
    # share of the width (plus its title), no more.
    tallest = max((width - 3.0) * w / sum(widths) * c.height / max(c.radius, 1.0) for w, c in zip(widths, counts))
    top = min(max(tallest, 1.5), 6.0) + 0.6
    fig = plt.figure(figsize=(width, top + 3.2))
    grid = fig.add_gridspec(2, n, width_ratios=widths, height_ratios=[top, 2.4], hspace=0.3)
    limit = 0.0
    maps = []
    for (label, _, f), c in zip(runs, counts):
        ur, uz, _ = f.cumulative(c.cycles)
        w = fields.vorticity(ur, uz, f.cell)
        maps.append((ur, uz, w))
        if np.isfinite(w).any():
            limit = max(limit, float(np.nanpercentile(np.abs(w), 95)))
    limit = limit or 1.0
    for i, ((label, _, f), c, (ur, uz, w)) in enumerate(zip(runs, counts, maps)):
        ax = fig.add_subplot(grid[0, i])
        extent = (0.0, f.count.shape[2] * f.cell, 0.0, f.count.shape[1] * f.cell)
        image = ax.imshow(w, origin="lower", extent=extent, cmap="RdBu_r", vmin=-limit, vmax=limit,
                          interpolation="nearest")
        rr, zz = np.meshgrid(f.r, f.z)
        ax.quiver(rr, zz, ur, uz, angles="xy", scale_units="xy", scale=None, width=0.004)
        for b in [b for b in c.bands if b.share >= cells.CELL_SHARE][1:]:  # where a cell meets the one inside it
            ax.axvline(b.r_from, color="k", ls=":", lw=1)
        ax.set_xlim(0, c.radius)
        ax.set_ylim(0, c.height)
        ax.set_aspect("equal")
        ax.set_xlabel("r")
        if i == 0:
            ax.set_ylabel("z")
        # Short lines: a paper bed's map is about an inch wide beside a bed of 20,000.
        ax.set_title(f"{label}\n{c.cells} cell{'' if c.cells == 1 else 's'}, coh. {c.coherence:+.2f}", fontsize=8)
    fig.colorbar(image, ax=fig.axes, shrink=0.6, label="vorticity w = du_z/dr - du_r/dz")
    ax = fig.add_subplot(grid[1, :])
    for (label, _, _), c in zip(runs, counts):
        ax.plot(np.array(c.r) / c.radius, c.uz_profile, marker="o", ms=3, label=label)
    ax.axhline(0.0, color="k", lw=0.8)
    ax.set_xlabel("r / bed radius")
    ax.set_ylabel("grain-weighted mean u_z of the column")
    ax.legend(fontsize=8)
    span = f"cycle {cycles[0]}" if len(cycles) == 1 else f"cycles {cycles[0]}-{cycles[-1]}"
    fig.suptitle(f"Displacement over {span} (heating + cooling, arrows) and its vorticity (colour)", fontsize=11)
    return fig


def _shown(value: float, form: str) -> str:
    return format(value, form) if math.isfinite(value) else "n/a"


def _row(label: str, c: cells.CellCount) -> str:
    """One run's columns of the tables after its label."""
    bands = "; ".join(f"{b.r_from:g}-{b.r_to:g}: {b.share:.2f}, {b.sense}" for b in c.bands) or "none"
    return (f"| {label} | {c.radius:g} x {c.height:g} | {c.interior_cells} | {_shown(c.coherence, '+.2f')} "
            f"| {c.cells} | {bands} | {c.uz_sign_changes} | {_shown(c.uz_edge, '.2f')} "
            f"| {_shown(c.wall_band, '.1f')} | {_shown(c.uz_middle, '+.3f')} |")


_HEADER = ("| {run} | bed radius x height | interior cells | coherence | cells | bands (r range: share, sense) "
           "| u_z(r) sign changes | last at r/R | wall band | middle's u_z per cycle |")
_RULE = "|---|---|---|---|---|---|---|---|---|---|"


def _markdown(runs, counts: list[cells.CellCount], cycles: list[int],
              each: dict[str, list[cells.CellCount]] | None = None) -> str:
    lines = [f"# Convection cells over cycle(s) {', '.join(map(str, cycles))}", "",
             f"A band is a run of radial columns whose circulation C(r) has one sign; it is a cell "
             f"from {cells.CELL_SHARE:g} of the field's absolute circulation (scripts/analysis/cells.py "
             "says why). Coherence: the whole bed's circulation over its absolute circulation (+-1: "
             "one sense throughout). u_z(r): the grain-weighted mean vertical displacement of each "
             f"column; its last sign change going out (r/R) begins the band along the wall (its width); "
             f"the middle's u_z: its mean over r/R < {cells.MIDDLE:g}, per cycle.", "",
             _HEADER.format(run="run"), _RULE]
    lines += [_row(label, c) for (label, _, _), c in zip(runs, counts)]
    if each:
        lines += ["", "## Each cycle alone", "",
                  "The same figures of each cycle's heating and cooling by themselves (the middle's "
                  "u_z is then that cycle's).", "", _HEADER.format(run="run, cycle"), _RULE]
        lines += [_row(f"{label}, {c.cycles[0]}", c) for label, per_cycle in each.items() for c in per_cycle]
    lines += ["", "![cells](figures/cells.png)", ""]
    return "\n".join(lines)


def main(argv: Sequence[str] | None = None) -> int:
    try:
        args = _parse(argv)
        cycles = sorted(set(args.cycles))
        runs = _runs(args.runs, cycles)
    except SystemExit as e:
        if isinstance(e.code, str):
            print(e.code, file=sys.stderr)
            return 2
        return 2 if e.code else 0
    counts = [cells.count_cells(f, cycles) for _, _, f in runs]
    each = ({label: [cells.count_cells(f, [k]) for k in cycles] for label, _, f in runs}
            if args.each_cycle else None)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    caption = (f"Convection cells over cycle(s) {', '.join(map(str, cycles))}: "
               + "; ".join(f"{label} {c.cells} cell(s), coherence {c.coherence:+.2f}"
                           for (label, _, _), c in zip(runs, counts)))
    fig = _figure(runs, counts, cycles)
    save_figure(fig, out, "cells", caption)
    plt.close(fig)
    record = {"cycles": cycles, "cell_share": cells.CELL_SHARE,
              "runs": {label: dict(c.to_dict(), folder=str(path)) for (label, path, _), c in zip(runs, counts)}}
    if each:
        record["each_cycle"] = {label: {str(c.cycles[0]): c.to_dict() for c in per_cycle}
                                for label, per_cycle in each.items()}
    write_atomic(out / "cells.json", dumps(record) + "\n")
    write_atomic(out / "cells.md", _markdown(runs, counts, cycles, each))
    for (label, _, _), c in zip(runs, counts):
        print(f"convection-cells: {label}: {c.cells} cell(s), coherence {c.coherence:+.2f}, "
              f"{len(c.bands)} band(s), u_z(r) changes sign {c.uz_sign_changes} time(s)")
    print(f"convection-cells: wrote {out / 'cells.md'}, {out / 'cells.json'}, {out / 'figures' / 'cells.png'}")
    return 0
