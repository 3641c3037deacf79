#!/usr/bin/python3
"""Writes regression/compare_vectors.json, the test vectors of the comparison rule.

The expected figures are computed here with exact rational arithmetic (fractions) and
rounded to double once at the end: an oracle independent of both implementations
(scripts/regression/compare.py and regression/compare/compare.cpp), which must each
reproduce them to within the file's "rel_tolerance" (pytest
scripts/tests/test_regression_compare.py, GoogleTest regression/compare/compare_test.cpp).

Usage: /usr/bin/python3 regression/make_compare_vectors.py [--check]
  --check  do not write; exit 1 when the file on disk differs from what would be written.
The rule itself is stated in docs/regression.md.
"""

from __future__ import annotations

import json
import math
import sys
from fractions import Fraction as Fr
from pathlib import Path

HERE = Path(__file__).resolve().parent
OUT = HERE / "compare_vectors.json"
sys.path.insert(0, str(HERE.parent / "scripts"))  # for common

from common.fsutil import write_atomic  # noqa: E402

NAN, INF = math.nan, math.inf


def enc(x):
    if isinstance(x, float) and not math.isfinite(x):
        return "nan" if math.isnan(x) else ("inf" if x > 0 else "-inf")
    return x


def nonfinite(x):
    return isinstance(x, float) and not math.isfinite(x)


def det_err(a, b, floor):
    """Exact error (Fraction) or INF."""
    if nonfinite(a) or nonfinite(b):
        if isinstance(a, float) and isinstance(b, float) and math.isnan(a) and math.isnan(b):
            return Fr(0)
        return Fr(0) if a == b else INF
    if a == b:
        return Fr(0)
    return abs(Fr(a) - Fr(b)) / max(abs(Fr(b)), Fr(floor))


def ens_err(new, gold, floor):
    """(err, mean_new, mean_golden, se) with err exact up to the one sqrt."""
    vals = list(new) + list(gold)
    if any(nonfinite(v) for v in vals):
        if all(isinstance(v, float) and math.isnan(v) for v in vals):
            return Fr(0), NAN, NAN, 0.0
        if all(v == vals[0] for v in vals) and math.isinf(vals[0]):
            return Fr(0), vals[0], vals[0], 0.0
        return INF, NAN, NAN, NAN
    na, nb = len(new), len(gold)
    ma = sum(Fr(x) for x in new) / na
    mb = sum(Fr(x) for x in gold) / nb
    va = sum((Fr(x) - ma) ** 2 for x in new) / (na - 1) if na > 1 else Fr(0)
    vb = sum((Fr(x) - mb) ** 2 for x in gold) / (nb - 1) if nb > 1 else Fr(0)
    var = va / na + vb / nb
    se = math.sqrt(float(var))  # the one rounding before the division
    if ma == mb:
        return Fr(0), float(ma), float(mb), se
    denom = max(Fr(se), Fr(floor))
    return abs(ma - mb) / denom, float(ma), float(mb), se


def summary(errs, tol, scale):
    n = len(errs)
    allow = Fr(tol) * Fr(scale)
    failures = sum(1 for e in errs if e == INF or e > allow)
    worst = 0
    for i, e in enumerate(errs):
        if e > errs[worst]:  # Fraction against float inf compares as numbers
            worst = i
    if any(e == INF for e in errs):
        mean = std = INF
    else:
        m = sum(errs) / n
        mean = float(m)
        std = math.sqrt(float(sum((e - m) ** 2 for e in errs) / n))
    mx = errs[worst]
    return {"passed": failures == 0, "n": n, "failures": failures, "mean": enc(mean), "std": enc(std),
            "max": enc(INF if mx == INF else float(mx)), "worst_row": worst}


def det_vector(name, new, golden, tol, floor, scale, note):
    errs = [det_err(a, b, floor) for a, b in zip(new, golden)]
    exp = summary(errs, tol, scale)
    w = exp["worst_row"]
    exp["worst_new"], exp["worst_golden"] = enc(new[w]), enc(golden[w])
    return {"name": name, "kind": "deterministic", "note": note, "new": [enc(x) for x in new],
            "golden": [enc(x) for x in golden], "tol": tol, "floor": floor, "scale": scale, "expect": exp}


def ens_vector(name, new, golden, k, floor, scale, note):
    """new, golden: realization-major lists [realization][row]."""
    rows = len(golden[0])
    vals = [ens_err([r[i] for r in new], [r[i] for r in golden], floor) for i in range(rows)]
    exp = summary([v[0] for v in vals], k, scale)
    w = exp["worst_row"]
    exp["worst_new"], exp["worst_golden"], exp["worst_se"] = enc(vals[w][1]), enc(vals[w][2]), enc(vals[w][3])
    return {"name": name, "kind": "ensemble", "note": note, "new": [[enc(x) for x in r] for r in new],
            "golden": [[enc(x) for x in r] for r in golden], "tol": k, "floor": floor, "scale": scale,
            "expect": exp}


def key_vector(name, new, golden, note):
    first = -1
    for i, (a, b) in enumerate(zip(new, golden)):
        if det_err(a, b, 1.0) > Fr(1, 10 ** 12):
            first = i
            break
    return {"name": name, "note": note, "new": [enc(x) for x in new], "golden": [enc(x) for x in golden],
            "expect_first_mismatch": first}


def build():
    A_new, A_gold = [1.0, 2.5, -4.0, 0.5], [1.0, 2.0, -4.0, 0.25]
    det = [
        det_vector("identical", [1.0, 2.0, 3.0], [1.0, 2.0, 3.0], 1e-9, 1e-6, 1.0,
                   "equal values: every err is 0"),
        det_vector("relative_and_floor_pass", A_new, A_gold, 0.3, 1.0, 1.0,
                   "row 1: 0.5/2 = 0.25; row 3: |0.5-0.25| / max(0.25, floor 1) = 0.25 (floor active); "
                   "worst is the first of the tied rows"),
        det_vector("relative_and_floor_fail", A_new, A_gold, 0.2, 1.0, 1.0, "the same rows against tol 0.2: two fail"),
        det_vector("scale_two_passes", A_new, A_gold, 0.2, 1.0, 2.0, "tol-scale 2 doubles the allowance: 0.25 <= 0.4"),
        det_vector("scale_zero_fails_residuals", A_new, A_gold, 0.3, 1.0, 0.0,
                   "tol-scale 0: every nonzero residual fails, the figures are the real residuals"),
        det_vector("scale_zero_identical_passes", [0.1, -7.25], [0.1, -7.25], 1e-3, 1e-6, 0.0,
                   "tol-scale 0 with identical values passes"),
        det_vector("absolute_floor_near_zero", [1e-12, 0.0, -3e-13], [0.0, 0.0, 0.0], 1e-2, 1e-9, 1.0,
                   "golden 0: the floor 1e-9 is the denominator"),
        det_vector("boundary_inclusive", [-3.0], [-2.0], 0.5, 0.5, 1.0,
                   "|(-3)-(-2)| / max(|-2|, 0.5) = 0.5 <= 0.5: the bound is inclusive"),
        det_vector("integer_column_exact", [3.0, 4.0, 5.0], [3.0, 4.0, 6.0], 0.0, 1.0, 1.0,
                   "tol 0: any difference fails (1/6 at row 2)"),
        det_vector("matching_nonfinite", [NAN, 1.0, INF, -INF], [NAN, 1.0, INF, -INF], 1e-9, 1e-9, 1.0,
                   "NaN against NaN and equal infinities are equal"),
        det_vector("nan_against_number", [NAN, 1.0], [1.0, 1.0], 1e-9, 1e-9, 1.0,
                   "NaN against a number: err inf, mean and std inf"),
        det_vector("opposite_infinities", [1.0, INF], [1.0, -INF], 1e3, 1.0, 1.0,
                   "different infinities: err inf whatever the tolerance"),
        det_vector("negative_values", [-10.0, -1.0, -0.125], [-8.0, -1.0, -0.25], 0.3, 0.5, 1.0,
                   "|b| in the denominator: 2/8 = 0.25; |0.125| / max(0.25, 0.5) = 0.25"),
    ]
    ens = [
        ens_vector("ensemble_identical", [[1.0, 2.0], [3.0, 4.0], [5.0, 6.0]],
                   [[1.0, 2.0], [3.0, 4.0], [5.0, 6.0]], 3.0, 1e-6, 1.0, "the same realizations: err 0"),
        ens_vector("ensemble_shift_within_k", [[2.0, 7.0], [3.0, 7.0], [4.0, 7.0]],
                   [[1.0, 7.0], [2.0, 7.0], [3.0, 7.0]], 2.0, 0.1, 1.0,
                   "row 0: means 3 and 2, sample variances 1 and 1, se = sqrt(1/3 + 1/3), err = 1/se = 1.2247"),
        ens_vector("ensemble_shift_beyond_k", [[2.0, 7.0], [3.0, 7.0], [4.0, 7.0]],
                   [[1.0, 7.0], [2.0, 7.0], [3.0, 7.0]], 1.0, 0.1, 1.0, "the same with k 1: row 0 fails"),
        ens_vector("ensemble_zero_spread_floor", [[5.0], [5.0]], [[5.5], [5.5]], 2.0, 0.25, 1.0,
                   "no spread: se 0, the floor 0.25 is the denominator, err 2 <= k 2 (inclusive)"),
        ens_vector("ensemble_zero_spread_floor_fail", [[5.0], [5.0]], [[5.5], [5.5]], 1.5, 0.25, 1.0,
                   "the same with k 1.5 fails"),
        ens_vector("ensemble_one_realization", [[1.0]], [[1.5]], 5.0, 0.125, 1.0,
                   "one realization each: no spread (s = 0 when n = 1), err = 0.5 / 0.125 = 4"),
        ens_vector("ensemble_unequal_counts", [[1.0], [3.0]], [[2.0], [4.0], [6.0]], 2.0, 0.1, 1.0,
                   "means 2 and 4, sample variances 2 and 4, se = sqrt(2/2 + 4/3), err = 2/se"),
        ens_vector("ensemble_nonfinite", [[NAN, -INF, 1.0], [NAN, -INF, NAN]],
                   [[NAN, -INF, 1.0], [NAN, -INF, 1.0]], 3.0, 1e-6, 1.0,
                   "all NaN: 0; all -inf: 0; a NaN among numbers: inf"),
        ens_vector("ensemble_scale_zero", [[2.0, 7.0], [3.0, 7.0], [4.0, 7.0]],
                   [[1.0, 7.0], [2.0, 7.0], [3.0, 7.0]], 2.0, 0.1, 0.0,
                   "tol-scale 0: the shifted row fails, the equal row passes"),
    ]
    keys = [
        key_vector("keys_equal", [0.0, 0.1, 0.2], [0.0, 0.1, 0.2], "the same recorded times"),
        key_vector("keys_roundoff", [0.0, 0.30000000000000004, 1e6 + 1e-7],
                   [0.0, 0.3, 1e6], "differences below 1e-12 relative (floor 1) are the same key"),
        key_vector("keys_shifted", [0.0, 0.1, 0.2000001], [0.0, 0.1, 0.2], "row 2 differs: the rows are not aligned"),
    ]
    return {
        "format": 1,
        "description": ("Test vectors of the golden-curve comparison rule (docs/regression.md). Written by "
                        "regression/make_compare_vectors.py with exact rational arithmetic; both the Python "
                        "(scripts/regression/compare.py) and the C++ (regression/compare/compare.cpp) "
                        "implementations must reproduce every expected figure. Non-finite numbers are the "
                        "strings nan, inf, -inf. Ensemble inputs are realization-major: new[r][row]."),
        "rel_tolerance": 1e-12,
        "rel_tolerance_reason": ("the implementations round at every operation, the oracle once: they may "
                                 "differ from it by a few ulps; 1e-12 is far below any tolerance in use"),
        "key_tol": 1e-12,
        "key_floor": 1.0,
        "deterministic": det,
        "ensemble": ens,
        "keys": keys,
    }


def main(argv):
    text = json.dumps(build(), indent=1) + "\n"
    if "--check" in argv:
        same = OUT.is_file() and OUT.read_text() == text
        print(f"{OUT}: {'up to date' if same else 'differs from make_compare_vectors.py'}")
        return 0 if same else 1
    write_atomic(OUT, text)
    print(f"wrote {OUT}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
