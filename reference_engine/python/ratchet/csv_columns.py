"""Reading the engine's CSV files by column name (the engine may add columns; a reader
asks for the ones it needs, docs/output-format.md)."""

from __future__ import annotations

from pathlib import Path

import pandas as pd


def read_csv_columns(path: Path, wanted: tuple[str, ...] | None) -> pd.DataFrame | None:
    """The wanted columns that exist in the CSV (others skipped; None: every column);
    None if unreadable."""
    if not path.is_file():
        return None
    try:
        header = pd.read_csv(path, nrows=0).columns
        use = list(header) if wanted is None else [c for c in wanted if c in header]
        if not use:
            return pd.DataFrame()
        # round_trip: the engine writes 17 digits, and these read back to the same double.
        frame = pd.read_csv(path, usecols=use, float_precision="round_trip")
    except (OSError, ValueError, pd.errors.ParserError, pd.errors.EmptyDataError):
        return None
    for column in frame.columns:
        frame[column] = pd.to_numeric(frame[column], errors="coerce")
    return frame
