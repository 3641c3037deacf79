"""VTK output of `ratchet run` (docs/output-format.md, "VTK files") read back with VTK's
own readers (Debian's python3-vtk9), in both encodings (zlib-compressed binary, the
default, and ASCII on request: the same arrays), and checked against the run's CSVs: the .pvd indexes
list every snapshot with the time of its timeseries.csv row, the particles are the
bodies.csv rows of that step, the contacts with a positive normal force are the
`contacts` column of that step, and the container is drawn at the scale s_c of that row.
Also: outputs.vtk_cycles without thermal cycles is refused before any work, a killed run
leaves a valid index, and a rerun removes the earlier run's snapshots."""

import json
import math
import os
import signal
import subprocess
import sys
import time
import xml.etree.ElementTree as ET
from pathlib import Path

import pandas as pd
import pytest

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from common.paths import REPO_ROOT, engine_binary  # noqa: E402

try:
    import vtk
    from vtk.util.numpy_support import vtk_to_numpy
except ImportError as e:  # pragma: no cover - depends on the machine
    pytest.skip(f"VTK's Python module is not available ({e}); scripts/bootstrap installs python3-vtk9",
                allow_module_level=True)

RATCHET = engine_binary()
FREE_FALL = REPO_ROOT / "validation" / "free_fall" / "sphere.json"

pytestmark = pytest.mark.skipif(not RATCHET.is_file(), reason=f"engine not built ({RATCHET})")

# A cone of 8 segments with 8 spheres and a box, one short thermal cycle in which the
# container grows by up to 20 %: 450 steps, well under a second.
N_SEG, R_C, THETA_DEG, HEIGHT = 8, 2.5, 5.0, 4.0
EVERY = 40
SCENE = {
    "name": "vtk_output",
    "time": {"dt": 0.004},
    "solver": {"tolerance": 1e-6, "max_iterations": 500},
    "container": {"type": "cone", "bottom_radius": R_C, "opening_angle_deg": THETA_DEG, "segments": N_SEG,
                  "height": HEIGHT},
    "particles": {"bodies": [
        {"shape": "box", "half_extents": [0.4, 0.3, 0.25], "position": [0, 0, 0.6],
         "angular_velocity": [0, 0, 1.0]},
        {"shape": "sphere", "radius": 0.5, "position": [1, 0, 0.6], "velocity": [0.3, 0.1, 0]},
        {"shape": "sphere", "radius": 0.5, "position": [-1, 0, 0.6]},
        {"shape": "sphere", "radius": 0.5, "position": [0, 1, 0.6]},
        {"shape": "sphere", "radius": 0.5, "position": [0, -1, 0.6]},
        {"shape": "sphere", "radius": 0.5, "position": [0, 0, 1.8]},
        {"shape": "sphere", "radius": 0.5, "position": [1, 1, 1.8]},
        {"shape": "sphere", "radius": 0.5, "position": [-1, -1, 1.8]},
        {"shape": "sphere", "radius": 0.4, "position": [1, -1, 1.8]},
    ]},
    "thermal": {"start_time": 0.6, "heat_time": 0.4, "hold_time": 0.2, "cool_time": 0.4, "cycles": 1,
                "alpha_p": 1e-3, "alpha_c": 2e-3},
    "outputs": {"timeseries_every": 10, "bodies_every": 10, "vtk_every": EVERY, "vtk_cycles": [0]},
}
LAST_STEP = 450
END_HEATING_STEP, END_COOLING_STEP = 250, 400  # t = 1.0 and t = 1.6


def ratchet(*args) -> subprocess.CompletedProcess:
    return subprocess.run([str(RATCHET), *map(str, args), "--quiet"], capture_output=True, text=True)


def read_vtp(path: Path) -> vtk.vtkPolyData:
    assert path.is_file(), path
    r = vtk.vtkXMLPolyDataReader()
    r.SetFileName(str(path))
    r.Update()
    assert r.GetErrorCode() == 0, path
    return r.GetOutput()


def array(data, name):
    a = data.GetArray(name)
    assert a is not None, name
    return vtk_to_numpy(a)


def points(poly):
    return vtk_to_numpy(poly.GetPoints().GetData()) if poly.GetNumberOfPoints() > 0 else []


def read_pvd(path: Path):
    """[(timestep, file)] of a .pvd, in file order."""
    root = ET.parse(path).getroot()
    assert root.tag == "VTKFile" and root.get("type") == "Collection"
    return [(float(d.get("timestep")), d.get("file")) for d in root.find("Collection").findall("DataSet")]


def close(a, b, rel=1e-10):
    return abs(a - b) <= rel * max(1.0, abs(a), abs(b))


@pytest.fixture(scope="module")
def run(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("vtk")
    scene = folder / "scene.json"
    scene.write_text(json.dumps(SCENE))
    r = ratchet("run", scene, "--out", folder / "run")
    assert r.returncode == 0, r.stderr
    return folder / "run"


@pytest.fixture(scope="module")
def ascii_run(tmp_path_factory) -> Path:
    """The same run with outputs.vtk_format "ascii"."""
    folder = tmp_path_factory.mktemp("vtk_ascii")
    scene = folder / "scene.json"
    scene.write_text(json.dumps({**SCENE, "outputs": {**SCENE["outputs"], "vtk_format": "ascii"}}))
    r = ratchet("run", scene, "--out", folder / "run")
    assert r.returncode == 0, r.stderr
    return folder / "run"


@pytest.fixture(scope="module")
def csv(run):
    # round_trip: the CSVs' 17 digits read back to the very doubles the run had.
    ts = pd.read_csv(run / "timeseries.csv", float_precision="round_trip").set_index("step")
    bodies = pd.read_csv(run / "bodies.csv", float_precision="round_trip")
    return ts, bodies


def snapshots(run, kind):
    """[(timestep, path)] of vtk/<kind>.pvd."""
    return [(t, run / "vtk" / f) for t, f in read_pvd(run / "vtk" / f"{kind}.pvd")]


def step_of(poly) -> int:
    return int(array(poly.GetFieldData(), "step")[0])


def test_pvd_lists_every_snapshot_with_its_time(run, csv):
    ts, _ = csv
    expected = sorted(set(range(0, LAST_STEP + 1, EVERY)) | {LAST_STEP, END_HEATING_STEP})
    # The end of cooling (step 400) is also a step of vtk_every: indexed once.
    assert END_COOLING_STEP in expected
    for kind in ("particles", "contacts", "container"):
        entries = snapshots(run, kind)
        assert len(entries) == len(expected), kind
        steps = []
        for t, path in entries:
            poly = read_vtp(path)
            k = step_of(poly)
            steps.append(k)
            # The time of the file, of the index and of the CSV row: the same double.
            assert array(poly.GetFieldData(), "TimeValue")[0] == t
            assert ts.loc[k, "t"] == t, (kind, k)
        assert steps == expected, kind
        times = [t for t, _ in entries]
        assert times == sorted(times) and len(set(times)) == len(times)
    # The stage ends keep their names and hold the state of their step.
    assert step_of(read_vtp(run / "vtk" / "particles_cycle0_end_heating.vtp")) == END_HEATING_STEP
    assert step_of(read_vtp(run / "vtk" / "contacts_cycle0_end_cooling.vtp")) == END_COOLING_STEP
    assert (run / "vtk" / "container_cycle0_end_cooling.vtp").is_file()
    assert not list((run / "vtk").glob("*.partial"))


def all_arrays(poly) -> dict:
    """Every array of a file (field, point and cell data, points, cell connectivity) as numpy."""
    out = {}
    for kind, data in (("field", poly.GetFieldData()), ("point", poly.GetPointData()), ("cell", poly.GetCellData())):
        for i in range(data.GetNumberOfArrays()):
            out[f"{kind}/{data.GetArrayName(i)}"] = vtk_to_numpy(data.GetArray(i))
    if poly.GetNumberOfPoints() > 0:
        out["points"] = vtk_to_numpy(poly.GetPoints().GetData())
    for name in ("Verts", "Lines", "Polys"):
        cells = getattr(poly, f"Get{name}")()
        out[f"{name}/offsets"] = vtk_to_numpy(cells.GetOffsetsArray())
        out[f"{name}/connectivity"] = vtk_to_numpy(cells.GetConnectivityArray())
    return out


def test_binary_is_the_default_and_ascii_holds_the_same_arrays(run, ascii_run):
    files = sorted(p.name for p in (run / "vtk").glob("*.vtp"))
    assert files == sorted(p.name for p in (ascii_run / "vtk").glob("*.vtp")) and len(files) > 40
    compared = 0
    for name in files:
        binary, text = (run / "vtk" / name).read_bytes(), (ascii_run / "vtk" / name).read_bytes()
        # The encodings as docs/output-format.md states them.
        assert b'compressor="vtkZLibDataCompressor"' in binary and b'<AppendedData encoding="raw">' in binary
        assert b'format="appended"' in binary and b"compressor" not in text and b'format="appended"' not in text
        a, b = all_arrays(read_vtp(run / "vtk" / name)), all_arrays(read_vtp(ascii_run / "vtk" / name))
        assert a.keys() == b.keys(), name
        for key in a:
            assert a[key].dtype == b[key].dtype, (name, key)
            # Bit for bit: the ASCII text reads back to the very doubles of the binary file.
            assert a[key].tobytes() == b[key].tobytes(), (name, key)
            compared += a[key].size
        assert len(binary) < len(text) or "contacts" in name or "force_chains" in name, name
    assert compared > 10000


def test_particles_are_the_bodies_rows_of_their_step(run, csv):
    _, bodies = csv
    n_bodies = len(SCENE["particles"]["bodies"])
    moved = False
    for _, path in snapshots(run, "particles"):
        poly = read_vtp(path)
        rows = bodies[bodies["step"] == step_of(poly)].set_index("id")
        assert len(rows) == n_bodies
        pd_, cd = poly.GetPointData(), poly.GetCellData()
        ids = array(pd_, "body_id")
        assert sorted(set(ids.tolist())) == sorted(rows.index.tolist())
        assert sorted(set(array(cd, "body_id").tolist())) == sorted(rows.index.tolist())
        xyz, radius = points(poly), array(pd_, "radius")
        vel, ang, scale = array(pd_, "velocity"), array(pd_, "angular_velocity"), array(pd_, "scale")
        volume, r_eq = array(pd_, "volume"), array(pd_, "equivalent_radius")
        assert poly.GetNumberOfVerts() == n_bodies - 1  # the spheres
        assert poly.GetNumberOfPolys() == 6             # the box's faces
        for i, row in rows.iterrows():
            mine = ids == i
            # A sphere is its centre; the box's vertices average to its centre.
            centre = xyz[mine].mean(axis=0)
            for a, b in zip(centre, (row.x, row.y, row.z)):
                assert close(a, b), (path.name, i)
            assert mine.sum() == (8 if i == 0 else 1)
            assert (radius[mine] > 0).all() == (i != 0)
            # Every body has a size, the box too; a sphere's equivalent radius is its radius.
            assert (r_eq[mine] > 0).all() and (volume[mine] > 0).all()
            assert all(close(v, 4.0 / 3.0 * math.pi * r ** 3) for v, r in zip(volume[mine], r_eq[mine]))
            if i != 0:
                assert all(close(a, b) for a, b in zip(r_eq[mine], radius[mine]))
            for p in range(int(mine.sum())):
                assert all(close(a, b) for a, b in zip(vel[mine][p], (row.vx, row.vy, row.vz)))
                assert all(close(a, b) for a, b in zip(ang[mine][p], (row.wx, row.wy, row.wz)))
                assert close(scale[mine][p], row.scale)
            if i == 0 and step_of(poly) > 0:
                moved = moved or abs(row.wz) > 1e-3
    assert moved  # the box's spin shows: the check above compares something that changes


def test_contacts_are_the_timeseries_contacts_of_their_step(run, csv):
    ts, _ = csv
    walls = 1 + N_SEG
    n_bodies = len(SCENE["particles"]["bodies"])
    some = 0
    for _, path in snapshots(run, "contacts"):
        poly = read_vtp(path)
        k = step_of(poly)
        container = read_vtp(run / "vtk" / path.name.replace("contacts_", "container_"))
        if poly.GetNumberOfPoints() == 0:
            assert ts.loc[k, "contacts"] == 0
            continue
        pd_ = poly.GetPointData()
        fn = array(pd_, "normal_force_magnitude")
        normal, f_n, f_t = array(pd_, "normal"), array(pd_, "normal_force"), array(pd_, "tangential_force")
        a, b, gap = array(pd_, "body_a"), array(pd_, "body_b"), array(pd_, "gap")
        assert poly.GetNumberOfVerts() == poly.GetNumberOfPoints()
        # The `contacts` column counts the contact points with a positive normal impulse;
        # the file has every detected point, open ones with a zero force.
        assert int((fn > 0).sum()) == ts.loc[k, "contacts"], path.name
        some += int((fn > 0).sum())
        assert ((a >= 0) & (a < n_bodies)).all() and ((b >= -walls) & (b < n_bodies)).all()
        assert all(math.isfinite(g) for g in gap)
        wall_normal = array(container.GetCellData(), "normal")
        side_id = array(container.GetCellData(), "side_id")
        for i in range(len(fn)):
            assert close(sum(x * x for x in normal[i]), 1.0)
            assert all(close(f_n[i][c], fn[i] * normal[i][c]) for c in range(3))
            assert abs(sum(f_t[i][c] * normal[i][c] for c in range(3))) <= 1e-9 * max(1.0, fn[i])
            if b[i] < 0:  # a wall contact's normal is its wall's
                w = list(side_id).index(b[i])
                assert all(abs(normal[i][c] - wall_normal[w][c]) < 1e-9 for c in range(3))
        # The walls' forces add up to the timeseries columns.
        force = array(container.GetCellData(), "normal_force")
        assert close(force[0], ts.loc[k, "wall_force_bottom"], 1e-9)
        assert close(force[1:].sum(), ts.loc[k, "wall_force_side"], 1e-9)
    assert some > 0


def test_force_chains_are_the_contacts_as_lines_between_the_centres(run, csv):
    _, bodies = csv
    chains = 0
    statuses = set()
    for _, path in snapshots(run, "force_chains"):
        poly = read_vtp(path)
        contacts = read_vtp(run / "vtk" / path.name.replace("force_chains_", "contacts_"))
        n = contacts.GetNumberOfPoints()
        assert poly.GetNumberOfLines() == n and poly.GetNumberOfPoints() == 2 * n, path.name
        if n == 0:
            continue
        cd, pd_ = poly.GetCellData(), contacts.GetPointData()
        fn, ft, status = array(cd, "normal_force"), array(cd, "tangential_force"), array(cd, "status")
        a, b = array(cd, "body_a"), array(cd, "body_b")
        assert (a == array(pd_, "body_a")).all() and (b == array(pd_, "body_b")).all()
        f_t = array(pd_, "tangential_force")
        rows = bodies[bodies["step"] == step_of(poly)].set_index("id")
        xyz, contact_xyz = points(poly), points(contacts)
        for i in range(n):
            assert close(fn[i], array(pd_, "normal_force_magnitude")[i])
            assert close(ft[i], math.sqrt(sum(x * x for x in f_t[i])))
            # Open has no normal force; a slipping contact is on its cone (the default
            # friction 0.5 against bodies and walls alike).
            assert (status[i] == 0) == (fn[i] <= 0.0)
            if status[i] == 2:
                assert close(ft[i], 0.5 * fn[i], 1e-6)
            if status[i] == 1:
                assert ft[i] < 0.5 * fn[i] * (1 + 1e-6)
            centre_a = rows.loc[a[i]]
            assert all(close(p, q) for p, q in zip(xyz[2 * i], (centre_a.x, centre_a.y, centre_a.z)))
            end = contact_xyz[i] if b[i] < 0 else tuple(rows.loc[b[i]][["x", "y", "z"]])
            assert all(close(p, q) for p, q in zip(xyz[2 * i + 1], end))
            statuses.add(int(status[i]))
            chains += 1
    assert chains > 0 and len(statuses) >= 2, statuses  # the status tells contacts apart


def cone_corners(s_c):
    """The container's points at scale s_c: bottom ring, then top ring (docs/output-format.md)."""
    half = math.pi / N_SEG
    tan = math.tan(math.radians(THETA_DEG))
    out = []
    for z, apothem in ((0.0, R_C), (HEIGHT, R_C + HEIGHT * tan)):
        for j in range(N_SEG):
            psi = (2 * j - 1) * half
            r = apothem / math.cos(half)
            out.append((s_c * r * math.cos(psi), s_c * r * math.sin(psi), s_c * z))
    return out


def test_container_is_drawn_at_the_scale_of_its_step(run, csv):
    ts, _ = csv
    scales = []
    theta = math.radians(THETA_DEG)
    for _, path in snapshots(run, "container"):
        poly = read_vtp(path)
        s_c = ts.loc[step_of(poly), "s_c"]
        scales.append(s_c)
        xyz = points(poly)
        assert len(xyz) == 2 * N_SEG
        for p, q in zip(xyz, cone_corners(s_c)):
            assert all(abs(a - b) < 1e-9 for a, b in zip(p, q)), (path.name, p, q)
        # Floor, then segment k as wall k + 1; each side polygon lies on its wall's plane
        # at this scale: n . (x - s_c p_k) = 0.
        cd = poly.GetCellData()
        assert array(cd, "wall_index").tolist() == list(range(N_SEG + 1))
        assert array(cd, "side_id").tolist() == [-1 - w for w in range(N_SEG + 1)]
        assert poly.GetNumberOfPolys() == N_SEG + 1
        ids = vtk.vtkIdList()
        polys = poly.GetPolys()
        polys.InitTraversal()
        polys.GetNextCell(ids)
        assert ids.GetNumberOfIds() == N_SEG
        for k in range(N_SEG):
            polys.GetNextCell(ids)
            phi = 2 * math.pi * k / N_SEG
            n = (-math.cos(theta) * math.cos(phi), -math.cos(theta) * math.sin(phi), math.sin(theta))
            p0 = (s_c * R_C * math.cos(phi), s_c * R_C * math.sin(phi), 0.0)
            for m in range(ids.GetNumberOfIds()):
                x = xyz[ids.GetId(m)]
                assert abs(sum(n[c] * (x[c] - p0[c]) for c in range(3))) < 1e-9
    assert max(scales) > 1.1 and min(scales) == 1.0  # the scale did change between snapshots


def test_planes_container_is_a_square_patch_around_its_point(tmp_path):
    r = ratchet("run", FREE_FALL, "--out", tmp_path, "--set", "outputs.vtk_every=1000")
    assert r.returncode == 0, r.stderr
    ts = pd.read_csv(tmp_path / "timeseries.csv", float_precision="round_trip").set_index("step")
    entries = snapshots(tmp_path, "container")
    assert len(entries) == 5  # steps 0, 1000, ..., 4000 (the last)
    # The sphere (radius 0.5) starts 2 above the plane's point: half side 2 (2 + 0.5) = 5.
    xyz = points(read_vtp(entries[-1][1]))
    assert sorted(map(tuple, xyz.tolist())) == [(-5, -5, 0), (-5, 5, 0), (5, -5, 0), (5, 5, 0)]
    last = read_vtp(snapshots(tmp_path, "contacts")[-1][1])
    fn = array(last.GetPointData(), "normal_force_magnitude")
    assert int((fn > 0).sum()) == ts.loc[4000, "contacts"] == 1
    assert array(last.GetPointData(), "body_b").tolist() == [-1]  # wall 0
    assert close(fn[0], ts.loc[4000, "wall_force_total"], 1e-9)


def test_vtk_cycles_without_thermal_cycles_is_refused_before_any_work(tmp_path):
    out = tmp_path / "out"
    r = ratchet("run", FREE_FALL, "--out", out, "--set", "outputs.vtk_cycles=[0]")
    assert r.returncode == 2, (r.returncode, r.stderr)
    assert "'outputs.vtk_cycles'" in r.stderr and "thermal" in r.stderr, r.stderr
    assert not (out / "timeseries.csv").exists() and not (out / "vtk").exists()


def test_a_bad_vtk_format_is_refused_before_any_work(tmp_path):
    out = tmp_path / "out"
    r = ratchet("run", FREE_FALL, "--out", out, "--set", "outputs.vtk_format=xml")
    assert r.returncode == 2, (r.returncode, r.stderr)
    assert "field 'outputs.vtk_format': expected \"binary\" or \"ascii\", got \"xml\"" in r.stderr, r.stderr
    assert not out.exists() or not any(out.iterdir())


def test_no_vtk_unless_asked(tmp_path):
    r = ratchet("run", FREE_FALL, "--out", tmp_path)
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "run.json").is_file() and not (tmp_path / "vtk").exists()


def test_a_rerun_removes_the_earlier_snapshots(tmp_path):
    assert ratchet("run", FREE_FALL, "--out", tmp_path, "--set", "outputs.vtk_every=1000").returncode == 0
    (tmp_path / "vtk" / "notes.txt").write_text("mine")
    assert ratchet("run", FREE_FALL, "--out", tmp_path, "--set", "outputs.vtk_every=1500").returncode == 0
    names = sorted(p.name for p in (tmp_path / "vtk").iterdir())
    steps = ["00000000", "00001500", "00003000", "00004000"]
    kinds = ("particles", "contacts", "container", "force_chains")
    assert names == sorted(["notes.txt"] + [f"{k}.pvd" for k in kinds] +
                           [f"{k}_step{s}.vtp" for k in kinds for s in steps])
    assert ratchet("run", FREE_FALL, "--out", tmp_path).returncode == 0
    assert sorted(p.name for p in (tmp_path / "vtk").iterdir()) == ["notes.txt"]


def test_a_killed_run_leaves_a_valid_index(tmp_path):
    # A run far too long to finish: killed once its index lists a few snapshots.
    proc = subprocess.Popen([str(RATCHET), "run", str(FREE_FALL), "--out", str(tmp_path), "--quiet",
                             "--set", "time.duration=100000", "--set", "outputs.vtk_every=200",
                             "--set", "outputs.timeseries_every=1000000"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    pvd = tmp_path / "vtk" / "particles.pvd"
    try:
        deadline = time.monotonic() + 120
        while time.monotonic() < deadline and proc.poll() is None:
            if pvd.is_file() and len(read_pvd(pvd)) >= 5:
                break
            time.sleep(0.05)
        assert proc.poll() is None, proc.stderr.read()
    finally:
        proc.send_signal(signal.SIGKILL)
        proc.wait()
    assert not (tmp_path / "run.json").exists()
    for kind in ("particles", "contacts", "container"):
        entries = read_pvd(tmp_path / "vtk" / f"{kind}.pvd")  # whole XML: never a half-written index
        assert len(entries) >= 4
        for t, f in entries:
            poly = read_vtp(tmp_path / "vtk" / f)
            assert array(poly.GetFieldData(), "TimeValue")[0] == t
