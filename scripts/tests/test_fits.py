"""Tests of scripts/analysis/fits.py: fits, group statistics, ratio of means.

Run with Debian's interpreter: /usr/bin/python3 -m pytest -q scripts/tests
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from scipy import stats

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from analysis import fits  # noqa: E402

TRUTH = (3.0, -0.4, 0.05)   # c0 + c1 x + c2 x^2


def quadratic_data(seed=7, sigma=0.2, realizations=5, xs=(0, 2, 4, 6, 8)):
    rng = np.random.default_rng(seed)
    x = np.repeat(np.asarray(xs, dtype=float), realizations)
    y = TRUTH[0] + TRUTH[1] * x + TRUTH[2] * x ** 2 + rng.normal(0.0, sigma, x.size)
    return x, y


def test_quadratic_fit_recovers_the_coefficients_within_their_standard_errors():
    x, y = quadratic_data()
    fit = fits.quadratic_fit(x, y)
    assert fit.degree == 2 and fit.n == 25 and fit.dof == 22
    for c, se, truth in zip(fit.coef, fit.se, TRUTH):
        assert math.isfinite(se) and se > 0
        assert abs(c - truth) <= 2 * se, (c, se, truth)
    assert 0.7 < fit.r2 < 1.0   # the curve spans about 1, the noise 0.2


def test_unweighted_fit_agrees_with_numpy_polyfit_and_its_covariance():
    x, y = quadratic_data(seed=3)
    fit = fits.quadratic_fit(x, y)
    coef, cov = np.polyfit(x, y, 2, cov=True)   # highest power first
    np.testing.assert_allclose(fit.coef, coef[::-1], rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(fit.cov, cov[::-1, ::-1], rtol=1e-6)


def test_slope_standard_error_covers_the_truth_about_95_percent_of_the_time():
    rng = np.random.default_rng(11)
    x = np.repeat(np.arange(5.0), 3)
    inside = 0
    trials = 400
    for _ in range(trials):
        y = 1.0 + 0.3 * x + rng.normal(0.0, 0.5, x.size)
        fit = fits.linear_fit(x, y)
        inside += abs(fit.slope - 0.3) <= 2 * fit.slope_se
    # 2 SE with 13 degrees of freedom: about 93 % coverage (Student t).
    assert 0.88 <= inside / trials <= 0.98


def test_exact_quadratic_has_r2_one_and_exact_coefficients():
    x = np.array([1.0, 5.0, 10.0, 15.0, 20.0])
    y = TRUTH[0] + TRUTH[1] * x + TRUTH[2] * x ** 2
    fit = fits.quadratic_fit(x, y)
    assert fit.r2 == pytest.approx(1.0, abs=1e-12)
    np.testing.assert_allclose(fit.coef, TRUTH, rtol=1e-9, atol=1e-10)
    np.testing.assert_allclose(fit.se, 0.0, atol=1e-6)
    xs, ys = fit.curve(11)
    np.testing.assert_allclose(ys, TRUTH[0] + TRUTH[1] * xs + TRUTH[2] * xs ** 2, rtol=1e-9)


def test_r2_against_a_hand_computation():
    x = np.array([0.0, 1.0, 2.0, 3.0])
    y = np.array([0.0, 2.0, 1.0, 3.0])
    fit = fits.linear_fit(x, y)
    # Least squares: slope = Sxy/Sxx = 4/5 = 0.8, intercept = 1.5 - 0.8*1.5 = 0.3.
    assert fit.coef == pytest.approx([0.3, 0.8])
    residual = y - (0.3 + 0.8 * x)
    r2 = 1 - np.sum(residual ** 2) / np.sum((y - y.mean()) ** 2)
    assert fit.r2 == pytest.approx(r2)
    # SE(slope) = sqrt(s^2 / Sxx), s^2 = SS_res / (n - 2).
    assert fit.slope_se == pytest.approx(math.sqrt(np.sum(residual ** 2) / 2 / 5.0))


def test_weighted_fit_matches_numpy_with_weights_and_absolute_sigma():
    x, y = quadratic_data(seed=5, realizations=1, xs=np.linspace(0, 8, 9))
    sigma = np.linspace(0.1, 0.5, x.size)
    fit = fits.quadratic_fit(x, y, sigma=sigma, absolute_sigma=True)
    coef = np.polynomial.polynomial.polyfit(x, y, 2, w=1 / sigma)
    np.testing.assert_allclose(fit.coef, coef, rtol=1e-9, atol=1e-12)
    # absolute sigma: covariance = (J^T W J)^-1, independent of the residuals.
    _, cov_unscaled = np.polyfit(x, y, 2, w=1 / sigma, cov="unscaled")
    np.testing.assert_allclose(fit.cov, cov_unscaled[::-1, ::-1], rtol=1e-6)
    assert fit.weighted and fit.absolute_sigma
    # Relative weights only: covariance scaled by the reduced chi^2.
    relative = fits.quadratic_fit(x, y, sigma=sigma)
    chi2 = relative.ss_res / relative.dof
    np.testing.assert_allclose(relative.cov, cov_unscaled[::-1, ::-1] * chi2, rtol=1e-6)


def test_fit_over_realizations_equals_fit_of_means_weighted_by_count():
    x, y = quadratic_data(seed=9)
    keep = np.ones(x.size, bool)
    keep[[0, 1, 7]] = False   # unbalanced: 3, 4 and 5 realizations
    frame = pd.DataFrame({"x": x[keep], "y": y[keep]})
    groups = fits.group_stats(frame, "x", "y")
    all_points = fits.quadratic_fit(frame["x"], frame["y"])
    means = fits.quadratic_fit(groups["x"], groups["mean"], sigma=1 / np.sqrt(groups["n"]))
    np.testing.assert_allclose(all_points.coef, means.coef, rtol=1e-9, atol=1e-12)


def test_interpolating_fit_has_no_standard_error():
    fit = fits.quadratic_fit([0.0, 1.0, 2.0], [1.0, 0.0, 3.0])
    assert fit.dof == 0
    assert all(math.isnan(s) for s in fit.se)
    assert fit.r2 == pytest.approx(1.0)


def test_too_few_distinct_points_raise_and_try_fit_explains():
    with pytest.raises(fits.FitError):
        fits.linear_fit([2.0, 2.0, 2.0], [1.0, 2.0, 3.0])
    fit, why = fits.try_fit([1.0, 2.0], [1.0, 2.0], 2)
    assert fit is None and "3 distinct" in why


def test_non_finite_points_are_dropped():
    fit = fits.linear_fit([0.0, 1.0, np.nan, 2.0, 3.0], [1.0, 3.0, 5.0, np.inf, 7.0])
    assert fit.n == 3
    assert fit.coef == pytest.approx([1.0, 2.0])


def test_constant_data_give_undefined_r2():
    fit = fits.linear_fit([0.0, 1.0, 2.0], [4.0, 4.0, 4.0])
    assert math.isnan(fit.r2)
    assert fit.slope == pytest.approx(0.0, abs=1e-12)


def test_group_stats_against_a_hand_computation():
    frame = pd.DataFrame({"theta": [0, 0, 0, 6, 6, 8],
                          "P": [9.0, 10.0, 11.0, 4.0, 6.0, 3.0]})
    groups = fits.group_stats(frame, "theta", "P")
    assert list(groups["x"]) == [0, 6, 8]
    assert list(groups["n"]) == [3, 2, 1]
    assert list(groups["mean"]) == pytest.approx([10.0, 5.0, 3.0])
    assert groups["std"][0] == pytest.approx(1.0)
    assert groups["std"][1] == pytest.approx(math.sqrt(2.0))
    assert groups["sem"][0] == pytest.approx(1 / math.sqrt(3))
    assert groups["sem"][1] == pytest.approx(1.0)
    assert math.isnan(groups["std"][2]) and math.isnan(groups["sem"][2])


def test_group_stats_ignores_non_finite_values():
    frame = pd.DataFrame({"x": [1, 1, 1], "y": [1.0, np.nan, 3.0]})
    groups = fits.group_stats(frame, "x", "y")
    assert groups["n"][0] == 2 and groups["mean"][0] == pytest.approx(2.0)


def test_ratio_of_means_and_its_propagated_uncertainty():
    at_6 = [4.0, 5.0, 6.0]       # mean 5, std 1, sem 1/sqrt(3)
    at_0 = [8.0, 10.0, 12.0]     # mean 10, std 2, sem 2/sqrt(3)
    result = fits.ratio_of_means(at_6, at_0)
    assert result["ratio"] == pytest.approx(0.5)
    sem_a, sem_b = 1 / math.sqrt(3), 2 / math.sqrt(3)
    hand = 0.5 * math.sqrt((sem_a / 5.0) ** 2 + (sem_b / 10.0) ** 2)
    assert result["sigma"] == pytest.approx(hand)
    assert result["numerator"]["n"] == 3 and result["denominator"]["sem"] == pytest.approx(sem_b)
    assert "first order" in result["propagation"]


def test_ratio_of_means_without_replicates_has_no_uncertainty():
    result = fits.ratio_of_means([5.0], [10.0, 11.0])
    assert result["ratio"] == pytest.approx(5.0 / 10.5)
    assert math.isnan(result["sigma"])


def test_ratio_with_a_zero_denominator_is_undefined():
    result = fits.ratio_of_means([1.0, 2.0], [0.0, 0.0])
    assert math.isnan(result["ratio"]) and math.isnan(result["sigma"])


def test_fit_result_serializes():
    x, y = quadratic_data(seed=1)
    data = fits.linear_fit(x, y).to_dict(curve_points=5)
    assert data["degree"] == 1 and len(data["coefficients"]) == 2
    assert len(data["curve"]["x"]) == 5 and data["dof"] == 23


# --------------------------------------------------------------------------- tests of shape


def test_curvature_test_pooled_is_the_f_test_of_nested_fits_and_the_t_test_of_c2():
    x, y = quadratic_data(sigma=0.2)
    pooled = fits.curvature_test(x, y)["pooled"]
    line, quad = fits.linear_fit(x, y), fits.quadratic_fit(x, y)
    f_value = (line.ss_res - quad.ss_res) / (quad.ss_res / (x.size - 3))
    assert pooled["F"] == pytest.approx(f_value)
    assert pooled["F"] == pytest.approx(pooled["t"] ** 2)      # one extra parameter
    assert pooled["p"] == pytest.approx(stats.f.sf(f_value, 1, x.size - 3))
    assert pooled["dof"] == x.size - 3


def test_curvature_test_uses_each_points_own_scatter_with_satterthwaite_dof():
    x, y = quadratic_data(sigma=0.2)
    whole = fits.curvature_test(x, y)
    test = whole["per_point"]
    assert whole["c2"] == pytest.approx(fits.quadratic_fit(x, y).coef[2])
    # Var(c2) = sum_g s_g^2 sum_{j in g} a_j^2, a the x^2 row of the pseudo-inverse.
    a = np.linalg.pinv(np.vander(x, 3, increasing=True))[2]
    terms = [np.var(y[x == v], ddof=1) * np.sum(a[x == v] ** 2) for v in np.unique(x)]
    var = sum(terms)
    assert test["se"] == pytest.approx(math.sqrt(var))
    assert test["dof"] == pytest.approx(var ** 2 / sum(t ** 2 / 4 for t in terms))
    assert 4 <= test["dof"] <= 20                               # between one point's n - 1 and the sum
    assert test["p"] == pytest.approx(2 * stats.t.sf(abs(test["t"]), test["dof"]))
    assert test["p"] < 0.05 and whole["c2"] > 0                # TRUTH bends up by 0.05
    # Resolved only where both tests resolve it: the larger p is the test's.
    assert whole["p"] == max(test["p"], whole["pooled"]["p"])
    assert whole["scatter"] == ("per point" if test["p"] >= whole["pooled"]["p"] else "pooled")


def test_a_zigzag_of_exact_points_is_not_resolved_by_its_zero_scatter():
    # Two identical realizations per point: no scatter within a point, so the per-point
    # SE of c2 is 0; the pooled residual holds the zigzag and keeps it unresolved.
    x = np.repeat([1.0, 5.0, 10.0, 15.0, 20.0], 2)
    y = np.repeat([2.0, 9.0, 3.0, 10.0, 4.0], 2)
    test = fits.curvature_test(x, y)
    assert test["per_point"]["p"] == 0.0 and test["pooled"]["p"] > 0.05
    assert test["scatter"] == "pooled" and test["p"] == test["pooled"]["p"]


def test_a_point_of_one_realization_borrows_the_noisiest_replicated_scatter():
    rng = np.random.default_rng(5)
    x = np.array([1.0] * 5 + [2.5, 5.0, 7.5] + [10.0] * 5)
    y = 1.0 + 2.0 * x + rng.normal(0.0, 1.0, x.size) * np.where(x < 5, 0.1, 3.0)
    test = fits.curvature_test(x, y)["per_point"]
    assert test["borrowed"] == [2.5, 5.0, 7.5] and test["borrowed_from"] == 10.0
    a = np.linalg.pinv(np.vander(x, 3, increasing=True))[2]
    s2 = {v: np.var(y[x == v], ddof=1) for v in (1.0, 10.0)}
    term_1 = s2[1.0] * np.sum(a[x == 1.0] ** 2)
    term_10 = s2[10.0] * np.sum(a[x >= 2.5] ** 2)              # the borrowed share joins ratio 10's term
    assert test["se"] == pytest.approx(math.sqrt(term_1 + term_10))
    assert test["dof"] == pytest.approx((term_1 + term_10) ** 2 / (term_1 ** 2 / 4 + term_10 ** 2 / 4))


def test_where_the_scatter_grows_along_the_sweep_the_pooled_test_over_claims_and_this_one_does_not():
    # A straight line, 5 realizations at the ends, one at each inner point, the scatter
    # 30 times larger at one end: how often each test calls the line curved at 5 %.
    called = {"per point": 0, "pooled": 0}
    draws = 400
    for seed in range(draws):
        rng = np.random.default_rng(seed)
        x = np.array([1.0] * 5 + [2.5, 5.0, 7.5] + [10.0] * 5)
        sd = np.where(x == 1.0, 0.1, 3.0)
        test = fits.curvature_test(x, 1.0 + 2.0 * x + rng.normal(0.0, 1.0, x.size) * sd)
        called["per point"] += test["p"] < 0.05
        called["pooled"] += test["pooled"]["p"] < 0.05
    assert called["per point"] <= 0.08 * draws                 # at most its level (borrowing: conservative)
    assert called["pooled"] >= 0.10 * draws, called            # the pooled scatter: twice its level or more


def test_without_a_replicated_point_only_the_pooled_test_exists():
    x = np.array([0.0, 1.0, 2.0, 3.0, 4.0, 5.0])
    test = fits.curvature_test(x, 1.0 + x + 0.5 * x ** 2 + np.array([0.1, -0.1, 0.05, 0.0, -0.05, 0.1]))
    assert test["scatter"] == "pooled" and test["per_point"] is None
    assert test["p"] == test["pooled"]["p"] and test["dof"] == 3


def test_curvature_test_of_a_straight_line_is_not_significant_in_most_draws():
    # Under a straight line p is uniform: about 5 % of the draws fall below 0.05.
    below = 0
    for seed in range(200):
        rng = np.random.default_rng(seed)
        x = np.repeat(np.arange(5.0), 5)
        below += fits.curvature_test(x, 1.0 + 0.5 * x + rng.normal(0, 0.3, x.size))["p"] < 0.05
    assert 2 <= below <= 20   # binomial(200, 0.05): mean 10, sd 3.1


def test_curvature_test_needs_a_scatter_estimate():
    with pytest.raises(fits.FitError):
        fits.curvature_test([0.0, 1.0, 2.0], [0.0, 1.0, 4.0])


def test_a_k_se_rule_widens_to_student_t_at_its_dof():
    # k = 2 is 95.45 % two-sided in the normal limit; Student t at that level.
    assert fits.widened_k(2.0, 1) == pytest.approx(13.968, abs=1e-3)
    assert fits.widened_k(2.0, 8) == pytest.approx(2.3664, abs=1e-3)
    assert fits.widened_k(2.0, 1e9) == pytest.approx(2.0, abs=1e-6)
    ks = [fits.widened_k(2.5, dof) for dof in (1, 2, 5, 20, 100)]
    assert ks == sorted(ks, reverse=True) and ks[-1] > 2.5
    assert math.isnan(fits.widened_k(2.0, 0))


def test_t_quantile_and_mean_interval_are_student_t():
    assert fits.t_quantile(0.95, 4) == pytest.approx(2.776445, rel=1e-6)
    assert math.isnan(fits.t_quantile(0.95, 0))
    stat = fits.mean_interval([1.0, 2.0, 3.0], 0.95)
    assert stat["sem"] == pytest.approx(1.0 / math.sqrt(3.0))
    assert stat["low"] == pytest.approx(2.0 - 4.302653 / math.sqrt(3.0), rel=1e-6)
    assert math.isnan(fits.mean_interval([1.0], 0.95)["low"])


def test_ratio_dof_is_welch_satterthwaite():
    a, b = [10.0, 11.0, 12.0, 9.0, 13.0], [20.0, 26.0, 22.0]
    r = fits.ratio_of_means(a, b)
    first = r["numerator"]["sem"] / r["denominator"]["mean"]
    second = r["ratio"] * r["denominator"]["sem"] / r["denominator"]["mean"]
    assert r["sigma"] == pytest.approx(math.hypot(first, second))
    assert r["dof"] == pytest.approx(r["sigma"] ** 4 / (first ** 4 / 4 + second ** 4 / 2))
    assert 2 <= r["dof"] <= 6
