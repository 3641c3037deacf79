"""Atomic file writing: a temporary file in the same folder, then a rename.

A reader sees either the old file or the complete new one, never a partial file; on
any error the temporary file is removed and the old file (if any) is left as it was.
The one implementation: the harness takes it from here (scripts/common/fsutil.py).
"""

from __future__ import annotations

import os
import tempfile


def write_atomic(path: str | os.PathLike, content: str | bytes) -> None:
    """Writes `content` to `path` atomically: str as UTF-8 text, bytes as they are.

    The folder is created if missing. The new file gets the usual mode (0666 less the
    umask), not the 0600 of a temporary file.
    """
    if isinstance(content, str):
        data = content.encode("utf-8")
    elif isinstance(content, (bytes, bytearray, memoryview)):
        data = bytes(content)
    else:
        raise TypeError(f"write_atomic: content must be str or bytes, not {type(content).__name__}")
    path = os.fspath(path)
    folder = os.path.dirname(os.path.abspath(path))
    os.makedirs(folder, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix="." + os.path.basename(path) + ".", suffix=".partial", dir=folder)
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
            fh.flush()
            os.fsync(fh.fileno())
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise
