"""The package's exceptions."""


class SceneError(ValueError):
    """A scene (or a setting of it, or a packing) the engine refuses. The message is the
    engine's own: the file or origin, the field and what was expected."""


class RunFailed(RuntimeError):
    """The engine stopped a run or a sweep with an error (its message is the engine's)."""
