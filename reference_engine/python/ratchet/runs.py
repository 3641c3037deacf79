"""ratchet.run and ratchet.sweep: the `ratchet` program driven from Python, so a run from
here is exactly a run from the shell (same files, same checks, resumable).

The program is the one of the same build as the module (launch.program:
$RATCHET_BIN, else <build>/reference_engine/ratchet), or the one passed as `ratchet=`.
"""

from __future__ import annotations

import json
import os
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Sequence

import pandas as pd

from .errors import SceneError
from .files import write_atomic
from .launch import call, command, program
from .run_data import RunData, load_run

#: The file a scene given as a dict is written to in the run's folder: run.json then
#: names a file that exists, and the folder holds its own input.
SCENE_FILE = "scene.json"
#: The same for a sweep given as a dict, in the sweep's folder.
SWEEP_FILE = "sweep.json"


def _input_file(data: str | os.PathLike | Mapping[str, Any], folder: Path, name: str, origin: str) -> str:
    """The path of a scene or sweep: a file as it is, a dict written atomically to
    folder/name first (SceneError naming `origin` if it is not JSON)."""
    if not isinstance(data, Mapping):
        return os.fspath(data)
    try:
        text = json.dumps(data, indent=2, allow_nan=False)
    except (TypeError, ValueError) as e:
        raise SceneError(f"{origin}: cannot be written as JSON ({e})") from None
    path = folder / name
    write_atomic(path, text + "\n")
    return str(path)


def run(scene: str | os.PathLike | Mapping[str, Any], out: str | os.PathLike,
        settings: Mapping[str, Any] | None = None, *, packing: str | os.PathLike | None = None,
        quiet: bool = True, ratchet: str | os.PathLike | None = None, **keywords: Any) -> RunData:
    """`ratchet run SCENE --out OUT [--packing FILE] [--set k=v ...]`; returns load_run(out).

    scene:     a scene file, or a dict (written to OUT/scene.json first)
    settings:  {"materials.friction": 0.3, ...}; keywords spell the dots as double
               underscores (materials__friction=0.3)
    Raises SceneError for input the program refuses (exit 2), RunFailed otherwise.
    """
    binary = program(ratchet)
    out = Path(out)
    arguments = [_input_file(scene, out, SCENE_FILE, "<scene dict>"), "--out", str(out)]
    if packing is not None:
        arguments += ["--packing", os.fspath(packing)]
    line = command("run", *arguments, settings=settings, ratchet=binary, **keywords)
    if quiet:
        line.append("--quiet")
    call(line, quiet=quiet)
    return load_run(out)


@dataclass
class SweepData:
    """A sweep folder: summary.csv (docs/sweeps.md) and its runs."""

    folder: Path
    summary: pd.DataFrame

    def run(self, run_id: int) -> RunData:
        """The run folder DIR/runs/<id>/ of one row of the summary."""
        return load_run(self.folder / "runs" / str(int(run_id)))


def _sweep_dict(sweep: Mapping[str, Any]) -> dict[str, Any]:
    """A sweep given as a dict, as its file in the sweep's folder must say it: a relative
    `scene` path is taken from the current folder (a file's is from the file's folder)."""
    data = dict(sweep)
    scene = data.get("scene")
    if isinstance(scene, (str, os.PathLike)) and not os.path.isabs(scene):
        data["scene"] = os.path.abspath(scene)
    return data


def sweep(sweep: str | os.PathLike | Mapping[str, Any], out: str | os.PathLike,
          settings: Mapping[str, Any] | None = None, *, jobs: int | None = None, quiet: bool = True,
          ratchet: str | os.PathLike | None = None, extra_args: Sequence[str] = (), **keywords: Any) -> SweepData:
    """`ratchet sweep SWEEP --out OUT [--jobs N] [--set k=v ...]`; resumable: completed runs
    are kept. Returns the summary; raises as run() does (a run that did not complete
    makes the program exit 1: RunFailed).

    sweep:  a sweep file, or a dict (docs/sweeps.md) written to OUT/sweep.json first; a
            relative `scene` path in it is taken from the current folder
    """
    binary = program(ratchet)
    out = Path(out)
    if isinstance(sweep, Mapping):
        sweep = _sweep_dict(sweep)
    arguments = [_input_file(sweep, out, SWEEP_FILE, "<sweep dict>"), "--out", str(out)]
    if jobs is not None:
        arguments += ["--jobs", str(int(jobs))]
    call(command("sweep", *arguments, settings=settings, ratchet=binary, **keywords) + list(extra_args),
         quiet=quiet)
    return SweepData(folder=out, summary=pd.read_csv(out / "summary.csv", float_precision="round_trip"))
