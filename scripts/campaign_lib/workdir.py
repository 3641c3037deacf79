"""The work folder (outside git): one folder per run, each a one-run `ratchet sweep`
(so the engine's checkpoints, resume and packings apply), and a pool of packings shared
between them (docs/campaign.md, "The work folder")."""

from __future__ import annotations

import json
import os
import re
import shutil
import struct
from dataclasses import dataclass
from pathlib import Path

from common.flock import try_lock
from common.fsutil import write_atomic

from .engine import Engine, same_engine
from .plan import Plan, Run

PACKING = re.compile(r"^[0-9a-f]{16}\.state$")
#: Suffix of the CSVs a run is still writing (docs/output-format.md).
GROWING = "partial"


@dataclass
class Progress:
    stage: str                     # "not started", "pouring", "running", "interrupted", "completed", "failed"
    step: int | None = None
    total: int | None = None
    first: int = 0                 # the packing's step: a run from a packing starts there
    checkpoint: int | None = None
    step_time: float | None = None  # when `step` reached the disk (the growing timeseries' mtime, epoch s)

    @property
    def fraction(self) -> float:
        """Of the run's own steps (after its packing), as far as the last checkpoint."""
        if self.stage == "completed":
            return 1.0
        if self.checkpoint is None or not self.total or self.total <= self.first:
            return 0.0
        return min(1.0, max(0.0, (self.checkpoint - self.first) / (self.total - self.first)))

    def text(self) -> str:
        if self.stage == "pouring" and self.checkpoint is not None:
            return f"pouring (its checkpoint at step {self.checkpoint})"
        if self.stage in ("not started", "pouring", "completed"):
            return self.stage
        if self.total:
            at = self.step if self.step is not None else self.checkpoint
            return (f"{self.stage}, step {at} of {self.total} "
                    f"(checkpoint {self.checkpoint}: {100 * self.fraction:.1f}% of the run)")
        return f"{self.stage}, step {self.step}" if self.step is not None else self.stage


def read_state_header(path: Path) -> tuple[dict, int] | None:
    """(metadata, step) of a state file (docs/output-format.md, "State files")."""
    try:
        with open(path, "rb") as fh:
            head = fh.read(40)
            if len(head) < 40 or head[:8] != b"RATCHETS":
                return None
            (m,) = struct.unpack_from("<I", head, 12)
            meta = json.loads(fh.read(m))
            (step,) = struct.unpack("<q", fh.read(8))
            return meta, step
    except (OSError, ValueError, struct.error):
        return None


def last_step(csv_path: Path) -> int | None:
    """The step of the last complete row of a growing timeseries CSV."""
    try:
        with open(csv_path, "rb") as fh:
            fh.seek(0, os.SEEK_END)
            size = fh.tell()
            fh.seek(max(0, size - 65536))
            lines = fh.read().split(b"\n")
    except OSError:
        return None
    for line in reversed(lines[:-1]):      # the text after the last newline may be cut
        try:
            return int(line.split(b",", 1)[0])
        except ValueError:
            continue
    return None


class RunFolder:
    def __init__(self, work: Path, run: Run):
        self.run = run
        self.root = work / "runs" / run.point.name / f"seed{run.seed}"
        self.sweep_file = self.root / "sweep.json"
        self.out = self.root / "out"
        self.run_dir = self.out / "runs" / "0"
        self.log = self.root / "engine.log"
        self.ledger_file = self.root / "ledger.json"
        self.lock_file = self.root / "lock"

    def sweep(self, plan: Plan) -> dict:
        """The one-run sweep: the plan's `set`, the point's fields as a one-value grid, the seed."""
        return {"description": f"campaign {plan.name}: {self.run.label} (written by scripts/campaign)",
                "scene": str(plan.scene_path), "set": plan.set,
                "grid": {k: [v] for k, v in run_point_items(self.run)}, "seeds": [self.run.seed]}

    def write_sweep(self, plan: Plan) -> None:
        write_atomic(self.sweep_file, json.dumps(self.sweep(plan), indent=1) + "\n")

    def ledger(self) -> dict:
        try:
            return json.loads(self.ledger_file.read_text())
        except (OSError, ValueError):
            return {"engine": None, "segments": []}

    def save_ledger(self, ledger: dict) -> None:
        write_atomic(self.ledger_file, json.dumps(ledger, indent=1) + "\n")

    def forget_other_engine(self, engine: Engine) -> bool:
        """A checkpoint continues bit for bit only on the engine that wrote it: work of
        another engine is removed (the engine checks its version string only)."""
        ledger = self.ledger()
        if ledger.get("engine") is None or same_engine(ledger["engine"], engine.record()):
            return False
        shutil.rmtree(self.out, ignore_errors=True)
        self.save_ledger({"engine": None, "segments": []})
        return True

    def lock(self):
        """An exclusive lock, handed to the engine process so that it lasts as long as the
        run does (even if the campaign dies); None when another process holds it."""
        self.root.mkdir(parents=True, exist_ok=True)
        return try_lock(self.lock_file)

    def busy(self) -> bool:
        if not self.lock_file.exists():
            return False
        fd = self.lock()
        if fd is None:
            return True
        os.close(fd)
        return False

    def progress(self) -> Progress:
        meta_path = self.run_dir / "run.json"
        status = None
        try:
            status = json.loads(meta_path.read_text()).get("status")
        except (OSError, ValueError):
            pass
        if status == "completed":
            return Progress("completed")
        if not self.run_dir.is_dir():
            if not self.out.is_dir():
                return Progress("not started")
            # A pour stopped at its checkpoint goes on from there (docs/cli.md, *Stopping and resuming*).
            pours = [h for h in map(read_state_header, sorted((self.out / "packings").glob("*.pour-checkpoint"))) if h]
            return Progress("pouring", checkpoint=max(step for _, step in pours) if pours else None)
        header = read_state_header(self.run_dir / "checkpoint.state")
        total, first, checkpoint = None, 0, None
        if header:
            meta, checkpoint = header
            total = (meta.get("world") or {}).get("steps")
            packing = (meta.get("run") or {}).get("packing") or {}
            first = packing.get("step", 0) if isinstance(packing, dict) else 0
        # The engine's own growing file (read only; this module writes no such file).
        growing = self.run_dir / f"timeseries.csv.{GROWING}"
        step = last_step(growing)
        try:
            step_time = growing.stat().st_mtime if step is not None else None
        except OSError:
            step_time = None
        stage = "interrupted" if status == "interrupted" else ("failed" if status == "failed" else "running")
        return Progress(stage, step=step, total=total, first=first, checkpoint=checkpoint, step_time=step_time)


def run_point_items(run: Run):
    return sorted(run.point.set.items())


def share_packings(pool: Path, sweep_out: Path) -> None:
    """Hard-links every pooled packing into the run's sweep folder (a copy across file
    systems). The engine checks each packing's key before use, and replaces a damaged one
    by a rename, so a shared inode is never written through."""
    target = sweep_out / "packings"
    target.mkdir(parents=True, exist_ok=True)
    for path in pool.glob("*.state"):
        if PACKING.match(path.name) and not (target / path.name).exists():
            _link(path, target / path.name)


def collect_packings(pool: Path, sweep_out: Path) -> None:
    pool.mkdir(parents=True, exist_ok=True)
    for path in (sweep_out / "packings").glob("*.state"):
        if PACKING.match(path.name) and not (pool / path.name).exists():
            _link(path, pool / path.name)


def _link(src: Path, dst: Path) -> None:
    try:
        os.link(src, dst)
    except FileExistsError:
        pass
    except OSError:
        write_atomic(dst, src.read_bytes())
