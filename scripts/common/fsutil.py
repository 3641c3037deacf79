"""Atomic file writing: a temporary file in the same folder, then a rename.

A reader sees either the old file or the complete new one, never a partial file; on
any error the temporary file is removed and the old file (if any) is left as it was.
write_atomic itself is the Python package's (reference_engine/python/ratchet/files.py),
so the package and the harness share one implementation.
"""

from __future__ import annotations

import hashlib
import io
import json
import os
from pathlib import Path

from common import paths  # noqa: F401  (puts this checkout's package `ratchet` on sys.path)
from ratchet.files import write_atomic

__all__ = ["write_atomic", "write_csv_atomic", "write_marked_folder", "FIGURE_FORMATS", "figure_format",
           "save_figure_atomic"]


def write_csv_atomic(df, path: str | os.PathLike, **kwargs) -> None:
    """pandas DataFrame -> CSV, atomically; floats with 17 significant digits (they read
    back to the same double) and no index unless asked for."""
    kwargs.setdefault("index", False)
    kwargs.setdefault("float_format", "%.17g")
    write_atomic(path, df.to_csv(**kwargs))


def write_marked_folder(folder: Path, items, marker: str, record: dict, max_bytes: int) -> dict:
    """Replaces the files of `folder` by `items` ((name, bytes) pairs, each written atomically;
    one larger than max_bytes is left out and named) and writes `marker` last: `record` with
    each file's size and SHA-256 ("files") and the omitted ones ("omitted"). The old marker
    goes first, so a folder whose marker says it is complete never holds a mix (a campaign's
    stored run, compare-settings' kept run). Returns what the marker holds."""
    folder = Path(folder)
    (folder / marker).unlink(missing_ok=True)
    folder.mkdir(parents=True, exist_ok=True)
    files, omitted = {}, []
    for name, data in items:
        if len(data) > max_bytes:
            omitted.append({"file": name, "bytes": len(data), "why": f"larger than {max_bytes} bytes"})
            continue
        write_atomic(folder / name, data)
        files[name] = {"bytes": len(data), "sha256": hashlib.sha256(data).hexdigest()}
    for old in folder.iterdir():
        if old.is_file() and old.name not in files and old.name != marker:
            old.unlink()
    content = {**record, "files": files, "omitted": omitted}
    write_atomic(folder / marker, json.dumps(content, indent=1, sort_keys=True) + "\n")
    return content


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
