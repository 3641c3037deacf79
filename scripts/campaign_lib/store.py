"""Stored results: RESULTS/<point>/seed<s>/ holds a finished run's small files and its
provenance.json, written last, so a folder without it is not a stored run
(docs/campaign.md, "Stored results")."""

from __future__ import annotations

import csv
import io
import json
import re
from dataclasses import dataclass
from pathlib import Path

from common.fsutil import write_marked_folder

from .engine import same_engine
from .golden import passes_of, same_golden_pass
from .plan import Run, same_json

PROVENANCE = "provenance.json"
#: The small files of a run folder worth keeping (docs/output-format.md); bodies.csv,
#: timeseries.csv, bodies_shapes.json, vtk/ and the checkpoint are left in the work folder.
KEEP = re.compile(r"^(run\.json|cycles\.csv|wall_profile\.csv|stage_fields\.csv|displacement_\d+_\d+\.csv)$")
#: A kept kind larger than this is not stored (named in the provenance instead).
MAX_BYTES = 2_000_000
#: Derived from timeseries.csv: its V/V0 series alone (the columns below, each row's
#: text as the engine wrote it), for the peak density and the dilation during cooling
#: (scripts/analysis/fields.py); about 60 kB for a paper run against 600 kB.
VOLUME_FILE = "volume.csv"
VOLUME_COLUMNS = ("step", "t", "T", "V_over_V0")


def volume_series(timeseries: Path) -> bytes | None:
    """The VOLUME_COLUMNS of a timeseries.csv as CSV text, or None when it lacks one of
    them (a scene without outputs.volume) or cannot be read."""
    try:
        with open(timeseries, newline="", encoding="utf-8") as fh:
            rows = csv.reader(fh)
            header = next(rows)
            if not set(VOLUME_COLUMNS).issubset(header):
                return None
            at = [header.index(c) for c in VOLUME_COLUMNS]
            out = io.StringIO()
            write = csv.writer(out, lineterminator="\n")
            write.writerow(VOLUME_COLUMNS)
            for row in rows:
                if len(row) == len(header):  # a cut last line of an interrupted write is left out
                    write.writerow([row[i] for i in at])
    except (OSError, UnicodeDecodeError, StopIteration, csv.Error):
        return None
    return out.getvalue().encode()


@dataclass
class Stored:
    folder: Path
    provenance: dict
    run_json: dict


@dataclass
class Verdict:
    current: bool
    reason: str


def folder_of(results: Path, run: Run) -> Path:
    return results / run.point.name / f"seed{run.seed}"


def read(results: Path, run: Run) -> Stored | None:
    folder = folder_of(results, run)
    try:
        provenance = json.loads((folder / PROVENANCE).read_text())
        run_json = json.loads((folder / "run.json").read_text())
    except (OSError, ValueError):
        return None
    if run_json.get("status") != "completed":
        return None
    return Stored(folder=folder, provenance=provenance, run_json=run_json)


def judge(stored: Stored, scene: dict, engine: dict, golden_now: dict | None) -> Verdict:
    """The reuse rule: the same scene, and the same engine or two engines that both
    reproduced the same golden data bit for bit."""
    if not same_json(stored.run_json.get("scene"), scene):
        return Verdict(False, "its scene differs from the plan's (plan or base scene changed)")
    old = stored.provenance.get("engine", {})
    if same_engine(old, engine):
        return Verdict(True, "same engine")
    passes = passes_of(stored.provenance)
    if any(same_golden_pass(check, golden_now) for check in passes):
        return Verdict(True, f"engine {str(old.get('engine_commit'))[:10]} -> current: both pass the "
                             "bit-for-bit golden check on the same golden data")
    if not passes:
        why = "no golden pass recorded for its engine"
    elif golden_now is None:
        why = "the current engine's golden check has not been run"
    elif not golden_now.get("passed"):
        why = "the current engine fails the bit-for-bit golden check"
    else:
        why = ("the two golden checks used different golden data (--recheck-golden with its binary "
               "checks it on today's)")
    dirty = "+dirty" if old.get("engine_dirty") else ""
    return Verdict(False, f"engine {str(old.get('engine_commit'))[:10]}{dirty} is not the current one and {why}")


def store(results: Path, run: Run, run_dir: Path, provenance: dict) -> Path:
    """Copies the run's small files and writes provenance.json last. A stale result there
    is replaced: its provenance goes first, so the folder never looks complete meanwhile."""
    folder = folder_of(results, run)
    kept = [(path.name, path.read_bytes()) for path in sorted(run_dir.iterdir())
            if path.is_file() and KEEP.match(path.name)]
    series = volume_series(run_dir / "timeseries.csv")
    if series is not None:
        kept.append((VOLUME_FILE, series))
    write_marked_folder(folder, kept, PROVENANCE, provenance, MAX_BYTES)
    return folder
