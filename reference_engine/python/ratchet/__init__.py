"""ratchet from Python (docs/python.md).

    World(scene, settings, **kw)   a world in this process: step it, read its state as numpy
    run(scene, out, settings, **kw)  `ratchet run` into a folder; returns load_run(out)
    sweep(sweep, out, settings, **kw) `ratchet sweep` of a file or dict; returns its summary
    load_run(folder)                run.json and DataFrames with stage and cycle columns
    program(), command(), call()    the program itself: which one, a command line, running it

Only World needs the compiled module ratchet._engine, which the build puts in
<build>/python/ratchet (locate.module_dir); the rest is plain Python and the program.
"""

from .locate import module_dir as _module_dir

# The compiled module lives in the build folder, not beside this file.
__path__.append(str(_module_dir()))  # noqa: F821 (__path__ is the package's own)

from .contacts import Contacts  # noqa: E402
from .errors import ProgramNotFound, RunFailed, SceneError  # noqa: E402
from .launch import call, command, program  # noqa: E402
from .run_data import RunData, load_run  # noqa: E402
from .run_folder import RunInputError  # noqa: E402
from .runs import SweepData, run, sweep  # noqa: E402
from .world import World  # noqa: E402

__all__ = ["World", "Contacts", "run", "sweep", "load_run", "RunData", "SweepData", "program", "command",
           "call", "SceneError", "RunFailed", "RunInputError", "ProgramNotFound"]
