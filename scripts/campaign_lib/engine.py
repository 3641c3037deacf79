"""Which engine made a result: the binary, its version, and the git state of the
engine's sources (docs/campaign.md, "The reuse rule")."""

from __future__ import annotations

import hashlib
import os
import subprocess
from dataclasses import dataclass
from pathlib import Path

from common.paths import REPO_ROOT
from ratchet import ProgramNotFound, command, program

#: What the `ratchet` binary is built from. The repository's HEAD moves with every stored
#: result (--commit), so the engine is named by the last commit that touched these instead.
#: The engine's tests, benchmarks, fuzz targets and Python bindings are left out: a new
#: benchmark does not make a new engine (reference_engine/CMakeLists.txt, which is in,
#: changes when a folder starts feeding the binary).
ENGINE_SOURCES = ("reference_engine/src", "reference_engine/app", "reference_engine/cmake",
                  "reference_engine/CMakeLists.txt", "CMakeLists.txt")


class EngineError(Exception):
    pass


def git(*args, repo=REPO_ROOT) -> str | None:
    try:
        done = subprocess.run(["git", "-C", os.fspath(repo), *args], capture_output=True, text=True,
                              timeout=30, check=False)
    except (OSError, subprocess.SubprocessError):
        return None
    return done.stdout.strip() if done.returncode == 0 else None


def sources_state(paths, repo=REPO_ROOT) -> dict:
    """The last commit touching `paths`, a hash of their trees at HEAD and whether they
    differ from HEAD (untracked files included)."""
    commit = git("log", "-1", "--format=%H", "--", *paths, repo=repo)
    trees = [git("rev-parse", f"HEAD:{p}", repo=repo) or "-" for p in paths]
    status = git("status", "--porcelain", "--", *paths, repo=repo)
    tree = hashlib.sha256(" ".join(trees).encode()).hexdigest()[:40] if commit else None
    return {"commit": commit, "tree": tree, "dirty": status is None or bool(status)}


def file_sha256(path: Path) -> str:
    digest = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


@dataclass(frozen=True)
class Engine:
    binary: Path
    version: str
    binary_sha256: str
    repo_head: str | None
    commit: str | None
    tree: str | None
    dirty: bool     # sources changed since HEAD, or newer than the binary
    stale: tuple = ()   # engine source files newer than the binary (stale_sources)

    @property
    def key(self) -> str:
        """Names the engine for work-folder reuse (checkpoints, packings): the source tree
        when clean, else the binary itself."""
        return f"tree-{self.tree[:16]}" if self.tree and not self.dirty else f"bin-{self.binary_sha256[:16]}"

    @property
    def short(self) -> str:
        return (self.commit or "unknown")[:10] + ("+dirty" if self.dirty else "")

    def record(self) -> dict:
        binary = self.binary.resolve()
        shown = binary.relative_to(REPO_ROOT) if REPO_ROOT in binary.parents else binary
        return {"binary": str(shown), "version": self.version, "binary_sha256": self.binary_sha256,
                "repo_head": self.repo_head, "engine_commit": self.commit, "engine_tree": self.tree,
                "engine_dirty": self.dirty, "engine_sources": list(ENGINE_SOURCES)}


def version_of(binary: Path, option: str) -> str:
    """`BIN --version`; an EngineError naming the option when the binary cannot say it."""
    try:
        done = subprocess.run(command("--version", ratchet=binary), capture_output=True, text=True, timeout=60)
    except OSError as error:
        raise EngineError(f"{option} {binary}: cannot run it ({error})") from None
    if done.returncode != 0:
        raise EngineError(f"{option} {binary}: '--version' failed: {done.stderr.strip()}")
    return done.stdout.strip()


def identify(ratchet: str | os.PathLike | None = None) -> Engine:
    """The engine `ratchet` (--ratchet), else the build's (ratchet.program: $RATCHET_BIN,
    else <$RATCHET_BUILD_DIR or build>/reference_engine/ratchet)."""
    try:
        binary = program(ratchet)
    except ProgramNotFound as e:
        raise EngineError(f"--ratchet {e.filename}: no engine binary there (build it: RATCHET_JOBS=1 scripts/build "
                          "-DRATCHET_BUILD_BENCHMARKS=OFF)") from None
    version = version_of(binary, "--ratchet")
    state = sources_state(ENGINE_SOURCES)
    # A binary older than its sources may not be built from them: the tree then does
    # not name it, and the record and the reuse key fall back to its SHA-256.
    stale = tuple(stale_sources(binary))
    return Engine(binary=binary, version=version, binary_sha256=file_sha256(binary),
                  repo_head=git("rev-parse", "HEAD"), commit=state["commit"], tree=state["tree"],
                  dirty=state["dirty"] or bool(stale), stale=stale)


def same_engine(a: dict, b: dict) -> bool:
    """Two engine records (Engine.record()) name the same engine: the same clean source
    tree, or the same binary."""
    if a.get("binary_sha256") and a.get("binary_sha256") == b.get("binary_sha256"):
        return True
    return (bool(a.get("engine_tree")) and a.get("engine_tree") == b.get("engine_tree")
            and not a.get("engine_dirty", True) and not b.get("engine_dirty", True))


def stale_sources(binary: Path) -> list:
    """Engine source files newer than the binary (a build that may not be the sources')."""
    try:
        built = Path(binary).stat().st_mtime
    except OSError:
        return []
    newer = []
    for top in ENGINE_SOURCES:
        root = REPO_ROOT / top
        files = [root] if root.is_file() else [p for p in root.rglob("*") if p.is_file()]
        newer += [p for p in files if p.stat().st_mtime > built]
    return newer
