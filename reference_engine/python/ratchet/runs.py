"""ratchet.run and ratchet.sweep: the `ratchet` program driven from Python, so a run from
here is exactly a run from the shell (same files, same checks, resumable).

The program is the one of the same build as the module (locate.engine_binary:
$RATCHET_BIN, else <build>/reference_engine/ratchet), or the one passed as `ratchet=`.
"""

from __future__ import annotations

import json
import os
import subprocess
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Sequence

import pandas as pd

from . import settings as _settings
from .errors import RunFailed, SceneError
from .locate import engine_binary
from .run_data import RunData, load_run

#: The file a scene given as a dict is written to in the run's folder: run.json then
#: names a file that exists, and the folder holds its own input.
SCENE_FILE = "scene.json"
#: The program's exit status for input it refuses (docs/cli.md, "Exit status").
EXIT_BAD_INPUT = 2


def _program(ratchet: str | os.PathLike | None) -> Path:
    program = Path(ratchet) if ratchet else engine_binary()
    if not (program.is_file() and os.access(program, os.X_OK)):
        raise FileNotFoundError(f"the ratchet program {program} is not built (run scripts/build, or set "
                                "RATCHET_BIN or RATCHET_BUILD_DIR)")
    return program


def _scene_path(scene: str | os.PathLike | Mapping[str, Any], folder: Path) -> str:
    if not isinstance(scene, Mapping):
        return os.fspath(scene)
    try:
        text = json.dumps(scene, indent=2, allow_nan=False)
    except (TypeError, ValueError) as e:
        raise SceneError(f"<scene dict>: cannot be written as JSON ({e})") from None
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / SCENE_FILE
    path.write_text(text + "\n", encoding="utf-8")
    return str(path)


def _call(command: list[str], quiet: bool) -> None:
    """Runs the program; quiet: its messages kept for the exception, else shown as they come."""
    done = subprocess.run(command, stdin=subprocess.DEVNULL, text=True,
                          stdout=subprocess.DEVNULL if quiet else None,
                          stderr=subprocess.PIPE if quiet else None)
    if done.returncode == 0:
        return
    said = (done.stderr or "").strip().splitlines()
    errors = [line.removeprefix("ratchet: error: ") for line in said if line.startswith("ratchet: error: ")]
    message = "\n".join(errors or said[-5:]) or "see its messages above"
    kind = SceneError if done.returncode == EXIT_BAD_INPUT else RunFailed
    raise kind(f"{message} (ratchet {command[1]}: exit status {done.returncode})")


def run(scene: str | os.PathLike | Mapping[str, Any], out: str | os.PathLike,
        settings: Mapping[str, Any] | None = None, *, packing: str | os.PathLike | None = None,
        quiet: bool = True, ratchet: str | os.PathLike | None = None, **keywords: Any) -> RunData:
    """`ratchet run SCENE --out OUT [--packing FILE] [--set k=v ...]`; returns load_run(out).

    scene:     a scene file, or a dict (written to OUT/scene.json first)
    settings:  {"materials.friction": 0.3, ...}; keywords spell the dots as double
               underscores (materials__friction=0.3)
    Raises SceneError for input the program refuses (exit 2), RunFailed otherwise.
    """
    program = _program(ratchet)
    out = Path(out)
    command = [str(program), "run", _scene_path(scene, out), "--out", str(out)]
    if packing is not None:
        command += ["--packing", os.fspath(packing)]
    for assignment in _settings.overrides(settings, keywords):
        command += ["--set", assignment]
    if quiet:
        command.append("--quiet")
    _call(command, quiet)
    return load_run(out)


@dataclass
class SweepData:
    """A sweep folder: summary.csv (docs/sweeps.md) and its runs."""

    folder: Path
    summary: pd.DataFrame

    def run(self, run_id: int) -> RunData:
        """The run folder DIR/runs/<id>/ of one row of the summary."""
        return load_run(self.folder / "runs" / str(int(run_id)))


def sweep(sweep_file: str | os.PathLike, out: str | os.PathLike, settings: Mapping[str, Any] | None = None,
          *, jobs: int | None = None, quiet: bool = True, ratchet: str | os.PathLike | None = None,
          extra_args: Sequence[str] = (), **keywords: Any) -> SweepData:
    """`ratchet sweep SWEEP --out OUT [--jobs N] [--set k=v ...]`; resumable: completed runs
    are kept. Returns the summary; raises as run() does (a run that did not complete
    makes the program exit 1: RunFailed)."""
    program = _program(ratchet)
    out = Path(out)
    command = [str(program), "sweep", os.fspath(sweep_file), "--out", str(out)]
    if jobs is not None:
        command += ["--jobs", str(int(jobs))]
    for assignment in _settings.overrides(settings, keywords):
        command += ["--set", assignment]
    _call(command + list(extra_args), quiet)
    return SweepData(folder=out, summary=pd.read_csv(out / "summary.csv", float_precision="round_trip"))
