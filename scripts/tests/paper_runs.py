"""Synthetic stored runs of the paper campaign, in the exact format the campaign stores
them (docs/campaign.md, "Stored results"): RESULTS/<point>/seed<s>/ with run.json (the
plan's scene for the run, status, summary), cycles.csv, volume.csv,
displacement_<a>_<b>.csv and provenance.json, written last. A helper of the tests, not a test file.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import pandas as pd

SCRIPTS = Path(__file__).resolve().parent.parent
if str(SCRIPTS) not in sys.path:
    sys.path.insert(0, str(SCRIPTS))

from campaign_lib.plan import Plan, load_plan  # noqa: E402
from common.paths import REPO_ROOT  # noqa: E402

PAPER_PLAN = REPO_ROOT / "validation" / "campaigns" / "paper.json"
CYCLES = 20


def peaks(p_max: float, seed: int, cycles: int = CYCLES) -> np.ndarray:
    """A rise over the first cycles, then steady at p_max with a small scatter whose sign
    pattern differs between seeds, so that the realizations' steady slopes scatter
    around 0 (a steady state the check can see)."""
    c = np.arange(cycles)
    rise = np.where(c < 6, 0.6 + 0.4 * c / 6, 1.0)
    wiggle = 0.01 * np.sin(1.7 * c + 2.1 * seed)
    return p_max * rise * (1.0 + wiggle)


#: Samples of the synthetic V/V0 series per stage: heating, hot hold, cooling, cold hold.
STAGE_ROWS = (10, 5, 10, 5)


def volume_rows(cycles=10, v_low=0.97, dilation=0.005, swing=0.04, noise=0.0005, seed=0) -> pd.DataFrame:
    """A V/V0 series as timeseries.csv samples it: each cooling ramp falls by swing (the
    container's contraction) to the cycle's lowest V/V0, v_low (+ noise), over its first
    seven samples and then rises by `dilation` (the dilation during cooling); the cold
    hold keeps half of that rise, and the heating climbs back by swing."""
    rng = np.random.default_rng(seed)
    heat, hot, cool, cold = STAGE_ROWS
    t, T, V = [0.0], [0.0], [v_low + 0.5 * dilation]
    for _ in range(cycles):
        low = v_low + noise * rng.normal()
        start = V[-1]
        for i in range(1, heat + 1):
            T.append(100.0 * i / heat)
            V.append(start + (low + swing - start) * i / heat)
        T += [100.0] * hot
        V += [V[-1]] * hot
        top = V[-1]
        for i in range(1, cool + 1):
            T.append(100.0 * (1 - i / cool))
            V.append(top + (low - top) * i / 7 if i <= 7 else low + dilation * (i - 7) / (cool - 8))
        T += [0.0] * cold
        V += [low + 0.5 * dilation] * cold
    t = np.arange(len(T)) * 0.4
    return pd.DataFrame({"step": np.arange(len(T)) * 100, "t": t, "T": T, "V_over_V0": V})


def vortex(cells: int = 8, strength: float = 0.01) -> str:
    """A displacement field turning one way around a ring in the (r, z) plane, as CSV."""
    lines = ["ir,iz,r,z,ur,uz,count,w"]
    for iz in range(cells):
        for ir in range(cells):
            r, z = ir + 0.5, iz + 0.5
            ur = -strength * (z - cells / 2)
            uz = strength * (r - cells / 2)
            lines.append(f"{ir},{iz},{r},{z},{ur:.6g},{uz:.6g},5,{2 * strength:.6g}")
    return "\n".join(lines) + "\n"


def store_run(results: Path, point: str, seed: int, p_max: float, *, plan: Plan | None = None,
              engine_commit: str = "0123456789abcdef", scene: dict | None = None,
              w_rms: float = 0.05, cpu_seconds: float = 6480.0) -> Path:
    """One stored run of the plan's point and seed; returns its folder."""
    plan = plan or load_plan(PAPER_PLAN)
    run = next(r for r in plan.runs if r.point.name == point and r.seed == seed)
    folder = Path(results) / point / f"seed{seed}"
    folder.mkdir(parents=True, exist_ok=True)
    series = peaks(p_max, seed)
    v_cool = 1.0 - 0.03 * (1.0 - np.exp(-(np.arange(CYCLES) + 1) / 2.0))
    rows = ["cycle,peak_pressure,t_peak,V_over_V0_end_heating,V_over_V0_end_cooling,contacts_mean,"
            "iterations_mean,unconverged_steps"]
    for k in range(CYCLES):
        rows.append(f"{k},{series[k]:.17g},{25.0 * k + 20.0},{v_cool[k] + 0.002:.17g},"
                    f"{v_cool[k]:.17g},9000,30,0")
    (folder / "cycles.csv").write_text("\n".join(rows) + "\n")
    volume_rows(CYCLES, v_low=float(v_cool[-1]) - 0.005, seed=seed).to_csv(folder / "volume.csv", index=False)
    (folder / "displacement_0_10.csv").write_text(vortex(strength=0.02))
    (folder / "displacement_10_20.csv").write_text(vortex(strength=0.01))
    steady = series[10:20]
    w_rms = w_rms * (1.0 + 0.05 * np.sin(3.1 * seed))  # realizations scatter
    run_json = {
        "status": "completed", "scene": scene if scene is not None else plan.scene_for(run),
        "scene_hash": "00000000deadbeef", "packing": {"key": f"pack-{seed}"},
        "summary": {"P_max": float(steady.mean()), "P_max_std": float(steady.std(ddof=1)),
                    "V_over_V0_end": float(v_cool[-1]), "W_rms_0_10": 2 * w_rms,
                    "W_rms_10_20": w_rms, "cycles_completed": CYCLES, "steady_cycles": [10, 19],
                    "unconverged_steps": 0, "unconverged_fraction": 0.0},
    }
    (folder / "run.json").write_text(json.dumps(run_json, indent=1))
    provenance = {"campaign": plan.name, "point": point, "seed": seed, "cpu_seconds": cpu_seconds,
                  "wall_seconds": cpu_seconds, "date": "2026-11-26T09:00:00+00:00",
                  "engine": {"engine_commit": engine_commit, "engine_tree": "t", "engine_dirty": False}}
    (folder / "provenance.json").write_text(json.dumps(provenance, indent=1))
    return folder


def store_halving(results: Path, p0=(1.0, 1.02), p6=(0.5, 0.51)) -> None:
    """Two realizations each at theta_c = 0 and 6 deg, ratio 10 (the plan's part halving)."""
    for seed, value in enumerate(p0, start=1):
        store_run(results, "theta0_ratio10", seed, value)
    for seed, value in enumerate(p6, start=1):
        store_run(results, "theta6_ratio10", seed, value)
