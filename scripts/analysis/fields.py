"""The paper's Fig. 5 and Fig. 6 statements and its steady-state statements, measured.

Inputs (docs/output-format.md): a run's ``stage_fields.csv`` (outputs.displacement.stages:
the displacement over each heating and each cooling, averaged over the polar angle on
the (r, z) cells, both stages of a cycle binned where the grains were at the start of
that cycle), its ``cycles.csv`` (peak pressure per cycle) and its V/V0 series
(``timeseries.csv``, or the ``volume.csv`` a campaign stores). Per run this module
returns numbers with uncertainties; ``checks(a)`` turns them into the CheckResults of the checks defined in trends.CHECKS (``stage_*``,
``still_zone``, ``toroidal_cell``, ``pmax_rise``, ``pmax_follows_density``, ``steady_*``,
``cooling_dilation_*``).

Uncertainties: per run, the standard error over its cycles (the bed's own noise); per
sweep point, the standard error over the realizations when there are at least two,
else the one run's standard error; intervals are 95 % Student t (n - 1 dof), slopes
over all runs use the tier's k SE widened to Student t at the fit's dof
(fits.widened_k), as the other slope checks of trends.py. The checks follow the states
of docs/trends.md: passed, unresolved, contradicted (below the paper tier) or failed
(at it), skipped.

Signs: u_r > 0 is away from the axis, u_z > 0 upward. The circulation of a field in
the (r, z) half-plane, r to the right and z up, is Gamma = sum over interior cells of
w h^2 with w = du_z/dr - du_r/dz (the vorticity of docs/output-format.md): Gamma > 0
is counter-clockwise, grains rising along the wall and sinking at the axis; Gamma < 0
sinking along the wall and rising at the axis.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd
from scipy import stats

from . import fits
from .inputs import read_csv_columns, read_cycles, read_volume_series, run_dir

#: The checks this module evaluates (their definitions: trends.CHECKS).
CHECK_IDS = ("stage_heating_direction", "stage_cooling_direction", "still_zone", "toroidal_cell",
             "pmax_rise", "steady_time_theta", "steady_time_ratio", "steady_volume_flat", "cooling_dilation_ratio",
             "cooling_dilation_present", "pmax_follows_density")
STAGE_FILE = "stage_fields.csv"
STAGE_COLUMNS = ("cycle", "ir", "iz", "r", "z", "count", "ur_heating", "uz_heating",
                 "ur_cooling", "uz_cooling")
#: The bottom-axis region whose grains the paper sees still: cells whose centre lies
#: within this fraction of the bed's radius from the axis and of its height above the
#: floor (a cone of still grains fits in it; at least the cell on the axis at the floor).
STILL_R_FRACTION = 1.0 / 3.0
STILL_Z_FRACTION = 1.0 / 4.0
#: Interior cells a run's core needs before its circulation counts: with one or two the
#: coherence is +-1 whatever the field, and a ring needs a core to turn around.
MIN_CORE_CELLS = 4
#: The steady band of the peak pressure: mean of the steady cycles (the second half)
#: +- max(BAND_SIGMAS sigma, BAND_FLOOR mean), sigma their sample standard deviation:
#: 2 sigma holds about 95 % of the steady peaks if they scatter normally; the floor
#: keeps the band open when a few steady peaks happen to agree closely.
BAND_SIGMAS = 2.0
BAND_FLOOR = 0.05


class FieldsError(Exception):
    """A stage_fields.csv that exists but does not follow the format."""


@dataclass
class StageFields:
    """The stage fields of one run on the (ir, iz) grid: arrays [cycle, iz, ir]."""

    path: Path
    cell: float
    cycles: np.ndarray          # the cycle numbers, ascending
    count: np.ndarray           # 0 where a cell is empty
    ur_heating: np.ndarray      # NaN where a cell is empty
    uz_heating: np.ndarray
    ur_cooling: np.ndarray
    uz_cooling: np.ndarray

    @property
    def r(self) -> np.ndarray:
        return (np.arange(self.count.shape[2]) + 0.5) * self.cell

    @property
    def z(self) -> np.ndarray:
        return (np.arange(self.count.shape[1]) + 0.5) * self.cell

    def cumulative(self, cycles=None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(u_r, u_z, populated) of heating plus cooling summed over `cycles` (default
        all): a cell counts where it is populated in every one of them."""
        pick = np.ones(len(self.cycles), bool) if cycles is None else np.isin(self.cycles, list(cycles))
        if not pick.any():
            raise ValueError(f"{self.path}: none of the cycles {list(cycles)} is in the file")
        populated = (self.count[pick] > 0).all(axis=0)
        ur = np.nansum(self.ur_heating[pick] + self.ur_cooling[pick], axis=0)
        uz = np.nansum(self.uz_heating[pick] + self.uz_cooling[pick], axis=0)
        return np.where(populated, ur, np.nan), np.where(populated, uz, np.nan), populated


def read_stage_fields(folder: Path | None) -> StageFields | None:
    """The stage fields of a run folder; None when it has no stage_fields.csv. Raises
    FieldsError naming the file and the column for a file that breaks the format."""
    if folder is None:
        return None
    path = Path(folder) / STAGE_FILE
    if not path.is_file():
        return None
    frame = read_csv_columns(path, STAGE_COLUMNS)
    if frame is None:
        raise FieldsError(f"{path}: cannot be read as CSV")
    missing = [c for c in STAGE_COLUMNS if c not in frame.columns]
    if missing:
        raise FieldsError(f"{path}: missing column(s) {', '.join(missing)} (expected "
                          f"{','.join(STAGE_COLUMNS)})")
    for column in ("cycle", "ir", "iz", "count"):
        values = frame[column].to_numpy(dtype=float)
        if not np.all(np.isfinite(values)) or np.any(values < 0) or np.any(values != np.round(values)):
            raise FieldsError(f"{path}: column '{column}': expected integers >= 0")
    if frame.empty:
        raise FieldsError(f"{path}: no rows (no cycle reached its end of cooling)")
    ir, iz = frame["ir"].to_numpy(int), frame["iz"].to_numpy(int)
    cells = frame["r"].to_numpy(float) / (ir + 0.5)
    cell = float(np.median(cells))
    if not cell > 0 or not np.allclose(cells, cell, rtol=1e-4):
        raise FieldsError(f"{path}: column 'r': expected (ir + 1/2) cell with one cell size")
    cycles = np.unique(frame["cycle"].to_numpy(int))
    shape = (len(cycles), int(iz.max()) + 1, int(ir.max()) + 1)
    index = np.searchsorted(cycles, frame["cycle"].to_numpy(int))
    arrays = {}
    for column in ("ur_heating", "uz_heating", "ur_cooling", "uz_cooling"):
        grid = np.full(shape, np.nan)
        grid[index, iz, ir] = frame[column].to_numpy(float)
        arrays[column] = grid
    count = np.zeros(shape, dtype=int)
    count[index, iz, ir] = frame["count"].to_numpy(int)
    return StageFields(path=path, cell=cell, cycles=cycles, count=count, **arrays)


# --------------------------------------------------------------------------- statistics


@dataclass
class Estimate:
    """A value with its standard error and where the error comes from."""

    value: float
    se: float
    n: int
    source: str            # "cycles" (one run's cycles) or "realizations"

    def significance(self, sign: float) -> float:
        """sign * value / se: how many standard errors beyond 0 on the side of `sign`."""
        if not math.isfinite(self.value):
            return math.nan
        if not self.se > 0:
            return math.copysign(math.inf, sign * self.value) if self.value else 0.0
        return sign * self.value / self.se

    def text(self, digits: int = 3) -> str:
        se = f" +- {self.se:.{digits}g}" if math.isfinite(self.se) else " (no SE)"
        return f"{self.value:.{digits}g}{se}"

    def to_dict(self) -> dict:
        return {"value": self.value, "se": self.se, "n": self.n, "source": self.source}


def mean_se(values, source: str) -> Estimate:
    """Mean and standard error (sample std / sqrt n; NaN for one value) of the finite values."""
    v = np.asarray([x for x in values if x is not None and math.isfinite(x)], dtype=float)
    if v.size == 0:
        return Estimate(math.nan, math.nan, 0, source)
    se = float(np.std(v, ddof=1) / math.sqrt(v.size)) if v.size > 1 else math.nan
    return Estimate(float(v.mean()), se, int(v.size), source)


def combine(per_run: list[Estimate]) -> Estimate:
    """A sweep point from its realizations: the scatter between them when there are
    two or more, else the one run's own (cycle) standard error."""
    runs = [e for e in per_run if math.isfinite(e.value)]
    if len(runs) >= 2:
        return mean_se([e.value for e in runs], "realizations")
    if len(runs) == 1:
        return runs[0]
    return Estimate(math.nan, math.nan, 0, "none")


def steady_cycles_of(cycles: np.ndarray) -> np.ndarray:
    """The second half of the cycles reached, as outputs.steady_cycles' default."""
    cycles = np.sort(np.asarray(cycles))
    return cycles[len(cycles) // 2:] if len(cycles) > 1 else cycles


# --------------------------------------------------------------------------- per run


def _weighted(values: np.ndarray, count: np.ndarray, mask: np.ndarray) -> float:
    w = np.where(mask & (count > 0) & np.isfinite(values), count, 0)
    return float((np.nan_to_num(values) * w).sum() / w.sum()) if w.sum() > 0 else math.nan


def stage_directions(f: StageFields) -> dict[str, Estimate]:
    """Grain means of u_r (over grains off the axis: cells from ir = 1 on) and of u_z
    (all grains) on heating and on cooling, each averaged over the cycles with its
    cycle-to-cycle standard error."""
    off_axis = np.arange(f.count.shape[2])[None, :] >= 1
    everywhere = np.ones(f.count.shape[1:], bool)
    out = {}
    for name, grid, mask in (("ur_heating", f.ur_heating, off_axis), ("uz_heating", f.uz_heating, everywhere),
                             ("ur_cooling", f.ur_cooling, off_axis), ("uz_cooling", f.uz_cooling, everywhere)):
        mask = np.broadcast_to(mask, f.count.shape[1:])
        out[name] = mean_se([_weighted(grid[k], f.count[k], mask) for k in range(len(f.cycles))], "cycles")
    return out


def bed_extent(f: StageFields) -> tuple[float, float]:
    """(radius, height) of the bed: the outer edges of the populated cells."""
    populated = (f.count > 0).any(axis=0)
    iz, ir = np.nonzero(populated)
    return float((ir.max() + 1) * f.cell), float((iz.max() + 1) * f.cell)


def still_region(f: StageFields, forced_only: bool = False):
    """The bottom-axis cells [iz, ir] (STILL_R_FRACTION, STILL_Z_FRACTION); at least
    the cell on the axis at the floor. forced_only: (region, True when no cell centre
    lies within the fractions, so the region is that one forced cell: a grid coarser
    than the zone)."""
    radius, height = bed_extent(f)
    region = (f.r[None, :] < STILL_R_FRACTION * radius) & (f.z[:, None] < STILL_Z_FRACTION * height)
    forced = not region.any()
    region[0, 0] = True
    return (region, forced) if forced_only else region


def still_zone_ratio(f: StageFields) -> Estimate:
    """Mean magnitude |u| of the stage fields in the bottom-axis cells over that of the
    whole bed (grain-weighted, heating and cooling alike), averaged over the cycles."""
    region = still_region(f)
    everywhere = np.ones_like(region)
    ratios = []
    for k in range(len(f.cycles)):
        heat = np.hypot(f.ur_heating[k], f.uz_heating[k])
        cool = np.hypot(f.ur_cooling[k], f.uz_cooling[k])
        magnitude = 0.5 * (heat + cool)
        whole = _weighted(magnitude, f.count[k], everywhere)
        ratios.append(_weighted(magnitude, f.count[k], region) / whole if whole > 0 else math.nan)
    return mean_se(ratios, "cycles")


def vorticity(ur: np.ndarray, uz: np.ndarray, cell: float) -> np.ndarray:
    """w = du_z/dr - du_r/dz by central differences on interior cells (populated, not on
    the grid edge, four populated neighbours), NaN elsewhere: the rule of
    observe/displacement_field.hpp."""
    w = np.full(ur.shape, np.nan)
    ok = np.isfinite(ur) & np.isfinite(uz)
    inner = np.zeros_like(ok)
    inner[1:-1, 1:-1] = ok[1:-1, 1:-1] & ok[1:-1, 2:] & ok[1:-1, :-2] & ok[2:, 1:-1] & ok[:-2, 1:-1]
    dz_dr = np.full(ur.shape, np.nan)
    dr_dz = np.full(ur.shape, np.nan)
    dz_dr[1:-1, 1:-1] = (uz[1:-1, 2:] - uz[1:-1, :-2]) / (2 * cell)
    dr_dz[1:-1, 1:-1] = (ur[2:, 1:-1] - ur[:-2, 1:-1]) / (2 * cell)
    w[inner] = dz_dr[inner] - dr_dz[inner]
    return w


@dataclass
class Circulation:
    gamma: float           # sum of w h^2 over the interior cells of the cumulative field
    coherence: float       # gamma / sum |w| h^2: 1 or -1 when w has one sign throughout
    per_cycle: Estimate    # gamma of each cycle's heating + cooling: mean and SE
    cells: int             # interior cells

    @property
    def sense(self) -> str:
        if not math.isfinite(self.gamma) or self.gamma == 0:
            return "none"
        return "rising at the wall" if self.gamma > 0 else "sinking at the wall"


def circulation(f: StageFields, cycles=None) -> Circulation:
    """Circulation of the cumulative field (heating + cooling summed over `cycles`,
    default: the steady cycles, the second half) over the bed's core (its interior
    cells)."""
    cycles = steady_cycles_of(f.cycles) if cycles is None else np.asarray(list(cycles))
    ur, uz, _ = f.cumulative(cycles)
    w = vorticity(ur, uz, f.cell)
    area = f.cell ** 2
    interior = np.isfinite(w)
    gamma = float(np.sum(w[interior]) * area) if interior.any() else math.nan
    total = float(np.sum(np.abs(w[interior])) * area) if interior.any() else math.nan
    coherence = gamma / total if total and total > 0 else math.nan
    each = []
    for k in cycles:
        cu, cz, _ = f.cumulative([k])
        wk = vorticity(cu, cz, f.cell)
        each.append(float(np.nansum(wk) * area) if np.isfinite(wk).any() else math.nan)
    return Circulation(gamma, coherence, mean_se(each, "cycles"), int(interior.sum()))


def cycles_to_steady(cycles: pd.DataFrame) -> dict:
    """The first cycle whose peak pressure lies in the steady band (BAND_SIGMAS,
    BAND_FLOOR) of the second half of the cycles. Returns {"cycle", "band", "mean",
    "cycles", "rises", "rise"}; "cycle" is NaN with fewer than 2 cycles or no finite peak;
    "rises": the first peak lies below the band (the pressure rises into its steady state,
    where the paper's time scale of the rise is measured; at alpha_c/alpha_p = 1 the peaks
    fall); "rise": (mean - first peak) / mean, NaN unless the mean is positive."""
    none = {"cycle": math.nan, "band": math.nan, "mean": math.nan, "cycles": 0, "rises": False, "rise": math.nan}
    if cycles is None or not {"cycle", "peak_pressure"}.issubset(cycles.columns):
        return none
    frame = cycles.dropna(subset=["cycle", "peak_pressure"]).sort_values("cycle")
    frame = frame[np.isfinite(frame["peak_pressure"])]
    n = len(frame)
    if n < 2:
        return {**none, "cycles": n}
    peaks = frame["peak_pressure"].to_numpy(float)
    steady = peaks[n // 2:]
    mean = float(steady.mean())
    sigma = float(steady.std(ddof=1)) if steady.size > 1 else 0.0
    band = max(BAND_SIGMAS * sigma, BAND_FLOOR * abs(mean))
    inside = np.nonzero(np.abs(peaks - mean) <= band)[0]
    first = float(frame["cycle"].to_numpy(float)[inside[0]]) if inside.size else math.nan
    rise = (mean - peaks[0]) / mean if mean > 0 else math.nan
    return {"cycle": first, "band": band, "mean": mean, "cycles": n, "rises": bool(peaks[0] < mean - band),
            "rise": float(rise)}


def density_pressure(cycles: pd.DataFrame | None) -> dict:
    """Spearman's rank correlation over a run's cycles (scipy.stats.spearmanr) between the
    cycle's peak pressure and its packing density at the end of the cooling, -V/V0 there
    (the grains back at T_0, so the bed volumes of different cycles compare like for like).
    Returns {"rho", "cycles", "compaction"}: rho NaN with fewer than 3 cycles or a series
    that does not change (no ranks to correlate); compaction is V/V0 at the end of the
    first cooling minus that of the last."""
    none = {"rho": math.nan, "cycles": 0, "compaction": math.nan}
    columns = {"peak_pressure", "V_over_V0_end_cooling"}
    if cycles is None or not columns.issubset(cycles.columns):
        return none
    frame = cycles[sorted(columns)].apply(pd.to_numeric, errors="coerce")
    frame = frame[np.isfinite(frame).all(axis=1)]
    n = len(frame)
    if n < 2:
        return {**none, "cycles": n}
    peaks, volume = frame["peak_pressure"].to_numpy(float), frame["V_over_V0_end_cooling"].to_numpy(float)
    compaction = float(volume[0] - volume[-1])
    if n < 3 or np.ptp(peaks) == 0 or np.ptp(volume) == 0:
        return {"rho": math.nan, "cycles": n, "compaction": compaction}
    rho = float(stats.spearmanr(peaks, -volume).correlation)
    return {"rho": rho, "cycles": n, "compaction": compaction}


def thermal_stages(temperature: np.ndarray) -> tuple[np.ndarray, list[np.ndarray]]:
    """The stages of a sampled V/V0 series: (cycle of each row, the rows of each cooling
    ramp). A row heats when its T is above the row before's, cools when below it; a
    cycle begins with its heating, so the rows before the first heating are cycle -1.
    A cooling ramp's rows are those strictly between the series' lowest and highest T
    (the row sampled after the ramp has ended, at T0, already holds some of the cold
    hold); ramp i is cycle i's."""
    T = np.asarray(temperature, dtype=float)
    change = np.diff(T, prepend=T[:1])
    heating = change > 0
    starts = heating & ~np.concatenate([[False], heating[:-1]])
    cycle = np.cumsum(starts) - 1
    cooling = (change < 0) & (T > T.min()) & (T < T.max())
    ramps, first = [], None
    for i, on in enumerate(np.append(cooling, False)):
        if on and first is None:
            first = i
        elif not on and first is not None:
            ramps.append(np.arange(first, i))
            first = None
    return cycle, ramps


def _steady(per_cycle: list[float]) -> Estimate:
    """Mean and SE over the second half of the cycles (the steady ones, as P_max's)."""
    return mean_se(per_cycle[len(per_cycle) // 2:], "cycles")


def peak_density(series: pd.DataFrame | None) -> Estimate:
    """The bed's densest state of each cycle, its lowest V/V0 (the paper: "the material
    reaches nearly the same peak density for all investigated parameters"), mean and SE
    over the steady cycles. Cycles with a cooling ramp count (complete ones); V/V0 at the
    end of cooling is not it: the dilation during cooling, which the paper finds to
    differ between parameters, lifts it."""
    if series is None:
        return Estimate(math.nan, math.nan, 0, "cycles")
    volume = series["V_over_V0"].to_numpy(float)
    cycle, ramps = thermal_stages(series["T"].to_numpy(float))
    lows = [float(volume[cycle == cycle[r[0]]].min()) for r in ramps if cycle[r[0]] >= 0]
    return _steady(lows)


def cooling_dilation(series: pd.DataFrame | None) -> Estimate:
    """The dilation during cooling (the paper: "small increases [of V/V0] during the
    cooling at the steady state ... caused by dilatation"): in each cooling ramp, the
    largest rise of V/V0 above its lowest value so far in the ramp (0 when V/V0 only
    falls), mean and SE over the steady cycles. Not the difference between the ends of
    heating and cooling: that swing is mostly the container's own contraction, which
    grows with alpha_c whatever the grains do."""
    if series is None:
        return Estimate(math.nan, math.nan, 0, "cycles")
    volume = series["V_over_V0"].to_numpy(float)
    _, ramps = thermal_stages(series["T"].to_numpy(float))
    rises = [float(np.max(volume[r] - np.minimum.accumulate(volume[r]))) for r in ramps]
    return _steady(rises)


def run_measures(folder: Path | None) -> dict:
    """Every number of this module for one run folder (None where its file is missing)."""
    out: dict = {"folder": str(folder) if folder else None}
    try:
        fields = read_stage_fields(folder)
    except FieldsError as problem:  # one bad file must not hide the other runs' checks
        out["error"] = str(problem)
        fields = None
    if fields is not None:
        out["directions"] = stage_directions(fields)
        out["still_zone"] = still_zone_ratio(fields)
        out["still_forced"] = still_region(fields, forced_only=True)[1]
        out["circulation"] = circulation(fields)
        out["stage_cycles"] = len(fields.cycles)
    cycles = read_cycles(folder) if folder else None
    out["cycles_to_steady"] = cycles_to_steady(cycles)
    out["density_pressure"] = density_pressure(cycles)
    series, out["volume_source"] = read_volume_series(folder)
    out["steady_volume"] = peak_density(series)
    out["cooling_dilation"] = cooling_dilation(series)
    out["cycles"] = 0 if cycles is None else int(len(cycles))
    return out


# --------------------------------------------------------------------------- checks
#
# The rules of trends.py (docs/trends.md "States"): a check passes only when its value
# with its uncertainty shows the paper's statement; the opposite resolved is
# trends.against(tier) ("contradicted" below the paper tier, "failed" at it); anything
# within the uncertainty is "unresolved"; missing data "skipped". Results are built by
# trends._result, so reasons start with what the data show and a value that is not a
# number fails.


def interval(e: Estimate, level: float) -> dict:
    """e.value +- k e.se, k the Student t quantile at `level` for e.n - 1 dof (n
    realizations, or one run's n cycles); low/high NaN without an SE."""
    k = fits.t_quantile(level, e.n - 1)
    half = k * e.se if math.isfinite(k) and math.isfinite(e.se) else math.nan
    return {"value": e.value, "se": e.se, "n": e.n, "dof": e.n - 1, "k": k, "source": e.source,
            "low": e.value - half, "high": e.value + half}


def _side(iv: dict, sign: float) -> str:
    """"shown" when the interval lies entirely on the side of `sign` of 0, "opposite"
    when entirely on the other side, else "within" (also without an interval)."""
    low, high = iv["low"], iv["high"]
    if not (math.isfinite(low) and math.isfinite(high)):
        return "within"
    if (sign > 0 and low > 0) or (sign < 0 and high < 0):
        return "shown"
    if (sign > 0 and high < 0) or (sign < 0 and low > 0):
        return "opposite"
    return "within"


def _positive_verdict(a, iv: dict, level: float, trends, single: str, digits: str,
                      against_why: str) -> tuple[str, str]:
    """(status, why) of a per-point number the paper says is positive: passed when its
    interval lies above 0; against (trends.against) with against_why when below; else not
    resolved: one realization (single: its value, no interval) or an interval holding 0."""
    side = _side(iv, 1.0)
    if side == "shown":
        return "passed", ""
    if side == "opposite":
        return trends.against(a.tier), against_why
    if not math.isfinite(iv["low"]):
        return "unresolved", f"one realization ({single}) gives no scatter estimate"
    return "unresolved", f"the {level:.0%} interval [{iv['low']:{digits}}, {iv['high']:{digits}}] holds 0"


def _interval_text(name: str, iv: dict) -> str:
    if not math.isfinite(iv["low"]):
        return f"{name} {iv['value']:.3g} (no interval: n = {iv['n']} {iv['source']})"
    return (f"{name} {iv['value']:.3g} [{iv['low']:.3g}, {iv['high']:.3g}] (+- {iv['k']:.3g} SE, "
            f"{iv['dof']} dof over {iv['source']})")


def _per_point(a) -> list[tuple[float, list[int], list[dict]]]:
    """(parameter value, runs, their run_measures) per point of the analysis."""
    out = []
    for value in sorted(a.data[a.x].dropna().unique()):
        runs = [int(r) for r in a.data.loc[np.isclose(a.data[a.x], value), "run"]]
        out.append((float(value), runs, [run_measures(run_dir(a.sweep.folder, r)) for r in runs]))
    return out


def _missing(measures: list[dict]) -> str:
    errors = sorted({m["error"] for m in measures if "error" in m})
    if errors:
        return "; ".join(errors)
    return (f"no {STAGE_FILE} in the run folders (the scene's outputs.displacement.stages is off, "
            f"or the runs were stored without it)")


def _papers_point(a, value: float, trends) -> bool:
    """Whether the point is the one Fig. 5 is stated for (theta_c = 0 deg and
    alpha_c/alpha_p = 10, the paper's text): the swept value and the fixed one (a study
    without the fixed parameter's column runs at the paper's value, trends.study_runs)."""
    other, o_ref, _ = trends.fixed_parameter(a.kind)
    if not np.isclose(value, trends.PAPER_VALUE[a.kind]):
        return False
    fixed = a.data[other].dropna().unique() if other in a.data.columns else []
    return all(np.isclose(float(v), o_ref) for v in fixed)


FIG5_POINT = "the paper states it for theta_c = 0 deg and alpha_c/alpha_p = 10 only (Fig. 5)"


def _beyond_the_paper(a, d, check: str, trends, measured: str):
    """A Fig. 5 statement at another point: skipped, with what was measured there."""
    return trends._skip(a.case, d, check, f"{FIG5_POINT}; measured here, not a check: {measured}", a.tier)


def _direction_checks(a, points, trends) -> list:
    out = []
    for check_id, stage, signs in (("stage_heating_direction", "heating", (1.0, -1.0)),
                                   ("stage_cooling_direction", "cooling", (-1.0, 1.0))):
        d = trends.CHECKS[check_id]
        level = d.params(a.tier)["level"]
        words = (("outward", "downward") if stage == "heating" else ("inward", "upward"))
        for value, runs, measures in points:
            check = d.check.format(point=a.point_label(value))
            with_fields = [m for m in measures if "directions" in m]
            if not with_fields:
                out.append(trends._skip(a.case, d, check, _missing(measures), a.tier))
                continue
            ur = interval(combine([m["directions"][f"ur_{stage}"] for m in with_fields]), level)
            uz = interval(combine([m["directions"][f"uz_{stage}"] for m in with_fields]), level)
            sides = (_side(ur, signs[0]), _side(uz, signs[1]))
            texts = f"{_interval_text('u_r', ur)}; {_interval_text('u_z', uz)}"
            if not _papers_point(a, value, trends):
                out.append(_beyond_the_paper(a, d, check, trends, texts))
                continue
            if sides == ("shown", "shown"):
                status, why = "passed", ""
            elif "opposite" in sides:
                status = trends.against(a.tier)
                wrong = [f"{'u_r' if i == 0 else 'u_z'} resolved "
                         f"{('inward' if signs[0] > 0 else 'outward') if i == 0 else ('upward' if signs[1] < 0 else 'downward')}"
                         for i, side in enumerate(sides) if side == "opposite"]
                why = (f"{' and '.join(wrong)} on {stage} ({level:.0%} interval beyond 0), the opposite "
                       f"of the paper's {words[0]} and {words[1]}, over {len(with_fields)} "
                       f"realization(s) on the {a.tier} tier's beds")
            else:
                status = "unresolved"
                no_se = [n for n, iv in (("u_r", ur), ("u_z", uz)) if not math.isfinite(iv["low"])]
                why = (f"{' and '.join(no_se)} without a scatter estimate (one run of one cycle)" if no_se
                       else f"a {level:.0%} interval holds 0: {texts}")
            measured = min(signs[0] * ur["value"], signs[1] * uz["value"])
            out.append(trends._result(
                a, d, check, status, measured,
                f"> 0: {words[0]} ({'u_r > 0' if signs[0] > 0 else 'u_r < 0'}) and {words[1]} "
                f"({'u_z < 0' if signs[1] < 0 else 'u_z > 0'}), resolved",
                f"{level:.0%} intervals beyond 0 on the paper's side; {texts}; measured: the smaller "
                "of the two along the paper's direction", why,
                {"level": level, "ur": ur, "uz": uz, "sides": list(sides), "runs": runs}))
    return out


def _still_zone_checks(a, points, trends) -> list:
    d = trends.CHECKS["still_zone"]
    p = d.params(a.tier)
    f_max, level = p["f_max"], p["level"]
    out = []
    for value, runs, measures in points:
        check = d.check.format(point=a.point_label(value))
        with_fields = [m for m in measures if "still_zone" in m]
        if not with_fields:
            out.append(trends._skip(a.case, d, check, _missing(measures), a.tier))
            continue
        estimate = combine([m["still_zone"] for m in with_fields])
        if not math.isfinite(estimate.value):
            out.append(trends._skip(a.case, d, check, "the bed's mean displacement is 0", a.tier))
            continue
        iv = interval(estimate, level)
        coarse = any(m.get("still_forced") for m in with_fields)
        text = _interval_text("f", iv)
        if not _papers_point(a, value, trends):
            out.append(_beyond_the_paper(a, d, check, trends, text))
            continue
        if not math.isfinite(iv["low"]):
            status, why = "unresolved", "one run of one cycle gives no scatter estimate"
        elif iv["high"] < f_max:
            status, why = "passed", ""
        elif iv["low"] >= f_max and coarse:
            status = "unresolved"
            why = (f"the {level:.0%} interval [{iv['low']:.3g}, {iv['high']:.3g}] lies above "
                   f"{f_max:g}, but the bottom-axis region is the one floor-axis cell, coarser than "
                   "the zone: its moving grains outside the zone raise f")
        elif iv["low"] >= f_max:
            status = trends.against(a.tier)
            why = (f"the bottom-axis grains move as much as {iv['value']:.0%} of the bed's mean, "
                   f"{level:.0%} interval [{iv['low']:.3g}, {iv['high']:.3g}] above {f_max:g}: no "
                   f"still zone, over {len(with_fields)} realization(s) on the {a.tier} tier's beds")
        else:
            status = "unresolved"
            why = f"the {level:.0%} interval [{iv['low']:.3g}, {iv['high']:.3g}] holds {f_max:g}"
        out.append(trends._result(
            a, d, check, status, estimate.value, f"< {f_max:g}, resolved",
            f"{level:.0%} interval below {f_max:g}; {text}" + ("; region: the floor-axis cell only"
                                                              if coarse else ""),
            why, {"level": level, "f_max": f_max, "ratio": iv, "coarse_region": coarse, "runs": runs}))
    return out


def _toroidal_checks(a, points, trends) -> list:
    d = trends.CHECKS["toroidal_cell"]
    p = d.params(a.tier)
    s_min, s_fail, level = p["s_min"], p["s_fail"], p["level"]
    out = []
    for value, runs, measures in points:
        check = d.check.format(point=a.point_label(value))
        cells = [(r, m["circulation"]) for r, m in zip(runs, measures)
                 if "circulation" in m and math.isfinite(m["circulation"].coherence)
                 and m["circulation"].cells >= MIN_CORE_CELLS]
        if not cells:
            found = [m["circulation"].cells for m in measures if "circulation" in m]
            why = (f"interior cells per run {found}: a core needs >= {MIN_CORE_CELLS} (a bed at "
                   "least 4 cells wide and tall)" if found else _missing(measures))
            out.append(trends._skip(a.case, d, check, why, a.tier))
            continue
        coherence = np.array([c.coherence for _, c in cells])
        dominant = math.copysign(1.0, float(np.sum([c.gamma for _, c in cells])) or 1.0)
        aligned = coherence * dominant
        senses = {c.sense for _, c in cells}
        sense = cells[0][1].sense if len(senses) == 1 else "mixed"
        per_run = ", ".join(f"{r}: {c.coherence:+.2f}" for r, c in cells)
        detail = {"level": level, "runs": [r for r, _ in cells], "gamma": [c.gamma for _, c in cells],
                  "coherence": coherence.tolist(), "interior_cells": [c.cells for _, c in cells],
                  "gamma_per_cycle": [c.per_cycle.to_dict() for _, c in cells], "sense": sense}
        if len(cells) >= 2:
            along = fits.mean_interval(aligned, level)
            size = fits.mean_interval(np.abs(coherence), level)
            measured = along["mean"]
            detail.update({"aligned": along, "magnitude": size})
            tolerance = (f"{level:.0%} intervals over {len(cells)} realizations: mean a "
                         f"[{along['low']:.2f}, {along['high']:.2f}] >= {s_min:g} passes, mean |s| "
                         f"[{size['low']:.2f}, {size['high']:.2f}] < {s_fail:g} is no cell; sense: "
                         f"{sense}; coherence per run {per_run}")
            if along["low"] >= s_min:
                status, why = "passed", ""
            elif size["high"] < s_fail:
                status = trends.against(a.tier)
                why = (f"no dominant cell: the mean |s| {size['mean']:.2f} has its {level:.0%} "
                       f"interval [{size['low']:.2f}, {size['high']:.2f}] below {s_fail:g}, on "
                       f"{len(cells)} realizations on the {a.tier} tier's beds")
            else:
                status = "unresolved"
                why = (f"the {level:.0%} interval of the aligned coherence [{along['low']:.2f}, "
                       f"{along['high']:.2f}] reaches below {s_min:g} and that of |s| "
                       f"[{size['low']:.2f}, {size['high']:.2f}] above {s_fail:g}"
                       + ("; the realizations turn opposite ways" if sense == "mixed" else ""))
        else:
            run, circ = cells[0]
            turn = interval(circ.per_cycle, level)
            resolved = _side(turn, dominant) == "shown"
            measured = float(aligned[0])
            detail["per_cycle_interval"] = turn
            tolerance = (f"one realization: s {coherence[0]:+.2f} >= {s_min:g} with its sense resolved "
                         f"over the cycles; {_interval_text('circulation per cycle', turn)}; sense: {sense}")
            if measured >= s_min and resolved:
                status, why = "passed", ""
            else:
                status = "unresolved"
                why = ("one realization gives no scatter estimate of the coherence"
                       + (f" and its s {coherence[0]:+.2f} is below {s_min:g}" if measured < s_min else
                          "; the sense of its circulation is not resolved over its cycles"
                          if not resolved else ""))
        out.append(trends._result(a, d, check, status, measured,
                                  f">= {s_min:g} (one sense), resolved", tolerance, why, detail))
    return out


def _long_enough(a, d, points, need: str, trends, out: list):
    """(value, runs, measures, check) of each point whose shortest run has the check's
    min_cycles; a shorter point's skip goes into out, in the points' order."""
    minimum = d.params(a.tier)["min_cycles"]
    for value, runs, measures in points:
        check = d.check.format(point=a.point_label(value))
        fewest = min((m["cycles"] for m in measures), default=0)
        if fewest < minimum:
            out.append(trends._skip(a.case, d, check, f"runs of {fewest} cycle(s): {need} needs >= {minimum:g}",
                                    a.tier))
            continue
        yield value, runs, measures, check


def _rise_checks(a, points, trends) -> list:
    """pmax_rise per point: the relative rise from the first cycle's peak to the steady
    peaks, over the realizations (paired per run: the same bed's peaks)."""
    d = trends.CHECKS["pmax_rise"]
    level = d.params(a.tier)["level"]
    out = []
    need = "a first cycle and later ones to rise to"
    for value, runs, measures, check in _long_enough(a, d, points, need, trends, out):
        rises = [m["cycles_to_steady"]["rise"] for m in measures]
        if not all(math.isfinite(r) for r in rises):
            out.append(trends._skip(a.case, d, check, "a run without a positive steady peak pressure "
                                    "(no pressure on the walls to rise)", a.tier))
            continue
        iv = interval(mean_se(rises, "realizations"), level)
        text = _interval_text("r", iv)
        per_run = ", ".join(f"{r}: {x:+.3g}" for r, x in zip(runs, rises))
        status, why = _positive_verdict(
            a, iv, level, trends, f"r = {rises[0]:+.3g}", ".3g",
            f"the peaks fall into their steady state: the steady peak is {-iv['value']:.0%} below "
            f"the first cycle's ({level:.0%} interval [{iv['low']:.3g}, {iv['high']:.3g}] below 0), "
            f"over {len(rises)} realization(s) on the {a.tier} tier's beds")
        out.append(trends._result(
            a, d, check, status, iv["value"], "> 0, resolved",
            f"{level:.0%} interval above 0; {text}; r per run {per_run}", why,
            {"level": level, "rise": iv, "per_run": rises, "runs": runs}))
    return out


def _density_checks(a, points, trends) -> list:
    """pmax_follows_density per point: the rank correlation of a run's peak pressures with
    its packing density over the cycles, over the realizations."""
    d = trends.CHECKS["pmax_follows_density"]
    level = d.params(a.tier)["level"]
    out = []
    for value, runs, measures, check in _long_enough(a, d, points, "a correlation over the cycles", trends, out):
        found = [(r, m["density_pressure"]) for r, m in zip(runs, measures) if math.isfinite(m["density_pressure"]["rho"])]
        unchanged = len(runs) - len(found)
        left_out = f"; {unchanged} run(s) whose peaks or densities do not change left out" if unchanged else ""
        if not found:
            out.append(trends._skip(a.case, d, check, f"no run whose peaks and densities both change{left_out}",
                                    a.tier))
            continue
        rhos = [x["rho"] for _, x in found]
        compaction = [x["compaction"] for _, x in found]
        iv = interval(mean_se(rhos, "realizations"), level)
        if math.isfinite(iv["low"]):  # a correlation's bounds; clipping moves no bound across 0
            iv["low"], iv["high"] = max(iv["low"], -1.0), min(iv["high"], 1.0)
        per_run = ", ".join(f"{r}: {x['rho']:+.2f}" for r, x in found)
        text = f"{_interval_text('rho', iv)}; rho per run {per_run}{left_out}"
        squeeze = (f"V/V0 at the end of cooling falls by {min(compaction):.2g} to {max(compaction):.2g} from the "
                   f"first cycle to the last")
        status, why = _positive_verdict(
            a, iv, level, trends, f"rho = {rhos[0]:+.2f}", ".2f",
            f"the peak pressure falls as the bed's density rises: rho = {iv['value']:+.2f} ({level:.0%} "
            f"interval [{iv['low']:.2f}, {iv['high']:.2f}] below 0; {squeeze}), over {len(found)} "
            f"realization(s) on the {a.tier} tier's beds")
        out.append(trends._result(
            a, d, check, status, iv["value"], "> 0, resolved", f"{level:.0%} interval above 0; {text}", why,
            {"level": level, "rho": iv, "per_run": rhos, "compaction": compaction, "runs": [r for r, _ in found],
             "unchanged": unchanged}))
    return out


def _dilation_present_checks(a, points, trends) -> list:
    """cooling_dilation_present per point of the angle study: the dilation during cooling
    above d_min, over the realizations (or one run's steady cycles)."""
    d = trends.CHECKS["cooling_dilation_present"]
    p = d.params(a.tier)
    level, d_min = p["level"], p["d_min"]
    out = []
    for value, runs, measures, check in _long_enough(a, d, points, "the steady state", trends, out):
        with_series = [(r, m["cooling_dilation"]) for r, m in zip(runs, measures)
                       if math.isfinite(m["cooling_dilation"].value)]
        unseries = len(runs) - len(with_series)
        left_out = f"; {unseries} run(s) without a V/V0 series left out" if unseries else ""
        if not with_series:
            out.append(trends._skip(a.case, d, check, f"no run with a V/V0 series{left_out}", a.tier))
            continue
        iv = interval(combine([e for _, e in with_series]), level)
        text = _interval_text("dilation", iv) + left_out
        if not math.isfinite(iv["low"]):
            status, why = "unresolved", "one run of one steady cycle gives no scatter estimate"
        elif iv["low"] > d_min:
            status, why = "passed", ""
        elif iv["high"] < d_min:
            status = trends.against(a.tier)
            why = (f"no visible dilation: V/V0 rises by {iv['value']:.2g} in a cooling, the {level:.0%} "
                   f"interval [{iv['low']:.2g}, {iv['high']:.2g}] below {d_min:g}, over {len(with_series)} "
                   f"realization(s) on the {a.tier} tier's beds")
        else:
            status, why = "unresolved", f"the {level:.0%} interval [{iv['low']:.2g}, {iv['high']:.2g}] holds {d_min:g}"
        out.append(trends._result(
            a, d, check, status, iv["value"], f"> {d_min:g}, resolved",
            f"{level:.0%} interval above {d_min:g}; {text}", why,
            {"level": level, "d_min": d_min, "dilation": iv, "runs": [r for r, _ in with_series],
             "without_series": unseries}))
    return out


def _trend_check(a, points, trends, check_id: str, key: str, direction: str) -> list:
    """A slope of a per-run number against the swept parameter over all runs, with the
    rules of trends._slope_check: "decrease"/"increase": passed beyond k SE on the paper's
    side, the other side resolved is against(tier), else not resolved; "flat" (only the
    steady V/V0): trends.flat_verdict against the bed's compaction 1 - V/V0; "depends" (only
    the cycles to the steady state against the ratio): passed beyond k SE on either side,
    against(tier) when the whole k-SE change across the range lies within FLAT_RESOLUTION
    of the runs' mean, else not resolved."""
    d = trends.CHECKS[check_id]
    p = d.params(a.tier)
    check = d.check.format(x=a.x_label)
    xs, ys, cycles, unseries, no_rise = [], [], [], [], 0
    for value, runs, measures in points:
        for m in measures:
            v = m[key]["cycle"] if key == "cycles_to_steady" else m[key].value
            cycles.append(m["cycles"])
            if direction == "depends" and not m[key]["rises"]:  # no rise: no time scale of it
                no_rise += 1
                continue
            if math.isfinite(v):
                xs.append(value)
                ys.append(v)
            elif key in ("steady_volume", "cooling_dilation") and m.get("volume_source", "").startswith("no "):
                unseries.append(m["volume_source"])
    fewest = min(cycles) if cycles else 0
    if fewest < p["min_cycles"]:
        return [trends._skip(a.case, d, check, f"runs of {fewest} cycle(s): the steady state needs "
                             f">= {p['min_cycles']:g} (the second half of the cycles is the steady band)",
                             a.tier)]
    flat_start = (f"; {no_rise} run(s) whose peaks do not rise into the steady state (they fall "
                  "or start in it) left out" if no_rise else "")
    if len(set(xs)) < 2 or len(xs) < 3:
        without = f"; {len(unseries)} run(s) without a V/V0 series ({unseries[0]})" if unseries else ""
        without += flat_start
        return [trends._skip(a.case, d, check, f"{len(xs)} runs at {len(set(xs))} {a.x_label} value(s) "
                             "with a finite value; a slope with a standard error needs >= 3 runs at "
                             f">= 2 values{without}", a.tier)]
    fit, why = fits.try_fit(pd.Series(xs), pd.Series(ys), 1)
    if fit is None or not math.isfinite(fit.slope_se):
        return [trends._skip(a.case, d, check, f"no linear fit: {why}", a.tier)]
    slope, se, k_tier = fit.slope, fit.slope_se, p["k"]
    k = fits.widened_k(k_tier, fit.dof)  # few runs: Student t at the fit's dof
    if np.ptp(ys) <= 1e-12 * abs(float(np.mean(ys))):  # all runs alike: the fit's slope is round-off
        slope, se = 0.0, 0.0
    in_se = slope / se if se > 0 else (math.copysign(math.inf, slope) if slope else 0.0)
    detail = {"k": k, "k_tier": k_tier, "dof": fit.dof, "slope": slope, "se": se, "slope_in_se": in_se, "n": len(xs),
              "points": len(set(xs)), "x": xs, "y": ys}
    left_out = f"; {len(unseries)} run(s) without a V/V0 series left out" if unseries else ""
    left_out += flat_start
    fit_text = f"slope {slope:.3g} +- {se:.2g} ({in_se:.2g} SE, {len(xs)} runs at {len(set(xs))} values{left_out})"
    if unseries:
        detail["without_series"] = len(unseries)
    if direction == "flat":
        expected = "0"
        tolerance = (f"abs {k:.3g} SE ({k_tier:g} SE widened to Student t at {fit.dof} dof) = "
                     f"{k * se:.4g} (SE {se:.4g}; {len(xs)} runs at {len(set(xs))} values)")
        compaction = abs(1.0 - float(np.mean(ys)))  # V/V0 is near 1: its margin is the compaction's
        status, why, detail["allowed_change"] = trends.flat_verdict(
            slope, se, k, max(xs) - min(xs), compaction, f"the compaction 1 - V/V0 = {compaction:.3g}",
            a.tier)
        if status == trends.against(a.tier):
            why = f"the {fit_text} resolves a dependence on {a.x_label}, on the {a.tier} tier's beds: {why}"
    elif direction == "depends":
        expected = "!= 0"
        span = max(xs) - min(xs)
        mean_time = float(np.mean(ys))
        margin = trends.FLAT_RESOLUTION * mean_time
        allowed = (abs(slope) + k * se) * span
        detail["allowed_change"] = allowed
        tolerance = (f"{k:.3g} SE ({k_tier:g} SE widened to Student t at {fit.dof} dof) from 0, either sign "
                     f"(SE {se:.4g}; {len(xs)} runs at {len(set(xs))} values); no dependence: a change "
                     f"across the range within {trends.FLAT_RESOLUTION:g} x the mean {mean_time:.3g} cycles")
        if abs(slope) - k * se > 0:
            status = "passed"
            why = (f"the rise {'lengthens' if slope > 0 else 'shortens'} with {a.x_label}: "
                   f"{slope * span:+.3g} cycles across the range")
        elif allowed <= margin:
            status = trends.against(a.tier)
            why = (f"the {fit_text}: the cycles to the steady state change by at most {allowed:.3g} "
                   f"across the range, within {trends.FLAT_RESOLUTION:g} x their mean {mean_time:.3g}: "
                   f"no time scale set by {a.x_label}, on the {a.tier} tier's beds")
        else:
            status = "unresolved"
            why = (f"the {fit_text} is within {k:.3g} SE of 0, and a change of up to {allowed:.3g} "
                   f"cycles across the range is more than {trends.FLAT_RESOLUTION:g} x the mean "
                   f"{mean_time:.3g}")
    else:
        sign = -1.0 if direction == "decrease" else 1.0
        expected = "< 0" if direction == "decrease" else "> 0"
        tolerance = (f"{k:.3g} SE ({k_tier:g} SE widened to Student t at {fit.dof} dof) beyond 0 "
                     f"(SE {se:.4g}; {len(xs)} runs at {len(set(xs))} values)")
        if sign * slope - k * se > 0:
            status, why = "passed", ""
        elif sign * slope + k * se < 0:
            status = trends.against(a.tier)
            why = (f"the {fit_text} is resolved {'above' if sign < 0 else 'below'} 0, the opposite "
                   f"of the paper, on the {a.tier} tier's beds")
        else:
            status = "unresolved"
            why = f"the {fit_text} is within {k:.3g} SE of 0"
    return [trends._result(a, d, check, status, slope, expected, tolerance, why, detail)]


def checks(a) -> list:
    """The Fig. 5 / Fig. 6 and steady-state checks of one trends Analysis."""
    from . import trends  # here: trends calls this module
    points = _per_point(a)
    out = _direction_checks(a, points, trends)
    out += _still_zone_checks(a, points, trends)
    out += _toroidal_checks(a, points, trends)
    out += _rise_checks(a, points, trends)
    out += _density_checks(a, points, trends)
    if a.kind == "angle":
        out += _trend_check(a, points, trends, "steady_time_theta", "cycles_to_steady", "decrease")
        out += _dilation_present_checks(a, points, trends)
    out += _trend_check(a, points, trends, "steady_volume_flat", "steady_volume", "flat")
    if a.kind == "ratio":
        out += _trend_check(a, points, trends, "steady_time_ratio", "cycles_to_steady", "depends")
        out += _trend_check(a, points, trends, "cooling_dilation_ratio", "cooling_dilation", "increase")
    return out
