"""Runs one scene with the NSCD engine and with LIGGGHTS (soft-sphere DEM) and compares
them: per-cycle peak wall pressures, the settled (static) bed, and, over several Young's
moduli, the trend of the DEM peak pressure towards the rigid (NSCD) limit.

Entry point: scripts/compare-methods (see `scripts/compare-methods --help` and
docs/liggghts.md).
"""

import argparse
import json
import math
import os
import shutil
import subprocess
import sys
import time

import numpy as np
import pandas as pd

from common.fsutil import save_figure_atomic, write_atomic, write_csv_atomic
from common.jsonsafe import dumps
from common import paths  # noqa: F401  (puts this checkout's package `ratchet` on sys.path)
from ratchet import ProgramNotFound, command, program

from .parse import ParseError, dem_wall_profile, log_completed, parse_run, read_dump
from .scene import EngineError, SceneError, load_scene
from .translate import DECK, LOG, add_dem_arguments, options_from_args, translate
from .units import Units, frustum_volume

class CompareError(RuntimeError):
    pass


def say(msg):
    print(f"compare-methods: {msg}", file=sys.stderr, flush=True)


def e_label(E):
    return f"E{E:.3g}".replace("+", "")


# ----------------------------------------------------------------------------- runs

def engine_snapshot_every(scene):
    """bodies_every that puts a snapshot at the end of the settling stage."""
    if scene.thermal is not None and scene.thermal.start_time > 0.0:
        return max(1, int(round(scene.thermal.start_time / scene.dt)))
    return 0


def engine_command(ratchet, scene_path, outdir, scene, extra_sets=()):
    cmd = command("run", scene_path, "--out", outdir, ratchet=ratchet)
    k = engine_snapshot_every(scene)
    if k > 0:
        cmd += ["--set", f"outputs.bodies_every={k}"]
    for s in extra_sets:
        cmd += ["--set", s]
    return cmd


def engine_check_scene(ratchet, scene_path, extra_sets=()):
    """`ratchet run --explain`: the engine's own parser checks the scene (it is the
    authority on the format). Returns (ok, message)."""
    cmd = command("run", "--explain", scene_path, ratchet=ratchet)
    for s in extra_sets:
        cmd += ["--set", s]
    r = subprocess.run(cmd, capture_output=True, text=True)
    return r.returncode == 0, (r.stderr or r.stdout).strip()


def check_generated_positions(engine_dir, scene):
    """The translation takes its particles from `ratchet bodies` (scene.py); the run's
    first bodies.csv rows must hold exactly the same centres (same scene, same build)."""
    b = pd.read_csv(os.path.join(engine_dir, "bodies.csv"), float_precision="round_trip")
    b0 = b[b["step"] == 0].sort_values("id")
    mine = np.array([s.position for s in scene.spheres])
    theirs = b0[["x", "y", "z"]].to_numpy()
    if mine.shape != theirs.shape or not np.array_equal(mine, theirs):
        worst = float(np.max(np.abs(mine - theirs))) if mine.shape == theirs.shape else float("nan")
        raise CompareError(
            f"{engine_dir}/bodies.csv: the run's initial particle centres differ from the ones `ratchet bodies` "
            f"gave the translation ({len(theirs)} vs {len(mine)} bodies, largest difference {worst:.3g}): the "
            "engine run and the bodies file were made from different scenes or by different builds")


def engine_complete(outdir):
    try:
        with open(os.path.join(outdir, "run.json")) as fh:
            return json.load(fh).get("status") == "completed"
    except (OSError, ValueError):
        return False


def start_engine(ratchet, scene_path, scene, outdir, threads=None, extra_sets=()):
    cmd = engine_command(ratchet, scene_path, outdir, scene, extra_sets)
    env = dict(os.environ)
    if threads:
        env["OMP_NUM_THREADS"] = str(threads)
    say("engine: " + " ".join(cmd))
    log = open(os.path.join(os.path.dirname(outdir) or ".", "engine.stderr.txt"), "w")
    return subprocess.Popen(cmd + ["--quiet"], stdout=log, stderr=subprocess.STDOUT, env=env), log, time.monotonic()


def finish_engine(proc, log, t0, outdir):
    rc = proc.wait()
    seconds = time.monotonic() - t0
    log.close()
    if rc != 0 or not engine_complete(outdir):
        with open(log.name) as fh:
            tail = fh.read()[-2000:]
        raise CompareError(f"engine run failed (exit {rc}); its messages ({log.name}):\n{tail}")
    return seconds


def liggghts_command(mpi):
    exe = shutil.which("liggghts") or "/usr/bin/liggghts"
    if mpi and mpi > 1:
        mpirun = shutil.which("mpirun") or "mpirun"
        cmd = [mpirun, "-n", str(mpi)]
        if hasattr(os, "geteuid") and os.geteuid() == 0:
            cmd.append("--allow-run-as-root")
        return cmd + [exe]
    return [exe]


def run_dem(scene, deckdir, opts, mpi=None, reuse=False):
    """Translates, runs LIGGGHTS in `deckdir`, parses; returns (timeseries, meta, seconds)."""
    meta = translate(scene, deckdir, opts)
    log = os.path.join(deckdir, LOG)
    if reuse and log_completed(log):
        say(f"LIGGGHTS {deckdir}: reusing the finished log")
        seconds = float("nan")
        try:
            with open(os.path.join(deckdir, "wall_seconds.txt")) as fh:
                seconds = float(fh.read())
        except (OSError, ValueError):
            pass
    else:
        cmd = liggghts_command(mpi) + ["-in", DECK, "-log", LOG]
        say(f"LIGGGHTS: {' '.join(cmd)} (in {deckdir}; {meta['total_steps']} steps of {meta['dt_si']:.3g} s, "
            f"E = {opts.youngs_modulus:g} Pa)")
        t0 = time.monotonic()
        with open(os.path.join(deckdir, "screen.txt"), "w") as screen:
            rc = subprocess.call(cmd, cwd=deckdir, stdout=screen, stderr=subprocess.STDOUT)
        seconds = time.monotonic() - t0
        if rc != 0 or not log_completed(log):
            with open(os.path.join(deckdir, "screen.txt"), errors="replace") as fh:
                lines = fh.read().splitlines()
            errs = [l for l in lines if "ERROR" in l] or lines[-15:]
            raise CompareError(f"LIGGGHTS failed (exit {rc}) in {deckdir}:\n" + "\n".join(errs[-15:]))
        write_atomic(os.path.join(deckdir, "wall_seconds.txt"), f"{seconds!r}\n")
        say(f"LIGGGHTS finished in {seconds:.1f} s")
    ts = parse_run(deckdir)
    write_csv_atomic(ts, os.path.join(deckdir, "timeseries.csv"))
    return ts, meta, seconds


# ------------------------------------------------------------------------- analysis

def smooth(df, column, window):
    """Centred moving average over `window` time units (rows are about evenly spaced)."""
    if window <= 0 or len(df) < 3:
        return df[column].to_numpy()
    dt = np.median(np.diff(df["t"].to_numpy()))
    n = 2 * int(round(0.5 * window / dt)) + 1 if dt > 0 else 1  # odd: centred
    return df[column].rolling(n, center=True, min_periods=1).mean().to_numpy()


def cycle_peaks(df, windows, window_smooth):
    """Peak of the smoothed pressure in each cycle window: DataFrame(cycle, t_begin, t_end, peak, t_peak)."""
    p = smooth(df, "pressure", window_smooth)
    t = df["t"].to_numpy()
    rows = []
    for c, a, b in windows:
        m = (t >= a) & (t <= b)
        if not m.any():
            rows.append(dict(cycle=c, t_begin=a, t_end=b, peak=np.nan, t_peak=np.nan))
            continue
        i = np.argmax(np.where(m, p, -np.inf))
        rows.append(dict(cycle=c, t_begin=a, t_end=b, peak=p[i], t_peak=t[i]))
    return pd.DataFrame(rows, columns=["cycle", "t_begin", "t_end", "peak", "t_peak"])


def window_mean(df, column, a, b):
    m = (df["t"] >= a) & (df["t"] <= b)
    if not m.any():
        return float("nan")
    return float(df.loc[m, column].mean())


def sphere_volume_below(z, r, c):
    """Volume of the part of each sphere (centre height z, radius r) below the plane z = c."""
    z, r = np.asarray(z, float), np.asarray(r, float)
    h = np.clip(c - (z - r), 0.0, 2.0 * r)
    return math.pi * h * h * (3.0 * r - h) / 3.0


def bed_measures(z, r, scene, s_c=1.0, slab=2.0):
    """Packing measures of a bed in a cone: bed height H = max(z + r); phi_H = sphere
    volume / frustum volume up to H; phi_bulk = sphere volume below H - 2 r_max / frustum
    volume up to there (away from the loose top layer); profile = phi in slabs of `slab`."""
    z, r = np.asarray(z, float), np.asarray(r, float)
    H = float(np.max(z + r))
    th = scene.theta
    vol = float(np.sum(4.0 / 3.0 * math.pi * r ** 3))
    out = dict(bed_height=H, phi_H=vol / frustum_volume(H, scene.bottom_radius, th, scene.segments, s_c))
    r_max = float(np.max(r))
    cut = H - 2.0 * r_max
    if cut > 0:
        out["phi_bulk"] = float(np.sum(sphere_volume_below(z, r, cut))) / frustum_volume(
            cut, scene.bottom_radius, th, scene.segments, s_c)
    else:
        out["phi_bulk"] = float("nan")
    prof = []
    a = 0.0
    while a + slab <= cut + 1e-9:
        v = np.sum(sphere_volume_below(z, r, a + slab) - sphere_volume_below(z, r, a))
        fv = frustum_volume(a + slab, scene.bottom_radius, th, scene.segments, s_c) - frustum_volume(
            a, scene.bottom_radius, th, scene.segments, s_c)
        prof.append((a, a + slab, float(v / fv)))
        a += slab
    out["profile"] = prof
    return out


def engine_settled_bed(engine_dir, scene):
    """(z, radius) of the mobile bodies at the end of the settling stage (bodies.csv)."""
    k = engine_snapshot_every(scene)
    b = pd.read_csv(os.path.join(engine_dir, "bodies.csv"), float_precision="round_trip")
    snap = b[b["step"] == k].sort_values("id")
    if snap.empty:
        raise CompareError(f"{engine_dir}/bodies.csv: no snapshot at step {k} (end of settling)")
    radii = np.array([sp.radius for sp in scene.spheres])
    mobile = np.array([not sp.fixed for sp in scene.spheres])
    ids = snap["id"].to_numpy()
    return snap["z"].to_numpy()[mobile[ids]], (radii[ids] * snap["scale"].to_numpy())[mobile[ids]]


def dem_settled_bed(deckdir, meta):
    d = next((x for x in meta["dumps"] if meta["stages"][x["stage"]]["kind"] == "settle"), None)
    if d is None:
        raise CompareError(f"{deckdir}: the deck has no settling stage")
    snap = read_dump(os.path.join(deckdir, d["file"]), meta)
    return snap["z"].to_numpy(), snap["radius"].to_numpy()


def static_measures(ts, z, r, scene, t_end, average):
    """Settled-bed numbers at the end of settling (time averages over [t_end - average, t_end])."""
    a = t_end - average
    m = bed_measures(z, r, scene)
    g = math.sqrt(sum(c * c for c in scene.gravity)) if scene.effects["gravity"] else 0.0
    weight = scene.density * float(np.sum(4.0 / 3.0 * math.pi * np.asarray(r) ** 3)) * g
    side = window_mean(ts, "wall_force_side", a, t_end)
    bottom = window_mean(ts, "wall_force_bottom", a, t_end)
    return dict(
        bed_height=m["bed_height"], phi_H=m["phi_H"], phi_bulk=m["phi_bulk"],
        pressure=window_mean(ts, "pressure", a, t_end), wall_force_side=side, wall_force_bottom=bottom,
        bottom_fraction=bottom / weight if weight > 0 else float("nan"),
        kinetic_energy=window_mean(ts, "kinetic_energy", a, t_end), weight=weight, profile=m["profile"])


def rel(a, b):
    return (a - b) / abs(b) if b not in (0.0,) and np.isfinite(b) else float("nan")


# ---------------------------------------------------------------------------- plots

def plot_comparison(path, scene, engine_ts, engine_peaks, dem, window_smooth):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (ax, axT) = plt.subplots(2, 1, figsize=(9, 6.5), sharex=True, gridspec_kw=dict(height_ratios=[3, 1]))
    for c, a, b in scene.cycle_windows():
        ax.axvspan(a, b, color="0.93" if c % 2 == 0 else "0.97", zorder=0)
    ax.plot(engine_ts["t"], engine_ts["pressure"], color="k", lw=0.4, alpha=0.35)
    ax.plot(engine_ts["t"], smooth(engine_ts, "pressure", window_smooth), color="k", lw=1.6, label="NSCD (ratchet)")
    ax.plot(engine_peaks["t_peak"], engine_peaks["peak"], "o", color="k", ms=6)
    colors = plt.cm.viridis(np.linspace(0.15, 0.85, max(1, len(dem))))
    for (E, d), col in zip(sorted(dem.items()), colors):
        ax.plot(d["ts"]["t"], smooth(d["ts"], "pressure", window_smooth), color=col, lw=1.2,
                label=f"DEM (LIGGGHTS), E = {E:.3g} Pa")
        ax.plot(d["peaks"]["t_peak"], d["peaks"]["peak"], "o", color=col, ms=5)
    ax.set_ylabel("wall pressure P  [ρ g r_max]")
    ax.set_title(f"{scene.name}: side-wall pressure (moving average {window_smooth:g}); dots = peak per cycle")
    ax.legend(fontsize=8, loc="upper left")
    axT.plot(engine_ts["t"], engine_ts["T"], color="tab:red")
    axT.set_ylabel("T")
    axT.set_xlabel("t  [sqrt(r_max / g)]")
    fig.tight_layout()
    save_figure_atomic(fig, path)
    plt.close(fig)


def plot_stiffness(path, scene, stiff, nscd_mean, nscd_peaks, units):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    ax.plot(stiff["E"], stiff["dem_mean_peak_pressure"], "o-", color="tab:blue", label="DEM (LIGGGHTS), mean peak")
    cyc_cols = [c for c in stiff.columns if c.startswith("dem_peak_cycle")]
    for c in cyc_cols:
        ax.plot(stiff["E"], stiff[c], ".", color="tab:blue", alpha=0.5)
    ax.axhline(nscd_mean, color="k", lw=1.5, label="NSCD (rigid), mean peak")
    if len(nscd_peaks) > 1:
        ax.axhspan(float(np.nanmin(nscd_peaks)), float(np.nanmax(nscd_peaks)), color="k", alpha=0.08)
    ax.set_xscale("log")
    ax.set_xlabel(f"Young's modulus E  [Pa]  (r_max = {units.length:g} m, ρ = {units.density_si:g} kg/m³)")
    # Dimensionless stiffness E / (rho g r_max): the parameter that carries over to other units.
    scale = units.density_si * units.g0 * units.length
    top = ax.secondary_xaxis("top", functions=(lambda e: e / scale, lambda k: k * scale))
    top.set_xlabel("E / (ρ g r_max)")
    ax.set_ylabel("peak wall pressure  [ρ g r_max]")
    ax.set_title(f"{scene.name}: peak pressure vs stiffness")
    ax.legend(fontsize=8)
    fig.tight_layout()
    save_figure_atomic(fig, path)
    plt.close(fig)


# ----------------------------------------------------------------------------- main

def parse_args(argv):
    ap = argparse.ArgumentParser(
        prog="compare-methods",
        description="Run a sphere scene with the NSCD engine and with LIGGGHTS and compare them.")
    ap.add_argument("scene", help="scene JSON (spheres only)")
    ap.add_argument("--out", required=True, help="output folder")
    add_dem_arguments(ap, multiple_E=True)
    ap.add_argument("--mpi", type=int, default=0, metavar="N", help="run LIGGGHTS with mpirun -n N")
    ap.add_argument("--smooth", type=float, default=0.5,
                    help="moving-average window (engine time units) applied to both pressures before "
                         "taking peaks (default 0.5)")
    ap.add_argument("--static-average", type=float, default=2.0,
                    help="time window at the end of settling over which static forces are averaged (default 2)")
    ap.add_argument("--profile-bins", type=int, default=4,
                    help="bands of the side-wall stress profile (DEM at the end of settling and of each cooling; "
                         "the engine averaged over --static-average before cycling and over each cold hold); "
                         "0: none (default 4)")
    ap.add_argument("--parallel", action="store_true",
                    help="run the engine (1 OpenMP thread) at the same time as the LIGGGHTS runs")
    ap.add_argument("--reuse", action="store_true",
                    help="reuse finished runs found in --out instead of running again")
    return ap.parse_args(argv)


def main(argv=None):
    args = parse_args(argv)
    try:
        return _main(args)
    except (SceneError, ParseError, CompareError, EngineError) as e:
        print(f"compare-methods: error: {e}", file=sys.stderr)
        return 2 if isinstance(e, SceneError) else 1


def _main(args):
    try:
        ratchet = str(program())  # the build's: $RATCHET_BIN, else <$RATCHET_BUILD_DIR or build>/reference_engine/ratchet
    except ProgramNotFound as e:
        raise CompareError(f"engine binary not found or not executable: {e.filename} (set RATCHET_BIN)") from None
    scene = load_scene(args.scene, ratchet)  # the spheres: `ratchet bodies`
    out = args.out
    os.makedirs(out, exist_ok=True)
    engine_dir = os.path.join(out, "engine")
    Es = list(dict.fromkeys(args.E))
    timings = []

    ok, msg = engine_check_scene(ratchet, os.path.abspath(args.scene))
    if not ok:
        raise CompareError(f"the engine rejects the scene: {msg}")
    extra_sets = []
    if args.profile_bins > 0 and scene.container_type == "cone" and scene.thermal is not None:
        # The engine's profile of the settled bed is averaged over the same window as the
        # static forces (NSCD wall impulses are intermittent; one step is mostly zeros).
        probe = [f"outputs.wall_profile_bins={args.profile_bins}",
                 f"outputs.settled_profile_time={args.static_average:g}"]
        if engine_check_scene(ratchet, os.path.abspath(args.scene), probe)[0]:
            extra_sets.extend(probe)
        else:
            say("this engine build has no outputs.wall_profile_bins / settled_profile_time: wall profiles from "
                "the DEM only")

    proc = None
    if args.reuse and engine_complete(engine_dir):
        say(f"engine: reusing {engine_dir}")
        with open(os.path.join(engine_dir, "run.json")) as fh:
            timings.append(dict(method="nscd", E=np.nan, wall_seconds=json.load(fh).get("wall_seconds", np.nan),
                                steps=scene.steps, dt=scene.dt, note="reused"))
    else:
        proc, elog, t0 = start_engine(ratchet, os.path.abspath(args.scene), scene, engine_dir,
                                      threads=1 if args.parallel else None, extra_sets=extra_sets)
        if not args.parallel:
            sec = finish_engine(proc, elog, t0, engine_dir)
            say(f"engine finished in {sec:.1f} s")
            timings.append(dict(method="nscd", E=np.nan, wall_seconds=sec, steps=scene.steps, dt=scene.dt,
                                note=""))
            proc = None

    dem = {}
    for E in Es:
        vals = vars(args).copy()
        vals["E"] = E
        opts = options_from_args(argparse.Namespace(**vals))
        deckdir = os.path.join(out, f"dem_{e_label(E)}")
        ts, meta, sec = run_dem(scene, deckdir, opts, mpi=args.mpi, reuse=args.reuse)
        dem[E] = dict(ts=ts, meta=meta, dir=deckdir)
        timings.append(dict(method="dem", E=E, wall_seconds=sec, steps=meta["total_steps"], dt=meta["dt_si"],
                            note=f"mpi {args.mpi}" if args.mpi else ""))

    if proc is not None:
        say("waiting for the engine")
        sec = finish_engine(proc, elog, t0, engine_dir)
        say(f"engine finished in {sec:.1f} s (ran alongside LIGGGHTS)")
        timings.insert(0, dict(method="nscd", E=np.nan, wall_seconds=sec, steps=scene.steps, dt=scene.dt,
                               note="parallel with LIGGGHTS, 1 thread"))

    check_generated_positions(engine_dir, scene)
    engine_ts = pd.read_csv(os.path.join(engine_dir, "timeseries.csv"), float_precision="round_trip")
    windows = scene.cycle_windows()
    engine_peaks = cycle_peaks(engine_ts, windows, args.smooth)
    for E in Es:
        dem[E]["peaks"] = cycle_peaks(dem[E]["ts"], windows, args.smooth)

    # comparison.csv: per-cycle peaks side by side.
    comp = engine_peaks.rename(columns={"peak": "nscd_peak_pressure", "t_peak": "nscd_peak_time"})
    for E in Es:
        lab = e_label(E)
        pk = dem[E]["peaks"]
        comp[f"dem_{lab}_peak_pressure"] = pk["peak"].to_numpy()
        comp[f"dem_{lab}_peak_time"] = pk["t_peak"].to_numpy()
        comp[f"dem_{lab}_rel_diff"] = [rel(d, n) for d, n in zip(pk["peak"], engine_peaks["peak"])]
    write_csv_atomic(comp, os.path.join(out, "comparison.csv"))
    plot_comparison(os.path.join(out, "comparison.png"), scene, engine_ts, engine_peaks, dem, args.smooth)

    summary = dict(scene=os.path.abspath(args.scene), scene_name=scene.name, E=Es, smooth=args.smooth,
                   cycles=comp.to_dict(orient="list"),
                   options={k: v for k, v in vars(args).items() if k not in ("scene", "out")})

    # Static: the settled bed at the end of the settling stage.
    if engine_snapshot_every(scene) > 0:
        t_end = scene.thermal.start_time
        z, r = engine_settled_bed(engine_dir, scene)
        st = {"nscd": static_measures(engine_ts, z, r, scene, t_end, args.static_average)}
        for E in Es:
            z, r = dem_settled_bed(dem[E]["dir"], dem[E]["meta"])
            st[f"dem_{e_label(E)}"] = static_measures(dem[E]["ts"], z, r, scene, t_end, args.static_average)
        keys = ["bed_height", "phi_H", "phi_bulk", "pressure", "wall_force_side", "wall_force_bottom",
                "bottom_fraction", "kinetic_energy", "weight"]
        rows = []
        for k in keys:
            row = dict(quantity=k, nscd=st["nscd"][k])
            for E in Es:
                lab = f"dem_{e_label(E)}"
                row[lab] = st[lab][k]
                row[f"{lab}_rel_diff"] = rel(st[lab][k], st["nscd"][k])
            rows.append(row)
        write_csv_atomic(pd.DataFrame(rows), os.path.join(out, "static.csv"))
        summary["static"] = st
        summary["static_time"] = t_end

    # Side-wall stress profiles: DEM at the end of settling and of every cooling ramp;
    # the engine's wall_profile.csv (settled bed, then every cold hold) when this build writes it.
    if args.profile_bins > 0 and scene.container_type == "cone":
        prof = []
        for E in Es:
            meta = dem[E]["meta"]
            ncool = 0
            for wd in meta.get("wall_dumps", []):
                df, H, _ = dem_wall_profile(dem[E]["dir"], meta, wd, args.profile_bins)
                cycle = ncool if wd["kind"] == "cool" else -1
                ncool += wd["kind"] == "cool"
                df.insert(0, "t", wd["t"])
                df.insert(0, "cycle", cycle)
                df.insert(0, "moment", "end_of_settling" if wd["kind"] == "settle" else "end_of_cooling")
                df.insert(0, "method", f"dem_{e_label(E)}")
                prof.append(df)
        ep = os.path.join(engine_dir, "wall_profile.csv")
        if os.path.exists(ep):
            e = pd.read_csv(ep, float_precision="round_trip")
            # cycle -1: the settled bed, averaged over the last --static-average before cycling.
            e.insert(0, "moment", np.where(e["cycle"] < 0, "end_of_settling", "end_of_cooling"))
            e.insert(0, "method", "nscd")
            prof.append(e[["method", "moment", "cycle", "t", "bin", "z_lo", "z_hi", "wall_stress"]])
        if prof:
            profile = pd.concat(prof, ignore_index=True)
            write_csv_atomic(profile, os.path.join(out, "wall_profile.csv"))
            summary["wall_profile"] = profile.to_dict(orient="list")
            summary["wall_profile_engine"] = os.path.exists(ep)

    if len(Es) > 1:
        rows = []
        for E in Es:
            pk = dem[E]["peaks"]["peak"].to_numpy()
            u = Units.from_dict(dem[E]["meta"]["units"])
            row = dict(E=E, E_dimensionless=E / (u.density_si * u.g0 * u.length), dem_mean_peak_pressure=float(np.nanmean(pk)) if len(pk) else np.nan,
                       nscd_mean_peak_pressure=float(np.nanmean(engine_peaks["peak"])) if len(pk) else np.nan)
            for c, v in enumerate(pk):
                row[f"dem_peak_cycle{c}"] = v
            row["rel_diff"] = rel(row["dem_mean_peak_pressure"], row["nscd_mean_peak_pressure"])
            rows.append(row)
        stiff = pd.DataFrame(rows)
        write_csv_atomic(stiff, os.path.join(out, "stiffness.csv"))
        if len(windows):
            plot_stiffness(os.path.join(out, "stiffness.png"), scene, stiff,
                           float(np.nanmean(engine_peaks["peak"])), engine_peaks["peak"].to_numpy(),
                           Units.from_dict(dem[Es[0]]["meta"]["units"]))
        summary["stiffness"] = stiff.to_dict(orient="list")

    tim = pd.DataFrame(timings)
    write_csv_atomic(tim, os.path.join(out, "timings.csv"))
    summary["timings"] = tim.to_dict(orient="records")
    write_atomic(os.path.join(out, "summary.json"), dumps(summary))

    for _, row in comp.iterrows():
        msg = f"cycle {int(row['cycle'])}: NSCD peak {row['nscd_peak_pressure']:.4g}"
        for E in Es:
            lab = e_label(E)
            msg += f", DEM {E:.3g} Pa {row[f'dem_{lab}_peak_pressure']:.4g} ({100 * row[f'dem_{lab}_rel_diff']:+.1f}%)"
        say(msg)
    for _, t in tim.iterrows():
        say(f"wall time {t['method']}{'' if t['method'] == 'nscd' else f' E={t.E:.3g}'}: {t['wall_seconds']:.1f} s")
    say(f"results in {out}")
    return 0
