"""The side-wall stress against depth in a bed, read as Janssen's balance, whose sign says
whether the wall friction holds the grains up or pushes them down.

Janssen (1895; translated and discussed by Sperl, Granular Matter 8 (2006) 59-65): in a
column of radius R the mean vertical stress at depth d obeys
dσ_v/dd = γ - (2 μ_w K / R) σ_v when the wall friction carries part of the weight (a
settled bed), K = σ_w / σ_v the ratio of the wall's normal stress to the vertical one,
μ_w the mobilised wall friction, γ the bed's weight per volume. When the container
shrinks onto the bed and pushes the grains up its wall (the end of cooling at
α_c > α_p), the wall friction acts downward on them and the sign turns. Both cases are

    σ_w(d) = A (e^{a d} - 1) / a,    A = K γ,  a = ±2 μ_w K / R,

a > 0: the stress grows faster than the weight with depth (friction against an upward
motion), a < 0: it saturates (Janssen's silo), a = 0: hydrostatic. fit_profile fits the
band-averaged form to a wall_profile.csv profile (each band's stress is a time average
over the band's wall area, docs/output-format.md). If the squeeze's stress comes from this
balance with the same μ_w K at every width, a R is the same at every width and the
narrower bed's stress grows faster with depth.

The same balance says how the mean wall pressure over the bed's height H falls with the
width: the mean of σ_w over [0, H] is A H g(a H), g(x) = (e^x - 1 - x)/x², so at one
height and one μ_w K (c = 2 μ_w K = a R)

    P(R) = A H g(c H / R).

fit_widths fits A and c to the cycle's peak pressures of beds of several widths: a second
measure of c, from the peaks during cooling rather than from the profile of the cold hold.

A cone of opening angle θ leans its wall outward, so the wall's normal stress pushes the
grains up by σ_w sin θ while the friction pushes them down by μ_w σ_w cos θ: the balance's
friction becomes μ_w cos θ - sin θ and c(θ) = c (cos θ - sin θ / μ_w). fit_angles fits
A and μ_w to the peaks of beds of several angles at one radius, c from the width fit
(the cone's widening with height, about R tan θ over the bed, is left out).

With A held, one peak fixes its c (invert_c: g rises monotonically), so a realization's
peaks at 0 and at θ give 2 μ_w K and 2 K (μ_w cos θ − sin θ), hence K and μ_w
(friction_pair). A wall of another friction moves μ_w; if K is the bed's, the same K
holds at every wall friction, and the 0° peak predicts the θ peak (predicted_ratio).
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd
from scipy.optimize import brentq, curve_fit

from .inputs import read_csv_columns, read_cycles

PROFILE_FILE = "wall_profile.csv"
PROFILE_COLUMNS = ("cycle", "bin", "z_lo", "z_hi", "wall_stress")
#: Fewer bands than this leave the two parameters without a residual to judge them by.
MIN_BANDS = 4


class ProfileError(ValueError):
    """A run folder whose profile cannot be read; the message names the file and field."""


@dataclass
class Profile:
    folder: Path
    radius: float              # the container's bottom radius (run.json's effective scene)
    table: pd.DataFrame        # wall_profile.csv

    def cycles(self) -> list[int]:
        return sorted(int(c) for c in self.table["cycle"].unique())

    def bands(self, cycle: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(depth of each band's top, depth of its bottom, its stress), depth from the bed
        height H (the top band's upper limit) down."""
        rows = self.table[self.table["cycle"] == cycle].sort_values("bin")
        height = float(rows["z_hi"].max())
        return (height - rows["z_hi"].to_numpy(float), height - rows["z_lo"].to_numpy(float),
                rows["wall_stress"].to_numpy(float))


@dataclass
class DepthFit:
    cycle: int
    radius: float
    height: float
    amplitude: float           # A = K γ, the stress gradient at the top
    amplitude_se: float
    rate: float                # a, per length (positive: growth, negative: saturation)
    rate_se: float
    rms_residual: float        # of the band stresses, in stress units
    mean_stress: float         # the bands' mean (each band the same height)

    @property
    def rate_times_radius(self) -> float:
        return self.rate * self.radius

    def to_dict(self) -> dict:
        return {"cycle": self.cycle, "radius": self.radius, "height": self.height,
                "amplitude": self.amplitude, "amplitude_se": self.amplitude_se,
                "rate": self.rate, "rate_se": self.rate_se, "rate_times_radius": self.rate_times_radius,
                "rate_times_radius_se": self.rate_se * self.radius, "rms_residual": self.rms_residual,
                "mean_stress": self.mean_stress}


def read_profile(folder: Path, radius: float | None = None) -> Profile:
    """The run's wall_profile.csv and its container radius (read from run.json unless the
    caller has it); ProfileError naming the file and field otherwise."""
    folder = Path(folder)
    path = folder / PROFILE_FILE
    if not path.is_file():
        raise ProfileError(f"{path}: no such file (a run writes it with outputs.wall_profile_bins > 0)")
    table = read_csv_columns(path, PROFILE_COLUMNS)
    if table is None:
        raise ProfileError(f"{path}: not a readable CSV")
    missing = [c for c in PROFILE_COLUMNS if c not in table.columns]
    if missing:
        raise ProfileError(f"{path}: expected the columns {', '.join(PROFILE_COLUMNS)}; missing {', '.join(missing)}")
    if table.empty:
        raise ProfileError(f"{path}: no rows (the container is not a cone, or no cycle ended)")
    return Profile(folder=folder, radius=read_cone(folder)[0] if radius is None else radius, table=table)


@dataclass
class RunScene:
    radius: float                  # the container's bottom radius
    angle: float                   # its opening angle, degrees
    wall_friction: float | None    # materials.wall_friction (None: the scene does not say)
    seed: int | None               # the realization (None: the scene does not say)


def read_scene(folder: Path) -> RunScene:
    """The run's cone, wall friction and seed, from one reading of run.json's effective scene."""
    run_json = Path(folder) / "run.json"
    try:
        scene = json.loads(run_json.read_text()).get("effective_scene") or {}
    except (OSError, ValueError) as e:
        raise ProfileError(f"{run_json}: not readable ({e})") from None
    container = scene.get("container") if isinstance(scene, dict) else None
    values = []
    for field in ("bottom_radius", "opening_angle_deg"):
        try:
            values.append(float(container[field]))
        except (KeyError, TypeError, ValueError):
            raise ProfileError(f"{run_json}: field 'effective_scene.container.{field}': expected a number "
                               "(the run's cone)") from None
    friction = (scene.get("materials") or {}).get("wall_friction")
    if friction is not None and not isinstance(friction, (int, float)):
        raise ProfileError(f"{run_json}: field 'effective_scene.materials.wall_friction': expected a number")
    seed = scene.get("seed")
    if seed is not None and not isinstance(seed, int):
        raise ProfileError(f"{run_json}: field 'effective_scene.seed': expected an integer")
    return RunScene(radius=values[0], angle=values[1],
                    wall_friction=None if friction is None else float(friction), seed=seed)


def read_cone(folder: Path) -> tuple[float, float]:
    """The container's bottom radius and opening angle in degrees (run.json's effective scene)."""
    scene = read_scene(folder)
    return scene.radius, scene.angle


def read_peak(folder: Path, cycle: int) -> float:
    """The cycle's peak pressure (cycles.csv, docs/output-format.md)."""
    path = Path(folder) / "cycles.csv"
    table = read_cycles(Path(folder))
    if table is None:
        raise ProfileError(f"{path}: not a readable CSV")
    if "cycle" not in table.columns or "peak_pressure" not in table.columns:
        raise ProfileError(f"{path}: expected the columns cycle and peak_pressure")
    rows = table[table["cycle"] == cycle]
    if rows.empty:
        raise ProfileError(f"{path}: field 'cycle': no row of cycle {cycle} (it has "
                           f"{sorted(int(c) for c in table['cycle'])})")
    return float(rows["peak_pressure"].iloc[0])


def _grown(x: np.ndarray) -> np.ndarray:
    """(e^x - 1 - x) / x², with its series where the closed form would lose digits."""
    x = np.asarray(x, float)
    small = np.abs(x) < 1e-2
    safe = np.where(small, 1.0, x)
    series = 0.5 + x / 6.0 + x * x / 24.0 + x ** 3 / 120.0 + x ** 4 / 720.0  # next term below 2e-15 of it
    return np.where(small, series, (np.expm1(safe) - safe) / (safe * safe))


def band_mean(top: np.ndarray, bottom: np.ndarray, amplitude: float, rate: float) -> np.ndarray:
    """The mean of A (e^{a d} - 1)/a over each band [top, bottom] of depth: the integral
    from 0 to d is A d² g(a d), g(x) = (e^x - 1 - x)/x², finite and smooth through a = 0
    (the hydrostatic A d²/2)."""
    top, bottom = np.asarray(top, float), np.asarray(bottom, float)
    integral = bottom ** 2 * _grown(rate * bottom) - top ** 2 * _grown(rate * top)
    return amplitude * integral / (bottom - top)


def fit_profile(profile: Profile, cycle: int) -> DepthFit:
    """Least squares of the band-averaged form to the cycle's bands (scipy's curve_fit;
    standard errors from its covariance, scaled by the residual)."""
    if cycle not in profile.cycles():
        raise ProfileError(f"{profile.folder / PROFILE_FILE}: field 'cycle': no rows of cycle {cycle} "
                           f"(it has {profile.cycles()})")
    top, bottom, stress = profile.bands(cycle)
    if len(stress) < MIN_BANDS:
        raise ProfileError(f"{profile.folder / PROFILE_FILE}: cycle {cycle} has {len(stress)} bands; "
                           f"a fit needs at least {MIN_BANDS} (outputs.wall_profile_bins)")
    height = float(bottom.max())
    slope = max(float(stress.mean()) / (0.5 * height), 1e-12)  # the hydrostatic A with the same mean

    def model(_, amplitude, rate):
        return band_mean(top, bottom, amplitude, rate)

    (amplitude, rate), covariance = curve_fit(model, np.zeros_like(stress), stress, p0=(slope, 0.0),
                                              maxfev=10000)
    se = np.sqrt(np.diag(covariance)) if np.all(np.isfinite(covariance)) else (math.nan, math.nan)
    residual = stress - band_mean(top, bottom, amplitude, rate)
    return DepthFit(cycle=cycle, radius=profile.radius, height=height, amplitude=float(amplitude),
                    amplitude_se=float(se[0]), rate=float(rate), rate_se=float(se[1]),
                    rms_residual=float(np.sqrt(np.mean(residual ** 2))), mean_stress=float(stress.mean()))


@dataclass
class WidthFit:
    height: float              # the common bed height the fit assumes
    amplitude: float           # A
    amplitude_se: float
    c: float                   # 2 μ_w K, the growth rate times the radius
    c_se: float
    radii: list[float]
    pressures: list[float]
    predicted: list[float]

    def to_dict(self) -> dict:
        return {"height": self.height, "amplitude": self.amplitude, "amplitude_se": self.amplitude_se,
                "c": self.c, "c_se": self.c_se, "radii": self.radii, "pressures": self.pressures,
                "predicted": self.predicted}


def mean_pressure(radius, height: float, amplitude: float, c: float) -> np.ndarray:
    """A H g(c H / R): the mean of A (e^{a d} - 1)/a over [0, H] at a = c / R."""
    radius = np.asarray(radius, float)
    return amplitude * height * _grown(c * height / radius)


def fit_widths(radii, pressures, height: float) -> WidthFit:
    """Least squares of log P(R) (the peaks span more than a decade, and their scatter
    between realizations is a share of their size) for A and c."""
    radii, pressures = np.asarray(radii, float), np.asarray(pressures, float)
    if len(set(radii.tolist())) < 3:
        raise ProfileError(f"a fit of the peak pressure against the width needs beds of at least 3 widths; "
                           f"got the radii {sorted(set(radii.tolist()))}")

    def model(r, log_amplitude, c):
        return np.log(mean_pressure(r, height, math.exp(log_amplitude), c))

    start = math.log(float(np.min(pressures)) / (0.5 * height))
    (log_amplitude, c), covariance = curve_fit(model, radii, np.log(pressures), p0=(start, 0.5), maxfev=10000)
    se = np.sqrt(np.diag(covariance)) if np.all(np.isfinite(covariance)) else (math.nan, math.nan)
    amplitude = math.exp(log_amplitude)
    return WidthFit(height=height, amplitude=amplitude, amplitude_se=float(amplitude * se[0]), c=float(c),
                    c_se=float(se[1]), radii=radii.tolist(), pressures=pressures.tolist(),
                    predicted=mean_pressure(radii, height, amplitude, c).tolist())


@dataclass
class AngleFit:
    radius: float
    height: float
    c: float                   # c at 0 deg, from the width fit (held)
    amplitude: float
    amplitude_se: float
    mu: float                  # the friction the angles' peaks give
    mu_se: float
    angles: list[float]
    pressures: list[float]
    predicted: list[float]

    def to_dict(self) -> dict:
        return {"radius": self.radius, "height": self.height, "c": self.c, "amplitude": self.amplitude,
                "amplitude_se": self.amplitude_se, "mu": self.mu, "mu_se": self.mu_se, "angles": self.angles,
                "pressures": self.pressures, "predicted": self.predicted}


def angle_pressure(angle_deg, radius: float, height: float, amplitude: float, c: float, mu: float) -> np.ndarray:
    """A H g(c (cos θ - sin θ / μ) H / R)."""
    theta = np.radians(np.asarray(angle_deg, float))
    return amplitude * height * _grown(c * (np.cos(theta) - np.sin(theta) / mu) * height / radius)


def fit_angles(angles, pressures, radius: float, height: float, c: float) -> AngleFit:
    """Least squares of log P(θ) for A and μ_w at the width fit's c."""
    angles, pressures = np.asarray(angles, float), np.asarray(pressures, float)
    if len(set(angles.tolist())) < 3:
        raise ProfileError(f"a fit of the peak pressure against the opening angle needs beds of at least 3 "
                           f"angles at one radius; got the angles {sorted(set(angles.tolist()))}")

    def model(a, log_amplitude, mu):
        return np.log(angle_pressure(a, radius, height, math.exp(log_amplitude), c, mu))

    start = math.log(float(np.max(pressures)) / (height * float(_grown(c * height / radius))))
    (log_amplitude, mu), covariance = curve_fit(model, angles, np.log(pressures), p0=(start, 0.5),
                                                bounds=([-np.inf, 1e-3], [np.inf, 10.0]), maxfev=10000)
    se = np.sqrt(np.diag(covariance)) if np.all(np.isfinite(covariance)) else (math.nan, math.nan)
    amplitude = math.exp(log_amplitude)
    return AngleFit(radius=radius, height=height, c=c, amplitude=amplitude, amplitude_se=float(amplitude * se[0]),
                    mu=float(mu), mu_se=float(se[1]), angles=angles.tolist(), pressures=pressures.tolist(),
                    predicted=angle_pressure(angles, radius, height, amplitude, c, mu).tolist())


def invert_c(pressure: float, radius: float, height: float, amplitude: float) -> float:
    """The c for which A H g(c H / R) equals the pressure; g rises monotonically from 0
    (x → −∞) through 1/2 (x = 0) without bound, so there is exactly one."""
    target = pressure / (amplitude * height)
    if not (math.isfinite(target) and target > 0):
        raise ProfileError(f"a peak pressure of {pressure} with A = {amplitude}: expected both positive")
    lo, hi = -1.0, 1.0
    while _grown(lo) > target:
        lo *= 2.0
    while _grown(hi) < target:
        hi *= 2.0
    x = brentq(lambda v: float(_grown(v)) - target, lo, hi, xtol=1e-14, rtol=1e-14)
    return x * radius / height


def friction_pair(c0: float, c_theta: float, theta_deg: float) -> tuple[float, float]:
    """(μ_w, K) from c at 0 (2 μ_w K) and at θ (2 K (μ_w cos θ − sin θ))."""
    theta = math.radians(theta_deg)
    k = (c0 * math.cos(theta) - c_theta) / (2.0 * math.sin(theta))
    return c0 / (2.0 * k), k


def predicted_ratio(p0: float, theta_deg: float, k: float, radius: float, height: float,
                    amplitude: float) -> float:
    """P(θ)/P(0) when the 0° peak p0 fixes 2 μ_w K and K is given: c(θ) = c0 cos θ − 2 K sin θ."""
    theta = math.radians(theta_deg)
    c0 = invert_c(p0, radius, height, amplitude)
    c_theta = c0 * math.cos(theta) - 2.0 * k * math.sin(theta)
    return float(mean_pressure([radius], height, amplitude, c_theta)[0]) / p0
