"""Command line of scripts/wall-stress-depth: Janssen's balance fitted to runs' side-wall
stress profiles and to their peak pressures against the width (analysis/wall_depth.py),
as OUT/wall_depth.md, OUT/wall_depth.json and OUT/figures/wall_depth.png.

Exit status: 0 written; 2 a bad option, a run folder without a readable cycles.csv or
run.json, a broken wall_profile.csv, or a cycle it does not have (nothing is written then).
"""

from __future__ import annotations

import argparse
import math
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Sequence

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from scipy import stats  # noqa: E402

from common.figures import save_figure  # noqa: E402
from common.fsutil import write_atomic  # noqa: E402
from common.jsonsafe import dumps  # noqa: E402

from . import wall_depth  # noqa: E402


@dataclass
class Run:
    label: str
    folder: Path
    radius: float
    angle: float                                  # the cone's opening angle, degrees
    peak: float                                   # the cycle's peak pressure (cycles.csv)
    wall_friction: float | None = None            # materials.wall_friction (None: not in run.json)
    seed: int | None = None
    profile: wall_depth.Profile | None = None     # None: the run wrote no wall_profile.csv
    fit: wall_depth.DepthFit | None = None


def _parse(argv: Sequence[str] | None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(
        prog="wall-stress-depth",
        description="Fits Janssen's balance, σ_w(d) = A (e^{a d} - 1)/a, to the side-wall stress "
                    "profile of each run (wall_profile.csv, outputs.wall_profile_bins) and gives the "
                    "growth rate a with depth (a > 0: the wall friction pushes the grains down, as "
                    "when the container shrinks onto the bed; a < 0: it holds them up, Janssen's "
                    "silo) and a R, the same at every width if one μ_w K sets the balance. With beds "
                    "of 3 or more widths, also fits the balance's mean wall pressure A H g(c H / R) "
                    "to the cycle's peak pressures (cycles.csv), a second measure of c = a R "
                    "(analysis/wall_depth.py). Writes OUT/wall_depth.md, OUT/wall_depth.json and "
                    "OUT/figures/wall_depth.png.",
        epilog="Exit status: 0 written; 2 bad option, unreadable cycles.csv, run.json or profile, "
               "or a missing cycle.")
    parser.add_argument("runs", nargs="+", metavar="[LABEL=]DIR",
                        help="a run folder with cycles.csv and run.json, and wall_profile.csv for the "
                             "depth fit (a stored campaign run's folder will do), optionally labelled")
    parser.add_argument("--cycle", type=int, default=0, metavar="K",
                        help="the cycle whose cold-hold profile and peak pressure are used (default 0)")
    parser.add_argument("--height", type=float, metavar="H",
                        help="the bed height of the width fit (default: the mean of the profiles' "
                             "heights; the beds are meant to share one height)")
    parser.add_argument("--pair-angle", type=float, default=6.0, metavar="DEG",
                        help="the opening angle paired with 0 deg in the wall-friction test (default 6): runs at "
                             "a second wall friction (materials.wall_friction) at 0 deg and at DEG give per "
                             "friction the ratio of the peaks, μ and K, and the ratio the reference friction's "
                             "K predicts")
    parser.add_argument("--out", required=True, metavar="OUT", help="output folder")
    args = parser.parse_args(argv)
    if args.height is not None and not (math.isfinite(args.height) and args.height > 0):
        parser.error(f"--height: expected a positive bed height, got {args.height}")
    if not (0 < args.pair_angle < 90):
        parser.error(f"--pair-angle: expected an opening angle between 0 and 90 degrees, got {args.pair_angle}")
    return args


def _read(specs: Sequence[str], cycle: int) -> list[Run]:
    out = []
    for spec in specs:
        label, _, name = spec.rpartition("=")
        folder = Path(name)
        try:
            scene = wall_depth.read_scene(folder)
            run = Run(label=label or folder.name, folder=folder, radius=scene.radius, angle=scene.angle,
                      peak=wall_depth.read_peak(folder, cycle), wall_friction=scene.wall_friction,
                      seed=scene.seed)
            if (folder / wall_depth.PROFILE_FILE).exists():
                run.profile = wall_depth.read_profile(folder, scene.radius)  # run.json read once
                run.fit = wall_depth.fit_profile(run.profile, cycle)
        except wall_depth.ProfileError as e:
            raise SystemExit(f"wall-stress-depth: {e}")
        out.append(run)
    return out


def _mean_se(x) -> tuple[float, float | None]:
    x = np.asarray(x, float)
    return float(x.mean()), (float(x.std(ddof=1) / math.sqrt(len(x))) if len(x) > 1 else None)


def by_radius(fits: list[wall_depth.DepthFit]) -> dict[float, dict]:
    """Per container radius: the runs' mean a R and its standard error (None from one run)."""
    groups: dict[float, list[float]] = {}
    for f in fits:
        groups.setdefault(f.radius, []).append(f.rate_times_radius)
    out = {}
    for radius in sorted(groups):
        mean, se = _mean_se(groups[radius])
        out[radius] = {"runs": len(groups[radius]), "rate_times_radius": mean, "se": se}
    return out


def profiles_c(fits: list[wall_depth.DepthFit]) -> tuple[float, float | None]:
    """The mean of a R over the profiled runs and its standard error (None from one run)."""
    return _mean_se([f.rate_times_radius for f in fits])


def reference_friction(runs: list[Run]) -> float | None:
    """The wall friction of the width fit: that of the upright runs spanning 3 or more
    radii (one such friction; None when the runs say none)."""
    spans = {}
    for r in runs:
        if r.angle == 0:
            spans.setdefault(r.wall_friction, set()).add(r.radius)
    wide = [f for f, radii in spans.items() if len(radii) >= 3]
    if len(wide) > 1:
        raise SystemExit(f"wall-stress-depth: the upright runs span 3 or more radii at the wall frictions "
                         f"{sorted(wide)}; the width fit takes one: give the widths at one friction")
    return wide[0] if wide else (next(iter(spans)) if len(spans) == 1 else None)


def _width_fit(runs: list[Run], height: float | None, friction: float | None) -> wall_depth.WidthFit | None:
    # The width relation is of upright cylinders, at one wall friction.
    runs = [r for r in runs if r.angle == 0 and r.wall_friction == friction]
    if len({r.radius for r in runs}) < 3:
        return None
    heights = [r.fit.height for r in runs if r.fit is not None]
    if height is None and not heights:
        raise SystemExit("wall-stress-depth: --height: no run has a profile to take the bed height from; "
                         "give it")
    try:
        return wall_depth.fit_widths([r.radius for r in runs], [r.peak for r in runs],
                                     height if height is not None else float(np.mean(heights)))
    except wall_depth.ProfileError as e:
        raise SystemExit(f"wall-stress-depth: {e}")


def _angle_fit(runs: list[Run], widths: wall_depth.WidthFit | None, friction: float | None) -> wall_depth.AngleFit | None:
    """The angles' fit at the one radius of the runs with an opening angle, c from the widths
    (the runs at the width fit's wall friction)."""
    runs = [r for r in runs if r.wall_friction == friction]
    leaning = [r for r in runs if r.angle != 0]
    if not leaning:
        return None
    radii = sorted({r.radius for r in leaning})
    if len(radii) > 1:
        raise SystemExit(f"wall-stress-depth: the runs with an opening angle have the radii {radii}; the angle "
                         "fit needs them at one radius")
    if widths is None:
        raise SystemExit("wall-stress-depth: the angle fit takes c from the width fit: give runs at 0 deg of "
                         "3 or more radii")
    group = [r for r in runs if r.radius == radii[0]]
    if len({r.angle for r in group}) < 3:
        return None  # two angles fix no curve of two parameters (the wall-friction test may pair them)
    try:
        return wall_depth.fit_angles([r.angle for r in group], [r.peak for r in group], radii[0],
                                     widths.height, widths.c)
    except wall_depth.ProfileError as e:
        raise SystemExit(f"wall-stress-depth: {e}")


def friction_test(runs: list[Run], widths: wall_depth.WidthFit | None, angle: float,
                  reference: float | None) -> dict | None:
    """Per wall friction, the realizations run at 0 deg and at `angle` at one radius: their
    peaks, the ratio of the mean peaks, and each realization's μ_w and K (A and H of the
    width fit held); against the reference friction's K, the ratio the form predicts from
    each other friction's 0 deg peak. None unless runs at a second wall friction are given."""
    others = [r for r in runs if r.wall_friction != reference and r.angle in (0.0, angle)]
    if not others:
        return None
    if widths is None:
        raise SystemExit("wall-stress-depth: the wall-friction test holds A from the width fit: give runs at "
                         "0 deg of 3 or more radii")
    radii = sorted({r.radius for r in others})
    if len(radii) > 1:
        raise SystemExit(f"wall-stress-depth: the runs at other wall frictions have the radii {radii}; the "
                         "test needs them at one radius")
    radius, height, amplitude = radii[0], widths.height, widths.amplitude
    groups = {}
    labels = {}
    for r in runs:
        if r.radius == radius and r.angle in (0.0, angle):
            key = (r.wall_friction, r.angle, r.seed)
            if key in labels:
                raise SystemExit(f"wall-stress-depth: {labels[key]} and {r.label} are both seed {r.seed} at the wall "
                                 f"friction {r.wall_friction} and {r.angle:g} deg; the test pairs one run per seed")
            labels[key] = r.label
            groups.setdefault(r.wall_friction, {}).setdefault(r.angle, {})[r.seed] = r.peak
    out = []
    for friction in sorted(groups, key=lambda f: (f is None, f)):
        at = groups[friction]
        seeds = sorted(set(at.get(0.0, {})) & set(at.get(angle, {})), key=str)
        if not seeds:
            continue
        p0 = [at[0.0][k] for k in seeds]
        pt = [at[angle][k] for k in seeds]
        pairs = [wall_depth.friction_pair(wall_depth.invert_c(a, radius, height, amplitude),
                                          wall_depth.invert_c(b, radius, height, amplitude), angle)
                 for a, b in zip(p0, pt)]
        (m0, s0), (mt, st) = _mean_se(p0), _mean_se(pt)
        ratio = mt / m0
        ratio_se = ratio * math.hypot(st / mt, s0 / m0) if s0 is not None and st is not None else None
        mu, mu_se = _mean_se([m for m, _ in pairs])
        k, k_se = _mean_se([k for _, k in pairs])
        out.append({"wall_friction": friction, "seeds": seeds, "peaks_0": p0, "peaks_theta": pt,
                    "mu_each": [m for m, _ in pairs], "k_each": [k for _, k in pairs],
                    "peak_0": m0, "peak_0_se": s0, "peak_theta": mt, "peak_theta_se": st,
                    "ratio": ratio, "ratio_se": ratio_se, "mu": mu, "mu_se": mu_se, "k": k, "k_se": k_se})
    ref = next((g for g in out if g["wall_friction"] == reference), None)
    for g in out:
        g.update(predicted_ratio=None, predicted_se=None, z=None, k_p=None)
        if ref is None or g is ref or ref["k_se"] is None:
            continue

        def ratio_at(k, p0):
            return wall_depth.predicted_ratio(p0, angle, k, radius, height, amplitude)

        predicted = ratio_at(ref["k"], g["peak_0"])
        # One standard error of K and of the 0 deg mean, propagated by finite differences.
        dk = ratio_at(ref["k"] + ref["k_se"], g["peak_0"]) - predicted
        dp = ratio_at(ref["k"], g["peak_0"] + g["peak_0_se"]) - predicted if g["peak_0_se"] is not None else 0.0
        g["predicted_ratio"], g["predicted_se"] = predicted, math.hypot(dk, dp)
        if g["ratio_se"] is not None:
            g["z"] = (g["ratio"] - predicted) / math.hypot(g["ratio_se"], g["predicted_se"])
            g["k_p"] = float(stats.ttest_ind(g["k_each"], ref["k_each"], equal_var=False).pvalue)
    return {"angle": angle, "radius": radius, "height": height, "amplitude": amplitude,
            "reference": reference, "groups": out}


def _figure(runs: list[Run], cycle: int, widths: wall_depth.WidthFit | None, angles: wall_depth.AngleFit | None,
            frictions: dict | None = None, friction: float | None = None):
    panels = 3 + (angles is not None) + (frictions is not None)
    fig, axes = plt.subplots(1, panels, figsize=(5.3 * panels, 4.8))
    left, middle, right = axes[:3]
    fitted = [r for r in runs if r.fit is not None]
    for r in fitted:
        top, bottom, stress = r.profile.bands(cycle)
        line, = left.plot(stress, 0.5 * (top + bottom), "o", ms=4, label=f"{r.label} (R = {r.radius:g})")
        depth = np.linspace(1e-6, r.fit.height, 200)
        # The form itself at each depth (the band mean of a vanishing band).
        curve = wall_depth.band_mean(depth - 1e-6, depth + 1e-6, r.fit.amplitude, r.fit.rate)
        left.plot(curve, depth, "-", color=line.get_color(), lw=1)
    left.invert_yaxis()
    left.set_xlabel("side-wall stress σ_w (cold hold)")
    left.set_ylabel("depth below the bed's top d")
    if fitted:
        left.legend(fontsize=7)
    left.set_title("profiles (points) and A (e^{a d} - 1)/a (lines)", fontsize=9)
    middle.errorbar([r.radius for r in fitted], [r.fit.rate_times_radius for r in fitted],
                    yerr=[r.fit.rate_se * r.radius for r in fitted], fmt="o", capsize=3, label="a R, each profile")
    if widths is not None:
        middle.axhspan(widths.c - widths.c_se, widths.c + widths.c_se, color="C1", alpha=0.25,
                       label=f"c from the peaks: {widths.c:.2f} ± {widths.c_se:.2f}")
    middle.axhline(0.0, color="k", lw=0.8)
    middle.set_xlabel("container bottom radius R")
    middle.set_ylabel("a R = 2 μ_w K")
    middle.legend(fontsize=7)
    middle.set_title("growth rate times radius (fit's standard error)", fontsize=9)
    upright = [r for r in runs if r.angle == 0 and r.wall_friction == friction]
    right.plot([r.radius for r in upright], [r.peak for r in upright], "o", label="each run at 0 deg")
    if widths is not None:
        grid = np.linspace(min(widths.radii) * 0.8, max(widths.radii) * 1.2, 200)
        right.plot(grid, wall_depth.mean_pressure(grid, widths.height, widths.amplitude, widths.c), "-",
                   label=f"A H g(c H / R), H = {widths.height:.2f}")
    right.set_xscale("log")
    right.set_yscale("log")
    right.set_xlabel("container bottom radius R")
    right.set_ylabel(f"peak wall pressure of cycle {cycle}")
    right.legend(fontsize=7)
    right.set_title("peak pressure against the width", fontsize=9)
    if angles is not None:
        ax = axes[3]
        ax.plot(angles.angles, angles.pressures, "o", label=f"each run at R = {angles.radius:g}")
        grid = np.linspace(0.0, max(angles.angles) * 1.1, 200)
        ax.plot(grid, wall_depth.angle_pressure(grid, angles.radius, angles.height, angles.amplitude, angles.c,
                                                angles.mu), "-",
                label=f"friction μ cos θ - sin θ, μ = {angles.mu:.2f} ± {angles.mu_se:.2f}")
        ax.set_yscale("log")
        ax.set_xlabel("opening angle θ (degrees)")
        ax.set_ylabel(f"peak wall pressure of cycle {cycle}")
        ax.legend(fontsize=7)
        ax.set_title(f"peak pressure against the angle (c = {angles.c:.2f} held)", fontsize=9)
    if frictions is not None:
        ax = axes[-1]
        groups = [g for g in frictions["groups"] if g["wall_friction"] is not None]
        ax.errorbar([g["wall_friction"] for g in groups], [g["ratio"] for g in groups],
                    yerr=[g["ratio_se"] or 0.0 for g in groups], fmt="o", capsize=3, label="ratio of the mean peaks")
        shown = [g for g in groups if g["predicted_ratio"] is not None]
        ax.errorbar([g["wall_friction"] for g in shown], [g["predicted_ratio"] for g in shown],
                    yerr=[g["predicted_se"] for g in shown], fmt="s", mfc="none", capsize=3,
                    label="the form at the reference's K")
        if frictions["angle"] == 6.0:
            ax.axhline(0.5, color="grey", ls=":", label="the paper's halving at 6 deg")
        ax.set_xlabel("the wall's friction (materials.wall_friction)")
        ax.set_ylabel(f"P({frictions['angle']:g} deg) / P(0 deg), cycle {cycle}")
        ax.legend(fontsize=7)
        ax.set_title(f"the peak ratio against the wall's friction (R = {frictions['radius']:g})", fontsize=9)
    fig.suptitle(f"Side-wall stress against depth and width, cycle {cycle}", fontsize=11)
    fig.tight_layout()
    return fig


def _markdown(runs: list[Run], cycle: int, widths: wall_depth.WidthFit | None,
              angles: wall_depth.AngleFit | None, frictions: dict | None = None,
              friction: float | None = None) -> str:
    lines = [f"# Side-wall stress against depth and width, cycle {cycle}", "",
             "σ_w(d) = A (e^{a d} - 1)/a fitted to each cold-hold profile's bands (band means; "
             "scripts/analysis/wall_depth.py says why): a > 0 the stress grows faster than the "
             "weight (wall friction pushing the grains down), a < 0 it saturates (Janssen's silo). "
             "± is the fit's standard error.", "",
             "| run | R | θ | peak pressure | H | mean σ_w (cold hold) | A | a | a R |",
             "|---|---|---|---|---|---|---|---|---|"]
    for r in runs:
        if r.fit is None:
            lines.append(f"| {r.label} | {r.radius:g} | {r.angle:g} | {r.peak:.4g} | no profile | | | | |")
            continue
        f = r.fit
        lines.append(f"| {r.label} | {f.radius:g} | {r.angle:g} | {r.peak:.4g} | {f.height:.2f} | {f.mean_stress:.3g} | "
                     f"{f.amplitude:.3g} ± {f.amplitude_se:.2g} | {f.rate:+.4f} ± {f.rate_se:.4f} | "
                     f"{f.rate_times_radius:+.3f} ± {f.rate_se * f.radius:.3f} |")
    fits = [r.fit for r in runs if r.fit is not None]
    if fits:
        lines += ["", "| R | runs | a R, mean over runs |", "|---|---|---|"]
        for radius, g in by_radius(fits).items():
            se = f" ± {g['se']:.3f}" if g["se"] is not None else " (one run)"
            lines.append(f"| {radius:g} | {g['runs']} | {g['rate_times_radius']:+.3f}{se} |")
    if widths is not None:
        lines += ["", f"**Peak pressure against the width**: P(R) = A H g(c H / R) fitted to the "
                  f"{len(widths.radii)} runs' peaks (least squares of log P; H = {widths.height:.2f}): "
                  f"c = {widths.c:.3f} ± {widths.c_se:.3f}, A = {widths.amplitude:.3g} ± {widths.amplitude_se:.2g}."]
        if fits:
            mean, se = profiles_c(fits)
            spread = f" ± {se:.3f}" if se is not None else " (one run)"
            lines.append(f"The profiles' a R: {mean:.3f}{spread} (mean over {len(fits)} runs).")
        lines += ["", "| run | R | peak | A H g(c H / R) | ratio |", "|---|---|---|---|---|"]
        upright = [r for r in runs if r.angle == 0 and r.wall_friction == friction]
        for r, predicted in zip(upright, widths.predicted):
            lines.append(f"| {r.label} | {r.radius:g} | {r.peak:.4g} | {predicted:.4g} | {r.peak / predicted:.2f} |")
    if angles is not None:
        lines += ["", f"**Peak pressure against the opening angle** at R = {angles.radius:g}: the friction of the "
                  f"balance μ cos θ - sin θ (the leaning wall's normal stress pushes the grains up), "
                  f"P(θ) = A H g(c (cos θ - sin θ / μ) H / R) with the width fit's c = {angles.c:.3f} held, fitted "
                  f"to the {len(angles.angles)} runs' peaks (least squares of log P): μ = {angles.mu:.3f} ± "
                  f"{angles.mu_se:.3f}, A = {angles.amplitude:.3g} ± {angles.amplitude_se:.2g}. The cone's widening "
                  "with height is left out.", "",
                  "| θ | runs | mean peak | the fit's | ratio |", "|---|---|---|---|---|"]
        for theta in sorted(set(angles.angles)):
            at = [k for k, a in enumerate(angles.angles) if a == theta]
            mean = float(np.mean([angles.pressures[k] for k in at]))
            lines.append(f"| {theta:g} | {len(at)} | {mean:.4g} | {angles.predicted[at[0]]:.4g} | "
                         f"{mean / angles.predicted[at[0]]:.2f} |")
    if frictions is not None:
        lines += _friction_markdown(frictions)
    lines += ["", "![wall stress against depth and width](figures/wall_depth.png)", ""]
    return "\n".join(lines)


def _pm(value: float | None, se: float | None, digits: str = ".3g") -> str:
    """value ± se in the given format ("(one run)" without a standard error)."""
    if value is None:
        return ""
    return f"{value:{digits}}" + (f" ± {se:{digits}}" if se is not None else " (one run)")


def _friction_markdown(t: dict) -> list[str]:
    angle = t["angle"]
    lines = ["", f"**Peak pressure against the wall's friction** at R = {t['radius']:g}, 0 and {angle:g} deg: with "
             f"A = {t['amplitude']:.3g} and H = {t['height']:.2f} of the width fit held, each realization's two peaks "
             f"give c(0) = 2 μ K and c({angle:g}) = 2 K (μ cos θ − sin θ), hence μ and K (mean ± SE over the "
             f"realizations). The form with one K for the bed predicts the ratio P({angle:g})/P(0) from the 0 deg "
             f"peak; the reference is the width fit's wall friction ({t['reference']}).", "",
             f"| wall friction | realizations | P(0) | P({angle:g}) | ratio | μ | K | ratio at the reference K | z | K against the reference (Welch p) |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for g in t["groups"]:
        predicted = (f"{g['predicted_ratio']:.3f} ± {g['predicted_se']:.3f}" if g["predicted_ratio"] is not None
                     else ("(reference)" if g["wall_friction"] == t["reference"] else ""))
        z = "" if g["z"] is None else f"{g['z']:+.1f}"
        k_p = "" if g["k_p"] is None else f"{g['k_p']:.2f}"
        lines.append(f"| {g['wall_friction']} | {len(g['seeds'])} | {_pm(g['peak_0'], g['peak_0_se'])} | "
                     f"{_pm(g['peak_theta'], g['peak_theta_se'])} | {_pm(g['ratio'], g['ratio_se'], '.3f')} | "
                     f"{_pm(g['mu'], g['mu_se'], '.3f')} | {_pm(g['k'], g['k_se'], '.2f')} | {predicted} | "
                     f"{z} | {k_p} |")
    for g in t["groups"]:
        if g["z"] is None:
            continue
        verdict = ("within two standard errors of the form's prediction" if abs(g["z"]) < 2 else
                   "more than two standard errors from the form's prediction: the form with one K does not "
                   "hold at this friction")
        lines.append("")
        lines.append(f"At the wall friction {g['wall_friction']} ({len(g['seeds'])} realizations): the ratio "
                     f"{g['ratio']:.3f} ± {g['ratio_se']:.3f} is {verdict} ({g['predicted_ratio']:.3f} ± "
                     f"{g['predicted_se']:.3f}, z = {g['z']:+.1f}); its K {_pm(g['k'], g['k_se'], '.2f')} against "
                     f"the reference's (Welch p = {g['k_p']:.2f}).")
    return lines


def main(argv: Sequence[str] | None = None) -> int:
    try:
        args = _parse(argv)
        runs = _read(args.runs, args.cycle)
        friction = reference_friction(runs)  # the width and angle fits' wall friction
        widths = _width_fit(runs, args.height, friction)
        angles = _angle_fit(runs, widths, friction)
        frictions = friction_test(runs, widths, args.pair_angle, friction)
    except SystemExit as e:
        if isinstance(e.code, str):
            print(e.code, file=sys.stderr)
            return 2
        return 2 if e.code else 0
    fits = [r.fit for r in runs if r.fit is not None]
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    fig = _figure(runs, args.cycle, widths, angles, frictions, friction)
    caption = (f"Side-wall stress against depth and width, cycle {args.cycle}: "
               + "; ".join(f"{r.label} (R {r.radius:g}) peak {r.peak:.3g}"
                           + (f", a R = {r.fit.rate_times_radius:+.2f}" if r.fit else "") for r in runs)
               + (f"; c from the peaks {widths.c:.2f} ± {widths.c_se:.2f}" if widths else "")
               + (f"; μ from the angles {angles.mu:.2f} ± {angles.mu_se:.2f}" if angles else "")
               + ("; the 0 / " + f"{frictions['angle']:g} deg peak ratio at the wall frictions "
                  + ", ".join(f"{g['wall_friction']}: {g['ratio']:.2f}" for g in frictions["groups"])
                  if frictions else ""))
    save_figure(fig, out, "wall_depth", caption)
    plt.close(fig)
    write_atomic(out / "wall_depth.json", dumps({
        "cycle": args.cycle,
        "runs": {r.label: {"folder": str(r.folder), "radius": r.radius, "angle": r.angle, "peak_pressure": r.peak,
                           "profile": r.fit.to_dict() if r.fit else None} for r in runs},
        "by_radius": {f"{k:g}": g for k, g in by_radius(fits).items()},
        "widths": widths.to_dict() if widths else None,
        "angles": angles.to_dict() if angles else None,
        "wall_friction": frictions}) + "\n")
    write_atomic(out / "wall_depth.md", _markdown(runs, args.cycle, widths, angles, frictions, friction))
    for r in runs:
        text = (f"a = {r.fit.rate:+.4f} ± {r.fit.rate_se:.4f}, a R = {r.fit.rate_times_radius:+.3f}"
                if r.fit else "no profile")
        print(f"wall-stress-depth: {r.label}: R {r.radius:g}, peak {r.peak:.4g}, {text}")
    if widths is not None:
        print(f"wall-stress-depth: peaks against the width: c = {widths.c:.3f} ± {widths.c_se:.3f}")
    if angles is not None:
        print(f"wall-stress-depth: peaks against the angle: mu = {angles.mu:.3f} ± {angles.mu_se:.3f}")
    for g in (frictions or {}).get("groups", []):
        test = (f", the form predicts {g['predicted_ratio']:.3f} ± {g['predicted_se']:.3f}"
                + (f" (z = {g['z']:+.1f})" if g["z"] is not None else " (one run: no z)")
                if g["predicted_ratio"] is not None else "")
        print(f"wall-stress-depth: wall friction {g['wall_friction']}: ratio {_pm(g['ratio'], g['ratio_se'], '.3f')}, "
              f"K {_pm(g['k'], g['k_se'], '.2f')}{test}")
    print(f"wall-stress-depth: wrote {out / 'wall_depth.md'}, {out / 'wall_depth.json'}, "
          f"{out / 'figures' / 'wall_depth.png'}")
    return 0
