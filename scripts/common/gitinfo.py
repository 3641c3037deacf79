"""The commit of a checkout, for the records of runs and reports, and committing a folder of results."""

from __future__ import annotations

import os
import subprocess
from pathlib import Path


def _git(repo, *args) -> str | None:
    try:
        done = subprocess.run(["git", "-C", os.fspath(repo), *args], capture_output=True, text=True,
                              timeout=20, check=False)
    except (OSError, subprocess.SubprocessError):
        return None
    return done.stdout.strip() if done.returncode == 0 else None


def git_commit(repo, short: int | None = None) -> tuple[str | None, bool]:
    """(commit hash, dirty): the HEAD commit of the checkout at `repo` (abbreviated to
    `short` digits when given), None when git or the checkout is missing; dirty is True
    when tracked files have uncommitted changes (untracked files do not count)."""
    commit = _git(repo, "rev-parse", f"--short={short}" if short else "--verify", "HEAD")
    if not commit:
        return None, False
    return commit, bool(_git(repo, "status", "--porcelain", "--untracked-files=no"))


def git_commit_folder(folder: Path, message: str) -> str:
    """Commits that folder only (other staged changes are left out); returns the commit."""
    top = subprocess.run(["git", "-C", str(folder), "rev-parse", "--show-toplevel"], capture_output=True,
                         text=True, check=False)
    if top.returncode != 0:
        raise RuntimeError(f"--commit: {folder} is not in a git checkout")
    repo = top.stdout.strip()
    for args in (["add", "--", str(folder)], ["commit", "-q", "-m", message, "--", str(folder)]):
        done = subprocess.run(["git", "-C", repo, *args], capture_output=True, text=True, check=False)
        if done.returncode != 0:
            raise RuntimeError(f"--commit: git {args[0]} failed: {done.stderr.strip() or done.stdout.strip()}")
    return subprocess.run(["git", "-C", repo, "rev-parse", "--short", "HEAD"], capture_output=True, text=True,
                          check=False).stdout.strip()
