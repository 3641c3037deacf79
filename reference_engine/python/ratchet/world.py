"""ratchet.World: a scene's world in this process, stepped as `ratchet run` steps it.

The state comes back as numpy arrays. positions, velocities, angular_velocities and
orientations are read-only views of the engine's memory (no copy): they follow the
world as it steps. contacts() and stats() are copies of the last step's.
"""

from __future__ import annotations

import json
import os
from collections.abc import Mapping
from typing import Any

import numpy as np

from . import settings as _settings
from .contacts import Contacts
from .errors import SceneError
from .locate import module_dir


def engine_module():
    """The compiled module ratchet._engine, or ImportError saying how to build it."""
    try:
        from . import _engine
    except ImportError as e:
        raise ImportError(
            f"the compiled module ratchet._engine is not built in {module_dir()} ({e}); build it with "
            "scripts/build (it needs Debian's pybind11-dev and python3-dev; with a build folder other "
            "than build/, set RATCHET_BUILD_DIR)") from None
    return _engine


class World:
    """A world built from a scene by the engine's own scene reader.

    scene:     a scene file (path) or a scene as a dict (docs/scene-format.md)
    settings:  {"solver.p_gap": 0.05, ...}, as `--set`; keywords spell the dots as
               double underscores: World("bed.json", materials__friction=0.3)

    A scene the engine refuses raises SceneError with the message `ratchet run` prints.
    """

    def __init__(self, scene: str | os.PathLike | Mapping[str, Any],
                 settings: Mapping[str, Any] | None = None, **keywords: Any):
        engine = engine_module()
        sets = _settings.overrides(settings, keywords)
        try:
            if isinstance(scene, Mapping):
                try:
                    text = json.dumps(scene, allow_nan=False)
                except (TypeError, ValueError) as e:
                    raise SceneError(f"<scene dict>: cannot be written as JSON ({e})") from None
                self._w = engine.World.from_json(text, "<scene dict>", sets)
            else:
                self._w = engine.World.from_file(os.fspath(scene), sets)
        except engine.SceneError as e:
            raise SceneError(str(e)) from None

    # -- stepping -------------------------------------------------------------------

    def step(self, n: int = 1) -> None:
        """n Moreau-Jean steps (the settle stage ends as in `ratchet run`)."""
        if n < 0:
            raise ValueError(f"step: n must be >= 0, got {n}")
        self._w.step(int(n))

    def finish(self) -> None:
        """Steps to the scene's end (step_count == steps)."""
        self.step(max(0, self.steps - self.step_count))

    # -- the state: views (no copy), read-only ---------------------------------------

    @property
    def positions(self) -> np.ndarray:
        """(N, 3) centres of mass, a view."""
        return self._w.positions

    @property
    def velocities(self) -> np.ndarray:
        """(N, 3) velocities, a view."""
        return self._w.velocities

    @property
    def angular_velocities(self) -> np.ndarray:
        """(N, 3) angular velocities, world frame, a view."""
        return self._w.angular_velocities

    @property
    def orientations(self) -> np.ndarray:
        """(N, 4) unit quaternions body -> world as (x, y, z, w), scalar last (the engine's
        memory order, and scipy's Rotation.from_quat); bodies.csv writes qw first. A view."""
        return self._w.orientations_xyzw

    # -- the last step: copies --------------------------------------------------------

    def contacts(self) -> Contacts:
        """The contact points of the last step with their impulses and forces."""
        return Contacts(**self._w.contacts())

    def stats(self) -> dict:
        """The last step's solver and wall-force numbers (timeseries.csv's columns)."""
        return self._w.stats()

    # -- scalars --------------------------------------------------------------------

    @property
    def step_count(self) -> int:
        return self._w.step_count

    @property
    def steps(self) -> int:
        """The scene's step count (its duration over dt; moved by the settle stage's end)."""
        return self._w.steps

    @property
    def t(self) -> float:
        return self._w.t

    @property
    def dt(self) -> float:
        return self._w.dt

    @property
    def T(self) -> float:  # noqa: N802 (the paper's symbol)
        return self._w.T

    @property
    def s_p(self) -> float:
        return self._w.s_p

    @property
    def s_c(self) -> float:
        return self._w.s_c

    @property
    def settling(self) -> bool:
        """The scene has a settle section whose stage has not ended yet."""
        return self._w.settling

    @property
    def kinetic_energy(self) -> float:
        return self._w.kinetic_energy

    @property
    def name(self) -> str:
        return self._w.name

    @property
    def scene(self) -> dict:
        """The scene as run (after the settings), as run.json stores it."""
        return json.loads(self._w.scene_json)

    @property
    def scene_hash(self) -> str:
        return self._w.scene_hash

    def __len__(self) -> int:
        return len(self._w.positions)

    def __repr__(self) -> str:
        return f"<ratchet.World {self.name!r}: {len(self)} bodies, step {self.step_count} of {self.steps}, t={self.t:.6g}>"
