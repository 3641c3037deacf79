"""scripts/bench-cycled on a small cycled bed: the summary it prints and writes must
agree with the run's own timeseries, and bad arguments must stop before any run."""

import json
import os
import subprocess
import sys
from pathlib import Path

import pandas as pd
import pytest

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from common.paths import REPO_ROOT, engine_binary  # noqa: E402

RATCHET = engine_binary()
BENCH = REPO_ROOT / "scripts" / "bench-cycled"
SCENE = REPO_ROOT / "validation" / "sweeps" / "bed_quick.json"

pytestmark = pytest.mark.skipif(not RATCHET.is_file(), reason=f"engine not built ({RATCHET})")


@pytest.fixture(scope="module")
def packing(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("pack") / "bed_quick.state"
    subprocess.run([str(RATCHET), "pack", str(SCENE), "--out", str(out), "--quiet"], check=True)
    return out


def run_bench(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run(["/usr/bin/python3", str(BENCH), *args], capture_output=True, text=True)


def test_summary_matches_the_runs_timeseries(packing, tmp_path):
    out, js = tmp_path / "run", tmp_path / "s.json"
    p = run_bench(str(SCENE), "--packing", str(packing), "--steps", "60", "--out", str(out), "--json", str(js),
                  "--set", "solver.max_iterations=40", "--label", "t")
    assert p.returncode == 0, p.stderr
    s = json.loads(js.read_text())
    ts = pd.read_csv(out / "timeseries.csv")
    steps = ts.iloc[1:]  # row 0 is the packing's state
    assert s["steps"] == 60 == len(steps)
    assert s["cap"] == 40
    assert s["sweeps_max"] == steps["iterations"].max() <= 40
    assert s["sweeps_mean"] == pytest.approx(steps["iterations"].mean())
    assert s["at_cap_fraction"] == pytest.approx((steps["iterations"] >= 40).mean())
    assert s["residual_max"] == pytest.approx(steps["residual"].max())
    assert s["solve_ms"] == pytest.approx(1e3 * steps["time_solve"].mean())
    assert s["cpu_s"] > 0
    assert p.stdout.splitlines()[-1].startswith("| t | 60 |")


def test_solver_knobs_may_differ_from_the_packing(packing, tmp_path):
    js = tmp_path / "s.json"
    p = run_bench(str(SCENE), "--packing", str(packing), "--steps", "30", "--json", str(js),
                  "--set", "solver.acceleration=anderson", "--set", "solver.tolerance=1e-6")
    assert p.returncode == 0, p.stderr
    assert json.loads(js.read_text())["steps"] == 30


@pytest.mark.parametrize("args, word", [
    (["--steps", "0"], "--steps"),
    (["--threads", "0"], "--threads"),
    (["--set", "solver.tolerance"], "--set"),
])
def test_bad_arguments_exit_2_naming_the_option(packing, args, word):
    p = run_bench(str(SCENE), "--packing", str(packing), *args)
    assert p.returncode == 2
    assert word in p.stderr


def test_missing_packing_is_named(tmp_path):
    p = run_bench(str(SCENE), "--packing", str(tmp_path / "none.state"))
    assert p.returncode == 2
    assert "--packing" in p.stderr and "none.state" in p.stderr
