"""The golden-curve comparison rule of ratchet, in Python (docs/regression.md).

The same rule is implemented in C++ in regression/compare/compare.{hpp,cpp}; both are
checked against the shared test vectors regression/compare_vectors.json (pytest
scripts/tests/test_regression_compare.py, GoogleTest regression/compare/compare_test.cpp).
Keep the two in step: the same formulas, the same order of floating-point operations
(plain left-to-right loops: Python's sum() of floats is compensated since 3.12, so it is
not used), the same handling of non-finite values.

The rule
--------
deterministic, one value pair (a new, b golden):
    err = |a - b| / max(|b|, floor)                      (0 when a == b or both NaN;
                                                          inf when only one is finite
                                                          or they are different infinities)
ensemble, one row of one column over n_a new and n_b golden realizations:
    m = mean over realizations, s = sample standard deviation (n - 1; 0 when n == 1)
    se = sqrt(s_a^2 / n_a + s_b^2 / n_b)
    err = |m_a - m_b| / max(se, floor)                   (0 when every value of both is NaN,
                                                          or all are the same infinity;
                                                          inf when some other value is not finite)
a row passes when err <= tol * scale (tol: the column's "tol", or "k" for an ensemble;
scale: the global tolerance scale, 1 by default; 0 shows the residuals: then only
err == 0 passes).

Per column: n rows, failures, mean and (population) standard deviation of err over the
rows (both inf when some err is inf), the worst err and the first row where it occurs.
Key columns (the recorded times, cycle numbers, run ids) must agree row by row to
KEY_TOL (err with floor 1), not scaled: they say which rows are compared.
"""

from __future__ import annotations

import csv
import json
import math
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Sequence

from common.fsutil import write_atomic

KEY_TOL = 1e-12
KEY_FLOOR = 1.0
INF = math.inf


# --------------------------------------------------------------------------- rule --

def value_error(a: float, b: float, floor: float) -> float:
    """Deterministic error of new value a against golden value b."""
    if a == b or (math.isnan(a) and math.isnan(b)):
        return 0.0
    if not (math.isfinite(a) and math.isfinite(b)):
        return INF
    denom = max(abs(b), floor)
    if denom == 0.0:  # floor is > 0 in a valid manifest; kept total for the test vectors
        return INF
    return abs(a - b) / denom


def _mean(xs: Sequence[float]) -> float:
    s = 0.0
    for x in xs:
        s += x
    return s / len(xs)


def _sample_var(xs: Sequence[float], m: float) -> float:
    if len(xs) < 2:
        return 0.0
    q = 0.0
    for x in xs:
        d = x - m
        q += d * d
    return q / (len(xs) - 1)


@dataclass
class EnsembleValue:
    err: float
    mean_new: float
    mean_golden: float
    se: float


def ensemble_error(new: Sequence[float], golden: Sequence[float], floor: float) -> EnsembleValue:
    """Ensemble error of the new realizations' mean against the golden realizations' mean."""
    if not new or not golden:
        raise ValueError("an ensemble needs at least one realization on each side")
    values = list(new) + list(golden)
    if not all(math.isfinite(v) for v in values):
        if all(math.isnan(v) for v in values):
            return EnsembleValue(0.0, math.nan, math.nan, 0.0)
        if all(v == values[0] for v in values) and math.isinf(values[0]):
            return EnsembleValue(0.0, values[0], values[0], 0.0)
        return EnsembleValue(INF, math.nan, math.nan, math.nan)
    ma, mb = _mean(new), _mean(golden)
    se = math.sqrt(_sample_var(new, ma) / len(new) + _sample_var(golden, mb) / len(golden))
    denom = max(se, floor)
    err = 0.0 if ma == mb else (abs(ma - mb) / denom if denom > 0.0 else INF)
    return EnsembleValue(err, ma, mb, se)


def within(err: float, tol: float, scale: float) -> bool:
    """The pass test of one row."""
    return err <= tol * scale


@dataclass
class ColumnResult:
    table: str
    column: str
    kind: str
    tol: float
    floor: float
    scale: float
    n: int = 0
    failures: int = 0
    mean: float = 0.0
    std: float = 0.0
    max: float = 0.0
    worst_row: int = -1
    worst_key: list = field(default_factory=list)
    worst_new: float = math.nan
    worst_golden: float = math.nan
    worst_se: float = math.nan  # ensemble only
    passed: bool = True

    def to_json(self) -> dict:
        return {"table": self.table, "column": self.column, "kind": self.kind, "tol": self.tol,
                "floor": self.floor, "scale": self.scale, "n": self.n, "failures": self.failures,
                "mean": self.mean, "std": self.std, "max": self.max, "worst_row": self.worst_row,
                "worst_key": self.worst_key, "worst_new": self.worst_new,
                "worst_golden": self.worst_golden, "worst_se": self.worst_se, "passed": self.passed}


def _summarize(res: ColumnResult, errs: Sequence[float]) -> None:
    res.n = len(errs)
    if not errs:
        return
    worst = 0
    for i, e in enumerate(errs):
        if e > errs[worst]:
            worst = i
        if not within(e, res.tol, res.scale):
            res.failures += 1
    res.worst_row = worst
    res.max = errs[worst]
    if any(math.isinf(e) for e in errs):
        res.mean = res.std = INF
    else:
        res.mean = _mean(errs)
        q = 0.0
        for e in errs:
            d = e - res.mean
            q += d * d
        res.std = math.sqrt(q / len(errs))
    res.passed = res.failures == 0


def compare_deterministic(column: str, new: Sequence[float], golden: Sequence[float], tol: float,
                          floor: float, scale: float, keys: Sequence[Sequence[Any]] | None = None,
                          table: str = "") -> ColumnResult:
    """Pointwise comparison of one column (rows already aligned by their keys)."""
    if len(new) != len(golden):
        raise ValueError(f"column '{column}': {len(new)} new rows against {len(golden)} golden rows")
    res = ColumnResult(table, column, "deterministic", tol, floor, scale)
    errs = [value_error(a, b, floor) for a, b in zip(new, golden)]
    _summarize(res, errs)
    if res.worst_row >= 0:
        res.worst_new, res.worst_golden = new[res.worst_row], golden[res.worst_row]
        res.worst_key = list(keys[res.worst_row]) if keys else []
    return res


def compare_ensemble(column: str, new: Sequence[Sequence[float]], golden: Sequence[Sequence[float]],
                     k: float, floor: float, scale: float,
                     keys: Sequence[Sequence[Any]] | None = None, table: str = "") -> ColumnResult:
    """Row-by-row comparison of the realizations' means; new[r][i] is realization r, row i."""
    if not new or not golden:
        raise ValueError(f"column '{column}': an ensemble needs at least one realization on each side")
    rows = len(golden[0])
    if any(len(r) != rows for r in list(new) + list(golden)):
        raise ValueError(f"column '{column}': realizations with different row counts")
    res = ColumnResult(table, column, "ensemble", k, floor, scale)
    values = [ensemble_error([r[i] for r in new], [r[i] for r in golden], floor) for i in range(rows)]
    _summarize(res, [v.err for v in values])
    if res.worst_row >= 0:
        w = values[res.worst_row]
        res.worst_new, res.worst_golden, res.worst_se = w.mean_new, w.mean_golden, w.se
        res.worst_key = list(keys[res.worst_row]) if keys else []
    return res


# ------------------------------------------------------------------ CSV tables --

class TableError(Exception):
    """A CSV file that cannot be compared (missing, unreadable, missing column, bad cell)."""


def parse_cell(text: str) -> float:
    """A CSV cell as a double: numbers (incl. nan, inf, -inf); an empty cell is NaN."""
    text = text.strip()
    if text == "":
        return math.nan
    return float(text)  # raises ValueError on text


@dataclass
class Table:
    path: Path
    header: list[str]
    rows: list[list[str]]

    def column(self, name: str) -> list[float]:
        if name not in self.header:
            raise TableError(f"{self.path}: no column '{name}' (columns: {', '.join(self.header)})")
        j = self.header.index(name)
        out = []
        for i, row in enumerate(self.rows):
            try:
                out.append(parse_cell(row[j]))
            except ValueError:
                raise TableError(f"{self.path}: row {i + 1}, column '{name}': not a number: '{row[j]}'")
        return out


def read_table(path: Path) -> Table:
    path = Path(path)
    if not path.is_file():
        raise TableError(f"{path}: missing")
    with open(path, newline="") as fh:
        lines = list(csv.reader(fh))
    if not lines:
        raise TableError(f"{path}: empty (no header)")
    header = lines[0]
    rows = lines[1:]
    for i, row in enumerate(rows):
        if len(row) != len(header):
            raise TableError(f"{path}: row {i + 1} has {len(row)} cells, the header {len(header)}")
    return Table(path, header, rows)


def format_cell(text: str) -> str:
    """A cell for a golden CSV: integers as they are, other numbers at %.17g (round trip)."""
    t = text.strip()
    if t == "":
        return ""
    try:
        return str(int(t))
    except ValueError:
        pass
    return "%.17g" % float(t)


def write_subset(src: Path, dst: Path, columns: Sequence[str]) -> int:
    """Copies the named columns of CSV src to dst (atomically, %.17g); returns the row count."""
    table = read_table(src)
    missing = [c for c in columns if c not in table.header]
    if missing:
        raise TableError(f"{src}: no column {', '.join(repr(c) for c in missing)}")
    idx = [table.header.index(c) for c in columns]
    lines = [",".join(columns)]
    for row in table.rows:
        lines.append(",".join(format_cell(row[j]) for j in idx))
    write_atomic(dst, "\n".join(lines) + "\n")
    return len(table.rows)


# --------------------------------------------------------------------- manifest --

class ManifestError(Exception):
    """A malformed manifest: the message names the file and the field."""


KINDS = ("deterministic", "ensemble")
LABELS = ("regression", "regression-long")
TOP_LEVEL = {"format", "case", "description", "kind", "labels", "scene", "sweep", "sweep_out", "set",
             "realizations", "engine", "generated", "tables", "notes"}


@dataclass
class ColumnSpec:
    name: str
    tol: float
    floor: float
    reason: str


@dataclass
class TableSpec:
    file: str
    keys: list[str]
    columns: list[ColumnSpec]


@dataclass
class Realization:
    folder: str
    seed: int | None
    scene_hash: Any  # str, list of str (sweep: one per run) or None before the first --update


@dataclass
class Manifest:
    path: Path
    raw: dict
    case: str
    kind: str
    labels: list[str]
    realizations: list[Realization]
    tables: list[TableSpec]

    @property
    def tol_name(self) -> str:
        return "k" if self.kind == "ensemble" else "tol"


def _fail(path: Path, where: str, what: str, got: Any = None, has_value: bool = False) -> ManifestError:
    msg = f"{path}: field '{where}': expected {what}"
    if has_value:
        text = json.dumps(got)
        msg += f", got {text[:80]}"
    return ManifestError(msg)


def _is_hash(x: Any) -> bool:
    return isinstance(x, str) and len(x) == 16 and all(c in "0123456789abcdef" for c in x)


def _number(x: Any) -> bool:
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)


def parse_manifest(path: Path, raw: Any) -> Manifest:
    """Checks a manifest (already read as JSON) and returns it; ManifestError names file and field."""
    path = Path(path)
    if not isinstance(raw, dict):
        raise ManifestError(f"{path}: expected a JSON object at the top level")

    def need(key: str) -> Any:
        if key not in raw:
            raise _fail(path, key, "a value (the field is required)")
        return raw[key]

    if need("format") != 1:
        raise _fail(path, "format", "1", raw["format"], True)
    unknown = set(raw) - TOP_LEVEL
    if unknown:
        raise _fail(path, sorted(unknown)[0], f"one of the known fields ({', '.join(sorted(TOP_LEVEL))}); "
                    "unknown field")
    case = need("case")
    if not isinstance(case, str) or not case:
        raise _fail(path, "case", "a non-empty string", case, True)
    if case != path.parent.name:
        raise _fail(path, "case", f"the name of the case folder '{path.parent.name}'", case, True)
    desc = need("description")
    if not isinstance(desc, str) or not desc.strip():
        raise _fail(path, "description", "a non-empty string", desc, True)
    kind = need("kind")
    if kind not in KINDS:
        raise _fail(path, "kind", '"deterministic" or "ensemble"', kind, True)
    labels = raw.get("labels", ["regression"])
    if not isinstance(labels, list) or len(labels) != 1 or labels[0] not in LABELS:
        raise _fail(path, "labels", '["regression"] or ["regression-long"]', labels, True)
    has_scene, has_sweep = "scene" in raw, "sweep" in raw
    if has_scene == has_sweep:
        raise _fail(path, "scene", "exactly one of 'scene' (a scene file or an inline scene) and 'sweep'")
    if has_scene and not (isinstance(raw["scene"], dict) or (isinstance(raw["scene"], str) and raw["scene"])):
        raise _fail(path, "scene", "a path (relative to the repository root) or an inline scene object",
                    raw["scene"], True)
    if has_sweep and not (isinstance(raw["sweep"], str) and raw["sweep"]):
        raise _fail(path, "sweep", "a sweep file path (relative to the repository root)", raw["sweep"], True)
    if "sweep_out" in raw and not (has_sweep and isinstance(raw["sweep_out"], str) and raw["sweep_out"]):
        raise _fail(path, "sweep_out", "a folder path (relative to the repository root), in a sweep case only",
                    raw["sweep_out"], True)
    sets = raw.get("set", [])
    if not isinstance(sets, list) or not all(isinstance(s, str) and "=" in s[1:] for s in sets):
        raise _fail(path, "set", 'a list of "key.path=value" strings', sets, True)
    if has_sweep and sets:
        raise _fail(path, "set", "no overrides in a sweep case (they belong in the sweep file)", sets, True)

    reals_raw = need("realizations")
    if not isinstance(reals_raw, list) or not reals_raw:
        raise _fail(path, "realizations", "a non-empty list", reals_raw, True)
    if kind == "deterministic" and len(reals_raw) != 1:
        raise _fail(path, "realizations", "exactly one realization for a deterministic case", reals_raw, True)
    if has_sweep and len(reals_raw) != 1:
        raise _fail(path, "realizations", "exactly one entry for a sweep case", reals_raw, True)
    realizations: list[Realization] = []
    folders: set[str] = set()
    for i, r in enumerate(reals_raw):
        where = f"realizations[{i}]"
        if not isinstance(r, dict):
            raise _fail(path, where, "an object", r, True)
        unknown = set(r) - {"folder", "seed", "scene_hash"}
        if unknown:
            raise _fail(path, f"{where}.{sorted(unknown)[0]}", "one of folder, seed, scene_hash (unknown field)")
        folder = r.get("folder")
        if not isinstance(folder, str) or not folder or "/" in folder or folder in folders:
            raise _fail(path, f"{where}.folder", "a unique folder name without '/'", folder, True)
        folders.add(folder)
        seed = r.get("seed")
        if not has_sweep and folder in (".", ".."):
            raise _fail(path, f"{where}.folder", "a folder name other than '.' and '..' (the driver empties it "
                        "before each run)", folder, True)
        if has_sweep:
            if seed is not None:
                raise _fail(path, f"{where}.seed", "null or absent in a sweep case (the sweep file has the seeds)",
                            seed, True)
            if folder != ".":
                raise _fail(path, f"{where}.folder", '"." in a sweep case (the sweep output folder)', folder, True)
        elif not (isinstance(seed, int) and not isinstance(seed, bool) and seed >= 0):
            raise _fail(path, f"{where}.seed", "an integer >= 0", seed, True)
        h = r.get("scene_hash")
        hash_ok = h is None or _is_hash(h) or (has_sweep and isinstance(h, list) and all(_is_hash(x) for x in h))
        if not hash_ok:
            raise _fail(path, f"{where}.scene_hash", "null or a 16-digit hex hash (a list of them for a sweep)",
                        h, True)
        realizations.append(Realization(folder, seed, h))

    tables_raw = need("tables")
    if not isinstance(tables_raw, list) or not tables_raw:
        raise _fail(path, "tables", "a non-empty list", tables_raw, True)
    tol_name = "k" if kind == "ensemble" else "tol"
    tables: list[TableSpec] = []
    for i, t in enumerate(tables_raw):
        where = f"tables[{i}]"
        if not isinstance(t, dict):
            raise _fail(path, where, "an object", t, True)
        f = t.get("file")
        if not isinstance(f, str) or not f.endswith(".csv") or "/" in f:
            raise _fail(path, f"{where}.file", "a CSV file name of the run folder (e.g. timeseries.csv)", f, True)
        keys = t.get("key")
        if isinstance(keys, str):
            keys = [keys]
        if not isinstance(keys, list) or not keys or not all(isinstance(k, str) and k for k in keys):
            raise _fail(path, f"{where}.key", "a column name or a list of column names", t.get("key"), True)
        cols_raw = t.get("columns")
        if not isinstance(cols_raw, dict) or not cols_raw:
            raise _fail(path, f"{where}.columns", "a non-empty object {column: {tolerance}}", cols_raw, True)
        cols: list[ColumnSpec] = []
        for name, spec in cols_raw.items():
            cw = f"{where}.columns.{name}"
            if name in keys:
                raise _fail(path, cw, "a column that is not a key column")
            if not isinstance(spec, dict):
                raise _fail(path, cw, f"an object {{\"{tol_name}\", \"floor\", \"reason\"}}", spec, True)
            allowed = {tol_name, "floor", "reason"}
            unknown = set(spec) - allowed
            if unknown:
                other = "tol" if tol_name == "k" else "k"
                hint = f" ('{other}' is for {'deterministic' if other == 'tol' else 'ensemble'} cases)" \
                    if other in unknown else ""
                raise _fail(path, f"{cw}.{sorted(unknown)[0]}",
                            f"one of {tol_name}, floor, reason (unknown field){hint}")
            tol = spec.get(tol_name)
            if not (_number(tol) and tol >= 0):
                raise _fail(path, f"{cw}.{tol_name}", "a finite number >= 0 (the field is required)",
                            tol, tol_name in spec)
            fl = spec.get("floor")
            if not (_number(fl) and fl > 0):
                raise _fail(path, f"{cw}.floor", "a finite number > 0 (the field is required)", fl, "floor" in spec)
            reason = spec.get("reason")
            if not isinstance(reason, str) or not reason.strip():
                raise _fail(path, f"{cw}.reason", "a non-empty string: why the tolerance has its value",
                            reason, "reason" in spec)
            cols.append(ColumnSpec(name, float(tol), float(fl), reason))
        tables.append(TableSpec(f, keys, cols))
    files = [t.file for t in tables]
    if len(set(files)) != len(files):
        raise _fail(path, "tables", "each file once", files, True)
    return Manifest(path, raw, case, kind, labels, realizations, tables)


def load_manifest(path: Path) -> Manifest:
    path = Path(path)
    if not path.is_file():
        raise ManifestError(f"{path}: missing")
    try:
        raw = json.loads(path.read_text())
    except json.JSONDecodeError as e:
        raise ManifestError(f"{path}: not valid JSON: {e}")
    return parse_manifest(path, raw)


# ------------------------------------------------------------------ case compare --

@dataclass
class CaseResult:
    case: str
    kind: str
    scale: float
    columns: list[ColumnResult] = field(default_factory=list)
    problems: list[str] = field(default_factory=list)  # structural failures (missing file, keys ...)

    @property
    def passed(self) -> bool:
        return not self.problems and all(c.passed for c in self.columns)

    def worst(self) -> ColumnResult | None:
        """The column with the largest err relative to its allowance tol * scale."""
        def ratio(c: ColumnResult) -> float:
            allow = c.tol * c.scale
            if c.max == 0.0:
                return 0.0
            return INF if allow == 0.0 else c.max / allow
        return max(self.columns, key=ratio, default=None)

    def to_json(self) -> dict:
        return {"case": self.case, "kind": self.kind, "scale": self.scale, "passed": self.passed,
                "problems": self.problems, "columns": [c.to_json() for c in self.columns]}


def _keys_of(table: Table, names: Sequence[str]) -> list[list[float]]:
    cols = [table.column(n) for n in names]
    return [list(v) for v in zip(*cols)] if cols else []


def _first_key_mismatch(new: list[list[float]], golden: list[list[float]]) -> int:
    for i, (a, b) in enumerate(zip(new, golden)):
        for x, y in zip(a, b):
            if value_error(x, y, KEY_FLOOR) > KEY_TOL:
                return i
    return -1


def compare_case(manifest: Manifest, golden_dir: Path, new_dir: Path, scale: float) -> CaseResult:
    """Compares the run folders under new_dir (one per realization, named as in the manifest)
    with the golden files under golden_dir."""
    golden_dir, new_dir = Path(golden_dir), Path(new_dir)
    res = CaseResult(manifest.case, manifest.kind, scale)
    for spec in manifest.tables:
        gold_tables, new_tables = [], []
        ok = True
        for r in manifest.realizations:
            for root, into, what in ((golden_dir, gold_tables, "golden"), (new_dir, new_tables, "new")):
                p = root / r.folder / spec.file
                try:
                    t = read_table(p)
                    for c in spec.keys + [c.name for c in spec.columns]:
                        t.column(c)  # presence and numeric cells
                    into.append(t)
                except TableError as e:
                    hint = (f" (golden data is never made silently: regenerate on purpose with "
                            f"regression/run --update {manifest.case})") if what == "golden" else ""
                    res.problems.append(f"{what} file: {e}{hint}")
                    ok = False
        if not ok:
            continue
        gold_keys = [_keys_of(t, spec.keys) for t in gold_tables]
        new_keys = [_keys_of(t, spec.keys) for t in new_tables]
        ref = gold_keys[0]
        for t, keys in list(zip(gold_tables, gold_keys)) + list(zip(new_tables, new_keys)):
            if len(keys) != len(ref):
                res.problems.append(f"{t.path}: {len(keys)} rows, the golden {gold_tables[0].path} has {len(ref)}")
                ok = False
                continue
            i = _first_key_mismatch(keys, ref)
            if i >= 0:
                res.problems.append(
                    f"{t.path}: key {'/'.join(spec.keys)} differs at row {i + 1}: {_fmt_key(keys[i])} against "
                    f"{_fmt_key(ref[i])} in {gold_tables[0].path} (the rows must be recorded at the same times)")
                ok = False
        if not ok:
            continue
        keys = [[_key_value(x) for x in k] for k in ref]
        for col in spec.columns:
            if manifest.kind == "deterministic":
                c = compare_deterministic(col.name, new_tables[0].column(col.name), gold_tables[0].column(col.name),
                                          col.tol, col.floor, scale, keys, spec.file)
            else:
                c = compare_ensemble(col.name, [t.column(col.name) for t in new_tables],
                                     [t.column(col.name) for t in gold_tables], col.tol, col.floor, scale,
                                     keys, spec.file)
            res.columns.append(c)
    return res


def _key_value(x: float):
    return int(x) if math.isfinite(x) and x == int(x) and abs(x) < 2 ** 53 else x


def _fmt_key(k: Sequence[float]) -> str:
    return "/".join("%.17g" % x for x in k)


# ------------------------------------------------------------------------ report --

def _g(x: float) -> str:
    return "%.3g" % x if isinstance(x, float) else str(x)


def format_report(res: CaseResult, spec_keys: dict[str, list[str]] | None = None) -> str:
    """The human report of one case comparison (the same layout as ratchet_regress)."""
    lines = [f"case {res.case} ({res.kind}, tol-scale {res.scale:g})"]
    header = f"  {'table':<15} {'column':<22} {'n':>5} {'fail':>4} {'mean':>9} {'std':>9} {'worst':>9}  " \
             f"{'at':<24} {'new':>12} {'golden':>12} {'tol':>8} {'floor':>8}  result"
    if res.columns:
        lines.append(header)
    for c in res.columns:
        where = "-"
        if c.worst_row >= 0:
            names = (spec_keys or {}).get(c.table)
            key = ",".join(f"{n}={_g(v)}" for n, v in zip(names, c.worst_key)) if names else \
                ",".join(_g(v) for v in c.worst_key)
            where = f"{key} (row {c.worst_row + 1})"
        lines.append(f"  {c.table:<15} {c.column:<22} {c.n:>5} {c.failures:>4} {_g(c.mean):>9} {_g(c.std):>9} "
                     f"{_g(c.max):>9}  {where:<24} {_g(c.worst_new):>12} {_g(c.worst_golden):>12} "
                     f"{_g(c.tol):>8} {_g(c.floor):>8}  {'pass' if c.passed else 'FAIL'}")
    for p in res.problems:
        lines.append(f"  problem: {p}")
    w = res.worst()
    verdict = "PASS" if res.passed else "FAIL"
    parts = []
    if res.problems:
        parts.append(f"{len(res.problems)} problem(s)")
    if w is not None:
        parts.append(f"worst: {w.table} {w.column} err {_g(w.max)}, allowed {_g(w.tol * w.scale)}")
    lines.append(f"case {res.case}: {verdict}" + (f" ({'; '.join(parts)})" if parts else ""))
    return "\n".join(lines)


def json_number(x: float):
    """A number for JSON output: non-finite values as the strings nan, inf, -inf."""
    if isinstance(x, float) and not math.isfinite(x):
        return "nan" if math.isnan(x) else ("inf" if x > 0 else "-inf")
    return x


def to_json_safe(obj):
    if isinstance(obj, dict):
        return {k: to_json_safe(v) for k, v in obj.items()}
    if isinstance(obj, list):
        return [to_json_safe(v) for v in obj]
    return json_number(obj)


def from_json_number(x) -> float:
    """Inverse of json_number (test vectors and JSON results)."""
    if isinstance(x, str):
        if x in ("nan", "inf", "-inf"):
            return float(x)
        raise ValueError(f"expected a number or one of nan, inf, -inf, got '{x}'")
    if isinstance(x, bool) or not isinstance(x, (int, float)):
        raise ValueError(f"expected a number, got {x!r}")
    return float(x)


# -------------------------------------------------------------- tolerance scale --

def tol_scale_from(arg: str | None, env: dict | None = None) -> float:
    """--tol-scale if given, else $RATCHET_TOL_SCALE, else 1. Raises ValueError when invalid."""
    env = os.environ if env is None else env
    text, where = (arg, "--tol-scale") if arg is not None else (env.get("RATCHET_TOL_SCALE"), "RATCHET_TOL_SCALE")
    if text is None or text == "":
        return 1.0
    try:
        v = float(text)
    except ValueError:
        raise ValueError(f"{where}: expected a number >= 0, got '{text}'")
    if not (math.isfinite(v) and v >= 0):
        raise ValueError(f"{where}: expected a number >= 0, got '{text}'")
    return v
