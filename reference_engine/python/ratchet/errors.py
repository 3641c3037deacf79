"""The package's exceptions."""

from __future__ import annotations

import errno
import os


class SceneError(ValueError):
    """A scene (or a setting of it, or a packing) the engine refuses. The message is the
    engine's own: the file or origin, the field and what was expected. Raised by the
    program (run, sweep, call): `returncode` is its exit status (2); by World: None."""

    returncode: int | None = None


class RunFailed(RuntimeError):
    """The engine stopped a run or a sweep with an error (its message is the engine's);
    `returncode` is the program's exit status."""

    returncode: int | None = None


class ProgramNotFound(FileNotFoundError):
    """The `ratchet` program is not there or not executable; `filename` is its path."""

    def __init__(self, path: str | os.PathLike, origin: str):
        super().__init__(errno.ENOENT, f"the ratchet program {os.fspath(path)} is not built or not executable "
                         f"({origin}; build it with scripts/build, or set RATCHET_BIN or RATCHET_BUILD_DIR)",
                         os.fspath(path))

    def __str__(self) -> str:
        return self.strerror
