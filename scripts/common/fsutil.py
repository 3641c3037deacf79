"""Atomic file writing: a temporary file in the same folder, then a rename.

A reader sees either the old file or the complete new one, never a partial file; on
any error the temporary file is removed and the old file (if any) is left as it was.
"""

from __future__ import annotations

import io
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


def write_csv_atomic(df, path: str | os.PathLike, **kwargs) -> None:
    """pandas DataFrame -> CSV, atomically; floats with 17 significant digits (they read
    back to the same double) and no index unless asked for."""
    kwargs.setdefault("index", False)
    kwargs.setdefault("float_format", "%.17g")
    write_atomic(path, df.to_csv(**kwargs))


#: Figure file formats by extension (matplotlib's names); the extension alone decides.
FIGURE_FORMATS = {".png": "png", ".pdf": "pdf", ".svg": "svg"}


def figure_format(path: str | os.PathLike) -> str:
    """The format of a figure file from its extension (case ignored); ValueError naming the
    file and the extensions known otherwise, so that a caller can refuse it before any work."""
    suffix = os.path.splitext(os.fspath(path))[1]
    try:
        return FIGURE_FORMATS[suffix.lower()]
    except KeyError:
        known = ", ".join(FIGURE_FORMATS)
        got = f"extension {suffix!r}" if suffix else "no extension"
        raise ValueError(f"{os.fspath(path)}: {got}; expected a figure file name ending in {known}") from None


def save_figure_atomic(fig, path: str | os.PathLike, dpi: int = 120, **savefig_kwargs) -> None:
    """Saves a matplotlib figure atomically in the format of the file's extension (PNG,
    PDF or SVG, `figure_format`; ValueError before anything is written otherwise); extra
    arguments go to savefig."""
    buf = io.BytesIO()
    # Explicit: savefig(BytesIO) has no file name to take the format from.
    fig.savefig(buf, format=figure_format(path), dpi=dpi, **savefig_kwargs)
    write_atomic(path, buf.getvalue())
