"""The bit-for-bit golden check of an engine: `regression/run --all --tol-scale 0`
against golden/ (docs/regression.md), once per engine and golden data, cached in the
work folder. Its record goes into every stored run's provenance, and is what lets a
result of another engine be reused (docs/campaign.md, "The reuse rule"). An earlier
engine's binary can be checked again on today's golden data (recheck_stored): its
stored runs then carry that record too."""

from __future__ import annotations

import datetime
import json
import os
import subprocess
import time
from pathlib import Path

from common.fsutil import write_atomic
from common.paths import REPO_ROOT

from .engine import Engine, sources_state

#: The cheapest form that detects any change of the results: the default cases (not the
#: quick sweeps of --long), every residual required to be 0.
COMMAND = ["regression/run", "--all", "--tol-scale", "0"]


def golden_state() -> dict:
    state = sources_state(("golden",))
    return {"golden_tree": state["tree"], "golden_dirty": state["dirty"]}


def cache_file(work: Path, engine: Engine, golden: dict) -> Path:
    tree = (golden["golden_tree"] or "none")[:16] + ("-dirty" if golden["golden_dirty"] else "")
    return work / "golden_checks" / f"{engine.binary_sha256[:16]}-{tree}.json"


def cached(work: Path, engine: Engine) -> dict | None:
    path = cache_file(work, engine, golden_state())
    try:
        return json.loads(path.read_text())
    except (OSError, ValueError):
        return None


def run_check(work: Path, engine: Engine, say) -> dict:
    """Runs the check (about a minute of CPU) unless its result is cached."""
    golden = golden_state()
    path = cache_file(work, engine, golden)
    known = cached(work, engine)
    if known is not None:
        return known
    command = [*COMMAND, "--ratchet", str(engine.binary), "--work", str(work / "golden_check" / "runs"),
               "--threads", "1"]
    say(f"golden check of engine {engine.short}: {' '.join(COMMAND)} (about a minute of CPU) ...")
    start, before = time.monotonic(), os.times()
    with open(work / "golden_check.log", "w") as log:
        done = subprocess.run(["/usr/bin/python3", str(REPO_ROOT / COMMAND[0]), *command[1:]], cwd=REPO_ROOT,
                              stdout=log, stderr=subprocess.STDOUT)
    after = os.times()
    record = {
        "passed": done.returncode == 0 and not golden["golden_dirty"],
        "exit_status": done.returncode,
        **golden,
        "command": " ".join(COMMAND),
        "engine": engine.record(),
        "date": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
        "wall_seconds": round(time.monotonic() - start, 1),
        "cpu_seconds": round((after.children_user - before.children_user)
                             + (after.children_system - before.children_system), 1),
    }
    write_atomic(path, json.dumps(record, indent=1) + "\n")
    verdict = "passed" if record["passed"] else f"FAILED (exit {done.returncode}; log {work / 'golden_check.log'})"
    if golden["golden_dirty"]:
        verdict += " (golden/ has uncommitted changes: not counted as a pass)"
    say(f"golden check of engine {engine.short}: {verdict}")
    return record


#: The field of provenance.json with the later golden checks of the run's engine.
RECHECKS = "golden_rechecks"


def passes_of(provenance: dict) -> list:
    """The golden checks a stored run's engine passed: the one made when it was stored,
    and those made later on newer golden data (recheck_stored)."""
    checks = [provenance.get("golden_check"), *provenance.get(RECHECKS, [])]
    return [c for c in checks if isinstance(c, dict) and c.get("passed")]


def add_recheck(provenance: dict, record: dict) -> bool:
    """Adds a passed check of the run's engine on golden data it has no pass for; True
    if it was added."""
    if not record.get("passed") or record.get("golden_dirty"):
        return False
    if any(c.get("golden_tree") == record.get("golden_tree") for c in passes_of(provenance)):
        return False
    provenance.setdefault(RECHECKS, []).append(record)
    return True


def same_golden_pass(old: dict | None, new: dict | None) -> bool:
    """Both engines reproduced the same committed golden data bit for bit."""
    return bool(old and new and old.get("passed") and new.get("passed") and old.get("golden_tree")
                and old.get("golden_tree") == new.get("golden_tree")
                and not old.get("golden_dirty") and not new.get("golden_dirty"))
