"""Tests of the LIGGGHTS log parser, the unit mapping of its columns, the pressure and
wall-profile formulas and the comparison helpers (scripts/liggghts/)."""

import json
import math
import os
import sys

import numpy as np
import pandas as pd
import pytest

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

from liggghts.compare import bed_measures, cycle_peaks, sphere_volume_below  # noqa: E402
from liggghts.parse import (ParseError, parse_run, read_local_dump, read_thermo_log,  # noqa: E402
                           wall_stress_profile)
from liggghts.scene import build_scene  # noqa: E402
from liggghts.units import Units, frustum_side_area, frustum_volume  # noqa: E402


def polygon_frustum_area(a0, theta, N, H):
    """Independent: lateral area from the corner points of the N-gon frustum."""
    r0 = a0 / math.cos(math.pi / N)
    r1 = (a0 + H * math.tan(theta)) / math.cos(math.pi / N)
    area = 0.0
    for k in range(N):
        p = [(r * math.cos(2 * math.pi * (k + s + 0.5) / N), r * math.sin(2 * math.pi * (k + s + 0.5) / N), z)
             for s in (0, 1) for r, z in ((r0, 0.0), (r1, H))]
        A, B, C, D = (np.array(x) for x in (p[0], p[2], p[3], p[1]))  # bottom k, bottom k+1, top k+1, top k
        area += 0.5 * np.linalg.norm(np.cross(B - A, C - A)) + 0.5 * np.linalg.norm(np.cross(C - A, D - A))
    return area


@pytest.mark.parametrize("theta_deg", [0, 4, 8, 30])
def test_frustum_area_is_the_engines_formula(theta_deg):
    th = math.radians(theta_deg)
    for H in (0.5, 7.0):
        for s_c in (1.0, 1.1):
            a0 = s_c * 4.5
            expect = 16 * (a0 + a0 + H * math.tan(th)) * math.tan(math.pi / 16) * H / math.cos(th)
            got = float(frustum_side_area(H, 4.5, th, 16, s_c))
            assert got == pytest.approx(expect, rel=1e-14)
            assert got == pytest.approx(polygon_frustum_area(a0, th, 16, H), rel=1e-12)
    assert float(frustum_side_area(0.0, 4.5, th, 16)) == 0.0


def test_frustum_volume():
    th = math.radians(6)
    H = 5.0
    # Numerical integral of the N-gon area N a(z)^2 tan(pi/N).
    z = np.linspace(0, H, 200001)
    a = 4.5 + z * math.tan(th)
    vol = np.trapz(16 * a * a * math.tan(math.pi / 16), z)
    assert frustum_volume(H, 4.5, th, 16) == pytest.approx(vol, rel=1e-9)


def test_wall_stress_profile_conserves_the_force():
    th = math.radians(6)
    z = [-0.1, 0.2, 1.9, 2.5, 3.99, 4.0, 4.3]  # below 0 and at/above H go to the end bands
    f = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0]
    prof = wall_stress_profile(z, f, 4.5, th, 16, 4.0, 4)
    dz = 1.0
    areas = [float(frustum_side_area(dz, 4.5 + k * dz * math.tan(th), th, 16)) for k in range(4)]
    assert np.sum(prof * areas) == pytest.approx(sum(f))
    assert prof[0] * areas[0] == pytest.approx(3.0)
    assert prof[1] * areas[1] == pytest.approx(3.0)
    assert prof[3] * areas[3] == pytest.approx(5.0 + 6.0 + 7.0)


# ------------------------------------------------------------------ log parsing

COLUMNS = ["step", "v_T", "v_sp", "v_sc", "c_ket", "c_kerot", "c_top",
           "f_w0[1]", "f_w0[2]", "f_w0[3]", "f_w1[1]", "f_w1[2]", "f_w1[3]", "f_w1[7]", "f_w1[8]", "f_w1[9]"]


def header():
    return "    Step T sp sc ket kerot top w0[1] w0[2] w0[3] w1[1] w1[2] w1[3] w1[7] w1[8] w1[9]\n"


def row(step, T, fz_floor, fx_side, top=0.05, ref_x=0.045):
    sp = 1 + 1e-4 * T
    sc = 1 + 1e-3 * T
    return (f"{step} {T} {sp} {sc} 1e-6 2e-6 {top} 0 0 {fz_floor} {fx_side} 0.01 0.002 {ref_x * sc} 0 0\n")


def write_case(tmp_path):
    """A synthetic deck folder: meta.json of a 2-wall 'cone' (floor + one side segment
    with normal -x through (4.5, 0, 0)) and a log of two runs."""
    L = 0.01
    u = Units(length=L)
    meta = dict(units=u.to_dict(), dt_si=1e-4, columns=COLUMNS, reference_wall="w1",
                container=dict(type="cone", bottom_radius=4.5, opening_angle_deg=0.0, segments=16),
                walls=[dict(id="w0", role="bottom", normal=[0, 0, 1], point=[0, 0, 0]),
                       dict(id="w1", role="side", normal=[-1, 0, 0], point=[4.5, 0, 0])],
                log="log.liggghts")
    (tmp_path / "meta.json").write_text(json.dumps(meta))
    F = u.force
    log = ["LIGGGHTS (Version LIGGGHTS-PUBLIC 3.8.0)\n", "run 100\n", header(),
           row(0, 0, 0, 0),
           row(50, 0, -2 * F, 3 * F),
           row(100, 0, -4 * F, 5 * F),
           "Loop time of 0.1 on 1 procs for 100 steps with 3 atoms\n", "\n",
           "WARNING: something harmless\n", "run 100\n", header(),
           row(100, 0, -8 * F, 10 * F),  # setup row: LIGGGHTS 3.8.0 counts the mesh forces twice here
           row(150, 50, -4 * F, 6 * F, top=0.06),
           "WARNING: printed inside a block\n",
           row(200, 100, -4 * F, 7 * F, top=0.07),
           "Loop time of 0.1 on 1 procs for 100 steps with 3 atoms\n", 'print "ratchet-deck-complete"\n',
           "ratchet-deck-complete\n"]
    (tmp_path / "log.liggghts").write_text("".join(log))
    return meta, u


def test_thermo_blocks_drop_setup_rows(tmp_path):
    meta, u = write_case(tmp_path)
    raw = read_thermo_log(str(tmp_path / "log.liggghts"), COLUMNS)
    assert list(raw["step"]) == [50, 100, 150, 200]
    assert raw.loc[raw["step"] == 100, "f_w0[3]"].item() == pytest.approx(-4 * u.force)  # end of run 1


def test_parse_maps_to_engine_units(tmp_path):
    meta, u = write_case(tmp_path)
    ts = parse_run(str(tmp_path))
    for c in ["step", "t", "T", "s_p", "s_c", "kinetic_energy", "wall_force_side", "wall_force_bottom",
              "wall_force_total", "bed_height", "pressure"]:
        assert c in ts.columns
    r = ts[ts["step"] == 200].iloc[0]
    assert r["t"] == pytest.approx(200 * 1e-4 / u.time)
    assert r["wall_force_bottom"] == pytest.approx(4.0)
    assert r["wall_force_side"] == pytest.approx(7.0)  # -F . n with n = -x
    assert r["wall_force_total"] == pytest.approx(11.0)
    assert r["bed_height"] == pytest.approx(7.0)
    assert r["kinetic_energy"] == pytest.approx(3e-6 / u.energy)
    a0 = 1.1 * 4.5
    area = 16 * 2 * a0 * math.tan(math.pi / 16) * 7.0
    assert r["pressure"] == pytest.approx(7.0 / area)
    assert r["dem_s_c_mesh"] == pytest.approx(1.1)
    assert r["wall_force_side_tangential"] == pytest.approx(math.hypot(0.01, 0.002) / u.force)


def test_parse_errors_name_the_file(tmp_path):
    with pytest.raises(ParseError, match="meta.json"):
        parse_run(str(tmp_path))
    write_case(tmp_path)
    (tmp_path / "log.liggghts").write_text("ERROR: Illegal fix command\n")
    with pytest.raises(ParseError, match="log.liggghts: no thermo rows"):
        parse_run(str(tmp_path))
    (tmp_path / "log.liggghts").write_text(header().replace(" w1[9]", ""))
    with pytest.raises(ParseError, match="thermo header has 15 columns"):
        parse_run(str(tmp_path))


def test_read_local_dump(tmp_path):
    text = ("ITEM: TIMESTEP\n9\nITEM: NUMBER OF ENTRIES\n2\nITEM: BOX BOUNDS ff ff ff\n0 1\n0 1\n0 1\n"
            "ITEM: ENTRIES c_wl[1] c_wl[2] c_wl[3] c_wl[4] c_wl[5] c_wl[6] \n1 0 5 0.1 0 0\n0 1 2 0 0 0.2\n"
            "ITEM: TIMESTEP\n10\nITEM: NUMBER OF ENTRIES\n0\nITEM: BOX BOUNDS ff ff ff\n0 1\n0 1\n0 1\n"
            "ITEM: ENTRIES c_wl[1] c_wl[2] c_wl[3] c_wl[4] c_wl[5] c_wl[6] \n")
    p = tmp_path / "w.local"
    p.write_text(text)
    snaps = read_local_dump(str(p))
    assert [s for s, _ in snaps] == [9, 10]
    assert snaps[0][1].shape == (2, 6) and snaps[0][1].iloc[1, 5] == 0.2
    assert len(snaps[1][1]) == 0


# ------------------------------------------------------------------ comparison helpers

def test_cycle_peaks_use_windows_and_smoothing():
    t = np.arange(0, 30.0001, 0.1)
    p = np.where((t > 5) & (t < 15), np.sin((t - 5) / 10 * math.pi), 0.0) * 2.0
    p[200] = 10.0  # one spike in cycle 1
    df = pd.DataFrame(dict(t=t, pressure=p))
    pk = cycle_peaks(df, [(0, 0.0, 15.0), (1, 15.0, 30.0)], 0.0)
    assert pk["peak"].tolist() == pytest.approx([2.0, 10.0], rel=1e-3)
    sm = cycle_peaks(df, [(0, 0.0, 15.0), (1, 15.0, 30.0)], 1.0)
    assert sm["peak"][1] == pytest.approx(10.0 / 11)  # the spike averaged over 11 rows
    assert sm["t_peak"][0] == pytest.approx(10.0, abs=0.11)


def test_sphere_volume_below_and_bed_measures():
    r = 0.8
    assert sphere_volume_below(1.0, r, 1.0 + r) == pytest.approx(4 / 3 * math.pi * r ** 3)
    assert sphere_volume_below(1.0, r, 1.0) == pytest.approx(2 / 3 * math.pi * r ** 3)
    assert sphere_volume_below(1.0, r, 0.1) == 0.0
    sc = build_scene({"name": "b", "time": {"dt": 0.01, "duration": 1},
                      "container": {"type": "cone", "bottom_radius": 4.5, "segments": 16},
                      "particles": {"bodies": [{"shape": "sphere", "radius": 1.0, "position": [0, 0, 1]}]}},
                     "b.json")
    m = bed_measures([1.0, 3.0, 5.0], [1.0, 1.0, 1.0], sc)
    assert m["bed_height"] == 6.0
    assert m["phi_H"] == pytest.approx(3 * 4 / 3 * math.pi / frustum_volume(6.0, 4.5, 0.0, 16))
    assert m["phi_bulk"] == pytest.approx(2 * 4 / 3 * math.pi / frustum_volume(4.0, 4.5, 0.0, 16))
