"""JSON-ready copies of results that hold numpy and pandas values."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pandas as pd


def plain(value):
    """A JSON-ready copy: dict keys to str, tuples and arrays to lists, numpy scalars to
    Python, NaN and infinities to None, DataFrames to lists of records, paths to str,
    other objects with to_dict() through it."""
    if isinstance(value, dict):
        return {str(k): plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [plain(v) for v in value]
    if isinstance(value, np.ndarray):
        return [plain(v) for v in value.tolist()]
    if isinstance(value, pd.DataFrame):
        return [plain(r) for r in value.to_dict(orient="records")]
    if isinstance(value, (np.bool_, bool)):
        return bool(value)
    if isinstance(value, np.integer):
        return int(value)
    if isinstance(value, (float, np.floating)):
        value = float(value)
        return value if math.isfinite(value) else None
    if isinstance(value, Path):
        return str(value)
    if hasattr(value, "to_dict"):
        return plain(value.to_dict())
    return value


def dumps(value) -> str:
    """plain(value) as indented JSON text with a final newline (never NaN or Infinity)."""
    return json.dumps(plain(value), indent=2, allow_nan=False) + "\n"
