"""The paper's trends as checks: definitions (one table), evaluation, records.

Every acceptance rule and tolerance lives in CHECKS below, with the reason for its
value per tier; the evaluation code reads its numbers only from there. A check passes
only when its value with its uncertainty shows the paper's statement at the scale it
ran. A check yields a CheckResult with one of five statuses (docs/trends.md, "States"):

- "passed": the data resolve the paper's statement;
- "unresolved": the data can show neither the statement nor its opposite (the scatter
  of the realizations is wider than the effect, a band widened for small beds, peaks
  that are not steady, a line that fits as well as the paper's quadratic). Shown as
  "not resolved", never as PASS; not a failure;
- "contradicted": the data resolve the opposite of the statement at a scale smaller
  than the paper's (quick and standard tiers, or --out-of-scale). Counted and shown
  apart; not a failure of the engine (exit status 0), never "passed": true;
- "failed": the opposite resolved at the paper's own scale (paper tier), or a measured
  value that is not a number;
- "skipped": not enough data (never a pass).

Passed, failed, unresolved and contradicted checks become JSON lines in the format of
validation/support/check_record.hpp (scripts/README.md): unresolved ones with
"passed": true, "resolved": false; contradicted ones with "passed": false,
"resolved": true, "contradicted": true. Skipped ones are listed in trends.md/trends.json
and on the terminal only, since that format has no skipped state.

Which data each check uses (docs/trends.md):
- slopes, curvatures and their standard errors: the fits over all completed
  realizations (each run one point, unweighted), so that SE reflects the scatter between
  realizations and the lack of fit;
- R^2 (reported, not a rule) and the plotted curves: the fit of the realization means
  weighted by the number of realizations n.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field
from typing import Mapping

import numpy as np
import pandas as pd
from scipy import stats

from . import fits
from .inputs import ANGLE, RATIO, Sweep, end_of_cycle_volumes, run_dir, steady_peaks

TIERS = ("quick", "standard", "paper")
#: The tier at the paper's own scale: there a resolved contradiction is a failure.
PAPER_TIER = "paper"
STATUSES = ("passed", "failed", "unresolved", "contradicted", "skipped")

#: What each tier means for the data (docs/method.md s. 11); printed in the reports.
TIER_SCALE = {
    "quick": "CI scale: a small bed, a few cycles, typically one realization per point; "
             "the steady state is not reached, so most trends read not resolved",
    "standard": "reduced scale (fewer particles, cycles and realizations than the paper, "
                "about 10 minutes on 2 cores); a trend passes only where resolved",
    "paper": "the paper's scale: 2000 particles, 20 cycles, 5 realizations per point",
}

#: Reference values of the paper: the fixed ratio of the angle study and the fixed
#: angle of the ratio study (used to slice a grid sweep), and the angles of the
#: "6 deg halves the peak pressure" statement.
PAPER_RATIO = 10.0
PAPER_ANGLE = 0.0
#: The paper's value of each swept parameter (what a study along one holds fixed:
#: fixed_parameter).
PAPER_VALUE = {"angle": PAPER_ANGLE, "ratio": PAPER_RATIO}
HALVING_ANGLES = (0.0, 6.0)


@dataclass(frozen=True)
class CheckDef:
    id: str
    sweep: str                 # "angle", "ratio" or "both"
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


#: A flat trend is shown only if the whole k-SE interval of the change across the swept
#: range lies within this fraction of the quantity's scale, and contradicted only if the
#: whole interval lies beyond it (flat_verdict): "practically independent" (Fig. 7a) means
#: well within the realizations' spread, which is of this order at the paper's scale.
FLAT_RESOLUTION = 0.25


def flat_verdict(slope: float, se: float, k: float, span: float, scale: float,
                 scale_text: str, tier: str, fraction: float = FLAT_RESOLUTION,
                 across: str = "the range") -> tuple[str, str, float]:
    """Status, reason and the largest change the data allow, for a claim of no (or no
    more than a small) dependence: an equivalence test with the margin fraction x scale.
    Flat is shown when the whole k-SE interval of the change lies within the margin,
    (|slope| + k SE) x range <= margin (two one-sided tests, Schuirmann 1987, J.
    Pharmacokin. Biopharm. 15:657); the claim is contradicted only when the whole
    interval lies beyond it, (|slope| - k SE) x range > margin; anything between is not
    resolved, including a slope resolved from 0 whose change may still be within the
    margin ("nearly the same" allows a small difference). The steady state of the peaks
    follows the same rule (docs/trends.md, pmax_steady): a verdict that read a resolved
    slope as against the claim whenever its interval reached past the margin made the
    same drift flat with quiet peaks and against with noisier ones."""
    allowed = (abs(slope) + k * se) * span
    least = max(abs(slope) - k * se, 0.0) * span
    margin = fraction * scale
    share = (lambda change: f"{change / scale:.0%} of {scale_text}") if scale > 0 else (lambda change: "the scale is 0")
    if least > margin:
        return against(tier), (f"the change across {across} is at least {least:.3g} ({share(least)}), "
                               f"beyond {fraction:g} x {scale_text}"), allowed
    if allowed <= margin:
        return "passed", "", allowed
    return "unresolved", (f"a change of {least:.3g} to {allowed:.3g} across {across} is within {k:.3g} SE "
                          f"(up to {share(allowed)}); flat needs <= {fraction:g} x {scale_text}, "
                          f"against it takes more than that"), allowed


#: The slope rules' k is the large-sample multiple; a fit of n runs has n - 2 dof, and
#: with few of them "k SE" over-claims (one dof needs 14 SE for k = 2's level).
_WIDENED = ("; k is the tier's, widened to the Student t quantile at the fit's dof "
            "(n - 2) for the two-sided level k has in the normal limit (fits.widened_k)")


def _same_at_every_tier(**tolerance) -> dict[str, dict]:
    """A tolerance that does not depend on the tier (each tier gets its own copy)."""
    return {tier: dict(tolerance) for tier in TIERS}


_K_MONOTONE = _same_at_every_tier(k=2.0)
_K_MONOTONE_REASONS = {
    "quick": "k = 2 as at every tier: a pass claims the sign at about 97.5 % one-sided "
             "confidence whatever the bed; a CI-scale bed's wider scatter reads not resolved",
    "standard": "k = 2: the slope differs from zero at about 97.5 % one-sided confidence "
                "for a normal estimate; fewer realizations widen SE and, through the fit's dof, k",
    "paper": "k = 2: the slope differs from zero at about 97.5 % one-sided confidence "
             "for a normal estimate (5 realizations per point)",
}
_LEVEL = _same_at_every_tier(level=0.95)
#: Per-run first-against-later checks: a first cycle and at least two after it.
_LEVEL_3_CYCLES = _same_at_every_tier(level=0.95, min_cycles=3)
#: Per-run measures over the cycles that need more than a first regime to go by.
_LEVEL_6_CYCLES = _same_at_every_tier(level=0.95, min_cycles=6)
_CURVATURE_REASONS = {
    "quick": "level 0.95 as at every tier: single beds per point leave a wide scatter, "
             "which reads 'a line fits as well' rather than a looser pass",
    "standard": "level 0.95: few runs give the t test few degrees of freedom, which widens "
                "the threshold on its own (pooled, n - 3: with 5 runs |c2| > 4.3 SE; a point's own "
                "scatter, n - 1 per point)",
    "paper": "level 0.95: the paper gives no number for 'fitted well'; a curvature "
             "resolved at 95 % is the least that tells a quadratic from a line",
}

CHECKS: dict[str, CheckDef] = {c.id: c for c in (
    CheckDef(
        id="pmax_steady", sweep="both", check="P_max steady ({point})",
        figure="Fig. 3a / 3c",
        rule="per run, the linear slope of the per-cycle peak pressure (cycles.csv) against "
             "the cycle number over the cycles P_max averages (run.json summary.steady_cycles, "
             "else the second half); with >= 2 runs their mean slope +- k sem (Student t, "
             "n - 1 dof), with 1 run of >= 3 such cycles its fit's slope +- k SE; "
             "k = t quantile at `level`. Steady (pass): a drift of (|slope| + k SE) over the "
             "window is <= drift x the mean peak (two one-sided tests), a trend resolved from 0 "
             "included; not steady: a drift of at least (|slope| - k SE) over the window "
             "beyond that margin, which makes every P_max check using the point not resolved "
             "('not steady'); between the two, not resolved",
        tolerance=_same_at_every_tier(level=0.95, drift=0.25),
        reason="paper: the peak pressure rises over the first cycles, then 'a steady state is "
               "reached where the pressure fluctuates around a relatively constant value'; "
               "P_max is the mean peak of that steady state (Fig. 3a, 3c)",
        tier_reasons={
            "quick": "a 3-cycle bed is short of the steady state (not steady is not resolved, "
                     "not a failure); drift 0.25 as FLAT_RESOLUTION",
            "standard": "the tier's steady cycles are a choice of the protocol, not the "
                        "paper's; not steady reads not resolved; drift 0.25 as FLAT_RESOLUTION",
            "paper": "the paper's bed holds its peak from about cycle 8 (docs/accuracy-cost.md), "
                     "so a drift in cycles 10-19 shown beyond the margin fails; drift 0.25 as "
                     "FLAT_RESOLUTION"}),
    CheckDef(
        id="pmax_theta_slope", sweep="angle", check="P_max slope vs theta_c",
        figure="Fig. 3b",
        rule="linear fit of P_max over all completed realizations: pass slope + k SE(slope) < 0; "
             "opposite resolved: slope - k SE(slope) > 0; else not resolved "
             "(quadratic fit reported); needs >= 2 angles and >= 3 runs" + _WIDENED,
        tolerance=_K_MONOTONE,
        reason="paper: the steady-state peak pressure decreases with the opening angle "
               "theta_c, close to linearly (Fig. 3b)",
        tier_reasons=_K_MONOTONE_REASONS),
    CheckDef(
        id="pmax_ratio_6_0", sweep="angle", check="P_max(6 deg)/P_max(0 deg)",
        figure="Results text, Fig. 3b",
        rule="R = mean P_max(6 deg) / mean P_max(0 deg), sigma_R by first-order propagation "
             "of the realization standard errors, interval R +- k sigma_R with k the Student "
             "t quantile at `level` for the Welch-Satterthwaite dof of sigma_R; pass: the "
             "interval inside target +- half_width; contradiction: the interval entirely "
             "outside it; else not resolved (one realization at an angle: not resolved); "
             "needs runs at 0 and 6 deg",
        tolerance=_same_at_every_tier(target=0.5, half_width=0.15, level=0.95),
        reason="paper: 'a conical container with an opening angle of only 6 deg halves the "
               "peak pressure compared to a cylindrical container'",
        tier_reasons={
            "quick": "the paper's band at every tier: a CI-scale bed that lowers the peak "
                     "by less reads not resolved or contradicted at this scale, never a pass",
            "standard": "the paper's band, not a widened one: the 200 bed's 0.67 +- 0.09 (a "
                        "third lower, docs/accuracy-cost.md) must not pass as 'halves'",
            "paper": "band 0.35-0.65: 'halves' is read off a figure of 5-realization means; "
                     "+- 0.15 (30 % of a half) keeps a third lower (0.67) and two thirds "
                     "lower (0.33) outside; 95 % interval from the realizations' scatter"}),
    CheckDef(
        id="pmax_ratio_slope", sweep="ratio", check="P_max slope vs alpha_c/alpha_p",
        figure="Fig. 3d",
        rule="linear fit of P_max over all completed realizations: pass slope - k SE(slope) > 0; "
             "opposite resolved: slope + k SE(slope) < 0; else not resolved; "
             "needs >= 2 ratios and >= 3 runs" + _WIDENED,
        tolerance=_K_MONOTONE,
        reason="paper: the peak pressure increases with alpha_c/alpha_p, the container strain "
               "per cycle and so the energy input (Fig. 3d)",
        tier_reasons=_K_MONOTONE_REASONS),
    CheckDef(
        id="pmax_ratio_quadratic", sweep="ratio", check="P_max curvature vs alpha_c/alpha_p",
        figure="Fig. 3d",
        rule="quadratic and linear fits of P_max over all completed realizations (unweighted); "
             "two-sided t test of the x^2 term c2 against each point's own scatter: Var(c2) = "
             "sum over points of the sample variance of its realizations times the sum of its "
             "runs' squared fit weights, a point of one realization taking the noisiest "
             "replicated point's variance, Welch-Satterthwaite dof), and against the pooled "
             "residual (the F test of the nested fits, 1 and n - 3 dof, which holds any lack of "
             "fit); p the larger of the two (fits.curvature_test; the pooled one alone without "
             "a replicated point): pass c2 > 0 with p < 1 - level; "
             "opposite resolved: c2 < 0 with p < 1 - level (bends down); else not resolved "
             "('a line fits as well'); R^2 of the quadratic and the line through the means "
             "reported, not a rule; needs >= 4 ratios and >= 4 runs",
        tolerance=_LEVEL,
        reason="paper: P_max(alpha_c/alpha_p) 'is fitted well by a quadratic function', "
               "bending up (Fig. 3d): a quadratic only says more than a line if its "
               "curvature is resolved",
        tier_reasons=_CURVATURE_REASONS),
    CheckDef(
        id="wrms_theta_flat", sweep="angle", check="W_rms[{window}] slope vs theta_c",
        figure="Fig. 7a",
        rule="linear fit of W_rms over all completed realizations, per vorticity window: "
             "pass when (|slope| + k SE(slope)) times the swept range is at most "
             "FLAT_RESOLUTION of the mean W_rms (two one-sided tests: the whole k-SE interval "
             "of the change within the margin); opposite resolved: (|slope| - k SE(slope)) times the "
             "range above that margin (the whole interval beyond it); "
             "else not resolved; needs >= 2 angles and >= 3 runs" + _WIDENED,
        tolerance={"quick": {"k": 3.0}, "standard": {"k": 2.5}, "paper": {"k": 2.0}},
        reason="paper: W_rms is practically independent of theta_c at every stage of the "
               "cycling (horizontal linear fits within the error bars, Fig. 7a)",
        tier_reasons={
            "quick": "k = 3: few runs give a standard error with few degrees of freedom, "
                     "itself uncertain; only a gross slope counts as resolved",
            "standard": "k = 2.5: a few realizations per point leave SE uncertain (Student t "
                        "with few degrees of freedom has wider tails than the normal)",
            "paper": "k = 2: consistent with zero at about 95 % two-sided confidence"}),
    CheckDef(
        id="wrms_ratio_slope", sweep="ratio", check="W_rms[{window}] slope vs alpha_c/alpha_p",
        figure="Fig. 7b",
        rule="linear fit of W_rms over all completed realizations, per vorticity window: "
             "pass slope - k SE(slope) > 0; opposite resolved: slope + k SE(slope) < 0; else "
             "not resolved; needs >= 2 ratios and >= 3 runs" + _WIDENED,
        tolerance=_K_MONOTONE,
        reason="paper: the magnitude of the vorticity increases monotonically with alpha_c "
               "(Fig. 7b)",
        tier_reasons=_K_MONOTONE_REASONS),
    CheckDef(
        id="wrms_ratio_quadratic", sweep="ratio", check="W_rms[{window}] curvature vs alpha_c/alpha_p",
        figure="Fig. 7b",
        rule="as pmax_ratio_quadratic, per vorticity window: pass c2 > 0 with the t test of "
             "c2 (as pmax_ratio_quadratic: the larger p of the per-point and pooled tests) p < 1 - level; c2 < 0 with p < 1 - level: "
             "opposite resolved; else not resolved ('a line fits as well'); needs >= 4 ratios "
             "and >= 4 runs",
        tolerance=_LEVEL,
        reason="paper: W_rms rises with alpha_c/alpha_p 'roughly quadratically', because the "
               "energy scales with the square of the strain (Fig. 7b)",
        tier_reasons=_CURVATURE_REASONS),
    CheckDef(
        id="wrms_ratio_monotone", sweep="ratio",
        check="W_rms[{window}] rises at every step of alpha_c/alpha_p",
        figure="Fig. 7b",
        rule="per vorticity window, between each two neighbouring ratios the difference of the "
             "realizations' mean W_rms, Welch's t test (scipy.stats.ttest_ind, unequal variances): "
             "pass when every step rises with one-sided p < (1 - level) / 2 (each step shown, so "
             "all of them are at that level); opposite resolved: a step falls with one-sided "
             "p < (1 - level) / (2 m), m the number of steps (Bonferroni: the lowest of m tests); "
             "else not resolved (a point of one realization leaves its steps so); needs >= 3 ratios",
        tolerance=_LEVEL,
        reason="paper: 'the magnitude of the vorticity increases monotonically with alpha_c' "
               "(Fig. 7b): a line can rise across the range over a step down, which the slope "
               "check does not see",
        tier_reasons={
            "quick": "level 0.95 as at every tier: one bed per point leaves each step without a "
                     "scatter estimate, not resolved",
            "standard": "level 0.95: the standard sweeps' one or two realizations per point leave "
                        "a step untested (one) or give each side of it 1 dof (two), so only a clear "
                        "step is resolved",
            "paper": "level 0.95: the paper gives no number; 5 realizations per point, Welch's t "
                     "with up to 8 dof per step"}),
    CheckDef(
        id="wrms_ratio_bend_later", sweep="ratio",
        check="W_rms curvature vs alpha_c/alpha_p, last window against the first",
        figure="Fig. 7b",
        rule="the first and last vorticity windows (of the same length, as wrms_early_larger); "
             "per run d = W_rms(last) / mean W_rms(last) - W_rms(first) / mean W_rms(first), "
             "each window scaled by its mean over the runs (the later window's vorticity is "
             "smaller: the shape is compared, not the size); quadratic fit of d against the "
             "ratio, paired per run: its c2 is the later window's relative curvature minus the "
             "earlier's; t test of c2 (as pmax_ratio_quadratic: the larger p of the per-point and pooled tests): pass "
             "c2 > 0 with p < 1 - level and the later window bending up (its own c2 > 0, as the "
             "paper's quadratic); opposite resolved: c2 < 0 with p < 1 - level; else not "
             "resolved; needs >= 4 ratios and >= 4 runs",
        tolerance=_LEVEL,
        reason="paper: 'the magnitude of the vorticity increases monotonically with alpha_c and "
               "the deviation from the linear approximation is stronger in the steady state, "
               "i.e., after the first 10 cycles' (Fig. 7b), read along its rising quadratic",
        tier_reasons=_CURVATURE_REASONS),
    CheckDef(
        id="wrms_early_larger", sweep="both", check="W_rms first window > last ({point})",
        figure="Fig. 6 text, Fig. 7a text",
        rule="per run, d = W_rms of the first vorticity window minus that of the last (summary.csv, "
             "the same run); over the realizations of the point, interval mean +- k sem, k the "
             "Student t quantile at `level` (n - 1 dof); pass: the interval above 0; opposite "
             "resolved: the interval below 0; else (or one realization) not resolved; needs two "
             "windows of the same length (the accumulated displacement grows with the cycles "
             "summed)",
        tolerance=_LEVEL,
        reason="paper: 'the magnitude of the vorticity in the first 10 cycles is higher than in "
               "the second 10 cycles because when the system has lower density, the particles "
               "can move more freely' (Fig. 6); 'the magnitudes are larger at the beginning "
               "stages of the thermal loading' (Fig. 7a)",
        tier_reasons={
            "quick": "level 0.95 as at every tier: one bed per point has no scatter estimate and "
                     "reads not resolved; its windows lie before any steady state",
            "standard": "level 0.95: paired per run (the same bed in both windows), so the beds' "
                        "own scatter cancels; 2 realizations give 1 dof (k = 12.7)",
            "paper": "level 0.95: the paper gives the order of the two windows, no number; "
                     "5 realizations per point, paired per run"}),
    CheckDef(
        id="volume_end", sweep="both", check="V/V0 at the end ({point})",
        figure="Fig. 4",
        rule="V_over_V0_end over the realizations of the point: interval mean +- k sem, k the "
             "Student t quantile at `level` (n - 1 dof); pass: the interval below 1 "
             "(compaction resolved); opposite resolved: the interval above 1; else (or one "
             "realization) not resolved",
        tolerance=_LEVEL,
        reason="paper: the bed compacts during the first cycles (V/V0 falls below 1) and keeps "
               "that density in the steady state (Fig. 4)",
        tier_reasons={
            "quick": "level 0.95 as at every tier: one bed per point has no scatter estimate "
                     "and reads not resolved",
            "standard": "level 0.95: 2 realizations give 1 dof (k = 12.7), so only a clear "
                        "compaction is resolved",
            "paper": "level 0.95: the paper gives no number for the compaction, only its sign"}),
    CheckDef(
        id="volume_saturation", sweep="both", check="V/V0 saturation ({point})",
        figure="Fig. 4",
        rule="per run, end-of-cycle V/V0 (V/V0 = 1 before cycling), N cycles, m = N // 3: "
             "d_first = v[0] - v[m], d_last = v[N-m] - v[N]; over the realizations, intervals "
             "mean +- k sem (Student t at `level`, n - 1 dof) of d_first and of d_last - "
             "d_first (measured); pass: d_first > 0 and d_last - d_first < 0, both resolved; "
             "opposite resolved: d_last - d_first > 0 or d_first < 0 resolved; else (or one "
             "realization) not resolved; needs N >= min_cycles",
        tolerance=_LEVEL_3_CYCLES,
        reason="paper: compaction in the first cycles followed by a saturation that matches "
               "the pressure's steady state (Fig. 4)",
        tier_reasons={
            "quick": "thirds need 3 cycles (fewer: skipped); one bed per point reads not resolved",
            "standard": "the first third compacts resolved more than the last, paired per run",
            "paper": "with 20 cycles the last third is in the steady state"}),
)}


#: Fig. 5, Fig. 6 and the steady state (issue 30 part 3), evaluated in analysis/fields.py
#: from each run's stage_fields.csv and cycles.csv, under the rules above: the paper's
#: thresholds at every tier, 95 % Student t intervals for means (as volume_end) and k = 2
#: SE for slopes (as the other monotone slopes); a resolved opposite is against(tier).
_FIELD_LEVEL_REASONS = {
    "quick": "level 0.95 as at every tier: one bed per point, so the interval is over its few "
             "cycles (3 cycles: 2 dof, k = 4.3); a CI-scale bed reads not resolved or "
             "contradicted at this scale, never a looser pass",
    "standard": "level 0.95: over the realizations (n - 1 dof; 2 realizations: k = 12.7), so "
                "only a clear motion is resolved",
    "paper": "level 0.95: over 5 realizations (4 dof, k = 2.78); the paper gives the sense of "
             "the motion, no number",
}
_K_STEADY = _same_at_every_tier(k=2.0, min_cycles=6)
_K_STEADY_REASONS = {
    "quick": "skipped: 3 cycles have no steady half to measure against (k = 2 as at every tier)",
    "standard": "k = 2 as at every tier (about 97.5 % one-sided confidence); 6 cycles resolve "
                "the steady half only roughly, which widens SE, not k",
    "paper": "k = 2: about 97.5 % one-sided confidence for a normal estimate, over 25 runs",
}
CHECKS.update({c.id: c for c in (
    CheckDef(
        id="stage_heating_direction", sweep="both", check="heating: outward and downward ({point})",
        figure="Fig. 5",
        rule="grain means over the heating of each cycle, averaged over the cycles: u_r of the grains "
             "off the axis (cells from ir = 1) and u_z of all grains; per point the mean over the "
             "realizations with its Student t interval at `level` (n - 1 dof; one realization: over "
             "its cycles, cycles - 1 dof); pass: the u_r interval above 0 and the u_z interval below "
             "0; opposite resolved: either interval entirely on the other side of 0; else (or one "
             "cycle of one run) not resolved; only at theta_c = 0 deg with alpha_c/alpha_p = 10, the "
             "point the paper shows Fig. 5 for: at other points skipped, with the intervals measured",
        tolerance=_LEVEL,
        reason="paper: during heating the grains move outwards and downwards (Fig. 5): the "
               "container widens more than the grains grow (alpha_c > alpha_p) and the bed slumps",
        tier_reasons=_FIELD_LEVEL_REASONS),
    CheckDef(
        id="stage_cooling_direction", sweep="both", check="cooling: inward and upward ({point})",
        figure="Fig. 5",
        rule="as stage_heating_direction over the cooling (from the end of heating to the end of "
             "cooling): pass: the u_r interval below 0 and the u_z interval above 0; opposite "
             "resolved: either interval entirely on the other side of 0; else not resolved; only at "
             "the paper's point of Fig. 5 (theta_c = 0 deg, alpha_c/alpha_p = 10), as "
             "stage_heating_direction",
        tolerance=_LEVEL,
        reason="paper: during cooling the grains move inwards and upwards (Fig. 5): the "
               "contracting container squeezes the bed",
        tier_reasons=_FIELD_LEVEL_REASONS),
    CheckDef(
        id="still_zone", sweep="both", check="still zone at the bottom ({point})",
        figure="Fig. 5",
        rule="f = grain mean of the stage displacement magnitude (heating and cooling alike) in the "
             "cells with r < R/3 and z < H/4 (R, H the bed's radius and height; at least the cell on "
             "the axis at the floor) over that of the whole bed, averaged over the cycles; per point "
             "the Student t interval at `level` as stage_heating_direction; pass: the interval below "
             "f_max; opposite resolved: the interval above f_max, unless a run's region is only the "
             "forced floor-axis cell (a cell coarser than the zone mixes moving grains in: not "
             "resolved); else not resolved; only at the paper's point of Fig. 5 (theta_c = 0 deg, "
             "alpha_c/alpha_p = 10), as stage_heating_direction",
        tolerance=_same_at_every_tier(f_max=0.3, level=0.95),
        reason="paper: a still conical zone at the bottom, grains that hardly move (Fig. 5)",
        tier_reasons={
            "quick": "the paper's reading at every tier: cells of 2 grain sizes put the zone's edge "
                     "into the bottom-axis cell, which reads not resolved, never a looser pass",
            "standard": "f_max 0.3 as at the paper tier: a bed a few cells wide that mixes the "
                        "zone's edge in reads not resolved or contradicted at this scale",
            "paper": "f_max 0.3: 'hardly move' read as under a third of the bed's mean; the paper "
                     "gives no number; 95 % interval over the realizations"}),
    CheckDef(
        id="toroidal_cell", sweep="both", check="toroidal convection cell ({point})",
        figure="Fig. 6",
        rule="per run, the cumulative field (heating + cooling summed over the second half of "
             "the cycles) and its vorticity w on the interior cells; coherence "
             "s = sum w / sum |w| (1 or -1: one sense over the whole core), a = s times the sense of "
             "the point's summed circulation; with >= 2 realizations, Student t intervals at `level` "
             "(n - 1 dof): pass: the interval of mean a at or above s_min; opposite resolved: the "
             "interval of mean |s| below s_fail (no dominant cell); else not resolved (realizations "
             "turning opposite ways widen the interval of a); one realization: pass when a >= s_min "
             "and its per-cycle circulation's interval (cycles - 1 dof) excludes 0, else not resolved",
        tolerance=_same_at_every_tier(s_min=0.5, s_fail=0.2, level=0.95),
        reason="paper: toroidal convection cells in every case (Fig. 6): the accumulated "
               "displacement turns one way around a ring in the (r, z) plane",
        tier_reasons={
            "quick": "the paper's thresholds at every tier: a 45-grain bed over 2 cycles has few "
                     "interior cells (often skipped) and one realization, never a contradiction",
            "standard": "as the paper tier: 6 cycles leave the cumulative field noisy, which widens "
                        "the interval and reads not resolved",
            "paper": "s_min 0.5 (three quarters of |w| turning one way); below 0.2 there is no "
                     "dominant cell, against the paper; 95 % intervals over 5 realizations"}),
    CheckDef(
        id="pmax_rise", sweep="both", check="P_max rises in the first cycles ({point})",
        figure="Fig. 3a / 3c",
        rule="per run, the rise r = (P_s - P_1) / P_s of the steady peak pressure P_s (the "
             "mean peak of the second half of the cycles, as the steady band of "
             "steady_time_theta) over the first cycle's peak P_1 (cycles.csv); over the "
             "realizations of the point, interval mean +- k sem, k the Student t quantile at "
             "`level` (n - 1 dof); pass: the interval above 0 (a rise resolved); opposite "
             "resolved: the interval below 0 (the peaks fall into their steady state); else "
             "(or one realization) not resolved; skipped below min_cycles or without a "
             "positive steady peak",
        tolerance=_LEVEL_3_CYCLES,
        reason="paper: 'two regimes appear for all parameters. In the first regime, i.e., during "
               "the first cycles, the pressure increases' (Fig. 3a, 3c), because the bed compacts",
        tier_reasons={
            "quick": "level 0.95 as at every tier: one bed per point has no scatter estimate and "
                     "reads not resolved; its 3 cycles give a 'steady' half of 2 cycles, which "
                     "still measures a rise from the first",
            "standard": "level 0.95: paired per run (the same bed's first and later peaks); 2 "
                        "realizations give 1 dof (k = 12.7), so only a clear rise is resolved",
            "paper": "level 0.95 over 5 realizations (4 dof, k = 2.78); the paper says the peaks "
                     "rise for all parameters, no number"}),
    CheckDef(
        id="pmax_follows_density", sweep="both", check="P_max rises with the packing density ({point})",
        figure="Fig. 3a / 3c, Fig. 4",
        rule="per run, Spearman's rank correlation rho (scipy.stats.spearmanr) over its cycles "
             "between the cycle's peak pressure and its packing density at the end of the cooling, "
             "-V/V0 there (cycles.csv; the grains back at T_0, so the bed volumes compare like for "
             "like); over the realizations of the point, interval mean rho +- k sem, k the Student "
             "t quantile at `level` (n - 1 dof), clipped to [-1, 1]; pass: the interval above 0; "
             "opposite resolved: the interval below 0 (the peaks fall while the bed compacts); else (or one realization) "
             "not resolved; runs whose peaks or densities do not change are left out; skipped below "
             "min_cycles",
        tolerance=_LEVEL_6_CYCLES,
        reason="paper: 'The first regime is due to compaction of the granular material, since "
               "pressure increases as the total packing density increases' (Fig. 3a, 3c with Fig. 4)",
        tier_reasons={
            "quick": "skipped: 3 cycles give a rank correlation of 3 points (level 0.95 as at every tier)",
            "standard": "level 0.95: one or two realizations per point (one: not resolved; two: 1 dof, "
                        "k = 12.7), so only a clear sense is resolved; 6 cycles",
            "paper": "level 0.95 over 5 realizations (4 dof, k = 2.78), 20 cycles each; the paper "
                     "gives the sense, no number"}),
    CheckDef(
        id="steady_time_theta", sweep="angle", check="cycles to the steady state vs theta_c",
        figure="Results text, Fig. 3a",
        rule="per run the first cycle whose peak pressure lies in the steady band: mean of the "
             "second half of the cycles +- max(2 sigma, 5 % of it), sigma their standard "
             "deviation; linear fit over all runs: pass slope + k SE < 0; opposite resolved: "
             "slope - k SE > 0; else not resolved; skipped below min_cycles" + _WIDENED,
        tolerance=_K_STEADY,
        reason="paper: the steady state comes sooner at larger opening angles",
        tier_reasons=_K_STEADY_REASONS),
    CheckDef(
        id="steady_time_ratio", sweep="ratio", check="cycles to the steady state vs alpha_c/alpha_p",
        figure="Fig. 3c",
        rule="per run whose peaks rise into the steady band (the first below it) the first "
             "cycle whose peak lies in the band (as steady_time_theta); runs whose peaks fall "
             "or start in the band have no rise to time and are left out, said; linear fit "
             "over the others: pass |slope| - k SE > 0, either sign "
             "(the sign is reported); no dependence resolved: (|slope| + k SE) x range at most "
             "FLAT_RESOLUTION of the runs' mean cycles to the steady state (two one-sided tests), "
             "against the paper; else not resolved; skipped below min_cycles" + _WIDENED,
        tolerance=_K_STEADY,
        reason="paper: 'alpha_c/alpha_p introduces a time scale that determines the rate of peak "
               "pressure increase as a function of the number of cycles' (Fig. 3c): the length of "
               "the rise, in cycles, depends on the ratio; the paper gives no direction, so either "
               "sign passes and only a resolved absence of any dependence is against it",
        tier_reasons=_K_STEADY_REASONS),
    CheckDef(
        id="steady_volume_flat", sweep="both", check="steady V/V0 vs {x}",
        figure="Fig. 4",
        rule="per run the peak density of each cycle, its lowest V/V0 (the V/V0 series: "
             "timeseries.csv, or a campaign's volume.csv), averaged over the second half of the "
             "cycles (not V/V0 at the end of cooling, which the dilation during cooling lifts); "
             "linear fit over all runs: pass when (|slope| + k SE) x range is at most "
             "FLAT_RESOLUTION of the bed's compaction 1 - V/V0 (two one-sided tests; V/V0 "
             "itself is near 1, so a margin of it would pass any scatter); opposite resolved: "
             "(|slope| - k SE) x range above that margin; else not resolved; skipped below "
             "min_cycles" + _WIDENED,
        tolerance={"quick": {"k": 3.0, "min_cycles": 6}, "standard": {"k": 2.5, "min_cycles": 6},
                   "paper": {"k": 2.0, "min_cycles": 6}},
        reason="paper: 'the material reaches nearly the same peak density for all investigated "
               "parameters' (conclusion, read off Fig. 4)",
        tier_reasons={
            "quick": "skipped: 3 cycles reach no steady density (k = 3 as wrms_theta_flat)",
            "standard": "k = 2.5 as wrms_theta_flat: a few realizations per point leave SE uncertain",
            "paper": "k = 2: consistent with zero at about 95 % two-sided confidence"}),
    CheckDef(
        id="cooling_dilation_present", sweep="angle", check="dilation during cooling ({point})",
        figure="Fig. 4a",
        rule="per run the dilation during cooling of cooling_dilation_ratio (in each cooling "
             "ramp the largest rise of V/V0 above its lowest value so far, averaged over the "
             "second half of the cycles; from the V/V0 series); per point the mean over the "
             "realizations with its Student t interval at `level` (n - 1 dof; one realization: "
             "over its steady cycles); pass: the interval above d_min (a rise the paper's "
             "Fig. 4 would show); opposite resolved: the interval below d_min (no visible "
             "dilation); else not resolved; runs without a V/V0 series left out, said; skipped "
             "below min_cycles",
        tolerance=_same_at_every_tier(level=0.95, d_min=1e-3, min_cycles=6),
        reason="paper: 'small increases [of V/V0] during the cooling at the steady state ... "
               "caused by dilatation ... dilatation is present for all angles theta_c' (Fig. 4a)",
        tier_reasons={
            "quick": "skipped: 3 cycles reach no steady state (d_min and level as at every tier)",
            "standard": "as the paper tier: 6 cycles give a steady half of 3 cycles per run",
            "paper": "d_min 1e-3: a tenth of a percent of the volume, about a hundredth of the "
                     "bed's compaction (V/V0 near 0.9), the least a figure of V/V0 over the "
                     "cycles shows; every V/V0 rise of the series is the grains' (the hull is "
                     "exact), so d_min separates visible from invisible, not signal from noise; "
                     "95 % interval over 5 realizations"}),
    CheckDef(
        id="cooling_dilation_ratio", sweep="ratio", check="dilation during cooling vs alpha_c/alpha_p",
        figure="Fig. 4b",
        rule="per run, in each cooling ramp the largest rise of V/V0 above its lowest value so "
             "far in the ramp (0 when V/V0 only falls; from the V/V0 series), averaged over the "
             "second half of the cycles; linear fit over all runs: pass slope - k SE > 0; "
             "opposite resolved: slope + k SE < 0; else not resolved; skipped below min_cycles"
             + _WIDENED,
        tolerance=_K_STEADY,
        reason="paper: 'small increases [of V/V0] during the cooling at the steady state ... "
               "caused by dilatation', whose magnitude 'decreases with decreasing alpha_c' (Fig. "
               "4b). The swing between the ends of heating and cooling is not it: the container's "
               "own contraction, alpha_c dT, makes it grow with alpha_c whatever the grains do",
        tier_reasons=_K_STEADY_REASONS),
)})


# --------------------------------------------------------------------------- results


@dataclass
class CheckResult:
    case: str
    check: str
    check_id: str
    status: str                      # one of STATUSES
    measured: float | None = None
    expected: str = ""
    tolerance: str = ""
    reason: str = ""
    detail: dict = field(default_factory=dict)

    @property
    def passed(self) -> bool:
        return self.status == "passed"

    def record(self) -> dict:
        """The JSON line of check_record.hpp (not for skipped checks): a not-resolved
        check has "passed": true, "resolved": false; a contradicted one "passed": false,
        "resolved": true, "contradicted": true."""
        measured = self.measured
        if measured is not None and not math.isfinite(measured):
            measured = None
        line = {"case": self.case, "check": self.check, "measured": measured,
                "expected": self.expected, "tolerance": self.tolerance,
                "reason": self.reason, "passed": self.status in ("passed", "unresolved")}
        if self.status == "unresolved":
            line["resolved"] = False
        if self.status == "contradicted":
            line["resolved"] = True
            line["contradicted"] = True
        return line

    def to_dict(self) -> dict:
        out = self.record()
        out["status"] = self.status
        out["id"] = self.check_id
        out["detail"] = self.detail
        return out


def against(tier: str) -> str:
    """The status of a resolved contradiction: failed at the paper's own scale,
    contradicted at a reduced one."""
    return "failed" if tier == PAPER_TIER else "contradicted"


_PREFIX = {"unresolved": "not resolved at this scale: ",
           "contradicted": "contradicted at this scale (reduced): ",
           "failed": "failed: "}


def _result(a: "Analysis", definition: CheckDef, check: str, status: str, measured,
            expected: str, tolerance: str, why: str, detail: dict) -> CheckResult:
    """A result whose reason starts with what the data show (why), then the physics and
    the tier's reason. A measured value that is not a number fails whatever the rule."""
    if measured is None or not math.isfinite(measured):
        status, why = "failed", f"the measured value is not a number{'; ' + why if why else ''}"
    reason = definition.reason_for(a.tier)
    if why:
        reason = f"{_PREFIX.get(status, '')}{why}. {reason}"
    return CheckResult(case=a.case, check=check, check_id=definition.id, status=status,
                       measured=None if measured is None else float(measured), expected=expected,
                       tolerance=tolerance, reason=reason, detail={"tier": a.tier, **detail})


def out_of_scale(result: CheckResult, reason: str | None) -> CheckResult:
    """A check whose paper statement does not cover the beds it ran on (scripts/trends
    --out-of-scale): a pass becomes not resolved (it cannot show the statement there);
    a resolved contradiction stays one, as "contradicted" (never "not resolved" or
    "passed"), since these beds are not the paper's scale. The measured value and the
    status the rule gave stay in view (detail.verdict_at_tolerance). Skipped,
    not-resolved and non-finite (failed) checks stay as they are."""
    if not reason or result.status not in ("passed", "failed", "contradicted"):
        return result
    finite = result.measured is not None and math.isfinite(result.measured)
    if result.status == "failed" and not finite:
        return result
    if result.status == "passed":
        status, text = "unresolved", f"not resolved at this scale: {reason} (the rule alone would pass it)"
    else:
        status, text = "contradicted", (f"contradicted at this scale (reduced): {reason}; the data "
                                        "resolve the opposite of the paper's statement")
    body = result.reason
    for prefix in _PREFIX.values():
        body = body.removeprefix(prefix)
    return CheckResult(case=result.case, check=result.check, check_id=result.check_id,
                       status=status, measured=result.measured, expected=result.expected,
                       tolerance=result.tolerance, reason=f"{text}. {body}",
                       detail={**result.detail, "verdict_at_tolerance": result.status})


def _skip(case: str, definition: CheckDef, check: str, why: str, tier: str) -> CheckResult:
    return CheckResult(case=case, check=check, check_id=definition.id, status="skipped",
                       measured=None, expected="", tolerance="",
                       reason=f"skipped: {why}", detail={"tier": tier})


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
    steady: dict = field(default_factory=dict)      # point -> {"state", "text", ...}
    results: list[CheckResult] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)

    def point_label(self, value: float) -> str:
        unit = X_UNITS[self.kind]
        return f"{self.x_label}={value:g}" + (f" {unit}" if unit else "")


def fixed_parameter(kind: str) -> tuple[str, float, str]:
    """The parameter a study along `kind` holds at the paper's value: (column, value, label)."""
    return (RATIO, PAPER_RATIO, "alpha_c/alpha_p") if kind == "angle" else (ANGLE, PAPER_ANGLE, "theta_c")


def study_runs(sweep: Sweep, kind: str, notes: list[str]) -> pd.DataFrame:
    """The completed runs along `kind`; a grid is cut where the paper fixed the other."""
    data = sweep.completed
    other, reference, label = fixed_parameter(kind)
    if other in data.columns:
        values = data[other].dropna().unique()
        if len(values) > 1:
            chosen = float(values[np.argmin(np.abs(values - reference))])
            notes.append(f"{label} varies too: the {kind} study uses the runs at {label} = "
                         f"{chosen:g} (nearest the paper's {reference:g})")
            data = data[np.isclose(data[other], chosen)]
    return data.copy()


def _values(data: pd.DataFrame, x: str, metric: str) -> pd.DataFrame:
    values = data[[x, metric]].apply(pd.to_numeric, errors="coerce")
    return values[np.isfinite(values[x]) & np.isfinite(values[metric])]


def metric_fits(data: pd.DataFrame, x: str, metric: str) -> dict:
    """Group statistics and linear/quadratic fits of one metric along x."""
    values = _values(data, x, metric)
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
    """direction: "decrease" (pass slope + k SE < 0), "increase" (pass slope - k SE > 0)
    or "flat" (pass |slope| <= k SE, resolved by FLAT_RESOLUTION); the opposite, resolved
    at the same k, is a contradiction."""
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
    k_tier, k = k, fits.widened_k(k, fit.dof)  # few runs: Student t at the fit's dof
    unit = f" per {X_UNITS[a.kind]}" if X_UNITS[a.kind] else ""
    if se > 0:
        in_se = slope / se
    else:  # no scatter: any nonzero slope is resolved
        in_se = math.copysign(math.inf, slope) if slope else 0.0
    detail = {"k": k, "k_tier": k_tier, "slope": slope, "se": se, "slope_in_se": in_se, "n": fit.n,
              "dof": fit.dof, "points": int(len(groups))}
    k_text = f"{k:.3g} SE ({k_tier:g} SE widened to Student t at {fit.dof} dof)"
    if direction == "flat":
        expected = "0"
        tolerance = f"abs {k_text} = {k * se:.4g} (SE {se:.4g}{unit})"
        span = float(groups["x"].max() - groups["x"].min())
        mean = float(np.average(groups["mean"], weights=groups["n"]))
        status, why, detail["allowed_change"] = flat_verdict(slope, se, k, span, abs(mean),
                                                            f"the mean {mean:.3g}", tier)
        if status == against(tier):
            why = (f"the slope {slope:.3g} +- {se:.2g}{unit} ({in_se:.2g} SE) resolves a "
                   f"dependence on {a.x_label}: {why}")
    else:
        sign = -1.0 if direction == "decrease" else 1.0
        expected = "< 0" if direction == "decrease" else "> 0"
        tolerance = f"{k_text} beyond 0 (SE {se:.4g}{unit})"
        if sign * slope - k * se > 0:
            status, why = "passed", ""
        elif sign * slope + k * se < 0:
            status = against(tier)
            why = (f"the slope {slope:.3g} +- {se:.2g}{unit} ({in_se:.2g} SE) is resolved "
                   f"{'above' if sign < 0 else 'below'} 0, the opposite of the paper")
        else:
            status = "unresolved"
            why = f"the slope {slope:.3g} +- {se:.2g}{unit} ({in_se:.2g} SE) is within {k:.3g} SE of 0"
    return _result(a, definition, check, status, slope, expected, tolerance, why, detail)


# ---- steady state


def _steady_checks(a: Analysis) -> list[CheckResult]:
    """pmax_steady per point; fills a.steady[point] with state "steady", "not steady" or
    "unknown" for the P_max checks (_gate_steady)."""
    definition = CHECKS["pmax_steady"]
    p = definition.params(a.tier)
    out = []
    for value in sorted(a.data[a.x].dropna().unique()):
        check = definition.check.format(point=a.point_label(value))
        runs = a.data[np.isclose(a.data[a.x], value)]
        series, why_not = [], []
        for run in runs["run"]:
            data, why = steady_peaks(run_dir(a.sweep.folder, int(run)))
            if data is None:
                why_not.append(f"run {int(run)}: {why}")
            elif len(data["peaks"]) >= 2:
                series.append(data)
            else:
                why_not.append(f"run {int(run)}: {len(data['peaks'])} finite peak(s) in its "
                               f"steady cycles {data['window']}")
        a.steady[float(value)] = {"state": "unknown", "text": ""}
        if not series:
            out.append(_skip(a.case, definition, check,
                             "no run with >= 2 steady cycles of peaks (" +
                             ("; ".join(why_not) or "no run") + ")", a.tier))
            continue
        if len(series) >= 2:
            slopes = [fits.linear_fit(s["cycles"], s["peaks"]).slope for s in series]
            stat = fits.mean_interval(slopes, p["level"])
            slope, se, k, dof = stat["mean"], stat["sem"], stat["k"], stat["dof"]
            how = f"mean of {len(series)} runs' slopes"
        else:
            fit = fits.linear_fit(series[0]["cycles"], series[0]["peaks"])
            slope, se, dof = fit.slope, fit.slope_se, fit.dof
            k = fits.t_quantile(p["level"], dof)
            how = "one run's fit"
        span = max(float(s["cycles"].max() - s["cycles"].min()) for s in series)
        mean_peak = float(np.mean(np.concatenate([s["peaks"] for s in series])))
        windows = sorted({tuple(s["window"]) for s in series})
        detail = {"slope": slope, "se": se, "k": k, "dof": dof, "runs": len(series),
                  "mean_peak": mean_peak, "steady_cycles": [list(w) for w in windows],
                  "window_source": series[0]["window_source"], "level": p["level"]}
        tolerance = (f"{p['level']:.0%} interval +- {k * se:.3g} per cycle ({how}, {dof} dof); "
                     f"drift over {span:g} cycles <= {p['drift']:g} x mean peak {mean_peak:.4g}"
                     if math.isfinite(k * se) else f"no interval: {how} with {dof} dof")
        if not math.isfinite(k * se):
            status = "unresolved"
            why = (f"one run with {len(series[0]['peaks'])} steady cycles gives no scatter "
                   "estimate of the peaks' trend")
        else:
            status, why, detail["allowed_drift"] = flat_verdict(
                slope, se, k, span, abs(mean_peak), f"the mean peak {mean_peak:.4g}", a.tier,
                fraction=p["drift"], across="the steady cycles")
            if status == "passed":
                a.steady[float(value)]["state"] = "steady"
            elif status != "unresolved":   # not steady: a failure only at the paper's scale
                status = "failed" if a.tier == PAPER_TIER else "unresolved"
                least = (abs(slope) - k * se) * span
                why = (f"not steady: the peak changes by {slope:.3g} +- {k * se:.2g} per cycle "
                       f"({p['level']:.0%} interval) over cycles {windows[0][0]}-{windows[0][1]}, at "
                       f"least {least / mean_peak:.0%} of the mean peak across them, beyond "
                       f"{p['drift']:g} x the mean peak")
                a.steady[float(value)] = {"state": "not steady", "text": why}
        out.append(_result(a, definition, check, status, slope, "0 (no trend)", tolerance, why,
                           detail))
    return out


def _gate_steady(a: Analysis, result: CheckResult, points) -> CheckResult:
    """A P_max check that uses a point whose peaks are resolved not steady reads not
    resolved ("not steady"), whatever its rule gave: P_max is the paper's steady-state
    mean and these cycles are not it."""
    if result.status == "skipped" or result.measured is None or not math.isfinite(result.measured):
        return result
    moving = [(v, a.steady[v]) for v in sorted(a.steady) if a.steady[v]["state"] == "not steady"
              and any(math.isclose(v, float(q)) for q in points)]
    if not moving:
        return result
    where = "; ".join(f"{a.point_label(v)}: {s['text'].removeprefix('not steady: ')}" for v, s in moving)
    body = result.reason
    for prefix in _PREFIX.values():
        body = body.removeprefix(prefix)
    return CheckResult(case=result.case, check=result.check, check_id=result.check_id,
                       status="unresolved", measured=result.measured, expected=result.expected,
                       tolerance=result.tolerance,
                       reason=(f"not resolved at this scale: not steady ({where}); on these "
                               f"cycles the rule gives '{result.status}'. {body}"),
                       detail={**result.detail, "verdict_if_steady": result.status,
                               "not_steady": [float(v) for v, _ in moving]})


# ---- the 6/0 deg ratio


def realizations_needed(ratio: dict, p: Mapping[str, float]) -> int | None:
    """Realizations per angle for the interval to settle the ratio: to lie inside the
    band (R inside it) or outside it (R outside), from sigma_R ~ 1/sqrt(n) at the
    measured scatter and the normal quantile (the large-n limit of Student t). None
    without a scatter estimate or with R on the band's edge."""
    sigma = ratio["sigma"]
    n = min(ratio["numerator"]["n"], ratio["denominator"]["n"])
    margin = abs(p["half_width"] - abs(ratio["ratio"] - p["target"]))
    if not math.isfinite(sigma) or n < 2 or margin <= 0:
        return None
    z = float(stats.norm.ppf(0.5 * (1.0 + p["level"])))
    return max(n, math.ceil(n * (z * sigma / margin) ** 2))


def _straddled(low: float, high: float, value: float, band: tuple[float, float], inside: bool) -> str:
    """Which edge of the band an interval that neither lies inside nor outside it crosses,
    and on which side of that edge the ratio itself lies (inside: R within the band): a
    ratio at 0.347 in [0.327, 0.366] against 0.35-0.65 is short of a half, not merely
    uncertain."""
    if low < band[0] and high > band[1]:
        return f"reaches beyond both edges of the paper's band {band[0]:g}-{band[1]:g}"
    edge = band[0] if low < band[0] else band[1]
    if inside:
        side = "inside the band"
    else:
        side = "below it" if value < band[0] else "above it"
    return f"straddles the paper's band's edge {edge:g} ({band[0]:g}-{band[1]:g}), R = {value:.3g} {side}"


def _halving_check(a: Analysis) -> CheckResult:
    definition = CHECKS["pmax_ratio_6_0"]
    p = definition.params(a.tier)
    low_angle, high_angle = HALVING_ANGLES
    data = a.data[[a.x, "P_max"]].apply(pd.to_numeric, errors="coerce")
    at_low = data.loc[np.isclose(data[a.x], low_angle), "P_max"].dropna()
    at_high = data.loc[np.isclose(data[a.x], high_angle), "P_max"].dropna()
    if at_low.empty or at_high.empty:
        missing = " and ".join(f"{v:g} deg" for v, s in ((low_angle, at_low), (high_angle, at_high))
                               if s.empty)
        return _skip(a.case, definition, definition.check,
                     f"no completed run with a finite P_max at {missing}", a.tier)
    ratio = fits.ratio_of_means(at_high, at_low)
    a.halving = ratio
    if not math.isfinite(ratio["ratio"]):
        return _skip(a.case, definition, definition.check,
                     f"mean P_max at {low_angle:g} deg is {ratio['denominator']['mean']:g}: "
                     "no ratio", a.tier)
    value, sigma = ratio["ratio"], ratio["sigma"]
    band = (p["target"] - p["half_width"], p["target"] + p["half_width"])
    k = fits.t_quantile(p["level"], ratio["dof"])
    needed = realizations_needed(ratio, p)
    detail = {**ratio, "k": k, "level": p["level"], "band": list(band),
              "interval": [value - k * sigma, value + k * sigma], "realizations_needed": needed}
    expected = f"{p['target']:g} +- {p['half_width']:g}"
    if not (math.isfinite(sigma) and math.isfinite(k)):
        tolerance = f"{p['level']:.0%} interval inside {band[0]:g}-{band[1]:g}; sigma_R n/a"
        why = ("one realization at 0 or 6 deg gives no estimate of the scatter, and single "
               "beds scatter by tens of per cent")
        return _result(a, definition, definition.check, "unresolved", value, expected,
                       tolerance, why, detail)
    low, high = value - k * sigma, value + k * sigma
    tolerance = (f"{p['level']:.0%} interval [{low:.3g}, {high:.3g}] inside {band[0]:g}-{band[1]:g} "
                 f"(R +- {k:.3g} sigma_R, sigma_R {sigma:.3g}, Student t, {ratio['dof']:.3g} dof)")
    inside = band[0] <= value <= band[1]
    more = (f"; about {needed} realizations per angle would resolve it ({'inside' if inside else 'outside'} "
            f"the band, if R stays at {value:.3g})" if needed else "")
    if band[0] <= low and high <= band[1]:
        status, why = "passed", ""
    elif high < band[0] or low > band[1]:
        status = against(a.tier)
        why = (f"the {p['level']:.0%} interval [{low:.3g}, {high:.3g}] lies outside the paper's "
               f"band {band[0]:g}-{band[1]:g}: the cone lowers the peak by "
               f"{1 - value:.0%}, not by a half")
    else:
        status = "unresolved"
        why = (f"the {p['level']:.0%} interval [{low:.3g}, {high:.3g}] "
               f"{_straddled(low, high, value, band, inside)}; the cone lowers the peak by {1 - value:.0%}, "
               f"and an exact halving, R = {p['target']:g}, lies "
               f"{'inside' if low <= p['target'] <= high else 'outside'} the interval{more}")
    return _result(a, definition, definition.check, status, value, expected, tolerance, why, detail)


# ---- curvature


def _scatter_said(test: dict) -> str:
    """Which scatter a curvature's SE came from, in a few words (fits.curvature_test)."""
    if test["scatter"] == "pooled":
        return f"pooled residual scatter, {test['dof']:.3g} dof"
    borrowed = test["per_point"]["borrowed"]
    said = f"each point's own scatter, {test['dof']:.3g} dof (Welch-Satterthwaite)"
    if borrowed:
        said += (f"; {', '.join(f'{v:g}' for v in borrowed)} of one realization take "
                 f"{test['per_point']['borrowed_from']:g}'s")
    pooled = test["pooled"]
    return said + f"; pooled scatter would give {pooled['t']:.2g} SE, p = {pooled['p']:.3g}"


def _curvature_detail(test: dict) -> dict:
    """The curvature test's numbers for a check's detail."""
    detail = {key: test[key] for key in ("c2", "se", "t", "F", "p", "dof", "scatter")}
    detail["pooled"] = dict(test["pooled"])
    if test["per_point"] is not None:
        detail["borrowed"] = test["per_point"]["borrowed"]
        detail["point_sd"] = {f"{x:g}": sd for x, sd in test["per_point"]["point_sd"].items()}
    return detail


def _curvature_check(a: Analysis, definition: CheckDef, metric: str, check: str) -> CheckResult:
    """Pass only a resolved upward curvature (t test of the x^2 term, fits.curvature_test)."""
    level = definition.params(a.tier)["level"]
    alpha = 1.0 - level
    if metric not in a.data.columns:
        return _skip(a.case, definition, check, f"no column {metric} in summary.csv", a.tier)
    values = _values(a.data, a.x, metric)
    points = int(values[a.x].nunique())
    if points < 4 or len(values) < 4:
        return _skip(a.case, definition, check,
                     f"{points} {a.x_label} value(s) and {len(values)} runs with a finite {metric}; "
                     "the curvature needs >= 4 values (a quadratic through 3 means says nothing "
                     "of its shape) and >= 4 runs", a.tier)
    test = fits.curvature_test(values[a.x], values[metric])
    c2, se, t, p_value = test["c2"], test["se"], test["t"], test["p"]
    means = a.metrics.get(metric, {}).get("means", {})
    r2 = {name: (means[name].r2 if means.get(name) is not None else math.nan)
          for name in ("linear", "quadratic")}
    detail = {**_curvature_detail(test), "level": level, "points": points, "n": int(len(values)),
              "r2_means_quadratic": r2["quadratic"], "r2_means_linear": r2["linear"],
              "coefficients": [float(c) for c in test["quadratic"].coef]}
    tolerance = (f"t test of c2 against a line p < {alpha:.2g} (p = {p_value:.3g}; c2 {c2:.4g} +- "
                 f"{se:.2g}, {t:.2g} SE; {_scatter_said(test)}; R^2 of the means: quadratic "
                 f"{r2['quadratic']:.3f}, line {r2['linear']:.3f})")
    if p_value < alpha and c2 > 0:
        status, why = "passed", ""
    elif p_value < alpha and c2 < 0:
        status = against(a.tier)
        why = (f"the curve bends down: c2 = {c2:.3g} +- {se:.2g} ({t:.2g} SE, p = "
               f"{p_value:.3g}), the opposite of the paper's rising quadratic")
    else:
        status = "unresolved"
        why = (f"a line fits as well: c2 = {c2:.3g} +- {se:.2g} ({t:.2g} SE), t test of the "
               f"quadratic term p = {p_value:.3g} >= {alpha:.2g}")
    return _result(a, definition, check, status, c2, "> 0, resolved against a line", tolerance,
                   why, detail)


def _monotone_check(a: Analysis, definition: CheckDef, metric: str, check: str) -> CheckResult:
    """Every step between neighbouring x values rises, each by Welch's t test; a resolved
    fall at any step (Bonferroni over the steps) is against the paper."""
    level = definition.params(a.tier)["level"]
    alpha = 1.0 - level
    if metric not in a.data.columns:
        return _skip(a.case, definition, check, f"no column {metric} in summary.csv", a.tier)
    values = _values(a.data, a.x, metric)
    xs = sorted(values[a.x].unique())
    if len(xs) < 3:
        return _skip(a.case, definition, check,
                     f"{len(xs)} {a.x_label} value(s) with a finite {metric}; steps need >= 3 values "
                     "(with 2 the slope check says it)", a.tier)
    m = len(xs) - 1
    steps = []
    for low, high in zip(xs[:-1], xs[1:]):
        below = values.loc[np.isclose(values[a.x], low), metric].to_numpy(dtype=float)
        above = values.loc[np.isclose(values[a.x], high), metric].to_numpy(dtype=float)
        step = {"from": float(low), "to": float(high), "n": [int(len(below)), int(len(above))],
                "d": float(above.mean() - below.mean()), "p_rise": math.nan, "p_fall": math.nan}
        if len(below) >= 2 and len(above) >= 2:
            with warnings.catch_warnings():
                # Identical values on both sides (no scatter): scipy warns of precision loss
                # and returns NaN, which reads "untested".
                warnings.simplefilter("ignore", RuntimeWarning)
                for key, side in (("p_rise", "greater"), ("p_fall", "less")):
                    step[key] = float(stats.ttest_ind(above, below, equal_var=False, alternative=side).pvalue)
        steps.append(step)
    shown, refuted = alpha / 2.0, alpha / (2.0 * m)
    rises = [s for s in steps if s["p_rise"] < shown]
    falls = [s for s in steps if s["p_fall"] < refuted]
    d_min = min(s["d"] for s in steps)

    def name(s):
        return f"{s['from']:g} to {s['to']:g}"

    detail = {"level": level, "steps": steps, "p_rise_max": shown, "p_fall_max": refuted}
    tolerance = (f"Welch t per step: every rise one-sided p < {shown:.3g}; a fall at p < {refuted:.3g} "
                 f"(Bonferroni over {m} steps) is against; step p (rise) "
                 + ", ".join(f"{name(s)}: " + (f"{s['p_rise']:.2g}" if math.isfinite(s["p_rise"]) else "untested")
                             for s in steps))
    if falls:
        worst = min(falls, key=lambda s: s["p_fall"])
        status = against(a.tier)
        why = (f"W_rms falls from {a.x_label} {name(worst)} by {-worst['d']:.3g} (Welch p = "
               f"{worst['p_fall']:.2g} < {refuted:.2g}), not monotone")
    elif len(rises) == m:
        status, why = "passed", ""
    else:
        open_steps = [s for s in steps if s not in rises]
        single = [name(s) for s in open_steps if min(s["n"]) < 2]
        why = (f"{len(open_steps)} of {m} steps not shown to rise (" +
               ", ".join(f"{name(s)}: {s['d']:+.3g}" + (f", p = {s['p_rise']:.2g}" if math.isfinite(s['p_rise'])
                                                         else ", one realization")
                         for s in open_steps) + ")")
        if single:
            why += "; a point of one realization has no scatter to test a step against"
        status = "unresolved"
    return _result(a, definition, check, status, d_min, "> 0 at every step, resolved", tolerance,
                   why, detail)


# ---- volume


def _interval_text(stat: dict, level: float, digits: int = 5) -> str:
    return (f"{level:.0%} interval [{stat['low']:.{digits}g}, {stat['high']:.{digits}g}] "
            f"(mean +- {stat['k']:.3g} sem, sem {stat['sem']:.2g}, n {stat['n']})")


def _volume_checks(a: Analysis) -> list[CheckResult]:
    out = []
    end_def, sat_def = CHECKS["volume_end"], CHECKS["volume_saturation"]
    level = end_def.params(a.tier)["level"]
    sat_level = sat_def.params(a.tier)["level"]
    min_cycles = int(sat_def.params(a.tier)["min_cycles"])
    points = sorted(a.data[a.x].dropna().unique())
    # V/V0 at the end, from summary.csv.
    if "V_over_V0_end" not in a.data.columns or not np.isfinite(
            pd.to_numeric(a.data["V_over_V0_end"], errors="coerce")).any():
        out.append(_skip(a.case, end_def, end_def.check.format(point="all points"),
                         "summary.csv has no finite V_over_V0_end (did the scenes ask for "
                         "the volume?)", a.tier))
    else:
        a.volume["end"] = fits.group_stats(a.data, a.x, "V_over_V0_end")
        values = _values(a.data, a.x, "V_over_V0_end")
        for value in points:
            check = end_def.check.format(point=a.point_label(value))
            here = values.loc[np.isclose(values[a.x], value), "V_over_V0_end"]
            if here.empty:
                out.append(_skip(a.case, end_def, check, "no finite V_over_V0_end", a.tier))
                continue
            stat = fits.mean_interval(here, level)
            detail = {k: stat[k] for k in ("n", "std", "sem", "k", "low", "high")}
            if stat["n"] < 2:
                status, why = "unresolved", "one realization gives no estimate of the scatter"
                tolerance = f"{level:.0%} interval below 1; n/a with one realization"
            else:
                tolerance = _interval_text(stat, level)
                if stat["high"] < 1.0:
                    status, why = "passed", ""
                elif stat["low"] > 1.0:
                    status = against(a.tier)
                    why = f"the bed dilates: the {level:.0%} interval lies above 1"
                else:
                    status = "unresolved"
                    why = (f"compaction within the scatter: the {level:.0%} interval "
                           f"[{stat['low']:.5g}, {stat['high']:.5g}] holds 1")
            out.append(_result(a, end_def, check, status, stat["mean"], "< 1", tolerance, why,
                               detail))
    # Saturation, from the per-run files.
    series_by_point, sources, why_not = {}, {}, {}
    for value in points:
        runs = a.data[np.isclose(a.data[a.x], value)]
        for run in runs["run"]:
            values, source = end_of_cycle_volumes(run_dir(a.sweep.folder, int(run)))
            if values is None:
                why_not.setdefault(value, []).append(f"run {int(run)}: {source}")
            else:
                series_by_point.setdefault(value, []).append(values)
                sources[value] = source
    curves = {}
    for value, series in series_by_point.items():
        length = min(len(s) for s in series)
        curves[value] = np.array([s[:length] for s in series])
    a.volume["end_of_cycle"] = {float(v): {"mean_curve": [float(x) for x in c.mean(axis=0)],
                                           "runs": int(len(c)), "source": sources.get(v, "")}
                                for v, c in curves.items()}
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
        runs = curves[value]
        cycles = runs.shape[1] - 1
        if cycles < min_cycles:
            out.append(_skip(a.case, sat_def, check,
                             f"{cycles} cycle(s) of V/V0; thirds need >= {min_cycles}", a.tier))
            continue
        m = cycles // 3
        d_first = runs[:, 0] - runs[:, m]
        d_last = runs[:, cycles - m] - runs[:, cycles]
        first = fits.mean_interval(d_first, sat_level)
        change = fits.mean_interval(d_last - d_first, sat_level)
        detail = {"d_first": first["mean"], "d_last": float(np.mean(d_last)),
                  "d_first_interval": [first["low"], first["high"]],
                  "change_interval": [change["low"], change["high"]], "sem": change["sem"],
                  "k": change["k"], "cycles": cycles, "m": m, "runs": int(len(runs)),
                  "source": sources.get(value, "")}
        texts = (f"d_first {first['mean']:.4g} (cycles 0-{m}), d_last {detail['d_last']:.4g} "
                 f"(cycles {cycles - m}-{cycles})")
        if len(runs) < 2:
            status, why = "unresolved", "one realization gives no estimate of the scatter"
            tolerance = f"{sat_level:.0%} intervals; n/a with one realization; {texts}"
        else:
            tolerance = (f"{sat_level:.0%} intervals: d_last - d_first [{change['low']:.3g}, "
                         f"{change['high']:.3g}] below 0, d_first [{first['low']:.3g}, "
                         f"{first['high']:.3g}] above 0; {texts}")
            if first["low"] > 0 and change["high"] < 0:
                status, why = "passed", ""
            elif change["low"] > 0 or first["high"] < 0:
                status = against(a.tier)
                why = ("the last third compacts resolved more than the first" if change["low"] > 0
                       else "the bed dilates resolved in the first third")
            else:
                status = "unresolved"
                why = "the slowing of the compaction is within the scatter of the realizations"
        out.append(_result(a, sat_def, check, status, change["mean"], "< 0, with d_first > 0",
                           tolerance, why, detail))
    return out


# ---- vorticity over the cycles


def _vorticity_decline_checks(a: Analysis) -> list[CheckResult]:
    """wrms_early_larger per point: the first window's W_rms against the last's, paired
    per run."""
    definition = CHECKS["wrms_early_larger"]
    level = definition.params(a.tier)["level"]
    points = sorted(a.data[a.x].dropna().unique())
    pair, why_not = _first_and_last_windows(a.sweep.windows)
    if pair is None:
        return [_skip(a.case, definition, definition.check.format(point="all points"), why_not, a.tier)]
    first, last = pair
    out = []
    for value in points:
        check = definition.check.format(point=a.point_label(value))
        rows = a.data[np.isclose(a.data[a.x], value)]
        early = pd.to_numeric(rows[first.column], errors="coerce")
        late = pd.to_numeric(rows[last.column], errors="coerce")
        d = (early - late)[np.isfinite(early) & np.isfinite(late)]
        if d.empty:
            out.append(_skip(a.case, definition, check,
                             f"no run with finite {first.column} and {last.column}", a.tier))
            continue
        stat = fits.mean_interval(d, level)
        detail = {k: stat[k] for k in ("n", "std", "sem", "k", "low", "high")}
        detail.update({"first": first.label, "last": last.label,
                       "first_mean": float(early[d.index].mean()), "last_mean": float(late[d.index].mean())})
        texts = (f"W_rms {detail['first_mean']:.4g} ({first.label}) against {detail['last_mean']:.4g} "
                 f"({last.label})")
        if stat["n"] < 2:
            status, why = "unresolved", "one realization gives no estimate of the scatter"
            tolerance = f"{level:.0%} interval of the difference above 0; n/a with one realization; {texts}"
        else:
            tolerance = f"{_interval_text(stat, level, 3)} of the difference above 0; {texts}"
            if stat["low"] > 0.0:
                status, why = "passed", ""
            elif stat["high"] < 0.0:
                status = against(a.tier)
                why = (f"the vorticity grows: W_rms of {last.label} exceeds that of {first.label}, "
                       f"the {level:.0%} interval of the difference lies below 0")
            else:
                status = "unresolved"
                why = (f"the change between the windows is within the scatter: the {level:.0%} "
                       f"interval [{stat['low']:.3g}, {stat['high']:.3g}] holds 0")
        out.append(_result(a, definition, check, status, stat["mean"], "> 0", tolerance, why, detail))
    return out


def _first_and_last_windows(windows):
    """The earliest and the latest vorticity window, or None with why not: fewer than two,
    or of unequal length (the accumulated displacement grows with the cycles a window
    sums: windows of unequal length would order W_rms by their length, not by the bed's
    state)."""
    if len(windows) < 2:
        return None, f"{len(windows)} vorticity window(s) in summary.csv; the comparison needs two"
    first = min(windows, key=lambda w: (w.first, w.last))
    last = max(windows, key=lambda w: (w.last, w.first))
    if first.last - first.first != last.last - last.first:
        return None, (f"the first and last vorticity windows ({first.label}, {last.label}) span "
                      "different numbers of cycles; the paper compares two of 10")
    return (first, last), ""


def _vorticity_bend_check(a: Analysis) -> CheckResult:
    """wrms_ratio_bend_later: the later window's relative curvature against the earlier's,
    paired per run (one quadratic fit of the difference of the scaled W_rms)."""
    definition = CHECKS["wrms_ratio_bend_later"]
    check = definition.check
    level = definition.params(a.tier)["level"]
    alpha = 1.0 - level
    pair, why_not = _first_and_last_windows(a.sweep.windows)
    if pair is None:
        return _skip(a.case, definition, check, why_not, a.tier)
    first, last = pair
    if first.column not in a.data.columns or last.column not in a.data.columns:
        return _skip(a.case, definition, check, f"no column {first.column} or {last.column} in summary.csv",
                     a.tier)
    values = a.data[[a.x, first.column, last.column]].apply(pd.to_numeric, errors="coerce")
    values = values[np.isfinite(values).all(axis=1)]
    points = int(values[a.x].nunique())
    if points < 4 or len(values) < 4:
        return _skip(a.case, definition, check,
                     f"{points} {a.x_label} value(s) and {len(values)} runs with both windows' W_rms; "
                     "the curvature needs >= 4 values and >= 4 runs", a.tier)
    early_mean, late_mean = float(values[first.column].mean()), float(values[last.column].mean())
    if not (early_mean > 0 and late_mean > 0):
        return _skip(a.case, definition, check, "a window's mean W_rms is not positive (no vorticity to "
                     "scale by)", a.tier)
    early, late = values[first.column] / early_mean, values[last.column] / late_mean
    test = fits.curvature_test(values[a.x], late - early)
    late_c2 = float(fits.quadratic_fit(values[a.x], late).coef[2])
    early_c2 = float(fits.quadratic_fit(values[a.x], early).coef[2])
    c2, se, t, p_value = test["c2"], test["se"], test["t"], test["p"]
    detail = {**_curvature_detail(test), "level": level, "points": points,
              "n": int(len(values)), "first": first.label, "last": last.label,
              "c2_first": early_c2, "c2_last": late_c2, "mean_first": early_mean, "mean_last": late_mean}
    shapes = (f"relative curvature {early_c2:.3g} ({first.label}) and {late_c2:.3g} ({last.label}) per "
              "unit ratio squared")
    tolerance = (f"t test of the difference's c2 p < {alpha:.2g} (p = {p_value:.3g}; c2 {c2:.4g} +- "
                 f"{se:.2g}, {t:.2g} SE; {_scatter_said(test)}); {shapes}")
    if p_value < alpha and c2 > 0 and late_c2 > 0:
        status, why = "passed", ""
    elif p_value < alpha and c2 < 0:
        status = against(a.tier)
        why = (f"the later window bends less upward than the earlier: the difference of their relative "
               f"curvatures is {c2:.3g} +- {se:.2g} ({t:.2g} SE, p = {p_value:.3g}), {shapes}, "
               f"on the {a.tier} tier's beds")
    elif p_value < alpha:
        status = "unresolved"
        why = (f"the later window's curvature exceeds the earlier's ({c2:.3g} +- {se:.2g}) but it does "
               f"not bend upward itself ({shapes})")
    else:
        status = "unresolved"
        why = (f"the two windows' shapes are within the scatter: the difference of their relative "
               f"curvatures is {c2:.3g} +- {se:.2g} ({t:.2g} SE, p = {p_value:.3g} >= {alpha:.2g})")
    return _result(a, definition, check, status, c2, "> 0, resolved", tolerance, why, detail)


def analyse(sweep: Sweep, kind: str, tier: str, case: str | None = None) -> Analysis:
    """All fits and checks of one sweep along `kind` ("angle" or "ratio")."""
    if tier not in TIERS:
        raise ValueError(f"unknown tier {tier!r} (expected one of {', '.join(TIERS)})")
    if kind not in X_COLUMNS:
        raise ValueError(f"unknown sweep kind {kind!r}")
    notes: list[str] = []
    data = study_runs(sweep, kind, notes)
    a = Analysis(sweep=sweep, kind=kind, case=case or f"trends_{kind}:{sweep.name}", tier=tier,
                 data=data, x=X_COLUMNS[kind], x_label=X_LABELS[kind], notes=notes)
    metrics = ["P_max"] + [w.column for w in sweep.windows]
    for metric in metrics:
        if metric in data.columns:
            a.metrics[metric] = metric_fits(data, a.x, metric)
    a.results.extend(_steady_checks(a))
    all_points = list(data[a.x].dropna().unique())
    if kind == "angle":
        slope = CHECKS["pmax_theta_slope"]
        a.results.append(_gate_steady(a, _slope_check(a, slope, "P_max", slope.check, "decrease"),
                                      all_points))
        a.results.append(_gate_steady(a, _halving_check(a), HALVING_ANGLES))
        w_defs = ((CHECKS["wrms_theta_flat"], "flat"),)
    else:
        slope, curve = CHECKS["pmax_ratio_slope"], CHECKS["pmax_ratio_quadratic"]
        a.results.append(_gate_steady(a, _slope_check(a, slope, "P_max", slope.check, "increase"),
                                      all_points))
        a.results.append(_gate_steady(a, _curvature_check(a, curve, "P_max", curve.check), all_points))
        w_defs = ((CHECKS["wrms_ratio_slope"], "increase"), (CHECKS["wrms_ratio_monotone"], "monotone"),
                  (CHECKS["wrms_ratio_quadratic"], "curvature"))
    for w_def, direction in w_defs:
        if not sweep.windows:
            a.results.append(_skip(a.case, w_def, w_def.check.format(window="any"),
                                   "summary.csv has no W_rms_<a>_<b> column", tier))
        for window in sweep.windows:
            check = w_def.check.format(window=window.label.replace("cycles ", ""))
            if direction == "curvature":
                a.results.append(_curvature_check(a, w_def, window.column, check))
            elif direction == "monotone":
                a.results.append(_monotone_check(a, w_def, window.column, check))
            else:
                a.results.append(_slope_check(a, w_def, window.column, check, direction))
    a.results.extend(_vorticity_decline_checks(a))
    if kind == "ratio":
        a.results.append(_vorticity_bend_check(a))
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
