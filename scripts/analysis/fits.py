"""Least-squares fits, group statistics over realizations and the ratio of two means.

Everything numerical goes through library routines: the polynomial fits use
scipy.optimize.curve_fit (with the exact Jacobian of the polynomial model, started
from numpy.polynomial.polynomial.polyfit), the statistics use numpy/pandas.

Conventions (docs/trends.md, "Fit formulas"):

- A polynomial of degree d is y = c0 + c1 x + ... + cd x^d; coefficients are stored
  in ascending order (``coef[1]`` is the slope of a linear fit).
- Unweighted fit (sigma=None): minimises sum (y - f(x))^2; the covariance is
  scaled by the residual variance s^2 = SS_res / (n - d - 1), so standard errors
  come from the scatter of the data about the fit.
- Weighted fit (sigma given): minimises sum ((y - f(x)) / sigma)^2. With
  absolute_sigma=False only the relative weights count (covariance scaled by the
  reduced chi^2, as unweighted); with absolute_sigma=True sigma is taken as the true
  one-standard-deviation error of each y and the covariance is not rescaled.
- R^2 = 1 - SS_res / SS_tot with SS_res = sum w (y - f)^2 and
  SS_tot = sum w (y - ybar_w)^2, w = 1/sigma^2 (w = 1 unweighted), ybar_w the
  weighted mean. NaN when SS_tot = 0 (constant data).
- With n = d + 1 points the fit interpolates (dof = 0): the coefficients are exact
  but, without absolute sigma, no standard error exists (NaN).
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from typing import Sequence

import numpy as np
import pandas as pd
from numpy.polynomial import polynomial as _poly
from scipy import stats
from scipy.optimize import OptimizeWarning, curve_fit


class FitError(ValueError):
    """Too few (distinct, finite) points for the requested fit."""


def _model(x, *coef):
    return _poly.polyval(x, coef)


def _jacobian(x, *coef):
    # d f / d c_k = x^k: the Vandermonde matrix, columns in ascending powers.
    return _poly.polyvander(np.asarray(x, dtype=float), len(coef) - 1)


@dataclass
class FitResult:
    """A polynomial least-squares fit (coefficients ascending: c0, c1, ...)."""

    degree: int
    coef: np.ndarray
    se: np.ndarray
    cov: np.ndarray
    r2: float
    n: int
    dof: int
    weighted: bool
    absolute_sigma: bool
    ss_res: float
    x_min: float
    x_max: float

    @property
    def slope(self) -> float:
        """c1: the slope of a linear fit (the linear coefficient in general)."""
        return float(self.coef[1])

    @property
    def slope_se(self) -> float:
        return float(self.se[1])

    def predict(self, x) -> np.ndarray:
        return _model(np.asarray(x, dtype=float), *self.coef)

    def curve(self, points: int = 101, x_min: float | None = None,
              x_max: float | None = None) -> tuple[np.ndarray, np.ndarray]:
        """The fitted curve sampled on [x_min, x_max] (default: the data range)."""
        lo = self.x_min if x_min is None else x_min
        hi = self.x_max if x_max is None else x_max
        xs = np.linspace(lo, hi, points)
        return xs, self.predict(xs)

    def formula(self, x: str = "x", digits: int = 4) -> str:
        terms = []
        for power, (c, s) in enumerate(zip(self.coef, self.se)):
            err = f" +- {s:.{digits}g}" if math.isfinite(s) else ""
            var = "" if power == 0 else (f" {x}" if power == 1 else f" {x}^{power}")
            terms.append(f"({c:.{digits}g}{err}){var}")
        return " + ".join(terms)

    def to_dict(self, curve_points: int = 51) -> dict:
        xs, ys = self.curve(curve_points)
        return {
            "degree": self.degree,
            "coefficients": [float(c) for c in self.coef],
            "standard_errors": [float(s) for s in self.se],
            "covariance": [[float(v) for v in row] for row in self.cov],
            "coefficient_order": "ascending: c0 + c1 x + c2 x^2",
            "r2": float(self.r2),
            "n": self.n,
            "dof": self.dof,
            "weighted": self.weighted,
            "absolute_sigma": self.absolute_sigma,
            "ss_res": float(self.ss_res),
            "x_range": [float(self.x_min), float(self.x_max)],
            "curve": {"x": [float(v) for v in xs], "y": [float(v) for v in ys]},
        }


def _clean(x, y, sigma):
    x = np.asarray(x, dtype=float).ravel()
    y = np.asarray(y, dtype=float).ravel()
    if x.shape != y.shape:
        raise ValueError(f"x and y differ in length ({x.size} and {y.size})")
    keep = np.isfinite(x) & np.isfinite(y)
    if sigma is not None:
        sigma = np.asarray(sigma, dtype=float).ravel()
        if sigma.shape != x.shape:
            raise ValueError(f"sigma has {sigma.size} values for {x.size} points")
        keep &= np.isfinite(sigma) & (sigma > 0)
        sigma = sigma[keep]
    return x[keep], y[keep], sigma


def polyfit(x: Sequence[float], y: Sequence[float], degree: int,
            sigma: Sequence[float] | None = None, absolute_sigma: bool = False) -> FitResult:
    """Least-squares polynomial fit of the given degree (1 linear, 2 quadratic).

    Points with a non-finite x, y (or a non-finite or non-positive sigma) are
    dropped. Raises FitError when fewer than degree + 1 distinct x remain.
    """
    if degree < 0:
        raise ValueError("degree must be >= 0")
    x, y, sigma = _clean(x, y, sigma)
    n_params = degree + 1
    distinct = np.unique(x).size
    if distinct < n_params:
        raise FitError(f"a degree-{degree} fit needs {n_params} distinct x values, "
                       f"got {distinct} (from {x.size} finite points)")
    weights = None if sigma is None else 1.0 / sigma
    p0 = _poly.polyfit(x, y, degree, w=weights)  # starting point: the exact solution
    with warnings.catch_warnings():
        # dof = 0 makes curve_fit warn that the covariance cannot be estimated.
        warnings.simplefilter("ignore", OptimizeWarning)
        coef, cov = curve_fit(_model, x, y, p0=p0, sigma=sigma, absolute_sigma=absolute_sigma,
                              jac=_jacobian, method="lm")
    cov = np.atleast_2d(np.asarray(cov, dtype=float))
    dof = x.size - n_params
    if dof == 0 and not (absolute_sigma and sigma is not None):
        cov = np.full((n_params, n_params), np.nan)
    cov[~np.isfinite(cov)] = np.nan
    se = np.sqrt(np.clip(np.diag(cov), 0.0, None))
    w = np.ones_like(y) if sigma is None else 1.0 / sigma ** 2
    residual = y - _model(x, *coef)
    ss_res = float(np.sum(w * residual ** 2))
    y_bar = float(np.sum(w * y) / np.sum(w))
    ss_tot = float(np.sum(w * (y - y_bar) ** 2))
    if ss_tot > 0:
        r2 = 1.0 - ss_res / ss_tot
    else:
        r2 = math.nan
    return FitResult(degree=degree, coef=np.asarray(coef, dtype=float), se=se, cov=cov,
                     r2=r2, n=int(x.size), dof=int(dof), weighted=sigma is not None,
                     absolute_sigma=bool(absolute_sigma and sigma is not None),
                     ss_res=ss_res, x_min=float(x.min()), x_max=float(x.max()))


def linear_fit(x, y, sigma=None, absolute_sigma=False) -> FitResult:
    return polyfit(x, y, 1, sigma, absolute_sigma)


def quadratic_fit(x, y, sigma=None, absolute_sigma=False) -> FitResult:
    return polyfit(x, y, 2, sigma, absolute_sigma)


def try_fit(x, y, degree, sigma=None, absolute_sigma=False) -> tuple[FitResult | None, str]:
    """polyfit, or (None, why) when there are too few points."""
    try:
        return polyfit(x, y, degree, sigma, absolute_sigma), ""
    except FitError as error:
        return None, str(error)


# --------------------------------------------------------------------------- groups


def group_stats(frame: pd.DataFrame, by: str, value: str) -> pd.DataFrame:
    """Mean, standard deviation and standard error of `value` per value of `by`.

    Rows with a non-finite `value` are left out. Columns: x, n, mean, std (sample
    standard deviation, ddof = 1; NaN for n = 1), sem = std / sqrt(n) (NaN for n = 1).
    Sorted by x.
    """
    data = frame[[by, value]].copy()
    data[value] = pd.to_numeric(data[value], errors="coerce")
    data = data[np.isfinite(data[value].to_numpy(dtype=float))]
    grouped = data.groupby(by, sort=True)[value]
    out = pd.DataFrame({
        "x": grouped.mean().index.to_numpy(dtype=float),
        "n": grouped.count().to_numpy(dtype=int),
        "mean": grouped.mean().to_numpy(dtype=float),
        "std": grouped.std(ddof=1).to_numpy(dtype=float),
    })
    out["sem"] = out["std"] / np.sqrt(out["n"])
    return out.reset_index(drop=True)


def mean_sem(values: Sequence[float]) -> tuple[float, float, float, int]:
    """(mean, std with ddof=1, sem, n) of the finite values; NaNs where undefined."""
    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v)]
    n = int(v.size)
    if n == 0:
        return math.nan, math.nan, math.nan, 0
    mean = float(np.mean(v))
    if n < 2:
        return mean, math.nan, math.nan, n
    std = float(np.std(v, ddof=1))
    return mean, std, std / math.sqrt(n), n


def ratio_of_means(numerator: Sequence[float], denominator: Sequence[float]) -> dict:
    """R = mean(numerator) / mean(denominator) with first-order error propagation.

    sigma_R = |R| * sqrt((sem_num / mean_num)^2 + (sem_den / mean_den)^2), with
    sem = sample standard deviation / sqrt(n) of each group's realizations. This is
    the delta method for a ratio of two independent means (the realizations of the
    two parameter points are different runs), valid when each sem is small against
    its mean. NaN when a group has fewer than two realizations.

    dof: the Welch-Satterthwaite degrees of freedom of sigma_R,
    sigma_R^4 / (a^4 / (n_num - 1) + b^4 / (n_den - 1)) with a = sem_num / |mean_den| and
    b = |R| sem_den / |mean_den| its two terms (as Welch's t test combines two standard
    errors); it lies between min(n) - 1 and n_num + n_den - 2 (the latter when sigma_R = 0).
    """
    m_num, s_num, e_num, n_num = mean_sem(numerator)
    m_den, s_den, e_den, n_den = mean_sem(denominator)
    if n_num == 0 or n_den == 0 or m_den == 0:
        ratio = math.nan
    else:
        ratio = m_num / m_den
    if math.isfinite(ratio) and math.isfinite(e_num) and math.isfinite(e_den):
        # |R| sqrt((e_a/m_a)^2 + (e_b/m_b)^2), written so that m_a = 0 is allowed.
        sigma = math.sqrt(e_num ** 2 + (ratio * e_den) ** 2) / abs(m_den)
    else:
        sigma = math.nan
    dof = math.nan
    if math.isfinite(sigma) and sigma > 0:
        a, b = e_num / abs(m_den), abs(ratio) * e_den / abs(m_den)
        dof = sigma ** 4 / (a ** 4 / (n_num - 1) + b ** 4 / (n_den - 1))
    elif math.isfinite(sigma):  # no scatter at all: the interval is the point, any k will do
        dof = float(n_num + n_den - 2)
    return {
        "ratio": ratio, "sigma": sigma, "dof": dof,
        "numerator": {"mean": m_num, "std": s_num, "sem": e_num, "n": n_num},
        "denominator": {"mean": m_den, "std": s_den, "sem": e_den, "n": n_den},
        "propagation": "first order (delta method), independent groups: "
                       "sigma_R = |R| sqrt((sem_a/mean_a)^2 + (sem_b/mean_b)^2)",
    }


# --------------------------------------------------------------------------- tests


def t_quantile(level: float, dof: float) -> float:
    """k of a two-sided confidence interval value +- k SE at `level` (e.g. 0.95) for an
    estimate with `dof` degrees of freedom: scipy.stats.t.ppf((1 + level) / 2, dof).
    NaN for dof < 1 or NaN (no interval)."""
    if not math.isfinite(dof) or dof <= 0:
        return math.nan
    return float(stats.t.ppf(0.5 * (1.0 + level), dof))


def widened_k(k: float, dof: float) -> float:
    """The multiple of the SE that a rule stated as "k SE" (the large-sample, normal
    limit: two-sided level erf(k / sqrt 2), 95.4 % at k = 2) needs for an estimate with
    `dof` degrees of freedom: t_quantile at that level. k itself when dof is infinite;
    14.0 for k = 2 at one degree of freedom, 2.09 at 20. NaN for dof < 1."""
    return t_quantile(math.erf(k / math.sqrt(2.0)), dof)


def mean_interval(values: Sequence[float], level: float) -> dict:
    """Mean of the finite values with its two-sided Student t interval at `level`:
    mean +- k sem, k = t_quantile(level, n - 1). Interval NaN for n < 2."""
    mean, std, sem, n = mean_sem(values)
    k = t_quantile(level, n - 1)
    return {"mean": mean, "std": std, "sem": sem, "n": n, "dof": n - 1, "k": k,
            "low": mean - k * sem, "high": mean + k * sem}


def _pooled_curvature(quad: FitResult, line: FitResult) -> dict:
    """The x^2 term against the fits' pooled residual scatter (every run the same):
    F = (SS_lin - SS_quad) / (SS_quad / (n - 3)), p = scipy.stats.f.sf(F, 1, n - 3);
    F = (c2 / SE(c2))^2, the two-sided t test of c2."""
    c2, se = float(quad.coef[2]), float(quad.se[2])
    if quad.ss_res > 0:
        f_value = (line.ss_res - quad.ss_res) / (quad.ss_res / quad.dof)
        p = float(stats.f.sf(f_value, 1, quad.dof))
    else:  # an exact quadratic: any curvature is resolved, none is not
        f_value = math.inf if line.ss_res > 0 else math.nan
        p = 0.0 if line.ss_res > 0 else 1.0
    if se > 0:
        t = c2 / se
    else:
        t = math.copysign(math.inf, c2) if c2 else math.nan
    return {"se": se, "t": t, "F": float(f_value), "p": p, "dof": float(quad.dof)}


def _per_point_curvature(x: np.ndarray, y: np.ndarray, c2: float) -> dict | None:
    """The x^2 term of the unweighted fit against each point's own scatter.

    c2 = sum_j a_j y_j (a: the x^2 row of the fit's pseudo-inverse), so
    Var(c2) = sum_g s_g^2 A_g with A_g = sum of a_j^2 over the runs of point g and s_g^2
    the sample variance of its realizations (pure error: no lack of fit enters). A point
    with one realization takes the largest s_g^2 of the replicated points (conservative
    where the scatter grows along the sweep). Terms sharing one estimate are summed before
    the Welch-Satterthwaite degrees of freedom, nu = Var^2 / sum_src (s^2 B)^2 / (n_src - 1)
    (Satterthwaite 1946, Biometrics Bull. 2, 110), as Welch's t test combines two groups.
    None when no point has two realizations (then only the pooled scatter exists)."""
    a = np.linalg.pinv(_poly.polyvander(x, 2))[2]
    values, group = np.unique(x, return_inverse=True)
    n = np.bincount(group, minlength=values.size)
    big_a = np.bincount(group, weights=a ** 2, minlength=values.size)
    replicated = [g for g in range(values.size) if n[g] >= 2]
    single = [g for g in range(values.size) if n[g] < 2]
    if not replicated:
        return None
    var = {g: float(np.var(y[group == g], ddof=1)) for g in replicated}
    noisiest = max(replicated, key=lambda g: var[g])
    share = {g: float(big_a[g]) for g in replicated}
    share[noisiest] += float(sum(big_a[g] for g in single))
    terms = {g: var[g] * share[g] for g in replicated}
    total = sum(terms.values())
    se = math.sqrt(total)
    record = {"se": se, "borrowed": [float(values[g]) for g in single],
              "borrowed_from": float(values[noisiest]) if single else None,
              "point_sd": {float(values[g]): math.sqrt(var[g]) for g in replicated}}
    if total > 0:
        dof = total ** 2 / sum(term ** 2 / (n[g] - 1) for g, term in terms.items() if term > 0)
        t = c2 / se
        p = float(2.0 * stats.t.sf(abs(t), dof))
    else:  # every point's realizations identical: any curvature is resolved, none is not
        dof = float(sum(n[g] - 1 for g in replicated))
        t = math.copysign(math.inf, c2) if c2 else math.nan
        p = 0.0 if c2 else 1.0
    return {**record, "t": t, "F": t * t, "p": p, "dof": float(dof)}


def curvature_test(x, y) -> dict:
    """Is a quadratic resolved against a straight line? The unweighted quadratic fit over
    all points (each realization one point); its x^2 term c2 is t-tested twice: against
    each point's own scatter with Welch-Satterthwaite degrees of freedom
    (_per_point_curvature: the scatter of these sweeps grows along them, 0.15 to 11 in
    P_max over the paper's ratio sweep, and a pooled scatter then claims too much), and
    against the fits' pooled residual, which holds any lack of fit (_pooled_curvature: a
    zigzag of exact points has a precise c2 that no quadratic follows). The curvature is
    resolved only where both resolve it, so the larger p is the test's (an
    intersection-union test, level at most that of each). Without a replicated point the
    pooled test is the only one. Raises FitError without 3 distinct x and n >= 4.

    Returns c2, its SE, t = c2 / SE, F = t^2, p (two-sided) and dof of the test with the
    larger p, "scatter" ("per point" or "pooled": which one that is), both tests under
    "per_point" (None without a replicated point) and "pooled", and both fits."""
    x, y, _ = _clean(x, y, None)
    quad = quadratic_fit(x, y)
    line = linear_fit(x, y)
    if quad.dof < 1:
        raise FitError(f"{quad.n} points: the curvature needs n >= 4 for a scatter estimate")
    c2 = float(quad.coef[2])
    pooled = _pooled_curvature(quad, line)
    per_point = _per_point_curvature(x, y, c2)
    if per_point is not None and not per_point["p"] < pooled["p"]:
        chosen, scatter = per_point, "per point"
    else:
        chosen, scatter = pooled, "pooled"
    return {"c2": c2, **{key: chosen[key] for key in ("se", "t", "F", "p", "dof")}, "scatter": scatter,
            "pooled": pooled, "per_point": per_point,
            "quadratic": quad, "linear": line}
