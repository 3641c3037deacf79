"""Scene overrides from Python: the `--set key=value` of the command line.

`settings` is a dict of dotted keys ({"solver.p_gap": 0.05}); keyword arguments spell the
dots as double underscores (solver__p_gap=0.05). Values are written as JSON, so numbers,
booleans, lists and strings reach the engine as the scene file would give them.
"""

from __future__ import annotations

import json
from typing import Any, Mapping


def overrides(settings: Mapping[str, Any] | None, keywords: Mapping[str, Any]) -> list[str]:
    """The `key=value` strings of both, settings first; a key given twice is an error."""
    merged: dict[str, Any] = dict(settings or {})
    for name, value in keywords.items():
        key = name.replace("__", ".")
        if key in merged:
            raise TypeError(f"scene setting {key!r} given twice (as {name} and in settings)")
        merged[key] = value
    out = []
    for key, value in merged.items():
        if not isinstance(key, str) or not key or "=" in key:
            raise TypeError(f"scene setting {key!r}: expected a dotted field name such as 'solver.p_gap'")
        try:
            text = json.dumps(value, allow_nan=False)
        except (TypeError, ValueError) as e:
            raise TypeError(f"scene setting {key!r}: {value!r} cannot be written as JSON ({e})") from None
        out.append(f"{key}={text}")
    return out
