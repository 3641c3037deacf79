"""scripts/method-cost on a tiny generated sphere bed (8 spheres, one short cycle, a few
seconds): its ensemble means and costs must be those of compare-methods' own summaries,
per seed, and bad arguments stop it before any run. Skipped without LIGGGHTS or the engine."""

import json
import math
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from scipy import stats

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from common.paths import engine_binary  # noqa: E402

TOOL = Path(__file__).resolve().parents[1] / "method-cost"
SCENE = {"name": "mc_small", "time": {"dt": 0.002},
         "container": {"type": "cone", "bottom_radius": 3.0, "opening_angle_deg": 0, "segments": 16},
         "particles": {"generate": {"count": 8, "shape": "sphere", "radius_range": [0.5, 1.0], "spacing": 2.3}},
         "thermal": {"T0": 0, "T1": 100, "start_time": 2.0, "heat_time": 1.0, "hold_time": 0.5, "cool_time": 1.0,
                     "cycles": 1, "alpha_p": 1e-4, "alpha_c": 1e-3}}

pytestmark = [pytest.mark.skipif(shutil.which("liggghts") is None, reason="liggghts is not installed"),
              pytest.mark.skipif(not engine_binary().is_file(), reason="engine not built")]


def call(*args):
    return subprocess.run(["/usr/bin/python3", str(TOOL), *map(str, args)], capture_output=True, text=True)


def test_means_and_costs_are_those_of_each_seeds_comparison(tmp_path):
    scene = tmp_path / "scene.json"
    scene.write_text(json.dumps(SCENE))
    r = call(scene, "--out", tmp_path / "out", "--seeds", 1, 2, 3, "--E", 5e6, "--jobs", 2,
             "--restitution", 0.5, "--dt-fraction", 0.2)
    assert r.returncode == 0, r.stderr
    res = json.loads((tmp_path / "out" / "comparison.json").read_text())
    assert res["settings"] == ["NSCD", "DEM E=5e6"]
    nscd, dem, cost = [], [], []
    for s in (1, 2, 3):
        summary = json.loads((tmp_path / "out" / f"seed{s}" / "summary.json").read_text())
        # the DEM knobs reach LIGGGHTS (time step as a fraction of the Rayleigh time)
        assert summary["options"]["restitution"] == 0.5 and summary["options"]["dt_fraction"] == 0.2
        nscd.append(summary["cycles"]["nscd_peak_pressure"][0])
        dem.append(summary["cycles"]["dem_E5e06_peak_pressure"][0])
        cost.append(next(t["wall_seconds"] for t in summary["timings"] if t["method"] == "dem"))
        # each seed is another bed: the engine ran the scene with that seed
        run = json.loads((tmp_path / "out" / f"seed{s}" / "engine" / "run.json").read_text())
        assert run["scene"]["seed"] == s
    p = res["observables"]["P_max"]
    assert p["NSCD"]["mean"] == pytest.approx(sum(nscd) / 3, rel=1e-12)
    assert p["DEM E=5e6"]["se"] == pytest.approx(stats.tstd(dem) / math.sqrt(3), rel=1e-12)
    assert p["DEM E=5e6"]["p"] == pytest.approx(stats.ttest_ind(dem, nscd, equal_var=False).pvalue)
    assert res["observables"]["wall_seconds"]["DEM E=5e6"]["mean"] == pytest.approx(sum(cost) / 3, rel=1e-12)
    assert "| P_max |" in (tmp_path / "out" / "comparison.md").read_text()


def test_one_seed_is_refused_before_any_run(tmp_path):
    scene = tmp_path / "scene.json"
    scene.write_text(json.dumps(SCENE))
    r = call(scene, "--out", tmp_path / "out", "--seeds", 4, 4)
    assert r.returncode == 2
    assert "--seeds: expected at least two different seeds" in r.stderr
    assert not (tmp_path / "out").exists()
