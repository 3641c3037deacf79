"""An earlier engine checked again on today's golden data (`--recheck-golden BIN`,
docs/campaign.md, "The reuse rule"): golden/ moves on (new cases, regenerated data)
while an engine's arithmetic may not. If the binary that made stored runs still
reproduces today's golden data bit for bit, the check's record is added to those runs'
provenance, and the reuse rule can pair them with the current engine's check."""

from __future__ import annotations

import json
from pathlib import Path

from common.fsutil import write_atomic
from common.gitinfo import git_commit_folder
from . import golden, store
from .engine import Engine, EngineError, build_facts, file_sha256, version_line, version_of


def stored_by(plan, results: Path, sha256: str) -> list:
    """The plan's stored runs whose provenance names this binary (SHA-256)."""
    out = []
    for run in plan.runs:
        stored = store.read(results, run)
        if stored is not None and stored.provenance.get("engine", {}).get("binary_sha256") == sha256:
            out.append(stored)
    return out


def engine_of(binary: Path, record: dict) -> Engine:
    """The binary as the engine its stored runs name (their commit and source tree)."""
    version = version_of(binary, "--recheck-golden")
    return Engine(binary=binary, version=version_line(version), binary_sha256=file_sha256(binary),
                  repo_head=record.get("repo_head"), commit=record.get("engine_commit"),
                  tree=record.get("engine_tree"), dirty=bool(record.get("engine_dirty", True)),
                  source_hash=build_facts(version).get("source hash"))


def recheck(plan, work: Path, results: Path, binary: Path, commit: bool, say) -> int:
    """Exit status: 0 the check passed (the runs carry it), 1 it failed, 2 no stored run of
    the plan was made by this binary."""
    if not binary.is_file():
        raise EngineError(f"--recheck-golden {binary}: no such file")
    sha = file_sha256(binary)
    runs = stored_by(plan, results, sha)
    if not runs:
        say(f"--recheck-golden {binary}: no stored run of plan {plan.name} in {results} was made by this "
            f"binary (SHA-256 {sha[:16]}); nothing to check")
        return 2
    engine = engine_of(binary, runs[0].provenance["engine"])
    work.mkdir(parents=True, exist_ok=True)
    record = golden.run_check(work, engine, say)
    if not record.get("passed"):
        say(f"golden recheck of engine {engine.short} failed: its {len(runs)} stored run(s) stay as they are")
        return 1
    added = []
    for stored in runs:
        if golden.add_recheck(stored.provenance, record):
            write_atomic(stored.folder / store.PROVENANCE,
                         json.dumps(stored.provenance, indent=1, sort_keys=True) + "\n")
            added.append(stored.folder.relative_to(results).as_posix())
    say(f"golden recheck of engine {engine.short} on golden data {str(record.get('golden_tree'))[:10]}: "
        f"passed; recorded in {len(added)} of its {len(runs)} stored run(s)"
        + (f": {', '.join(added)}" if added else " (all had it)"))
    if commit and added:
        where = git_commit_folder(results, f"campaign {plan.name}: engine {engine.short} passes the golden "
                                                 f"check again on golden data {str(record.get('golden_tree'))[:10]} "
                                                 f"(recorded in {len(added)} stored runs)")
        say(f"committed {where}")
    return 0
