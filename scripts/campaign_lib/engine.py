"""Which engine made a result: the binary, its version, and the git state of the
engine's sources (docs/campaign.md, "The reuse rule")."""

from __future__ import annotations

import hashlib
import os
import subprocess
from dataclasses import dataclass
from pathlib import Path

from common.paths import REPO_ROOT, shown
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


def sources_state(paths, repo=REPO_ROOT, rev: str = "HEAD") -> dict:
    """The last commit touching `paths` up to `rev`, a hash of their trees at `rev` and, at
    HEAD, whether the checkout differs from it (untracked files included)."""
    commit = git("log", "-1", "--format=%H", rev, "--", *paths, repo=repo)
    trees = [git("rev-parse", f"{rev}:{p}", repo=repo) or "-" for p in paths]
    status = git("status", "--porcelain", "--", *paths, repo=repo) if rev == "HEAD" else ""
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
    dirty: bool     # sources changed since HEAD, or the binary not built from them
    stale: tuple = ()   # engine source files newer than a binary that cannot say its sources
    source_hash: str | None = None   # the binary's, from `--version` (None: too old to say)
    sources_hash: str | None = None  # the checkout's, computed as the build does (source_hash)
    built_at: str | None = None      # a binary built elsewhere: the commit it was built at, checked (build_commit)

    @property
    def built_elsewhere(self) -> bool:
        """The binary was not built from the engine sources in this checkout: its source
        hash differs from theirs or, for a binary that cannot say, a source is newer."""
        return built_elsewhere(self.source_hash, self.sources_hash, self.stale)

    @property
    def key(self) -> str:
        """Names the engine for work-folder reuse (checkpoints, packings): the source tree
        when clean (the checkout's, or the commit a binary built elsewhere was built at),
        else the binary itself."""
        return f"tree-{self.tree[:16]}" if self.tree and not self.dirty else f"bin-{self.binary_sha256[:16]}"

    @property
    def short(self) -> str:
        return (self.commit or "unknown")[:10] + ("+dirty" if self.dirty else "")

    def record(self) -> dict:
        return {"binary": shown(self.binary), "version": self.version, "binary_sha256": self.binary_sha256,
                "repo_head": self.repo_head, "engine_commit": self.commit, "engine_tree": self.tree,
                "engine_dirty": self.dirty, "engine_sources": list(ENGINE_SOURCES),
                "source_hash": self.source_hash, **({"built_at": self.built_at} if self.built_at else {})}


def version_of(binary: Path, option: str) -> str:
    """`BIN --version` (all its lines; the record keeps the first, build_facts reads the
    rest); an EngineError naming the option when the binary cannot say it."""
    try:
        done = subprocess.run(command("--version", ratchet=binary), capture_output=True, text=True, timeout=60)
    except OSError as error:
        raise EngineError(f"{option} {binary}: cannot run it ({error})") from None
    if done.returncode != 0:
        raise EngineError(f"{option} {binary}: '--version' failed: {done.stderr.strip()}")
    if not done.stdout.strip():
        raise EngineError(f"{option} {binary}: '--version' printed nothing (expected 'ratchet VERSION (BUILD TYPE)')")
    return done.stdout.strip()


def version_line(version: str) -> str:
    """The first line of `ratchet --version` ("ratchet 0.1.0 (Release)"): what records keep."""
    return version.splitlines()[0]


def built_elsewhere(built: str | None, ours: str | None, stale) -> bool:
    """A binary whose source hash (`built`) is not the checkout's (`ours`); for a binary
    too old to print one, one with engine sources newer than it (`stale`)."""
    return built != ours if built is not None else bool(stale)


def build_facts(version: str) -> dict:
    """The `key: value` lines after the first of `ratchet --version` ("commit",
    "source hash", "compiler"; none from a binary built before 2026-12-06), and the
    build type from the first line, "ratchet 0.1.0 (Release)"."""
    first, *rest = version.splitlines()
    facts = dict(line.split(": ", 1) for line in rest if ": " in line)
    if first.endswith(")") and "(" in first:
        facts["build type"] = first[first.rindex("(") + 1:-1]
    return facts


HASHED_TOPS = ("reference_engine/src", "reference_engine/app")
HASHED_FILES = ("CMakeLists.txt", "reference_engine/CMakeLists.txt")


def hashed(path: str) -> bool:
    return path in HASHED_FILES or (path.endswith((".cpp", ".hpp"))
                                    and any(path.startswith(top + "/") for top in HASHED_TOPS))


def listing_hash(build_type: str, compiler: str, digests: dict) -> str:
    """reference_engine/cmake/build_info.cmake's hash of {path: SHA-256 of the file}."""
    listing = f"build_type {build_type}\ncompiler {compiler}\n"
    listing += "".join(f"{digests[f]} {f}\n" for f in sorted(digests))
    return hashlib.sha256(listing.encode()).hexdigest()[:16]


def source_hash(build_type: str, compiler: str, root: Path = REPO_ROOT) -> str:
    """The source hash a build of `root` would print, as reference_engine/cmake/
    build_info.cmake computes it: SHA-256 over the build type, the compiler and
    "<SHA-256 of the file> <path>" for each engine and program source (*.cpp, *.hpp
    under reference_engine/src and app) and the two CMakeLists.txt, sorted by path;
    its first 16 hex digits. Both sides must change together (test_campaign.py checks
    that they agree on the build)."""
    files = [p.relative_to(root).as_posix() for top in HASHED_TOPS
             for pattern in ("*.cpp", "*.hpp") for p in (root / top).rglob(pattern) if p.is_file()]
    return listing_hash(build_type, compiler, {f: file_sha256(root / f) for f in files + list(HASHED_FILES)})


def source_hash_at(rev: str, build_type: str, compiler: str, repo: Path = REPO_ROOT) -> str | None:
    """The source hash a build of commit `rev`'s tracked files would print (None: no such
    commit in this repository, or git cannot say)."""
    listed = git("ls-tree", "-r", "--full-tree", rev, "--", *HASHED_TOPS, *HASHED_FILES, repo=repo)
    if not listed:
        return None
    blobs = {}
    for line in listed.splitlines():
        meta, path = line.split("\t", 1)
        kind, oid = meta.split()[1:3]
        if kind == "blob" and hashed(path):
            blobs[path] = oid
    try:
        done = subprocess.run(["git", "-C", os.fspath(repo), "cat-file", "--batch"], capture_output=True,
                              input="".join(f"{oid}\n" for oid in blobs.values()).encode(), timeout=60, check=True)
    except (OSError, subprocess.SubprocessError):
        return None
    out, at, digests = done.stdout, 0, {}
    for path in blobs:              # each answer: "<oid> blob <size>\n<content>\n", in the order asked
        header_end = out.index(b"\n", at)
        size = int(out[at:header_end].split()[2])
        digests[path] = hashlib.sha256(out[header_end + 1:header_end + 1 + size]).hexdigest()
        at = header_end + 1 + size + 1
    return listing_hash(build_type, compiler, digests)


def build_commit(facts: dict, built: str | None, repo: Path = REPO_ROOT) -> str | None:
    """The commit a binary says it was built at ("commit: X", or "X+modified" when some
    tracked file differed), when that commit's engine sources give the binary's source
    hash: then the binary is that commit's engine, wherever the checkout is now (the hash
    covers all that makes the binary, so a modified file elsewhere does not matter). None
    otherwise."""
    commit = facts.get("commit", "").removesuffix("+modified")
    if not built or not commit or commit == "unknown":
        return None
    at = source_hash_at(commit, facts.get("build type", ""), facts.get("compiler", ""), repo)
    return commit if at == built else None


def identify(ratchet: str | os.PathLike | None = None, repo: Path = REPO_ROOT) -> Engine:
    """The engine `ratchet` (--ratchet), else the build's (ratchet.program: $RATCHET_BIN,
    else <$RATCHET_BUILD_DIR or build>/reference_engine/ratchet), named against the
    checkout `repo`."""
    try:
        binary = program(ratchet)
    except ProgramNotFound as e:
        raise EngineError(f"--ratchet {e.filename}: no engine binary there (build it: RATCHET_JOBS=1 scripts/build "
                          "-DRATCHET_BUILD_BENCHMARKS=OFF)") from None
    version = version_of(binary, "--ratchet")
    facts = build_facts(version)
    state = sources_state(ENGINE_SOURCES, repo=repo)
    # A binary not built from the sources beside it is not named by their tree. The
    # binary's source hash says so exactly; for an older binary that cannot say, a source
    # newer than it does. If the commit it says it was built at is here and gives its
    # source hash, it is named by that commit's sources; else by its SHA-256.
    if "source hash" in facts:
        built, ours, stale = facts["source hash"], source_hash(facts.get("build type", ""), facts.get("compiler", ""),
                                                           repo), ()
    else:
        built, ours, stale = None, None, tuple(stale_sources(binary, repo))
    elsewhere, at = built_elsewhere(built, ours, stale), None
    if elsewhere:
        at = build_commit(facts, built, repo)
        if at:
            state = sources_state(ENGINE_SOURCES, repo=repo, rev=at)
    return Engine(binary=binary, version=version_line(version), binary_sha256=file_sha256(binary),
                  repo_head=git("rev-parse", "HEAD", repo=repo), commit=state["commit"], tree=state["tree"],
                  dirty=state["dirty"] or (elsewhere and not at), stale=stale, source_hash=built,
                  sources_hash=ours, built_at=at)


def same_engine(a: dict, b: dict) -> bool:
    """Two engine records (Engine.record()) name the same engine: the same clean source
    tree, or the same binary."""
    if a.get("binary_sha256") and a.get("binary_sha256") == b.get("binary_sha256"):
        return True
    return (bool(a.get("engine_tree")) and a.get("engine_tree") == b.get("engine_tree")
            and not a.get("engine_dirty", True) and not b.get("engine_dirty", True))


def stale_sources(binary: Path, repo: Path = REPO_ROOT) -> list:
    """Engine source files newer than the binary (a build that may not be the sources')."""
    try:
        built = Path(binary).stat().st_mtime
    except OSError:
        return []
    newer = []
    for top in ENGINE_SOURCES:
        root = repo / top
        files = [root] if root.is_file() else [p for p in root.rglob("*") if p.is_file()]
        newer += [p for p in files if p.stat().st_mtime > built]
    return newer
