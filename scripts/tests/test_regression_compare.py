"""Tests of the Python side of the golden-curve comparison (scripts/regression/compare.py)
and of the driver regression/run on real engine runs.

The rule is checked against the shared test vectors regression/compare_vectors.json,
which the C++ implementation's GoogleTest (regression/compare/compare_test.cpp) checks
too: both implementations reproduce the same expected figures, so they are the same rule.

Run with Debian's interpreter: /usr/bin/python3 -m pytest -q scripts/tests
The driver tests need an engine binary: $RATCHET_BIN, else
<$RATCHET_BUILD_DIR or build>/reference_engine/ratchet (common.paths.engine_binary);
they are skipped (with the reason) when neither exists.
"""

from __future__ import annotations

import json
import math
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

SCRIPTS = Path(__file__).resolve().parent.parent
REPO = SCRIPTS.parent
sys.path.insert(0, str(SCRIPTS))

from common.paths import engine_binary  # noqa: E402
from regression import compare  # noqa: E402

VECTORS_PATH = REPO / "regression" / "compare_vectors.json"
VECTORS = json.loads(VECTORS_PATH.read_text())
REL = VECTORS["rel_tolerance"]
DRIVER = REPO / "regression" / "run"
PYTHON = "/usr/bin/python3"


def num(x):
    return compare.from_json_number(x)


def close(got: float, expected: float) -> bool:
    if math.isnan(expected):
        return math.isnan(got)
    if math.isinf(expected):
        return got == expected
    return abs(got - expected) <= REL * max(abs(expected), 1e-300)


def check_expect(res: compare.ColumnResult, exp: dict, name: str) -> None:
    assert res.passed is exp["passed"], name
    assert res.n == exp["n"], name
    assert res.failures == exp["failures"], name
    assert res.worst_row == exp["worst_row"], name
    for fld in ("mean", "std", "max", "worst_new", "worst_golden"):
        assert close(getattr(res, fld), num(exp[fld])), f"{name}: {fld} {getattr(res, fld)!r} != {exp[fld]!r}"
    if "worst_se" in exp:
        assert close(res.worst_se, num(exp["worst_se"])), f"{name}: worst_se"


# ------------------------------------------------------------ the shared vectors --

def test_vectors_file_is_what_the_oracle_writes():
    """compare_vectors.json is exactly what make_compare_vectors.py (the exact-arithmetic oracle) writes."""
    r = subprocess.run([PYTHON, str(REPO / "regression" / "make_compare_vectors.py"), "--check"],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stdout + r.stderr


@pytest.mark.parametrize("vec", VECTORS["deterministic"], ids=lambda v: v["name"])
def test_deterministic_vector(vec):
    res = compare.compare_deterministic("x", [num(x) for x in vec["new"]], [num(x) for x in vec["golden"]],
                                        vec["tol"], vec["floor"], vec["scale"])
    check_expect(res, vec["expect"], vec["name"])


@pytest.mark.parametrize("vec", VECTORS["ensemble"], ids=lambda v: v["name"])
def test_ensemble_vector(vec):
    res = compare.compare_ensemble("x", [[num(x) for x in r] for r in vec["new"]],
                                   [[num(x) for x in r] for r in vec["golden"]],
                                   vec["tol"], vec["floor"], vec["scale"])
    check_expect(res, vec["expect"], vec["name"])


@pytest.mark.parametrize("vec", VECTORS["keys"], ids=lambda v: v["name"])
def test_key_vector(vec):
    assert VECTORS["key_tol"] == compare.KEY_TOL and VECTORS["key_floor"] == compare.KEY_FLOOR
    got = compare._first_key_mismatch([[num(x)] for x in vec["new"]], [[num(x)] for x in vec["golden"]])
    assert got == vec["expect_first_mismatch"]


def test_vectors_cover_both_verdicts_and_the_diagnostic_scale():
    """The vectors would catch an implementation that always passes, always fails or ignores the scale."""
    for kind in ("deterministic", "ensemble"):
        verdicts = {v["expect"]["passed"] for v in VECTORS[kind]}
        assert verdicts == {True, False}, kind
        assert any(v["scale"] == 0.0 and not v["expect"]["passed"] for v in VECTORS[kind]), kind


# ----------------------------------------------------------------- rule details --

def test_value_error_formula():
    assert compare.value_error(1.5, 1.0, 1e-9) == 0.5
    assert compare.value_error(1e-10, 0.0, 1e-6) == pytest.approx(1e-4, rel=1e-15)
    assert compare.value_error(math.nan, math.nan, 1.0) == 0.0
    assert compare.value_error(math.inf, 1.0, 1.0) == math.inf
    assert compare.within(0.5, 0.5, 1.0) and not compare.within(0.5, 0.5, 0.99)


def test_sum_is_plain_left_to_right():
    """Same order of operations as the C++ loop (Python 3.12's sum() is compensated)."""
    xs = [1e16, 1.0, -1e16, 1.0]
    assert compare._mean(xs) == ((((0.0 + 1e16) + 1.0) - 1e16) + 1.0) / 4


def test_tol_scale_sources():
    assert compare.tol_scale_from(None, {}) == 1.0
    assert compare.tol_scale_from(None, {"RATCHET_TOL_SCALE": "0"}) == 0.0
    assert compare.tol_scale_from("2.5", {"RATCHET_TOL_SCALE": "0"}) == 2.5  # the option wins
    for bad in ("-1", "abc", "nan", "inf"):
        with pytest.raises(ValueError, match="expected a number >= 0"):
            compare.tol_scale_from(bad, {})
    with pytest.raises(ValueError, match="RATCHET_TOL_SCALE"):
        compare.tol_scale_from(None, {"RATCHET_TOL_SCALE": "x"})


# ------------------------------------------------------------------- manifests --

def _manifest(tmp_path: Path, **over) -> dict:
    m = {"format": 1, "case": "demo", "description": "d", "kind": "deterministic", "scene": "s.json",
         "realizations": [{"seed": 1, "folder": "seed-1", "scene_hash": None}],
         "tables": [{"file": "timeseries.csv", "key": "t",
                     "columns": {"x": {"tol": 1e-9, "floor": 1e-6, "reason": "why"}}}]}
    m.update(over)
    return m


@pytest.mark.parametrize("change, field", [
    ({"kind": "fuzzy"}, "'kind'"),
    ({"format": 2}, "'format'"),
    ({"case": "other"}, "'case'"),
    ({"tables": [{"file": "timeseries.csv", "key": "t", "columns": {"x": {"tol": 1e-9, "floor": 0, "reason": "r"}}}]},
     "'tables[0].columns.x.floor'"),
    ({"tables": [{"file": "timeseries.csv", "key": "t", "columns": {"x": {"tol": -1, "floor": 1, "reason": "r"}}}]},
     "'tables[0].columns.x.tol'"),
    ({"tables": [{"file": "timeseries.csv", "key": "t", "columns": {"x": {"tol": 1, "floor": 1}}}]},
     "'tables[0].columns.x.reason'"),
    ({"tables": [{"file": "timeseries.csv", "key": "t", "columns": {"x": {"k": 1, "floor": 1, "reason": "r"}}}]},
     "'tables[0].columns.x.k'"),
    ({"tables": [{"file": "timeseries.txt", "key": "t", "columns": {"x": {"tol": 1, "floor": 1, "reason": "r"}}}]},
     "'tables[0].file'"),
    ({"realizations": [{"seed": -1, "folder": "a"}]}, "'realizations[0].seed'"),
    ({"realizations": [{"seed": 1, "folder": "a"}, {"seed": 2, "folder": "b"}]}, "'realizations'"),
    ({"realizations": [{"seed": 1, "folder": "a", "scene_hash": "xyz"}]}, "'realizations[0].scene_hash'"),
    ({"labels": ["nightly"]}, "'labels'"),
])
def test_malformed_manifest_names_file_and_field(tmp_path, change, field):
    case = tmp_path / "demo"
    case.mkdir()
    path = case / "manifest.json"
    path.write_text(json.dumps(_manifest(tmp_path, **change)))
    with pytest.raises(compare.ManifestError) as e:
        compare.load_manifest(path)
    assert str(path) in str(e.value) and field in str(e.value)


def test_ensemble_manifest_wants_k(tmp_path):
    case = tmp_path / "demo"
    case.mkdir()
    m = _manifest(tmp_path, kind="ensemble")  # columns still say "tol"
    (case / "manifest.json").write_text(json.dumps(m))
    with pytest.raises(compare.ManifestError, match=r"columns\.x\.tol'.*'tol' is for deterministic"):
        compare.load_manifest(case / "manifest.json")


def test_invalid_json_manifest(tmp_path):
    case = tmp_path / "demo"
    case.mkdir()
    (case / "manifest.json").write_text("{ not json")
    with pytest.raises(compare.ManifestError, match="not valid JSON"):
        compare.load_manifest(case / "manifest.json")


def test_every_golden_manifest_is_valid_and_every_tolerance_has_a_reason():
    cases = sorted((REPO / "golden").glob("*/manifest.json"))
    assert cases, "no golden case found"
    for path in cases:
        m = compare.load_manifest(path)
        for t in m.tables:
            for c in t.columns:
                assert len(c.reason) > 20, f"{path}: {t.file} {c.name}: reason too short"
        assert all(r.scene_hash is not None for r in m.realizations), f"{path}: never generated (--update)"


# ------------------------------------------------------- case comparison on CSVs --

def _write(p: Path, text: str) -> None:
    p.parent.mkdir(parents=True, exist_ok=True)
    p.write_text(text)


def test_compare_case_structural_problems(tmp_path):
    case = tmp_path / "demo"
    _write(case / "manifest.json", json.dumps(_manifest(tmp_path)))
    m = compare.load_manifest(case / "manifest.json")
    new = tmp_path / "new"
    # Golden file missing: a failure that names it and says how to regenerate (never silently).
    _write(new / "seed-1" / "timeseries.csv", "t,x\n0,1\n")
    r = compare.compare_case(m, case, new, 1.0)
    assert not r.passed and "golden file" in r.problems[0] and "--update demo" in r.problems[0]
    # Rows recorded at other times.
    _write(case / "seed-1" / "timeseries.csv", "t,x\n0,1\n0.5,2\n")
    _write(new / "seed-1" / "timeseries.csv", "t,x\n0,1\n0.25,2\n")
    r = compare.compare_case(m, case, new, 1.0)
    assert not r.passed and "key t differs at row 2" in r.problems[0]
    # A missing column.
    _write(new / "seed-1" / "timeseries.csv", "t,y\n0,1\n0.5,2\n")
    r = compare.compare_case(m, case, new, 1.0)
    assert not r.passed and "no column 'x'" in r.problems[0]
    # Aligned: compared.
    _write(new / "seed-1" / "timeseries.csv", "t,x\n0,1\n0.5,2.0000000001\n")
    r = compare.compare_case(m, case, new, 1.0)
    assert r.passed and not r.problems and r.columns[0].max == pytest.approx(5e-11, rel=1e-5)
    assert r.columns[0].worst_key == [0.5]
    r0 = compare.compare_case(m, case, new, 0.0)
    assert not r0.passed and "FAIL" in compare.format_report(r0)


def test_write_subset_is_round_trip(tmp_path):
    src = tmp_path / "in.csv"
    src.write_text("step,t,x,junk\n0,0,0.1,a\n7,0.30000000000000004,nan,b\n")
    dst = tmp_path / "out" / "g.csv"
    assert compare.write_subset(src, dst, ["step", "t", "x"]) == 2
    assert dst.read_text() == "step,t,x\n0,0,0.10000000000000001\n7,0.30000000000000004,nan\n"
    t = compare.read_table(dst)
    assert t.column("t")[1] == 0.30000000000000004 and math.isnan(t.column("x")[1])
    assert not list(dst.parent.glob("*.partial"))


# --------------------------------------------------- the driver on the real engine --

def _ratchet() -> Path | None:
    """$RATCHET_BIN, else <$RATCHET_BUILD_DIR or build>/reference_engine/ratchet."""
    p = engine_binary()
    return p if p.is_file() and os.access(p, os.X_OK) else None


needs_engine = pytest.mark.skipif(_ratchet() is None,
                                  reason="no engine binary ($RATCHET_BIN, or $RATCHET_BUILD_DIR/build)")


def _driver(*args, env=None):
    e = dict(os.environ)
    e.update(env or {})
    return subprocess.run([PYTHON, str(DRIVER), *args], capture_output=True, text=True, env=e, timeout=600)


@needs_engine
def test_driver_passes_and_catches_a_change_on_the_real_engine(tmp_path):
    """single_particle_sphere (about 1 s) passes as it is, and fails when the particle's
    expansion coefficient changes by 10% (a real change of the physics)."""
    work = tmp_path / "work"
    r = _driver("single_particle_sphere", "--ratchet", str(_ratchet()), "--work", str(work))
    assert r.returncode == 0, r.stdout + r.stderr
    assert "case single_particle_sphere: PASS" in r.stdout
    r = _driver("single_particle_sphere", "--ratchet", str(_ratchet()), "--work", str(work),
                "--set", "thermal.alpha_p=1.1e-4")
    assert r.returncode == 1, r.stdout + r.stderr
    assert "case single_particle_sphere: FAIL" in r.stdout


@needs_engine
def test_driver_never_writes_golden_data_silently(tmp_path):
    """A case whose golden CSV is missing fails; the golden folder is left as it was."""
    golden = tmp_path / "golden"
    shutil.copytree(REPO / "golden" / "single_particle_sphere", golden / "single_particle_sphere")
    for p in (golden / "single_particle_sphere").rglob("timeseries.csv"):
        p.unlink()
    before = sorted(str(p) for p in golden.rglob("*"))
    r = _driver("single_particle_sphere", "--ratchet", str(_ratchet()), "--work", str(tmp_path / "w"),
                "--golden", str(golden))
    assert r.returncode == 1, r.stdout + r.stderr
    assert "--update single_particle_sphere" in r.stdout
    assert sorted(str(p) for p in golden.rglob("*")) == before


@needs_engine
def test_driver_update_regenerates_on_purpose(tmp_path):
    """--update on a copy of a case rewrites its CSVs and manifest; the case then passes."""
    golden = tmp_path / "golden"
    shutil.copytree(REPO / "golden" / "single_particle_sphere", golden / "single_particle_sphere")
    case = golden / "single_particle_sphere"
    man = json.loads((case / "manifest.json").read_text())
    man["realizations"][0]["scene_hash"] = None
    (case / "manifest.json").write_text(json.dumps(man))
    csv_path = next(case.rglob("timeseries.csv"))
    lines = csv_path.read_text().splitlines()
    lines[5] = lines[5].rsplit(",", 1)[0] + ",12345"
    csv_path.write_text("\n".join(lines) + "\n")
    args = ["--ratchet", str(_ratchet()), "--work", str(tmp_path / "w"), "--golden", str(golden)]
    assert _driver("single_particle_sphere", *args).returncode == 1
    r = _driver("--update", "single_particle_sphere", *args)
    assert r.returncode == 0, r.stdout + r.stderr
    man = json.loads((case / "manifest.json").read_text())
    assert isinstance(man["realizations"][0]["scene_hash"], str)
    assert "12345" not in csv_path.read_text()
    assert _driver("single_particle_sphere", *args).returncode == 0


def test_driver_usage_errors():
    r = _driver("--update")
    assert r.returncode == 2 and "name the cases" in r.stderr
    r = _driver("no_such_case")
    assert r.returncode == 2 and "no_such_case" in r.stderr
    r = _driver("--tol-scale", "-3", "single_particle_sphere")
    assert r.returncode == 2 and "--tol-scale" in r.stderr
