"""JSON with comments, read as the engine reads scene files.

The engine parses scenes with nlohmann::json and ignore_comments = true
(reference_engine/src/ratchet/scene/scene.cpp): `// ...` to the end of the line and
`/* ... */` are white space outside strings; an unterminated `/*` is an error.
"""

from __future__ import annotations

import json
import os


def strip_json_comments(text: str) -> str:
    """`text` without its // and /* */ comments; text inside strings is kept as it is
    (so "http://x" and "a /* b */" survive). A block comment becomes one space, so that
    it still separates tokens; a line comment keeps its newline. Raises ValueError on an
    unterminated /* comment."""
    out = []
    i, n = 0, len(text)
    in_str = False
    while i < n:
        c = text[i]
        if in_str:
            out.append(c)
            if c == "\\" and i + 1 < n:
                out.append(text[i + 1])
                i += 2
                continue
            if c == '"':
                in_str = False
            i += 1
        elif c == '"':
            in_str = True
            out.append(c)
            i += 1
        elif text.startswith("//", i):
            j = text.find("\n", i)
            i = n if j < 0 else j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            if j < 0:
                raise ValueError("unterminated /* comment")
            out.append(" ")
            i = j + 2
        else:
            out.append(c)
            i += 1
    return "".join(out)


def loads_json_with_comments(text: str):
    """json.loads of `text` after strip_json_comments (ValueError when malformed)."""
    return json.loads(strip_json_comments(text))


def load_json_with_comments(path: str | os.PathLike):
    """Reads a UTF-8 JSON file that may have comments (a scene file). Raises OSError
    when it cannot be read and ValueError (json.JSONDecodeError included) when it is
    not JSON."""
    with open(path, encoding="utf-8") as fh:
        return loads_json_with_comments(fh.read())
