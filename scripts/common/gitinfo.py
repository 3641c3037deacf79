"""The commit of a checkout, for the records of runs and reports."""

from __future__ import annotations

import os
import subprocess


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
