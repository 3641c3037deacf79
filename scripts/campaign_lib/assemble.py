"""Stored results as sweep output folders, one per part of the plan, in the format
`scripts/trends` reads (scripts/analysis/inputs.py; docs/sweeps.md, summary.csv):
OUT/<part>/summary.csv and OUT/<part>/runs/<id>/ with the stored files."""

from __future__ import annotations

import json
import math
import shutil
from pathlib import Path

from common.fsutil import write_atomic

from . import store
from .plan import Plan

ALPHA_P = "thermal.alpha_p"


def cell(value) -> str:
    if value is None or isinstance(value, bool):
        return ""
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return "%.17g" % value if math.isfinite(value) else ("nan" if math.isnan(value) else
                                                           ("inf" if value > 0 else "-inf"))
    return str(value)


def lookup(scene: dict, dotted: str):
    node = scene
    for part in dotted.split("."):
        if not isinstance(node, dict) or part not in node:
            return None
        node = node[part]
    return node


def assemble(plan: Plan, states: list, out: Path, say) -> list:
    """Writes one sweep folder per part from the current stored results (stale or missing
    runs are rows with status 'missing'); each folder is built aside and renamed into place,
    summary.csv last. Returns the folders."""
    by_label = {s.run.label: s for s in states}
    folders = []
    for part in plan.parts:
        # Sweep order: points as the part lists them, seeds innermost.
        runs = [r for name in part.points for r in plan.runs if r.point.name == name]
        building = out / f".{part.name}.assembling"
        shutil.rmtree(building, ignore_errors=True)
        rows, summary_keys = [], set()
        for run_id, run in enumerate(runs):
            state = by_label[run.label]
            row = {"run": run_id, part.sweep: run.point.set[part.sweep], "seed": run.seed}
            scene = plan.scene_for(run)
            if part.sweep != ALPHA_P:
                row[ALPHA_P] = lookup(scene, ALPHA_P)
            if state.done:
                meta = state.stored.run_json
                packing = meta.get("packing")
                row["packing"] = packing.get("key") if isinstance(packing, dict) else None
                summary = meta.get("summary") or {}
                for key, value in summary.items():
                    if value is None or (isinstance(value, (int, float)) and not isinstance(value, bool)):
                        row[key] = value
                        summary_keys.add(key)
                row["status"] = "completed"
                target = building / "runs" / str(run_id)
                target.mkdir(parents=True, exist_ok=True)
                for path in sorted(state.stored.folder.iterdir()):
                    if path.is_file() and path.name != store.PROVENANCE:
                        shutil.copyfile(path, target / path.name)
                write_atomic(target / "provenance.json", (state.stored.folder / store.PROVENANCE).read_text())
            else:
                row["status"] = "missing"
            rows.append(row)
        columns = ["run", part.sweep] + ([ALPHA_P] if part.sweep != ALPHA_P else []) + ["seed", "packing"]
        columns += sorted(summary_keys) + ["status"]
        lines = [",".join(columns)] + [",".join(cell(r.get(c)) for c in columns) for r in rows]
        building.mkdir(parents=True, exist_ok=True)
        write_atomic(building / "campaign.json", json.dumps(
            {"campaign": plan.name, "part": part.name, "description": part.description,
             "runs": [r.label for r in runs]}, indent=1) + "\n")
        write_atomic(building / "summary.csv", "\n".join(lines) + "\n")
        final = out / part.name
        shutil.rmtree(final, ignore_errors=True)
        building.rename(final)
        done = sum(1 for r in rows if r["status"] == "completed")
        say(f"assembled {part.name}: {done} of {len(rows)} runs completed -> {final}")
        folders.append(final)
    return folders
