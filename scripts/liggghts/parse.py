#!/usr/bin/python3
"""LIGGGHTS log of a translated deck -> CSV with the engine's timeseries.csv columns.

    /usr/bin/python3 scripts/liggghts/parse.py DECKDIR [--out DECKDIR/timeseries.csv]

Reads DECKDIR/meta.json (written by translate.py) and DECKDIR/log.liggghts (thermo
rows of every `run`), and writes the columns that both methods have, in the engine's
dimensionless units (scripts/liggghts/units.py; docs/liggghts.md):

  step               DEM step (not the engine's step: the time steps differ)
  t                  step dt_DEM / sqrt(L / g0)
  T, s_p, s_c        the deck's thermal variables (T as in the scene)
  kinetic_energy     (translational + rotational, compute ke + erotate/sphere) / (M g0 L)
  wall_force_side    sum over the side segments of the normal force -F_k . n_k, / (M g0)
                     (F_k = f_ID[1..3] of mesh/surface/stress: force of the particles on
                     mesh k; n_k the inward normal, so a pushing bed gives a positive value)
  wall_force_bottom  -F_floor . (0, 0, 1) / (M g0)
  wall_force_total   the same sum over every wall (side, floor, planes)
  bed_height         max over particles of z + radius, / L, never below 0
  pressure           wall_force_side / wetted frustum area (the engine's formula:
                     N (a0 + a1) tan(pi/N) H / cos(theta), a0 = s_c r_c, a1 = a0 + H tan(theta));
                     0 for a `planes` container

and two DEM-only columns: `dem_s_c_mesh` (container scale measured from the moved
reference point of the first moving wall: (n . x_ref) / (n . p), NaN without one) and
`wall_force_side_tangential` (magnitude of the summed in-plane side forces, force units).
M = rho_SI L^3 / rho_scene, so the force unit M g0 equals the engine's rho g r_max^3.
"""

import argparse
import json
import math
import os
import sys

if __package__ in (None, ""):
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    __package__ = "liggghts"  # noqa: A001

import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

from common.fsutil import write_csv_atomic  # noqa: E402

from .translate import COMPLETE_MARK  # noqa: E402
from .units import Units, frustum_side_area  # noqa: E402


class ParseError(ValueError):
    """A log or meta file that cannot be read; the message names the file."""


ENGINE_COLUMNS = ["step", "t", "T", "s_p", "s_c", "kinetic_energy", "wall_force_side", "wall_force_bottom",
                  "wall_force_total", "bed_height", "pressure"]


def read_meta(deckdir):
    path = os.path.join(deckdir, "meta.json")
    try:
        with open(path) as fh:
            meta = json.load(fh)
    except OSError as e:
        raise ParseError(f"{path}: cannot read ({e.strerror}); was the deck written by translate.py?") from None
    except ValueError as e:
        raise ParseError(f"{path}: not valid JSON: {e}") from None
    for key in ("columns", "units", "walls", "dt_si", "container"):
        if key not in meta:
            raise ParseError(f"{path}: field '{key}' is missing")
    return meta


def read_thermo_log(path, columns):
    """Thermo rows of every run in a LIGGGHTS/LAMMPS log as a DataFrame with the given
    column names (the deck's thermo_style keywords). A block starts after a header line
    whose first word is `Step` and ends at `Loop time of`.

    The first row of every block (the run's setup) is dropped: in LIGGGHTS 3.8.0 the
    mesh/surface/stress forces of that row count the setup force evaluation twice (the
    floor carries twice the weight of a bed at rest there). The step at a run boundary is
    therefore the last row of the earlier run, and the row of step 0 is not reported."""
    try:
        with open(path, errors="replace") as fh:
            lines = fh.readlines()
    except OSError as e:
        raise ParseError(f"{path}: cannot read the LIGGGHTS log ({e.strerror})") from None
    rows = []
    in_block = False
    first_of_block = False
    n = len(columns)
    for lineno, line in enumerate(lines, start=1):
        words = line.split()
        if not words:
            continue
        if words[0] == "Step":
            if len(words) != n:
                raise ParseError(f"{path}:{lineno}: thermo header has {len(words)} columns, meta.json lists {n}")
            in_block = True
            first_of_block = True
            continue
        if not in_block:
            continue
        if line.startswith("Loop time of"):
            in_block = False
            continue
        if len(words) != n or not _is_number(words[0]):
            # A warning printed in the middle of a block, or a cut last line.
            continue
        try:
            values = [float(w) for w in words]
        except ValueError:
            continue
        if first_of_block:
            first_of_block = False
            continue
        rows.append(values)
    if not rows:
        raise ParseError(f"{path}: no thermo rows found (did LIGGGHTS run? see the end of the log)")
    df = pd.DataFrame(rows, columns=columns)
    df = df.drop_duplicates(subset="step", keep="first").sort_values("step").reset_index(drop=True)
    return df


def _is_number(w):
    try:
        float(w)
        return True
    except ValueError:
        return False


def log_completed(path):
    """True when the log holds the line that the deck prints after its last run."""
    try:
        with open(path, errors="replace") as fh:
            tail = fh.read()[-4000:]
    except OSError:
        return False
    return any(line.strip() == COMPLETE_MARK for line in tail.splitlines())


def to_engine_units(raw, meta):
    """Thermo rows (SI) -> the engine's timeseries columns (dimensionless)."""
    u = Units.from_dict(meta["units"])
    out = pd.DataFrame()
    out["step"] = raw["step"].astype(np.int64)
    out["t"] = raw["step"] * meta["dt_si"] / u.time
    out["T"] = raw["v_T"]
    out["s_p"] = raw["v_sp"]
    out["s_c"] = raw["v_sc"]
    out["kinetic_energy"] = (raw["c_ket"] + raw["c_kerot"]) / u.energy
    side = np.zeros(len(raw))
    bottom = np.zeros(len(raw))
    total = np.zeros(len(raw))
    side_vec = np.zeros((len(raw), 3))
    for w in meta["walls"]:
        F = np.stack([raw[f"f_{w['id']}[{i}]"].to_numpy() for i in (1, 2, 3)], axis=1)
        nrm = np.asarray(w["normal"], dtype=float)
        fn = -(F @ nrm)
        total += fn
        if w["role"] == "side":
            side += fn
            side_vec += F + np.outer(fn, nrm)  # in-plane part F - (F . n) n
        elif w["role"] == "bottom":
            bottom += fn
    out["wall_force_side"] = side / u.force
    out["wall_force_bottom"] = bottom / u.force
    out["wall_force_total"] = total / u.force
    out["bed_height"] = np.maximum(raw["c_top"].to_numpy() / u.length, 0.0)
    c = meta["container"]
    if c["type"] == "cone":
        area = frustum_side_area(out["bed_height"].to_numpy(), c["bottom_radius"],
                                 math.radians(c["opening_angle_deg"]), c["segments"], out["s_c"].to_numpy())
        with np.errstate(divide="ignore", invalid="ignore"):
            out["pressure"] = np.where(area > 0.0, out["wall_force_side"].to_numpy() / area, 0.0)
    else:
        out["pressure"] = 0.0
    ref = meta.get("reference_wall")
    if ref:
        w = next(w for w in meta["walls"] if w["id"] == ref)
        x = np.stack([raw[f"f_{ref}[{i}]"].to_numpy() for i in (7, 8, 9)], axis=1) / u.length
        nrm = np.asarray(w["normal"], dtype=float)
        d0 = float(np.dot(nrm, w["point"]))
        out["dem_s_c_mesh"] = (x @ nrm) / d0 if d0 != 0.0 else np.nan
    else:
        out["dem_s_c_mesh"] = np.nan
    out["wall_force_side_tangential"] = np.linalg.norm(side_vec, axis=1) / u.force
    return out


def parse_run(deckdir, log_name=None):
    """meta.json + log -> DataFrame in engine units."""
    meta = read_meta(deckdir)
    log = os.path.join(deckdir, log_name or meta.get("log", "log.liggghts"))
    raw = read_thermo_log(log, meta["columns"])
    return to_engine_units(raw, meta)


def read_dump(path, meta=None):
    """A write_dump snapshot (id type x y z vx vy vz radius, SI) -> DataFrame; with
    `meta`, positions and radii in engine length units."""
    try:
        with open(path) as fh:
            lines = fh.readlines()
    except OSError as e:
        raise ParseError(f"{path}: cannot read the dump ({e.strerror})") from None
    try:
        i = next(k for k, l in enumerate(lines) if l.startswith("ITEM: ATOMS"))
    except StopIteration:
        raise ParseError(f"{path}: no 'ITEM: ATOMS' section") from None
    cols = lines[i].split()[2:]
    data = [l.split() for l in lines[i + 1:] if l.strip()]
    df = pd.DataFrame(data, columns=cols).astype(float)
    if meta is not None:
        L = meta["units"]["length"]
        for c in ("x", "y", "z", "radius"):
            df[c] = df[c] / L
    return df


def read_local_dump(path):
    """A LAMMPS `dump local` file -> list of (step, DataFrame of its entries)."""
    try:
        with open(path) as fh:
            lines = fh.read().splitlines()
    except OSError as e:
        raise ParseError(f"{path}: cannot read the local dump ({e.strerror})") from None
    out = []
    i = 0
    while i < len(lines):
        if lines[i].startswith("ITEM: TIMESTEP"):
            step = int(lines[i + 1])
            n = int(lines[i + 3])
            j = i + 4
            while not lines[j].startswith("ITEM: ENTRIES"):
                j += 1
            cols = lines[j].split()[2:]
            data = [l.split() for l in lines[j + 1:j + 1 + n]]
            out.append((step, pd.DataFrame(data, columns=cols, dtype=float) if n else pd.DataFrame(columns=cols)))
            i = j + 1 + n
        else:
            i += 1
    if not out:
        raise ParseError(f"{path}: no snapshot in the local dump")
    return out


def wall_stress_profile(z, fn, bottom_apothem, theta, segments, height, bins):
    """The engine's wall_stress_profile (observe/wall_pressure.hpp): [0, height] cut into
    `bins` bands of dz = height / bins; band k gets the normal force of the side
    contacts with k dz <= z < (k+1) dz (contacts outside go to the nearest band),
    divided by its lateral area, the frustum area of apothem a0 + k dz tan(theta) and
    height dz."""
    z = np.asarray(z, dtype=float)
    fn = np.asarray(fn, dtype=float)
    dz = height / bins
    k = np.clip(np.floor(z / dz).astype(int), 0, bins - 1) if len(z) else np.zeros(0, dtype=int)
    force = np.bincount(k, weights=fn, minlength=bins)[:bins]
    area = np.array([float(frustum_side_area(dz, bottom_apothem + b * dz * math.tan(theta), theta, segments))
                     for b in range(bins)])
    return force / area


def dem_wall_profile(deckdir, meta, wall_dump, bins):
    """Side-wall stress profile of the DEM at the end of a stage that has a wall dump:
    DataFrame(bin, z_lo, z_hi, wall_stress) in engine units, and the bed height used.
    The contact height is the particle centre moved by its radius towards the wall
    (z - r n_z); the force is the wall's force on the particle along the inward normal."""
    u = Units.from_dict(meta["units"])
    snaps = read_local_dump(os.path.join(deckdir, wall_dump["file"]))
    step, ent = next(((s, e) for s, e in snaps if s == wall_dump["step"]), snaps[-1])
    dump = next(d for d in meta["dumps"] if d["stage"] == wall_dump["stage"])
    parts = read_dump(os.path.join(deckdir, dump["file"]), meta).set_index("id")
    fixed = set(meta.get("fixed_ids", []))
    mobile = parts[~parts.index.isin(fixed)]
    H = float((mobile["z"] + mobile["radius"]).max())
    st = meta["stages"][wall_dump["stage"]]
    s_c = 1.0 + meta.get("alpha_c_used", 0.0) * (st["T_end"] - (meta["thermal"] or {}).get("T0", 0.0))
    c = meta["container"]
    theta = math.radians(c["opening_angle_deg"])
    zs, fns = [], []
    if len(ent):
        cols = list(ent.columns)
        for _, row in ent.iterrows():
            w = meta["walls"][int(row[cols[0]])]
            if w["role"] != "side":
                continue
            nrm = np.asarray(w["normal"], dtype=float)
            f = np.array([row[cols[3]], row[cols[4]], row[cols[5]]]) / u.force
            p = parts.loc[int(row[cols[2]])]
            zs.append(p["z"] - p["radius"] * nrm[2])
            fns.append(float(f @ nrm))
    prof = wall_stress_profile(zs, fns, s_c * c["bottom_radius"], theta, c["segments"], H, bins)
    df = pd.DataFrame(dict(bin=np.arange(bins), z_lo=H * np.arange(bins) / bins,
                           z_hi=H * (np.arange(bins) + 1) / bins, wall_stress=prof))
    return df, H, float(np.sum(fns))


def main(argv=None):
    ap = argparse.ArgumentParser(description="Parse the LIGGGHTS log of a translated deck into a timeseries CSV.")
    ap.add_argument("deckdir", help="folder written by translate.py and run by LIGGGHTS")
    ap.add_argument("--out", help="CSV to write (default DECKDIR/timeseries.csv)")
    ap.add_argument("--log", help="log file name inside DECKDIR (default from meta.json)")
    args = ap.parse_args(argv)
    try:
        df = parse_run(args.deckdir, args.log)
    except ParseError as e:
        print(f"parse: error: {e}", file=sys.stderr)
        return 2
    out = args.out or os.path.join(args.deckdir, "timeseries.csv")
    write_csv_atomic(df, out)
    print(f"parse: {len(df)} rows -> {out}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
