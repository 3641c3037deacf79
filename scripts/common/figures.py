"""The figure folder of a report: OUT/figures/<name>.png, with the caption in
OUT/figures/<name>.txt beside it (scripts/report.py embeds both; scripts/README.md)."""

from __future__ import annotations

import os
from pathlib import Path

from .fsutil import save_figure_atomic, write_atomic


def save_figure(figure, out_dir: str | os.PathLike, name: str, caption: str | None = None) -> Path:
    """Saves a matplotlib figure as OUT/figures/<name>.png (atomically, 120 dpi, tight
    bounding box) and, with a caption, OUT/figures/<name>.txt. Returns the PNG's path."""
    folder = Path(out_dir) / "figures"
    path = folder / f"{name}.png"
    save_figure_atomic(figure, path, dpi=120, bbox_inches="tight")
    if caption is not None:
        write_atomic(folder / f"{name}.txt", caption + "\n")
    return path


def figure_caption(figure: str | os.PathLike) -> str:
    """The text of the <name>.txt beside the PNG (white space folded) when there is one
    and it is not empty, else the PNG's file name."""
    figure = Path(figure)
    caption_file = figure.with_suffix(".txt")
    if caption_file.is_file():
        text = " ".join(caption_file.read_text(encoding="utf-8", errors="replace").split())
        if text:
            return text
    return figure.name
