"""Atomic file writing: a temporary file in the same folder, then a rename.

A reader sees either the old file or the complete new one, never a partial file; on
any error the temporary file is removed and the old file (if any) is left as it was.
write_atomic itself is the Python package's (reference_engine/python/ratchet/files.py),
so the package and the harness share one implementation.
"""

from __future__ import annotations

import io
import os

from common import paths  # noqa: F401  (puts this checkout's package `ratchet` on sys.path)
from ratchet.files import write_atomic

__all__ = ["write_atomic", "write_csv_atomic", "FIGURE_FORMATS", "figure_format", "save_figure_atomic"]


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
