"""A real, short LIGGGHTS run of a translated deck (a few seconds): five spheres dropped
on the floor of an expanding cone, one thermal cycle. The spheres come from the engine
(`ratchet bodies`). Skipped when LIGGGHTS is not installed or the engine not built."""

import json
import math
import os
import shutil
import subprocess
import sys

import numpy as np
import pytest

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

from common.paths import engine_binary  # noqa: E402
from liggghts.parse import log_completed, parse_run, read_dump, read_meta  # noqa: E402
from liggghts.scene import load_scene  # noqa: E402
from liggghts.translate import DemOptions, translate  # noqa: E402

LIGGGHTS = shutil.which("liggghts")

SCENE = {
    "name": "five_spheres_drop",
    "time": {"dt": 0.002},
    "container": {"type": "cone", "bottom_radius": 3.0, "opening_angle_deg": 6, "segments": 16},
    "particles": {"bodies": [
        {"shape": "sphere", "radius": 0.6, "position": [0, 0, 0.7]},
        {"shape": "sphere", "radius": 0.8, "position": [2.0, 0, 0.9]},
        {"shape": "sphere", "radius": 1.0, "position": [-1.8, 0.2, 1.1]},
        {"shape": "sphere", "radius": 0.5, "position": [0, 1.6, 0.6]},
        {"shape": "sphere", "radius": 0.7, "position": [0.1, -1.6, 0.8]}]},
    "thermal": {"T0": 0, "T1": 100, "start_time": 2.0, "heat_time": 1.0, "hold_time": 0.5, "cool_time": 1.0,
                "cycles": 1, "alpha_p": 1e-4, "alpha_c": 1e-3},
}


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    if LIGGGHTS is None:
        pytest.skip("liggghts is not installed")
    if not os.access(engine_binary(), os.X_OK):
        pytest.skip("engine binary not built")
    d = tmp_path_factory.mktemp("dem")
    p = d / "scene.json"
    p.write_text(json.dumps(SCENE))
    sc = load_scene(str(p))
    deck = d / "deck"
    meta = translate(sc, str(deck), DemOptions(youngs_modulus=5e6))
    r = subprocess.run([LIGGGHTS, "-in", "in.liggghts", "-log", "log.liggghts"], cwd=deck,
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stdout[-2000:]
    assert log_completed(str(deck / "log.liggghts"))
    return sc, str(deck), meta, parse_run(str(deck))


def weight(sc):
    return sum(4 / 3 * math.pi * s.radius ** 3 for s in sc.spheres)


def test_floor_carries_the_weight_at_rest(run):
    sc, deck, meta, ts = run
    settled = ts[(ts["t"] > 1.6) & (ts["t"] <= 2.0)]
    assert np.allclose(settled["wall_force_bottom"], weight(sc), rtol=2e-3)
    assert np.allclose(settled["wall_force_side"], 0.0)
    assert np.all(settled["kinetic_energy"] < 1e-3 * weight(sc))


def test_walls_move_with_the_container_scale(run):
    sc, deck, meta, ts = run
    # Reference point of a side mesh (moved by fix move/mesh) against s_c = 1 + alpha_c (T - T0).
    assert np.allclose(ts["dem_s_c_mesh"], ts["s_c"], atol=1e-9)
    assert ts["s_c"].max() == pytest.approx(1.1, abs=1e-9)
    assert ts["s_c"].iloc[-1] == pytest.approx(1.0, abs=1e-12)


def test_particles_grow_and_weight_stays_constant(run):
    sc, deck, meta, ts = run
    heat_end = next(d for d in meta["dumps"] if meta["stages"][d["stage"]]["kind"] == "heat")
    snap = read_dump(os.path.join(deck, heat_end["file"]), read_meta(deck)).sort_values("id")
    r0 = np.array([s.radius for s in sc.spheres])
    assert np.allclose(snap["radius"].to_numpy(), 1.01 * r0, rtol=1e-9)
    # fix adapt keeps the density (mass x s_p^3); gravity scaled by 1/s_p^3 keeps the weight.
    hot = ts[(ts["T"] == 100.0)]
    assert len(hot) > 3
    assert np.allclose(hot["wall_force_bottom"].iloc[-3:], weight(sc), rtol=5e-3)
