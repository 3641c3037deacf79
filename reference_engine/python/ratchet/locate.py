"""Where things are: the repository root, the build folder and the engine binary.

One rule for the package and the harness (scripts/common/paths.py re-exports it):
$RATCHET_BIN, else <build>/reference_engine/ratchet with <build> = $RATCHET_BUILD_DIR
(relative to the repository root) or build.
"""

from __future__ import annotations

import os
from pathlib import Path

#: The repository root (the folder that holds python/ and scripts/).
REPO_ROOT = Path(__file__).resolve().parents[3]


def build_dir() -> Path:
    """$RATCHET_BUILD_DIR when set and not empty, else build; a relative path is taken
    from the repository root (as scripts/build, test and validate take it)."""
    folder = Path(os.environ.get("RATCHET_BUILD_DIR") or "build")
    return folder if folder.is_absolute() else REPO_ROOT / folder


def engine_binary() -> Path:
    """$RATCHET_BIN when set and not empty, else <build_dir()>/reference_engine/ratchet
    (whether it exists is for the caller to check)."""
    binary = os.environ.get("RATCHET_BIN")
    return Path(binary) if binary else build_dir() / "reference_engine" / "ratchet"


def module_dir() -> Path:
    """Where the build puts the compiled module ratchet._engine."""
    return build_dir() / "python" / "ratchet"
