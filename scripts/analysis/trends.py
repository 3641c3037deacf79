"""The paper's trends as checks: definitions (one table), evaluation, records.

Every acceptance rule and tolerance lives in CHECKS below, with the reason for its
value per tier; the evaluation code reads its numbers only from there. A check
yields a CheckResult: "passed", "failed", "unresolved" or "skipped" (not enough
data: never a pass). "unresolved" is a measurement within the tolerance that still
cannot show the paper's statement, because the scatter of the realizations is wider
than the effect (docs/trends.md): it is reported as "not resolved", never as PASS,
and does not fail the run. Passed, failed and unresolved checks become JSON lines in
the format of validation/support/check_record.hpp (scripts/README.md; unresolved
ones with "resolved": false); skipped ones are listed in trends.md/trends.json and on
the terminal only, since that format has no skipped state.

Which data each check uses (docs/trends.md):
- slopes and their standard errors: the linear fit over all completed realizations
  (each run one point, unweighted), so that SE reflects the scatter between
  realizations and the lack of fit;
- R^2: the fit of the realization means weighted by the number of realizations n
  (the same coefficients as the fit over all realizations, the R^2 of the curve
  through the means that the paper's Fig. 3d shows).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Mapping

import numpy as np
import pandas as pd

from . import fits
from .inputs import ANGLE, RATIO, Sweep, end_of_cycle_volumes, run_dir

TIERS = ("quick", "standard", "paper")

#: What each tier means for the data (docs/method.md s. 11); printed in the reports.
TIER_SCALE = {
    "quick": "CI scale: a small bed, a few cycles, typically one realization per point; "
             "the steady state is not reached, so trends are checked in sign and roughly",
    "standard": "reduced scale (fewer particles, cycles and realizations than the paper, "
                "about 10 minutes on 2 cores); trends checked with loosened tolerances",
    "paper": "the paper's scale: 2000 particles, 20 cycles, 5 realizations per point",
}

#: Reference values of the paper: the fixed ratio of the angle study and the fixed
#: angle of the ratio study (used to slice a grid sweep), and the angles of the
#: "6 deg halves the peak pressure" statement.
PAPER_RATIO = 10.0
PAPER_ANGLE = 0.0
HALVING_ANGLES = (0.0, 6.0)


@dataclass(frozen=True)
class CheckDef:
    id: str
    sweep: str                 # "angle" or "ratio"
    check: str                 # name in the tables; {window} / {point} filled in
    figure: str                # the paper figure or statement it mirrors
    rule: str                  # the acceptance rule, in the symbols of `tolerance`
    tolerance: Mapping[str, Mapping[str, float]]   # tier -> named tolerance values
    reason: str                # the physics: why this trend is expected
    tier_reasons: Mapping[str, str]                # tier -> why the tolerance has its value

    def params(self, tier: str) -> Mapping[str, float]:
        return self.tolerance[tier]

    def reason_for(self, tier: str) -> str:
        return f"{self.reason} [{tier} tier: {self.tier_reasons[tier]}]"


#: A flat trend is shown only if a change of this fraction of the mean across the swept
#: range would have been detected: "practically independent" (Fig. 7a) means well
#: within the realizations' spread, which is of this order at the paper's scale.
FLAT_RESOLUTION = 0.25

_K_MONOTONE = {"quick": {"k": 1.0}, "standard": {"k": 2.0}, "paper": {"k": 2.0}}
_K_MONOTONE_REASONS = {
    "quick": "k = 1: typically one realization per point and a bed short of the steady "
             "state; only the sign of the trend is expected, with one standard error of margin",
    "standard": "k = 2: the slope differs from zero at about 97.5 % one-sided confidence "
                "for a normal estimate; fewer realizations than the paper widen SE, not k",
    "paper": "k = 2: the slope differs from zero at about 97.5 % one-sided confidence "
             "for a normal estimate (5 realizations per point)",
}

CHECKS: dict[str, CheckDef] = {c.id: c for c in (
    CheckDef(
        id="pmax_theta_slope", sweep="angle", check="P_max slope vs theta_c",
        figure="Fig. 3b",
        rule="linear fit of P_max over all completed realizations: slope + k SE(slope) < 0 "
             "(quadratic fit reported); needs >= 2 angles and >= 3 runs",
        tolerance=_K_MONOTONE,
        reason="paper: the steady-state peak pressure decreases with the opening angle "
               "theta_c, close to linearly (Fig. 3b)",
        tier_reasons=_K_MONOTONE_REASONS),
    CheckDef(
        id="pmax_ratio_6_0", sweep="angle", check="P_max(6 deg)/P_max(0 deg)",
        figure="Results text, Fig. 3b",
        rule="R = mean P_max(6 deg) / mean P_max(0 deg): |R - target| <= max(floor, k sigma_R), "
             "sigma_R by first-order propagation of the realization standard errors; "
             "needs runs at 0 and 6 deg",
        tolerance={"quick": {"target": 0.5, "floor": 0.35, "k": 2.0},
                   "standard": {"target": 0.5, "floor": 0.25, "k": 2.0},
                   "paper": {"target": 0.5, "floor": 0.15, "k": 2.0}},
        reason="paper: 'a conical container with an opening angle of only 6 deg halves the "
               "peak pressure compared to a cylindrical container'",
        tier_reasons={
            "quick": "band 0.15-0.85 (floor 0.35): a CI-scale bed is short of the steady "
                     "state and has a small container-to-particle size ratio; the check asks "
                     "only that the cone clearly lowers the peak pressure",
            "standard": "floor 0.25: fewer particles and cycles change how the wall stress "
                        "builds up; a ratio clearly below 1 and near one half is expected",
            "paper": "floor 0.15 (band 0.35-0.65): 'halves' is a statement read off a figure "
                     "of 5-realization means, not a fitted number with an error; 2 sigma_R "
                     "widens the band when the realizations scatter more than that"}),
    CheckDef(
        id="pmax_ratio_slope", sweep="ratio", check="P_max slope vs alpha_c/alpha_p",
        figure="Fig. 3d",
        rule="linear fit of P_max over all completed realizations: slope - k SE(slope) > 0; "
             "needs >= 2 ratios and >= 3 runs",
        tolerance=_K_MONOTONE,
        reason="paper: the peak pressure increases with alpha_c/alpha_p, the container strain "
               "per cycle and so the energy input (Fig. 3d)",
        tier_reasons=_K_MONOTONE_REASONS),
    CheckDef(
        id="pmax_ratio_quadratic_r2", sweep="ratio", check="P_max quadratic R^2 vs alpha_c/alpha_p",
        figure="Fig. 3d",
        rule="quadratic fit of the realization means (weighted by their count n): R^2 >= r2_min; "
             "needs >= 4 ratios (a quadratic through 3 points has R^2 = 1 whatever the data)",
        tolerance={"quick": {"r2_min": 0.8}, "standard": {"r2_min": 0.9},
                   "paper": {"r2_min": 0.95}},
        reason="paper: P_max(alpha_c/alpha_p) 'is fitted well by a quadratic function' (Fig. 3d)",
        tier_reasons={
            "quick": "0.8: typically single realizations, so each point carries the full "
                     "realization scatter",
            "standard": "0.9: means of a few realizations still scatter about the curve",
            "paper": "0.95: the paper gives no number for 'fitted well'; 0.95 is our reading "
                     "of it for means of 5 realizations"}),
    CheckDef(
        id="wrms_theta_flat", sweep="angle", check="W_rms[{window}] slope vs theta_c",
        figure="Fig. 7a",
        rule="linear fit of W_rms over all completed realizations, per vorticity window: "
             "|slope| <= k SE(slope); needs >= 2 angles and >= 3 runs; not resolved when "
             "k SE(slope) times the swept range exceeds FLAT_RESOLUTION of the mean W_rms "
             "(a change that large would have gone unseen)",
        tolerance={"quick": {"k": 3.0}, "standard": {"k": 2.5}, "paper": {"k": 2.0}},
        reason="paper: W_rms is practically independent of theta_c at every stage of the "
               "cycling (horizontal linear fits within the error bars, Fig. 7a)",
        tier_reasons={
            "quick": "k = 3: few runs give a standard error with few degrees of freedom, "
                     "itself uncertain; only a gross slope is flagged",
            "standard": "k = 2.5: a few realizations per point leave SE uncertain (Student t "
                        "with few degrees of freedom has wider tails than the normal)",
            "paper": "k = 2: consistent with zero at about 95 % two-sided confidence"}),
    CheckDef(
        id="wrms_ratio_slope", sweep="ratio", check="W_rms[{window}] slope vs alpha_c/alpha_p",
        figure="Fig. 7b",
        rule="linear fit of W_rms over all completed realizations, per vorticity window: "
             "slope - k SE(slope) > 0 (quadratic fit reported); needs >= 2 ratios and >= 3 runs",
        tolerance=_K_MONOTONE,
        reason="paper: the magnitude of the vorticity increases monotonically with alpha_c, "
               "roughly quadratically (Fig. 7b)",
        tier_reasons=_K_MONOTONE_REASONS),
    CheckDef(
        id="volume_end", sweep="both", check="V/V0 at the end ({point})",
        figure="Fig. 4",
        rule="mean over realizations of V_over_V0_end < 1 - margin",
        tolerance={"quick": {"margin": 0.0}, "standard": {"margin": 0.0}, "paper": {"margin": 0.0}},
        reason="paper: the bed compacts during the first cycles (V/V0 falls below 1) and keeps "
               "that density in the steady state (Fig. 4)",
        tier_reasons={
            "quick": "margin 0: any net compaction; V/V0 comes from the convex hull without "
                     "sampling noise, and even a few cycles compact a poured bed",
            "standard": "margin 0: any net compaction; the size of it depends on the bed size",
            "paper": "margin 0: any net compaction; the paper gives no number for it"}),
    CheckDef(
        id="volume_saturation", sweep="both", check="V/V0 saturation ({point})",
        figure="Fig. 4",
        rule="end-of-cycle V/V0 (mean over realizations, V/V0 = 1 before cycling), N cycles, "
             "m = N // 3: d_first = v[0] - v[m] > 0 and d_last = v[N-m] - v[N] < d_first; "
             "measured d_last - d_first; needs N >= 3",
        tolerance={"quick": {"min_cycles": 3}, "standard": {"min_cycles": 3},
                   "paper": {"min_cycles": 3}},
        reason="paper: compaction in the first cycles followed by a saturation that matches "
               "the pressure's steady state (Fig. 4)",
        tier_reasons={
            "quick": "strict inequalities; sweeps with fewer than 3 cycles are skipped",
            "standard": "strict inequalities; the first third compacts more than the last",
            "paper": "strict inequalities; with 20 cycles the last third is in the steady state"}),
)}


#: Fig. 5, Fig. 6 and the steady state (issue 30 part 3), evaluated in analysis/fields.py
#: from each run's stage_fields.csv and cycles.csv.
_K_FIELDS = {"quick": {"k": 1.0}, "standard": {"k": 2.0}, "paper": {"k": 2.0}}
_K_FIELDS_REASONS = {
    "quick": "k = 1: one realization per point, so the SE is the cycle-to-cycle scatter of "
             "3 cycles of a 45-grain bed; a sign one SE beyond 0 is all it can show",
    "standard": "k = 2: about 97.5 % one-sided confidence for a normal estimate",
    "paper": "k = 2: about 97.5 % one-sided confidence for a normal estimate (SE over 5 "
             "realizations)",
}
CHECKS.update({c.id: c for c in (
    CheckDef(
        id="stage_heating_direction", sweep="both", check="heating: outward and downward ({point})",
        figure="Fig. 5",
        rule="grain means over the heating of each cycle, averaged over the cycles: u_r of the grains "
             "off the axis (cells from ir = 1) and u_z of all grains; passed when u_r > k SE and "
             "u_z < -k SE, failed when either is beyond k SE on the other side, else not resolved; "
             "SE over the realizations (>= 2), else over the one run's cycles",
        tolerance=_K_FIELDS,
        reason="paper: during heating the grains move outwards and downwards (Fig. 5): the "
               "container widens more than the grains grow (alpha_c > alpha_p) and the bed slumps",
        tier_reasons=_K_FIELDS_REASONS),
    CheckDef(
        id="stage_cooling_direction", sweep="both", check="cooling: inward and upward ({point})",
        figure="Fig. 5",
        rule="as stage_heating_direction over the cooling (from the end of heating to the end of "
             "cooling): passed when u_r < -k SE and u_z > k SE",
        tolerance=_K_FIELDS,
        reason="paper: during cooling the grains move inwards and upwards (Fig. 5): the "
               "contracting container squeezes the bed",
        tier_reasons=_K_FIELDS_REASONS),
    CheckDef(
        id="still_zone", sweep="both", check="still zone at the bottom ({point})",
        figure="Fig. 5",
        rule="f = grain mean of the stage displacement magnitude (heating and cooling alike) in the "
             "cells with r < R/3 and z < H/4 (R, H the bed's radius and height; at least the cell on "
             "the axis at the floor) over that of the whole bed, averaged over the cycles: passed "
             "when f + k SE < f_max, failed when f - k SE >= f_max, else not resolved",
        tolerance={"quick": {"f_max": 0.5, "k": 1.0}, "standard": {"f_max": 0.4, "k": 2.0},
                   "paper": {"f_max": 0.3, "k": 2.0}},
        reason="paper: a still conical zone at the bottom, grains that hardly move (Fig. 5)",
        tier_reasons={
            "quick": "f_max 0.5, k = 1: cells of 2 grain sizes, so the bottom-axis cell holds "
                     "grains of the zone's edge too",
            "standard": "f_max 0.4, k = 2: a bed a few cells wide still mixes the zone's edge "
                        "into its bottom-axis cells",
            "paper": "f_max 0.3, k = 2: 'hardly move' read as under a third of the bed's mean; "
                     "the paper gives no number"}),
    CheckDef(
        id="toroidal_cell", sweep="both", check="toroidal convection cell ({point})",
        figure="Fig. 6",
        rule="per run, the cumulative field (heating + cooling summed over the second half of "
             "the cycles) and its vorticity w on the interior cells; coherence "
             "s = sum w / sum |w| (1 or -1: one sense over the whole core); passed when every "
             "realization has |s| >= s_min with one sense, failed when realizations with "
             "|s| >= s_min turn opposite ways or every |s| < s_fail, else not resolved",
        tolerance={"quick": {"s_min": 0.3, "s_fail": 0.0}, "standard": {"s_min": 0.4, "s_fail": 0.0},
                   "paper": {"s_min": 0.5, "s_fail": 0.2}},
        reason="paper: toroidal convection cells in every case (Fig. 6): the accumulated "
               "displacement turns one way around a ring in the (r, z) plane",
        tier_reasons={
            "quick": "s_min 0.3, never failed on coherence: a 45-grain bed over 2 cycles has "
                     "few interior cells and its cumulative field is mostly noise",
            "standard": "s_min 0.4, never failed on coherence: 6 cycles leave the cumulative "
                        "field noisy",
            "paper": "s_min 0.5 (three quarters of |w| turning one way); below 0.2 in every "
                     "realization there is no dominant cell, against the paper"}),
    CheckDef(
        id="steady_time_theta", sweep="angle", check="cycles to the steady state vs theta_c",
        figure="Results text, Fig. 3a",
        rule="per run the first cycle whose peak pressure lies in the steady band: mean of the "
             "second half of the cycles +- max(2 sigma, 5 % of it), sigma their standard "
             "deviation; linear fit over all runs: passed when slope + k SE < 0, failed when "
             "slope - k SE > 0, else not resolved; skipped below min_cycles",
        tolerance={"quick": {"k": 1.0, "min_cycles": 6}, "standard": {"k": 2.0, "min_cycles": 6},
                   "paper": {"k": 2.0, "min_cycles": 6}},
        reason="paper: the steady state comes sooner at larger opening angles",
        tier_reasons={
            "quick": "skipped: 3 cycles have no steady half to measure against",
            "standard": "k = 2; 6 cycles resolve the time to steady state only to 1-3 cycles",
            "paper": "k = 2 over 25 runs; 2 sigma holds about 95 % of normally scattered steady "
                     "peaks, the 5 % floor keeps the band open when they agree closely"}),
    CheckDef(
        id="steady_volume_flat", sweep="both", check="steady V/V0 vs {x}",
        figure="Fig. 4",
        rule="per run the mean V/V0 at the end of cooling over the second half of the cycles; "
             "linear fit over all runs: |slope| <= k SE, not resolved when k SE x range exceeds "
             "FLAT_RESOLUTION of the mean; skipped below min_cycles",
        tolerance={"quick": {"k": 3.0, "min_cycles": 6}, "standard": {"k": 2.5, "min_cycles": 6},
                   "paper": {"k": 2.0, "min_cycles": 6}},
        reason="paper: the same steady density for all parameters (Fig. 4)",
        tier_reasons={
            "quick": "skipped: 3 cycles reach no steady density",
            "standard": "k = 2.5: a few realizations per point leave SE uncertain",
            "paper": "k = 2: consistent with zero at about 95 % two-sided confidence"}),
    CheckDef(
        id="cooling_dilation_ratio", sweep="ratio", check="dilation during cooling vs alpha_c/alpha_p",
        figure="Fig. 4b",
        rule="per run the mean over the second half of the cycles of V/V0 at the end of heating "
             "minus V/V0 at the end of cooling (the dilation the cooling takes back; our reading "
             "of the paper's words); linear fit over all runs: passed when "
             "slope - k SE > 0, failed when slope + k SE < 0, else not resolved; skipped below "
             "min_cycles",
        tolerance={"quick": {"k": 1.0, "min_cycles": 6}, "standard": {"k": 2.0, "min_cycles": 6},
                   "paper": {"k": 2.0, "min_cycles": 6}},
        reason="paper: the dilation during cooling is weaker at small alpha_c (Fig. 4b): with "
               "alpha_c near alpha_p bed and container shrink alike, the swing is the grains' own",
        tier_reasons={
            "quick": "skipped: 3 cycles have no steady half",
            "standard": "k = 2: about 97.5 % one-sided confidence",
            "paper": "k = 2 over 25 runs"}),
)})


# --------------------------------------------------------------------------- results


@dataclass
class CheckResult:
    case: str
    check: str
    check_id: str
    status: str                      # "passed", "failed", "unresolved", "skipped"
    measured: float | None = None
    expected: str = ""
    tolerance: str = ""
    reason: str = ""
    detail: dict = field(default_factory=dict)

    @property
    def passed(self) -> bool:
        return self.status == "passed"

    def record(self) -> dict:
        """The JSON line of check_record.hpp (only for passed or failed checks)."""
        measured = self.measured
        if measured is not None and not math.isfinite(measured):
            measured = None
        line = {"case": self.case, "check": self.check, "measured": measured,
                "expected": self.expected, "tolerance": self.tolerance,
                "reason": self.reason, "passed": self.status in ("passed", "unresolved")}
        if self.status == "unresolved":
            line["resolved"] = False
        return line

    def to_dict(self) -> dict:
        out = self.record()
        out["status"] = self.status
        out["id"] = self.check_id
        out["detail"] = self.detail
        return out


def out_of_scale(result: CheckResult, reason: str | None) -> CheckResult:
    """A passed or failed check whose paper statement does not cover the beds it ran on
    (scripts/trends --out-of-scale): not resolved, with the measured value and the verdict
    the tier's tolerance gave kept in view. Skipped and unresolved checks stay as they are."""
    if not reason or result.status not in ("passed", "failed"):
        return result
    verdict = "pass" if result.status == "passed" else "fail"
    return CheckResult(case=result.case, check=result.check, check_id=result.check_id,
                       status="unresolved", measured=result.measured, expected=result.expected,
                       tolerance=result.tolerance,
                       reason=(f"not resolved at this scale: {reason} (the tolerance alone would "
                               f"{verdict} it). {result.reason}"),
                       detail={**result.detail, "verdict_at_tolerance": result.status})


def _skip(case: str, definition: CheckDef, check: str, why: str, tier: str) -> CheckResult:
    return CheckResult(case=case, check=check, check_id=definition.id, status="skipped",
                       measured=None, expected="", tolerance="",
                       reason=f"skipped: {why}", detail={"tier": tier})


def _verdict(ok: bool, measured: float | None) -> str:
    return "passed" if ok and measured is not None and math.isfinite(measured) else "failed"


# --------------------------------------------------------------------------- analysis


X_LABELS = {"angle": "theta_c", "ratio": "alpha_c/alpha_p"}
X_COLUMNS = {"angle": ANGLE, "ratio": RATIO}
X_UNITS = {"angle": "deg", "ratio": ""}


@dataclass
class Analysis:
    """The fits, statistics and checks of one sweep along one parameter."""

    sweep: Sweep
    kind: str                  # "angle" or "ratio"
    case: str
    tier: str
    data: pd.DataFrame         # completed runs of the slice analysed
    x: str                     # column of the parameter
    x_label: str
    metrics: dict = field(default_factory=dict)     # name -> {"groups", "fits"...}
    halving: dict | None = None
    volume: dict = field(default_factory=dict)
    results: list[CheckResult] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)

    def point_label(self, value: float) -> str:
        unit = X_UNITS[self.kind]
        return f"{self.x_label}={value:g}" + (f" {unit}" if unit else "")


def _slice(sweep: Sweep, kind: str, notes: list[str]) -> pd.DataFrame:
    """The completed runs along `kind`; a grid is cut where the paper fixed the other."""
    data = sweep.completed
    other, reference, label = ((RATIO, PAPER_RATIO, "alpha_c/alpha_p") if kind == "angle"
                               else (ANGLE, PAPER_ANGLE, "theta_c"))
    if other in data.columns:
        values = data[other].dropna().unique()
        if len(values) > 1:
            chosen = float(values[np.argmin(np.abs(values - reference))])
            notes.append(f"{label} varies too: the {kind} study uses the runs at {label} = "
                         f"{chosen:g} (nearest the paper's {reference:g})")
            data = data[np.isclose(data[other], chosen)]
    return data.copy()


def metric_fits(data: pd.DataFrame, x: str, metric: str) -> dict:
    """Group statistics and linear/quadratic fits of one metric along x."""
    values = data[[x, metric]].apply(pd.to_numeric, errors="coerce")
    values = values[np.isfinite(values[x]) & np.isfinite(values[metric])]
    groups = fits.group_stats(values, x, metric)
    out = {"groups": groups, "n_runs": int(len(values)), "realizations": {}, "means": {},
           "why_not": {}}
    for name, degree in (("linear", 1), ("quadratic", 2)):
        fit, why = fits.try_fit(values[x], values[metric], degree)
        out["realizations"][name] = fit
        if fit is None:
            out["why_not"][name] = why
        if len(groups):
            mean_fit, _ = fits.try_fit(groups["x"], groups["mean"], degree,
                                       sigma=1.0 / np.sqrt(groups["n"].to_numpy(dtype=float)))
        else:
            mean_fit = None
        out["means"][name] = mean_fit
    return out


def _slope_check(a: Analysis, definition: CheckDef, metric: str, check: str,
                 direction: str) -> CheckResult:
    """direction: "decrease" (slope + k SE < 0), "increase" (slope - k SE > 0) or
    "flat" (|slope| <= k SE)."""
    tier = a.tier
    k = definition.params(tier)["k"]
    info = a.metrics.get(metric)
    if info is None:
        return _skip(a.case, definition, check, f"no column {metric} in summary.csv", tier)
    groups = info["groups"]
    if len(groups) < 2:
        where = f" ({a.point_label(groups['x'].iloc[0])})" if len(groups) else ""
        return _skip(a.case, definition, check,
                     f"{len(groups)} {a.x_label} value(s) with a finite {metric} among the "
                     f"completed runs{where}; a slope needs 2", tier)
    fit = info["realizations"]["linear"]
    if fit is None or fit.dof < 1 or not math.isfinite(fit.slope_se):
        return _skip(a.case, definition, check,
                     f"{info['n_runs']} runs at {len(groups)} {a.x_label} values: the slope "
                     "has no standard error (needs >= 3 runs)", tier)
    slope, se = fit.slope, fit.slope_se
    unit = f" per {X_UNITS[a.kind]}" if X_UNITS[a.kind] else ""
    if direction == "decrease":
        ok, expected = slope + k * se < 0, "< 0"
    elif direction == "increase":
        ok, expected = slope - k * se > 0, "> 0"
    else:
        ok, expected = abs(slope) <= k * se, "0"
    status, reason = _verdict(ok, slope), definition.reason_for(tier)
    if direction == "flat":
        tolerance = f"abs {k:g} SE = {k * se:.4g} (SE {se:.4g}{unit})"
        span = float(groups["x"].max() - groups["x"].min())
        mean = float(np.average(groups["mean"], weights=groups["n"]))
        unseen = k * se * span
        if status == "passed" and not unseen <= FLAT_RESOLUTION * abs(mean):
            status = "unresolved"
            reason = (f"not resolved at this tier: a change of {unseen:.3g} across the range "
                      f"({unseen / abs(mean):.0%} of the mean {mean:.3g}) would go unseen; "
                      f"flat needs k SE x range <= {FLAT_RESOLUTION:g} x mean. {reason}")
    else:
        tolerance = f"{k:g} SE beyond 0 (SE {se:.4g}{unit})"
    return CheckResult(case=a.case, check=check, check_id=definition.id,
                       status=status, measured=float(slope), expected=expected,
                       tolerance=tolerance, reason=reason,
                       detail={"tier": tier, "k": k, "slope": slope, "se": se, "n": fit.n,
                               "dof": fit.dof, "points": int(len(groups))})


def _halving_check(a: Analysis) -> CheckResult:
    definition = CHECKS["pmax_ratio_6_0"]
    p = definition.params(a.tier)
    low, high = HALVING_ANGLES
    data = a.data[[a.x, "P_max"]].apply(pd.to_numeric, errors="coerce")
    at_low = data.loc[np.isclose(data[a.x], low), "P_max"].dropna()
    at_high = data.loc[np.isclose(data[a.x], high), "P_max"].dropna()
    if at_low.empty or at_high.empty:
        missing = " and ".join(f"{v:g} deg" for v, s in ((low, at_low), (high, at_high)) if s.empty)
        return _skip(a.case, definition, definition.check,
                     f"no completed run with a finite P_max at {missing}", a.tier)
    ratio = fits.ratio_of_means(at_high, at_low)
    a.halving = ratio
    if not math.isfinite(ratio["ratio"]):
        return _skip(a.case, definition, definition.check,
                     f"mean P_max at {low:g} deg is {ratio['denominator']['mean']:g}: "
                     "no ratio", a.tier)
    sigma = ratio["sigma"]
    band = max(p["floor"], p["k"] * sigma) if math.isfinite(sigma) else p["floor"]
    sigma_text = (f"sigma_R {sigma:.3g}" if math.isfinite(sigma)
                  else "sigma_R n/a: fewer than 2 realizations")
    measured = ratio["ratio"]
    ok = abs(measured - p["target"]) <= band
    status = _verdict(ok, measured)
    reason = definition.reason_for(a.tier)
    why = halving_unresolved(ratio, p)
    if status == "passed" and why:
        status = "unresolved"
        reason = f"not resolved at this tier: {why}. {reason}"
    return CheckResult(
        case=a.case, check=definition.check, check_id=definition.id,
        status=status, measured=float(measured), expected=f"{p['target']:g}",
        tolerance=f"abs {band:.4g} = max({p['floor']:g}, {p['k']:g} sigma_R; {sigma_text})",
        reason=reason,
        detail={"tier": a.tier, **{k: v for k, v in ratio.items()}, "band": band,
                "realizations_needed": realizations_needed(ratio, p)})


def realizations_needed(ratio: dict, p: Mapping[str, float]) -> int | None:
    """Realizations per angle for k sigma_R to shrink to the band's floor, from
    sigma_R ~ 1/sqrt(n) at the measured scatter; None without a scatter estimate."""
    sigma = ratio["sigma"]
    n = min(ratio["numerator"]["n"], ratio["denominator"]["n"])
    if not math.isfinite(sigma) or n < 2:
        return None
    return max(n, math.ceil(n * (p["k"] * sigma / p["floor"]) ** 2))


def halving_unresolved(ratio: dict, p: Mapping[str, float]) -> str:
    """Why a ratio inside the band still does not show the halving ("" when it does).

    Resolved means: the scatter is known (>= 2 realizations per angle), narrower than
    the band (k sigma_R <= floor, else the band only widened to hold the scatter) and
    the cone lowers the peak beyond it (R + k sigma_R < 1)."""
    sigma, value, k = ratio["sigma"], ratio["ratio"], p["k"]
    if not math.isfinite(sigma):
        return ("one realization at 0 or 6 deg gives no estimate of the scatter, and single "
                "beds scatter by tens of per cent")
    needed = realizations_needed(ratio, p)
    if k * sigma > p["floor"]:
        return (f"{k:g} sigma_R = {k * sigma:.3g} is wider than the band {p['floor']:g}; "
                f"about {needed} realizations per angle would resolve it")
    if value + k * sigma >= 1.0:
        return f"R + {k:g} sigma_R = {value + k * sigma:.3g} does not exclude 1 (no effect)"
    return ""


def _r2_check(a: Analysis) -> CheckResult:
    definition = CHECKS["pmax_ratio_quadratic_r2"]
    r2_min = definition.params(a.tier)["r2_min"]
    info = a.metrics.get("P_max")
    points = 0 if info is None else len(info["groups"])
    if points < 4:
        return _skip(a.case, definition, definition.check,
                     f"{points} {a.x_label} value(s) with a finite P_max; R^2 of a quadratic "
                     "needs >= 4 (through 3 points it is 1 whatever the data)", a.tier)
    fit = info["means"]["quadratic"]
    r2 = fit.r2 if fit is not None else math.nan
    if not math.isfinite(r2):
        return _skip(a.case, definition, definition.check,
                     "the means of P_max do not vary: R^2 is undefined", a.tier)
    return CheckResult(case=a.case, check=definition.check, check_id=definition.id,
                       status=_verdict(r2 >= r2_min, r2), measured=float(r2),
                       expected=f">= {r2_min:g}", tolerance="lower bound",
                       reason=definition.reason_for(a.tier),
                       detail={"tier": a.tier, "points": points, "coefficients": list(fit.coef)})


def _volume_checks(a: Analysis) -> list[CheckResult]:
    out = []
    end_def, sat_def = CHECKS["volume_end"], CHECKS["volume_saturation"]
    margin = end_def.params(a.tier)["margin"]
    min_cycles = int(sat_def.params(a.tier)["min_cycles"])
    points = sorted(a.data[a.x].dropna().unique())
    # V/V0 at the end, from summary.csv.
    if "V_over_V0_end" not in a.data.columns or not np.isfinite(
            pd.to_numeric(a.data["V_over_V0_end"], errors="coerce")).any():
        out.append(_skip(a.case, end_def, end_def.check.format(point="all points"),
                         "summary.csv has no finite V_over_V0_end (did the scenes ask for "
                         "the volume?)", a.tier))
    else:
        groups = fits.group_stats(a.data, a.x, "V_over_V0_end")
        a.volume["end"] = groups
        for value in points:
            check = end_def.check.format(point=a.point_label(value))
            row = groups[np.isclose(groups["x"], value)]
            if row.empty:
                out.append(_skip(a.case, end_def, check, "no finite V_over_V0_end", a.tier))
                continue
            mean = float(row["mean"].iloc[0])
            out.append(CheckResult(
                case=a.case, check=check, check_id=end_def.id,
                status=_verdict(mean < 1.0 - margin, mean), measured=mean,
                expected=f"< {1.0 - margin:g}", tolerance="upper bound (strict)",
                reason=end_def.reason_for(a.tier),
                detail={"tier": a.tier, "n": int(row["n"].iloc[0]),
                        "std": float(row["std"].iloc[0])}))
    # Saturation, from the per-run files.
    curves = {}
    sources = {}
    why_not = {}
    for value in points:
        runs = a.data[np.isclose(a.data[a.x], value)]
        series = []
        for run in runs["run"]:
            values, source = end_of_cycle_volumes(run_dir(a.sweep.folder, int(run)))
            if values is None:
                why_not.setdefault(value, []).append(f"run {int(run)}: {source}")
            else:
                series.append(values)
                sources[value] = source
        if series:
            length = min(len(s) for s in series)
            curves[value] = (np.mean([s[:length] for s in series], axis=0), len(series))
    a.volume["end_of_cycle"] = {float(v): {"mean_curve": [float(x) for x in c], "runs": n,
                                           "source": sources.get(v, "")}
                                for v, (c, n) in curves.items()}
    if not curves:
        reasons = sorted({w.split(': ', 1)[1] for ws in why_not.values() for w in ws})
        why = "; ".join(reasons) if reasons else "no completed run"
        out.append(_skip(a.case, sat_def, sat_def.check.format(point="all points"),
                         f"no per-run V/V0 data ({why})", a.tier))
        return out
    for value in points:
        check = sat_def.check.format(point=a.point_label(value))
        if value not in curves:
            out.append(_skip(a.case, sat_def, check, "; ".join(why_not.get(value, ["no data"])), a.tier))
            continue
        curve, n_runs = curves[value]
        cycles = len(curve) - 1
        if cycles < min_cycles:
            out.append(_skip(a.case, sat_def, check,
                             f"{cycles} cycle(s) of V/V0; thirds need >= {min_cycles}", a.tier))
            continue
        m = cycles // 3
        d_first = float(curve[0] - curve[m])
        d_last = float(curve[cycles - m] - curve[cycles])
        measured = d_last - d_first
        ok = d_first > 0 and d_last < d_first
        out.append(CheckResult(
            case=a.case, check=check, check_id=sat_def.id, status=_verdict(ok, measured),
            measured=measured, expected="< 0, with d_first > 0",
            tolerance=f"strict; d_first {d_first:.4g} (cycles 0-{m}), d_last {d_last:.4g} "
                      f"(cycles {cycles - m}-{cycles})",
            reason=sat_def.reason_for(a.tier),
            detail={"tier": a.tier, "d_first": d_first, "d_last": d_last, "cycles": cycles,
                    "m": m, "runs": n_runs, "source": sources.get(value, "")}))
    return out


def analyse(sweep: Sweep, kind: str, tier: str, case: str | None = None) -> Analysis:
    """All fits and checks of one sweep along `kind` ("angle" or "ratio")."""
    if tier not in TIERS:
        raise ValueError(f"unknown tier {tier!r} (expected one of {', '.join(TIERS)})")
    if kind not in X_COLUMNS:
        raise ValueError(f"unknown sweep kind {kind!r}")
    notes: list[str] = []
    data = _slice(sweep, kind, notes)
    a = Analysis(sweep=sweep, kind=kind, case=case or f"trends_{kind}:{sweep.name}", tier=tier,
                 data=data, x=X_COLUMNS[kind], x_label=X_LABELS[kind], notes=notes)
    metrics = ["P_max"] + [w.column for w in sweep.windows]
    for metric in metrics:
        if metric in data.columns:
            a.metrics[metric] = metric_fits(data, a.x, metric)
    if kind == "angle":
        a.results.append(_slope_check(a, CHECKS["pmax_theta_slope"], "P_max",
                                      CHECKS["pmax_theta_slope"].check, "decrease"))
        a.results.append(_halving_check(a))
        w_def, direction = CHECKS["wrms_theta_flat"], "flat"
    else:
        a.results.append(_slope_check(a, CHECKS["pmax_ratio_slope"], "P_max",
                                      CHECKS["pmax_ratio_slope"].check, "increase"))
        a.results.append(_r2_check(a))
        w_def, direction = CHECKS["wrms_ratio_slope"], "increase"
    if not sweep.windows:
        a.results.append(_skip(a.case, w_def, w_def.check.format(window="any"),
                               "summary.csv has no W_rms_<a>_<b> column", tier))
    for window in sweep.windows:
        a.results.append(_slope_check(a, w_def, window.column,
                                      w_def.check.format(window=window.label.replace("cycles ", "")),
                                      direction))
    a.results.extend(_volume_checks(a))
    from . import fields  # Fig. 5, Fig. 6, steady state; it imports this module
    a.results.extend(fields.checks(a))
    capped = sorted(r for r in data["run"] if int(r) in sweep.capped)
    if capped:
        worst = max(sweep.capped[int(r)] for r in capped)
        flag = (f" [built on {len(capped)} of {len(data)} runs with steps at the solver's iteration "
                f"cap, at most {worst:.2%} of a run's steps]")
        for r in a.results:
            if r.status != "skipped":
                r.reason += flag
                r.detail["capped_runs"] = [int(x) for x in capped]
    return a


# --------------------------------------------------------------------------- docs


def describe_checks(tiers=TIERS) -> str:
    """The check definitions as Markdown (scripts/trends --list-checks, docs/trends.md)."""
    out = []
    for definition in CHECKS.values():
        sweep = {"both": "angle and ratio"}.get(definition.sweep, definition.sweep)
        out += [f"### `{definition.id}`: {definition.check}", "",
                f"- sweep: {sweep}; mirrors: {definition.figure}",
                f"- rule: {definition.rule}",
                f"- why: {definition.reason}", "",
                "| tier | tolerance | reason |", "|---|---|---|"]
        for tier in tiers:
            values = ", ".join(f"{k} = {v:g}" for k, v in definition.params(tier).items())
            out.append(f"| {tier} | {values} | {definition.tier_reasons[tier]} |")
        out.append("")
    return "\n".join(out)
