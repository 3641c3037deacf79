"""Command line of scripts/wall-stress-depth: Janssen's balance fitted to runs' side-wall
stress profiles (analysis/wall_depth.py), as OUT/wall_depth.md, OUT/wall_depth.json and
OUT/figures/wall_depth.png.

Exit status: 0 written; 2 a bad option, a run folder without a readable wall_profile.csv
or run.json, or a cycle it does not have (nothing is written then).
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

from . import wall_depth  # noqa: E402


def _parse(argv: Sequence[str] | None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(
        prog="wall-stress-depth",
        description="Fits Janssen's balance, σ_w(d) = A (e^{a d} - 1)/a, to the side-wall stress "
                    "profile of each run (wall_profile.csv, outputs.wall_profile_bins) and gives the "
                    "growth rate a with depth (a > 0: the wall friction pushes the grains down, as "
                    "when the container shrinks onto the bed; a < 0: it holds them up, Janssen's "
                    "silo) and a R, the same at every width if one μ_w K sets the balance "
                    "(analysis/wall_depth.py). Writes OUT/wall_depth.md, OUT/wall_depth.json and "
                    "OUT/figures/wall_depth.png.",
        epilog="Exit status: 0 written; 2 bad option, unreadable profile or run.json, or a missing cycle.")
    parser.add_argument("runs", nargs="+", metavar="[LABEL=]DIR",
                        help="a run folder with wall_profile.csv and run.json (a stored campaign run's "
                             "folder will do), optionally labelled")
    parser.add_argument("--cycle", type=int, default=0, metavar="K",
                        help="the cycle whose cold-hold profile is fitted (default 0)")
    parser.add_argument("--out", required=True, metavar="OUT", help="output folder")
    return parser.parse_args(argv)


def _read(specs: Sequence[str], cycle: int) -> list[tuple[str, wall_depth.Profile, wall_depth.DepthFit]]:
    out = []
    for spec in specs:
        label, _, folder = spec.rpartition("=")
        label = label or Path(folder).name
        try:
            profile = wall_depth.read_profile(Path(folder))
            out.append((label, profile, wall_depth.fit_profile(profile, cycle)))
        except wall_depth.ProfileError as e:
            raise SystemExit(f"wall-stress-depth: {e}")
    return out


def by_radius(fits: list[wall_depth.DepthFit]) -> dict[float, dict]:
    """Per container radius: the runs' mean a R and its standard error (None from one run)."""
    groups: dict[float, list[float]] = {}
    for f in fits:
        groups.setdefault(f.radius, []).append(f.rate_times_radius)
    out = {}
    for radius in sorted(groups):
        x = np.array(groups[radius])
        out[radius] = {"runs": len(x), "rate_times_radius": float(x.mean()),
                       "se": float(x.std(ddof=1) / math.sqrt(len(x))) if len(x) > 1 else None}
    return out


def _figure(runs, cycle: int):
    fig, (left, right) = plt.subplots(1, 2, figsize=(11.5, 4.8))
    for label, profile, fit in runs:
        top, bottom, stress = profile.bands(cycle)
        middle = 0.5 * (top + bottom)
        line, = left.plot(stress, middle, "o", ms=4, label=f"{label} (R = {fit.radius:g})")
        depth = np.linspace(0.0, fit.height, 200)
        curve = wall_depth.band_mean(np.maximum(depth - 1e-6, 0.0), depth + 1e-6, fit.amplitude, fit.rate)
        left.plot(curve, depth, "-", color=line.get_color(), lw=1)
    left.invert_yaxis()
    left.set_xlabel("side-wall stress σ_w (cold hold)")
    left.set_ylabel("depth below the bed's top d")
    left.legend(fontsize=7)
    left.set_title("profiles (points) and A (e^{a d} - 1)/a (lines)", fontsize=9)
    radii = [fit.radius for _, _, fit in runs]
    products = [fit.rate_times_radius for _, _, fit in runs]
    errors = [fit.rate_se * fit.radius for _, _, fit in runs]
    right.errorbar(radii, products, yerr=errors, fmt="o", capsize=3)
    right.axhline(0.0, color="k", lw=0.8)
    right.set_xlabel("container bottom radius R")
    right.set_ylabel("a R (one value at every width: the balance's μ_w K)")
    right.set_title("growth rate times radius, each run (fit's standard error)", fontsize=9)
    fig.suptitle(f"Side-wall stress against depth, cycle {cycle}", fontsize=11)
    fig.tight_layout()
    return fig


def _markdown(runs, cycle: int, groups: dict) -> str:
    lines = [f"# Side-wall stress against depth, cycle {cycle}", "",
             "Fitted σ_w(d) = A (e^{a d} - 1)/a to the cold-hold profile's bands (band means; "
             "scripts/analysis/wall_depth.py says why): a > 0 the stress grows faster than the "
             "weight (wall friction pushing the grains down), a < 0 it saturates (Janssen's silo). "
             "± is the fit's standard error.", "",
             "| run | R | H | mean σ_w | A | a | a R | rms residual |", "|---|---|---|---|---|---|---|---|"]
    for label, _, f in runs:
        lines.append(f"| {label} | {f.radius:g} | {f.height:.2f} | {f.mean_stress:.3g} | {f.amplitude:.3g} "
                     f"± {f.amplitude_se:.2g} | {f.rate:+.4f} ± {f.rate_se:.4f} | {f.rate_times_radius:+.3f} "
                     f"± {f.rate_se * f.radius:.3f} | {f.rms_residual:.3g} |")
    lines += ["", "| R | runs | a R, mean over runs |", "|---|---|---|"]
    for radius, g in groups.items():
        se = f" ± {g['se']:.3f}" if g["se"] is not None else " (one run)"
        lines.append(f"| {radius:g} | {g['runs']} | {g['rate_times_radius']:+.3f}{se} |")
    lines += ["", "![wall stress against depth](figures/wall_depth.png)", ""]
    return "\n".join(lines)


def main(argv: Sequence[str] | None = None) -> int:
    try:
        args = _parse(argv)
        runs = _read(args.runs, args.cycle)
    except SystemExit as e:
        if isinstance(e.code, str):
            print(e.code, file=sys.stderr)
            return 2
        return 2 if e.code else 0
    groups = by_radius([fit for _, _, fit in runs])
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    fig = _figure(runs, args.cycle)
    caption = (f"Side-wall stress against depth, cycle {args.cycle}: "
               + "; ".join(f"{label} a R = {fit.rate_times_radius:+.2f}" for label, _, fit in runs))
    save_figure(fig, out, "wall_depth", caption)
    plt.close(fig)
    write_atomic(out / "wall_depth.json", dumps({
        "cycle": args.cycle,
        "runs": {label: dict(fit.to_dict(), folder=str(profile.folder)) for label, profile, fit in runs},
        "by_radius": {f"{r:g}": g for r, g in groups.items()}}) + "\n")
    write_atomic(out / "wall_depth.md", _markdown(runs, args.cycle, groups))
    for label, _, fit in runs:
        print(f"wall-stress-depth: {label}: R {fit.radius:g}, a = {fit.rate:+.4f} ± {fit.rate_se:.4f}, "
              f"a R = {fit.rate_times_radius:+.3f}")
    print(f"wall-stress-depth: wrote {out / 'wall_depth.md'}, {out / 'wall_depth.json'}, "
          f"{out / 'figures' / 'wall_depth.png'}")
    return 0
