"""Where things are: the repository root, the build folder and the engine binary.

The rule itself is the Python package's (reference_engine/python/ratchet/locate.py); importing this
module also puts this checkout's reference_engine/python/ first on sys.path, so the harness uses the
package of its own checkout, not one that a .pth file of another checkout points at.
"""

from __future__ import annotations

import sys
from pathlib import Path

#: scripts/
SCRIPTS_DIR = Path(__file__).resolve().parent.parent
#: The repository root (the folder that holds scripts/).
REPO_ROOT = SCRIPTS_DIR.parent
#: The Python package's folder (reference_engine/python/ratchet is the package `ratchet`).
PYTHON_DIR = REPO_ROOT / "reference_engine" / "python"

if str(PYTHON_DIR) not in sys.path:
    sys.path.insert(0, str(PYTHON_DIR))

from ratchet.locate import build_dir, engine_binary  # noqa: E402

__all__ = ["SCRIPTS_DIR", "REPO_ROOT", "PYTHON_DIR", "build_dir", "engine_binary", "shown"]


def shown(path) -> str:
    """A path relative to the repository when inside it (provenance and tables name no
    outside paths when they need not)."""
    path = Path(path).resolve()
    return str(path.relative_to(REPO_ROOT)) if REPO_ROOT in path.parents else str(path)
