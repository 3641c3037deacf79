"""An exclusive lock on a file that lasts as long as the process holding it.

flock(2) on a descriptor that the caller hands to the process doing the work
(subprocess.Popen's pass_fds), so the lock outlives the tool that took it if the tool
dies, and ends with the work. Used by the campaign's run folders and compare-settings'
packings and runs: a second instance skips what another one holds.
"""

from __future__ import annotations

import fcntl
import os
from pathlib import Path


def try_lock(path: Path) -> int | None:
    """The descriptor of path, exclusively locked, or None when another process holds it."""
    fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o644)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError:
        os.close(fd)
        return None
    return fd
