"""Tests of scripts/analysis/cells.py and scripts/convection-cells on synthetic stage
fields: one toroidal cell counts as one, two side by side in r as two, a weak second band
below the share threshold as one; bad inputs are refused before anything is written.

Run with Debian's interpreter: /usr/bin/python3 -m pytest -q scripts/tests/test_cells.py
"""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd

SCRIPTS = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(SCRIPTS))

from analysis import cells, fields  # noqa: E402

NR, NZ, CELL = 20, 8, 1.0
R, H = NR * CELL, NZ * CELL


def write(folder: Path, radial_cells=1, c=0.2, second=None, cycles=2, noise=0.002, seed=0):
    """Cooling fields of the stream function psi = c sin(k pi r / R) sin(pi z / H), k =
    radial_cells (cells side by side in r, turning opposite ways), heating zero; with
    `second` a second term of that amplitude with k = 2 (a weaker second cell)."""
    rng = np.random.default_rng(seed)
    folder.mkdir(parents=True, exist_ok=True)
    iz, ir = np.meshgrid(np.arange(NZ), np.arange(NR), indexing="ij")
    r, z = (ir + 0.5) * CELL, (iz + 0.5) * CELL

    def velocity(amplitude, k):
        a = k * math.pi / R
        m = math.pi / H
        return (amplitude * m * np.sin(a * r) * np.cos(m * z), -amplitude * a * np.cos(a * r) * np.sin(m * z))

    ur, uz = velocity(c, radial_cells)
    if second is not None:
        sr, sz = velocity(second, 2)
        ur, uz = ur + sr, uz + sz
    rows = []
    for k in range(cycles):
        frame = pd.DataFrame({"cycle": k, "ir": ir.ravel(), "iz": iz.ravel(), "r": r.ravel(), "z": z.ravel(),
                              "count": 5})
        frame["ur_heating"] = 0.0
        frame["uz_heating"] = 0.0
        frame["ur_cooling"] = ur.ravel() + noise * rng.normal(size=ur.size)
        frame["uz_cooling"] = uz.ravel() + noise * rng.normal(size=uz.size)
        rows.append(frame)
    pd.concat(rows).to_csv(folder / fields.STAGE_FILE, index=False, float_format="%.6g")
    return folder


def count(folder: Path, cycles=(0,)) -> cells.CellCount:
    return cells.count_cells(fields.read_stage_fields(folder), cycles)


def test_one_toroidal_cell_is_one_cell(tmp_path):
    c = count(write(tmp_path / "one"))
    assert c.cells == 1
    assert len(c.bands) == 1 and c.bands[0].share == 1.0
    assert c.uz_sign_changes == 1
    assert abs(c.coherence) > 0.95


def test_the_profile_says_where_the_wall_band_begins_and_how_fast_the_middle_moves(tmp_path):
    # One cell: u_z = -c (pi/R) cos(pi r/R) sin(pi z/H), so u_z changes sign at r = R/2
    # and the middle's mean is that of the formula over the inner columns (equal weights).
    folder = write(tmp_path / "one", noise=0.0)
    one = count(folder)
    # The columns either side of R/2 hold u_z of equal size and opposite sign: the
    # interpolation lands on R/2 up to rounding (1e-9).
    assert math.isclose(one.uz_edge, 0.5, abs_tol=1e-9) and math.isclose(one.wall_band, R / 2, abs_tol=1e-9)
    r, z = (np.arange(NR) + 0.5) * CELL, (np.arange(NZ) + 0.5) * CELL
    uz = -0.2 * (math.pi / R) * np.cos(math.pi * r / R)[:, None] * np.sin(math.pi * z / H)[None, :]
    expected = uz.mean(axis=1)[r < cells.MIDDLE * R].mean()
    assert math.isclose(one.uz_middle, expected, rel_tol=1e-4)   # the fields are written to 6 digits
    # Summed over two cycles, the middle's u_z is still one cycle's: it is per cycle (the
    # two cycles' fields are the same numbers, so only rounding differs: 1e-9).
    assert math.isclose(count(folder, cycles=(0, 1)).uz_middle, one.uz_middle, rel_tol=1e-9)
    # Two cells: the last change going out is at 3R/4 (cos(2 pi r/R) = 0); the columns
    # either side are symmetric about it as above, up to the 6 written digits (1e-3 of R
    # is far above what they can move it).
    two = count(write(tmp_path / "two", radial_cells=2, noise=0.0))
    assert math.isclose(two.uz_edge, 0.75, abs_tol=1e-3)
    still = cells.CellCount(cycles=[0], radius=4.0, height=1.0, interior_cells=0, coherence=math.nan,
                            uz_profile=[0.1, 0.2, 0.1, 0.05], r=[0.5, 1.5, 2.5, 3.5])
    assert math.isnan(still.uz_edge) and math.isnan(still.wall_band)   # no change of sign


def test_two_cells_side_by_side_are_two(tmp_path):
    c = count(write(tmp_path / "two", radial_cells=2))
    assert c.cells == 2
    assert [b.circulation > 0 for b in c.bands] in ([True, False], [False, True])  # opposite senses
    assert c.bands[0].r_to == c.bands[1].r_from and abs(c.bands[0].r_to - R / 2) <= 2 * CELL
    assert c.uz_sign_changes == 2
    assert abs(c.coherence) < 0.5


def test_a_weak_second_band_is_not_a_cell(tmp_path):
    # An equal k = 2 term turns the outer columns the other way: a second band holding
    # about a fifth of the circulation (noise of that size splits single-cycle fields of
    # the one-cell paper bed, analysis/cells.py), below the threshold's share.
    c = count(write(tmp_path / "weak", c=0.2, second=0.2))
    shares = sorted((b.share for b in c.bands), reverse=True)
    assert len(shares) == 2 and 0.1 < shares[1] < cells.CELL_SHARE
    assert c.cells == 1


def test_bands_of_skips_empty_columns_and_sums_runs():
    bands = cells.bands_of(np.array([np.nan, -1.0, -2.0, 0.0, -1.0, 3.0, np.nan]), 1.0)
    assert [(b.r_from, b.r_to, b.circulation) for b in bands] == [(1.0, 5.0, -4.0), (5.0, 6.0, 3.0)]
    assert math.isclose(bands[0].share, 4 / 7) and math.isclose(bands[1].share, 3 / 7)


def run_cli(*args):
    return subprocess.run([sys.executable, str(SCRIPTS / "convection-cells"), *map(str, args)],
                          capture_output=True, text=True)


def test_the_command_writes_table_json_and_figure(tmp_path):
    one, two = write(tmp_path / "one"), write(tmp_path / "two", radial_cells=2)
    out = tmp_path / "out"
    done = run_cli(f"narrow={one}", f"wide={two}", "--cycles", 0, 1, "--out", out)
    assert done.returncode == 0, done.stderr
    data = json.loads((out / "cells.json").read_text())
    assert data["cycles"] == [0, 1]
    assert data["runs"]["narrow"]["cells"] == 1 and data["runs"]["wide"]["cells"] == 2
    table = (out / "cells.md").read_text()
    assert "| narrow |" in table and "| wide |" in table
    # 0.05: a column is R/20 wide, and the fields' noise (0.002 against u_z of about 0.03
    # near the edge's columns) moves the crossing by well under one.
    assert abs(data["runs"]["narrow"]["uz_edge"] - 0.5) < 0.05 and "| wall band |" in table
    assert (out / "figures" / "cells.png").stat().st_size > 0
    assert "wide 2 cell(s)" in (out / "figures" / "cells.txt").read_text()
    assert "Each cycle alone" not in table and "each_cycle" not in data   # only when asked


def test_each_cycle_alone_is_counted_on_request(tmp_path):
    # A bed whose cycle 0 turns as one cell and cycle 1 as two: the per-cycle table must
    # tell them apart, whatever the sum of the two shows.
    one, two = write(tmp_path / "one", cycles=1), write(tmp_path / "two", radial_cells=2, cycles=1)
    mixed = tmp_path / "mixed"
    mixed.mkdir()
    frames = [pd.read_csv(one / fields.STAGE_FILE), pd.read_csv(two / fields.STAGE_FILE).assign(cycle=1)]
    pd.concat(frames).to_csv(mixed / fields.STAGE_FILE, index=False)
    out = tmp_path / "out"
    done = run_cli(f"bed={mixed}", "--cycles", 0, 1, "--each-cycle", "--out", out)
    assert done.returncode == 0, done.stderr
    data = json.loads((out / "cells.json").read_text())
    per_cycle = data["each_cycle"]["bed"]
    assert per_cycle["0"]["cells"] == 1 and per_cycle["1"]["cells"] == 2
    assert per_cycle["0"]["cycles"] == [0] and per_cycle["1"]["cycles"] == [1]
    table = (out / "cells.md").read_text()
    alone = table.split("## Each cycle alone")[1]
    assert "| bed, 0 |" in alone and "| bed, 1 |" in alone
    assert "| bed |" in table.split("## Each cycle alone")[0]   # the summed row stays first


def test_bad_inputs_are_refused_before_anything_is_written(tmp_path):
    one = write(tmp_path / "one", cycles=2)
    out = tmp_path / "out"
    missing = run_cli(tmp_path / "nowhere", "--out", out)
    assert missing.returncode == 2
    assert str(tmp_path / "nowhere" / fields.STAGE_FILE) in missing.stderr
    cycle = run_cli(one, "--cycles", 5, "--out", out)
    assert cycle.returncode == 2
    assert "--cycles" in cycle.stderr and "[5]" in cycle.stderr
    (tmp_path / "bad").mkdir()
    (tmp_path / "bad" / fields.STAGE_FILE).write_text("cycle,ir\n0,1\n")
    broken = run_cli(tmp_path / "bad", "--out", out)
    assert broken.returncode == 2 and "missing column" in broken.stderr
    assert not out.exists()
