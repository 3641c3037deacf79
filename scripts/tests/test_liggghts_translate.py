"""Tests of the LIGGGHTS translation: scene reading, the spheres taken from the engine
(`ratchet bodies`) and checked against its run, STL geometry, the deck's commands
(scripts/liggghts/, docs/liggghts.md)."""

import json
import math
import os
import re
import subprocess
import sys

import numpy as np
import pandas as pd
import pytest

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

from common.paths import engine_binary  # noqa: E402
from liggghts.scene import EngineError, SceneError, build_scene, engine_bodies, load_scene  # noqa: E402
from liggghts.translate import (DemOptions, cone_side_quad, quad_triangles, stl_text,  # noqa: E402
                                translate)
from liggghts.units import Units, rayleigh_time  # noqa: E402

RATCHET = str(engine_binary())



def engine_available():
    return os.path.isfile(RATCHET) and os.access(RATCHET, os.X_OK)


# The spheres of a scene come from the engine binary (`ratchet bodies`).
needs_engine = pytest.mark.skipif(not engine_available(), reason="engine binary not built")


# ------------------------------------------------------------------ scene reading

def scene_json(**over):
    j = {
        "name": "t",
        "seed": 3,
        "time": {"dt": 0.01, "duration": 1.0},
        "container": {"type": "cone", "bottom_radius": 4.5, "opening_angle_deg": 6, "segments": 16},
        "particles": {"generate": {"count": 20, "shape": "sphere", "radius_range": [0.5, 1.0], "spacing": 2.3}},
    }
    j.update(over)
    return j


@needs_engine
def test_a_scene_file_with_comments_is_read(tmp_path):
    # The engine's parser allows // and /* */ comments; so does load_scene (common.jsonc).
    text = json.dumps(scene_json(name="bed // not a comment"), indent=1)
    text = "// a scene\n" + text.replace('"seed": 3', '"seed": /* another bed */ 4')
    p = tmp_path / "s.json"
    p.write_text(text)
    sc = load_scene(str(p))
    assert sc.name == "bed // not a comment"
    assert sc.seed == 4


@pytest.mark.parametrize("mutate,field", [
    (lambda j: j["container"].update(opening_angle_deg=50), "container.opening_angle_deg"),
    (lambda j: j.update(time={"dt": 0.01}), "time.duration"),
    (lambda j: j.update(gravity=[0, 0]), "gravity"),
    (lambda j: j.update(settle={"ke_ratio": 1e-6, "max_time": 20}), "settle"),  # the deck's schedule is fixed
])
def test_scene_errors_name_file_and_field(mutate, field):
    j = scene_json()
    mutate(j)
    with pytest.raises(SceneError) as e:
        build_scene(j, "bad.json")
    assert str(e.value).startswith(f"bad.json: field '{field}'")


@needs_engine
@pytest.mark.parametrize("mutate,field", [
    # What only a sphere deck refuses: the engine builds these bodies, the translation does not take them.
    (lambda j: j["particles"]["generate"].update(shape="polyhedron", count=3), "particles.generate.shape"),
    (lambda j: j["particles"].update(bodies=[{"shape": "sphere", "radius": 0.5, "position": [0, 0, 9]},
                                             {"shape": "box", "half_extents": [1, 1, 1], "position": [0, 0, 12]}]),
     "particles.bodies[1].shape"),
    # The engine's own errors, passed on as they are.
    (lambda j: j["particles"]["generate"].update(spacing=2.0), "particles.generate.spacing"),
    (lambda j: j["particles"]["generate"].update(count=10 ** 6, region={"min": [0, 0, 0], "max": [5, 5, 5]}),
     "particles.generate.count"),
    (lambda j: j.update(particles={"bodies": []}), "particles"),
])
def test_body_errors_name_file_and_field(tmp_path, mutate, field):
    j = scene_json()
    mutate(j)
    p = tmp_path / "bad.json"
    p.write_text(json.dumps(j))
    with pytest.raises(SceneError) as e:
        load_scene(str(p))
    assert str(e.value).startswith(f"{p}: field '{field}'"), str(e.value)


def test_a_missing_engine_is_not_a_scene_error(tmp_path):
    p = tmp_path / "s.json"
    p.write_text(json.dumps(scene_json()))
    with pytest.raises(EngineError, match="engine binary not found or not executable: .*nope"):
        load_scene(str(p), ratchet=str(tmp_path / "nope"))


def test_load_scene_reports_missing_file_and_bad_json(tmp_path):
    with pytest.raises(SceneError, match="nope.json: cannot open"):
        load_scene(str(tmp_path / "nope.json"))
    p = tmp_path / "bad.json"
    p.write_text("{ not json")
    with pytest.raises(SceneError, match="bad.json: not valid JSON"):
        load_scene(str(p))


def test_thermal_stages_and_cycle_windows():
    j = scene_json(thermal={"start_time": 2, "heat_time": 3, "hold_time": 1, "cool_time": 2, "cycles": 2})
    j["time"] = {"dt": 0.01}
    sc = build_scene(j, "s.json")
    kinds = [s[0] for s in sc.stages()]
    assert kinds == ["settle", "heat", "hold", "cool", "hold", "heat", "hold", "cool", "hold"]
    assert sc.stages()[-1][2] == pytest.approx(2 + 2 * 7)
    assert sc.cycle_windows() == [(0, 2, 9), (1, 9, 16)]
    assert sc.thermal.temperature(3.5) == pytest.approx(50.0)
    assert sc.thermal.temperature(5.5) == 100.0
    assert sc.thermal.temperature(7.0) == pytest.approx(50.0)


# ------------------------------------------------------------------ geometry

@pytest.mark.parametrize("theta_deg", [0.0, 6.0, 20.0])
@pytest.mark.parametrize("k", [0, 3, 7, 12])
def test_cone_segment_stl_normal_and_plane(theta_deg, k):
    N, rc, s_max = 16, 4.5, 1.1
    th = math.radians(theta_deg)
    phi = 2 * math.pi * k / N
    n = np.array([-math.cos(th) * math.cos(phi), -math.cos(th) * math.sin(phi), math.sin(th)])
    p = np.array([rc * math.cos(phi), rc * math.sin(phi), 0.0])
    quad = cone_side_quad(k, N, rc, th, s_max, -1.0, 12.0, 1.0)
    for tri in quad_triangles(*quad):
        a, b, c = (np.array(v) for v in tri)
        nt = np.cross(b - a, c - a)
        nt /= np.linalg.norm(nt)
        assert np.allclose(nt, n, atol=1e-12)  # right-hand normal = the inward normal
    V = np.array(quad)
    assert np.allclose((V - p) @ n, 0.0, atol=1e-12)  # on the segment's plane
    assert V[:, 2].min() == pytest.approx(-1.0) and V[:, 2].max() == pytest.approx(12.0)
    # Covers the polygon corners of the expanded container at the floor and at the top
    # (faces translate along n when the container grows; their corners move to
    # s_max * a / cos(pi/N) at z = 0).
    tang = np.array([-math.sin(phi), math.cos(phi), 0.0])
    for z in (-1.0, 12.0):
        half = (s_max * rc + max(z, 0.0) * math.tan(th)) * math.tan(math.pi / N)
        w = np.sort([(v - p) @ tang for v in V if abs(v[2] - z) < 1e-9])
        assert len(w) == 2
        assert w[0] == pytest.approx(-(half + 1.0)) and w[1] == pytest.approx(half + 1.0)  # widened by 1


def test_stl_text_facets_have_consistent_normals(tmp_path):
    quad = cone_side_quad(2, 16, 4.0, math.radians(6), 1.1, -1.0, 10.0, 1.0)
    text = stl_text("w3", quad_triangles(*quad))
    facets = re.findall(r"facet normal (\S+) (\S+) (\S+)\s+outer loop\s+vertex (\S+) (\S+) (\S+)\s+"
                        r"vertex (\S+) (\S+) (\S+)\s+vertex (\S+) (\S+) (\S+)", text)
    assert len(facets) == 2 and text.startswith("solid w3") and text.rstrip().endswith("endsolid w3")
    for f in facets:
        v = np.array(f, dtype=float)
        n, a, b, c = v[:3], v[3:6], v[6:9], v[9:12]
        nc = np.cross(b - a, c - a)
        assert np.allclose(n, nc / np.linalg.norm(nc), atol=1e-12)


# ------------------------------------------------------------------ the deck

@needs_engine
def test_listed_spheres_keep_velocities_and_the_fixed_flag(tmp_path):
    j = scene_json(particles={"bodies": [
        {"shape": "sphere", "radius": 0.6, "position": [0, 0, 0.7], "velocity": [0.5, 0, -1],
         "angular_velocity": [0, 2, 0]},
        {"shape": "sphere", "radius": 0.4, "position": [2, 0, 0.5], "fixed": True}]})
    p = tmp_path / "listed.json"
    p.write_text(json.dumps(j))
    sc = load_scene(str(p))
    a, b = sc.spheres
    assert (a.position, a.radius, a.velocity, a.angular_velocity, a.fixed) == (
        (0.0, 0.0, 0.7), 0.6, (0.5, 0.0, -1.0), (0.0, 2.0, 0.0), False)
    assert (b.position, b.radius, b.fixed) == ((2.0, 0.0, 0.5), 0.4, True)
    out = tmp_path / "deck"
    translate(sc, str(out))
    data = (out / "particles.data").read_text()
    u = Units(length=0.01, density_si=2500.0, density_scene=1.0)
    rows = [[float(x) for x in line.split()] for line in data.split("\nVelocities\n\n")[1].splitlines()]
    assert rows[0] == [1, 0.5 * u.velocity, 0.0, -1.0 * u.velocity, 0.0, 2.0 / u.time, 0.0]
    assert rows[1] == [2, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]
    assert "group           fixed id 2" in (out / "in.liggghts").read_text()


def thermal_scene(tmp_path, E_scene=None, **over):
    j = scene_json(thermal={"start_time": 1.0, "heat_time": 2.0, "hold_time": 0.5, "cool_time": 2.0, "cycles": 1,
                            "alpha_p": 1e-4, "alpha_c": 1e-3},
                   materials={"friction": 0.4, "wall_friction": 0.3, "density": 1.0})
    j["time"] = {"dt": 0.01}
    j.update(over)
    p = tmp_path / "scene.json"
    p.write_text(json.dumps(j))
    return load_scene(str(p))


@needs_engine
def test_deck_contains_the_expected_fixes(tmp_path):
    sc = thermal_scene(tmp_path)
    out = tmp_path / "deck"
    meta = translate(sc, str(out), DemOptions(youngs_modulus=2e6))
    deck = (out / "in.liggghts").read_text()
    for needle in ["atom_style      granular", "units           si", "soft_particles  yes",
                   "read_data       particles.data",
                   "fix m4 all property/global coefficientFriction peratomtypepair 2 0.4 0.3 0.3 0.3",
                   "fix m3 all property/global coefficientRestitution peratomtypepair 2 0.2 0.2 0.2 0.2",
                   "fix m1 all property/global youngsModulus peratomtype 2000000 2000000",
                   "pair_style      gran model hertz tangential history",
                   "fix             r0 mobile store/state 0 radius",
                   "variable        dnew atom 2.0*f_r0*v_sp",
                   "fix             grow mobile adapt 1 atom diameter v_dnew",
                   "variable        gmag equal 9.81/(v_sp*v_sp*v_sp)",
                   "fix             grav mobile gravity v_gmag vector 0.0 0.0 -1.0",
                   "fix             integ mobile nve/sphere",
                   "fix             walls mobile wall/gran model hertz tangential history mesh n_meshes 17 meshes w0 w1",
                   "compute         wl mobile wall/gran/local id force",
                   'print           "ratchet-deck-complete"']:
        assert needle in deck, needle
    assert deck.count("mesh/surface/stress file meshes/") == 17
    assert "hard_particles" not in deck
    # One run per stage (plus the one-step runs that dump wall contacts), movers only in ramps.
    kinds = [s["kind"] for s in meta["stages"]]
    assert kinds == ["settle", "heat", "hold", "cool", "hold"]
    blocks = deck.split("# stage ")[1:]
    for st, block in zip(meta["stages"], blocks):
        movers = re.findall(r"fix +mv_(w\d+) all move/mesh mesh (w\d+) linear (\S+) (\S+) (\S+)", block)
        unfixes = re.findall(r"unfix +mv_(w\d+)", block)
        runs = [int(x) for x in re.findall(r"^run +(\d+)", block, re.M)]
        assert sum(runs) == st["step_end"] - st["step_begin"]
        if st["kind"] in ("heat", "cool"):
            assert len(movers) == 16 and sorted(unfixes) == sorted(m[0] for m in movers)
            # Displacement over the ramp = alpha_c dT (n . p) along n: the face offset of a
            # container scaled by s_c about the origin.
            dT = st["T_end"] - st["T_begin"]
            steps = st["step_end"] - st["step_begin"]
            for wid, _, vx, vy, vz in movers:
                w = next(x for x in meta["walls"] if x["id"] == wid)
                v = np.array([float(vx), float(vy), float(vz)])
                disp = v * steps * meta["dt_si"] / meta["units"]["length"]
                expect = 1e-3 * dT * np.dot(w["normal"], w["point"]) * np.array(w["normal"])
                assert np.allclose(disp, expect, rtol=1e-12, atol=1e-15)
            assert re.search(r"variable +T equal 0\.0\+\(100\.0\)\*\(step-\d+\)/\d+", block) or st["kind"] == "cool"
        else:
            assert not movers
    # Time step: 0.1 Rayleigh time of the smallest particle.
    r_min = min(s.radius for s in sc.spheres)
    assert meta["dt_si"] == pytest.approx(0.1 * rayleigh_time(r_min * 0.01, 2500.0, 2e6, 0.3))
    # Data file: same positions and radii.
    lines = (out / "particles.data").read_text().splitlines()
    i = lines.index("Atoms") + 2
    for s, line in zip(sc.spheres, lines[i:i + len(sc.spheres)]):
        f = line.split()
        assert float(f[2]) == pytest.approx(2 * s.radius * 0.01, rel=1e-15)
        assert [float(x) for x in f[4:7]] == pytest.approx([c * 0.01 for c in s.position], rel=1e-15)


@needs_engine
def test_deck_without_expansion_or_rotation(tmp_path):
    j = scene_json(effects={"rotation": False, "particle_expansion": False, "container_expansion": False},
                   thermal={"heat_time": 1.0, "cycles": 1})
    j["time"] = {"dt": 0.01}
    p = tmp_path / "s.json"
    p.write_text(json.dumps(j))
    out = tmp_path / "d"
    translate(load_scene(str(p)), str(out), DemOptions(youngs_modulus=2e9))
    deck = (out / "in.liggghts").read_text()
    assert "hard_particles  yes" in deck and "soft_particles" not in deck
    assert "adapt" not in deck and "move/mesh" not in deck
    assert "fix             integ mobile nve\n" in deck
    assert "fix             grav mobile gravity 9.81 vector" in deck


def test_units():
    u = Units(length=0.01, density_si=2500.0, density_scene=1.0)
    assert u.time == pytest.approx(math.sqrt(0.01 / 9.81))
    assert u.mass == pytest.approx(2500 * 1e-6)
    assert u.force == pytest.approx(2500 * 1e-6 * 9.81)
    assert u.pressure == pytest.approx(2500 * 9.81 * 0.01)
    # A sphere of engine radius r weighs rho (4/3) pi r^3 force units in both methods.
    r = 0.7
    m_si = 2500 * 4 / 3 * math.pi * (r * 0.01) ** 3
    assert m_si * 9.81 / u.force == pytest.approx(4 / 3 * math.pi * r ** 3)


# ------------------------------------------------------------------ against the engine binary

@needs_engine
@pytest.mark.parametrize("gen", [
    {"count": 40, "shape": "sphere", "radius_range": [0.5, 1.0], "spacing": 2.3},
    {"count": 25, "shape": "sphere", "radius_range": [0.3, 0.8],
     "region": {"min": [-3, -2, 0], "max": [3.5, 4, 30]}},
])
def test_translated_particles_are_the_engines(tmp_path, gen):
    """The deck's particles are what `ratchet bodies` wrote, and that is what `ratchet
    run` starts from: positions exactly equal to the run's step-0 bodies.csv, radii
    through the bed height at step 0 and the kinetic energy after one free-fall step
    (0.5 (g h)^2 sum m); particles.data carries the same numbers in SI."""
    j = scene_json(seed=11, particles={"generate": gen})
    j["time"] = {"dt": 0.001, "duration": 0.001}
    p = tmp_path / "gen.json"
    p.write_text(json.dumps(j))
    sc = load_scene(str(p))
    doc = engine_bodies(str(p))
    assert doc["format"] == "ratchet-bodies" and doc["version"] == 1 and doc["seed"] == 11
    assert [s.position for s in sc.spheres] == [tuple(b["position"]) for b in doc["bodies"]]
    assert [s.radius for s in sc.spheres] == [b["radius"] for b in doc["bodies"]]
    assert doc["shapes"] == [] and all(b["kind"] == "sphere" and b["shape"] is None for b in doc["bodies"])
    # Against the run.
    out = tmp_path / "run"
    r = subprocess.run([RATCHET, "run", str(p), "--out", str(out), "--quiet"], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    b = pd.read_csv(out / "bodies.csv", float_precision="round_trip")
    b0 = b[b["step"] == 0].sort_values("id")
    assert np.array_equal(b0[["x", "y", "z"]].to_numpy(), np.array([s.position for s in sc.spheres]))
    ts = pd.read_csv(out / "timeseries.csv", float_precision="round_trip")
    radii = np.array([s.radius for s in sc.spheres])
    z0 = np.array([s.position[2] for s in sc.spheres])
    assert ts["bed_height"].iloc[0] == pytest.approx(np.max(z0 + radii), rel=1e-14)
    ke = 0.5 * 0.001 ** 2 * np.sum(4 / 3 * math.pi * radii ** 3)
    assert ts["kinetic_energy"].iloc[-1] == pytest.approx(ke, rel=1e-9)
    # The run folder carries the same document (with the same bodies).
    with open(out / "bodies_shapes.json") as fh:
        assert json.load(fh)["bodies"] == doc["bodies"]
    # particles.data: diameter and position of every sphere, exactly the engine's x L.
    deck = tmp_path / "deck"
    translate(sc, str(deck))
    lines = (deck / "particles.data").read_text().splitlines()
    i = lines.index("Atoms") + 2
    rows = [line.split() for line in lines[i:i + len(doc["bodies"])]]
    assert len(rows) == len(doc["bodies"])
    for row, body in zip(rows, doc["bodies"]):
        assert int(row[0]) == body["index"] + 1
        assert float(row[2]) == 2.0 * body["radius"] * 0.01
        assert [float(x) for x in row[4:7]] == [c * 0.01 for c in body["position"]]
