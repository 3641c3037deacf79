"""The `ratchet` program: which one, its command lines, and running it. The one place the
package and the harness's scripts find and start the engine (docs/python.md).

    program(ratchet=None)       the program: `ratchet` when given (a script's --ratchet),
                                else locate.engine_binary() ($RATCHET_BIN, else
                                <build>/reference_engine/ratchet); ProgramNotFound if it is
                                not an executable file
    command(subcommand, *arguments, settings=None, ratchet=None, **keywords)
                                [program, subcommand, *arguments, --set k=v ...]
    call(command, quiet=True, env=None)
                                runs a command line; SceneError for input the program
                                refuses (exit 2), RunFailed for any other failure

ratchet.run and ratchet.sweep are built on these. A script that must hold the process
itself (a log file, a budget and signals, a run beside another program) builds its
command line with command() and starts it as it needs.
"""

from __future__ import annotations

import os
import subprocess
from collections.abc import Mapping
from pathlib import Path
from typing import Any, Sequence

from . import settings as _settings
from .errors import ProgramNotFound, RunFailed, SceneError
from .locate import engine_binary

#: The program's exit status for input it refuses (docs/cli.md, "Exit status").
EXIT_BAD_INPUT = 2
#: The prefix of the program's error lines (docs/cli.md).
ERROR_PREFIX = "ratchet: error: "


def _origin(given: bool) -> str:
    if given:
        return "as given"
    if os.environ.get("RATCHET_BIN"):
        return "from $RATCHET_BIN"
    return "in the build folder, $RATCHET_BUILD_DIR or build"


def program(ratchet: str | os.PathLike | None = None) -> Path:
    """The `ratchet` program to run: `ratchet` when given and not empty, else
    locate.engine_binary(). ProgramNotFound (a FileNotFoundError whose filename is the
    path) when it is not an executable file."""
    given = ratchet is not None and os.fspath(ratchet) != ""
    path = Path(ratchet) if given else engine_binary()
    if not (path.is_file() and os.access(path, os.X_OK)):
        raise ProgramNotFound(path, _origin(given))
    return path


def command(subcommand: str, *arguments: str | os.PathLike, settings: Mapping[str, Any] | None = None,
            ratchet: str | os.PathLike | None = None, **keywords: Any) -> list[str]:
    """[program(ratchet), subcommand, *arguments, --set k=v ...]: settings and keywords as
    ratchet.run takes them (settings.overrides), after the arguments."""
    line = [str(program(ratchet)), subcommand, *(os.fspath(a) for a in arguments)]
    for assignment in _settings.overrides(settings, keywords):
        line += ["--set", assignment]
    return line


def call(line: Sequence[str], *, quiet: bool = True, env: Mapping[str, str] | None = None) -> None:
    """Runs a command line of the program and waits for it.

    quiet: the program's messages are kept for the exception, else shown as they come.
    env:   the environment (default: this process's).
    Exit 0 returns; exit 2 raises SceneError, any other RunFailed, with the program's
    error lines (`ratchet: error: ` taken off) and `returncode` set.
    """
    line = [os.fspath(a) for a in line]
    done = subprocess.run(line, stdin=subprocess.DEVNULL, text=True, env=None if env is None else dict(env),
                          stdout=subprocess.DEVNULL if quiet else None,
                          stderr=subprocess.PIPE if quiet else None)
    if done.returncode == 0:
        return
    said = (done.stderr or "").strip().splitlines()
    errors = [text.removeprefix(ERROR_PREFIX) for text in said if text.startswith(ERROR_PREFIX)]
    message = "\n".join(errors or said[-5:]) or "see its messages above"
    kind = SceneError if done.returncode == EXIT_BAD_INPUT else RunFailed
    subcommand = line[1] if len(line) > 1 else line[0]
    error = kind(f"{message} (ratchet {subcommand}: exit status {done.returncode})")
    error.returncode = done.returncode
    raise error
