"""salsa from Python (docs/python.md).

    Session(test)   one test stepped in this process, its drones' state as numpy views
    load(folder)    a test's, a queue's or a tune's output folder as pandas DataFrames
    run(tests, out) tests run by the salsa program into `out`, then load(out)
    validate(tests) tests, queues and maps checked as `salsa validate` checks them
    Behavior        base of a behavior written in Python (numpy, one call per group per step);
                    register(cls) makes tests find it by its name; behaviors() lists them all
    Env             one group of a test as a batched reinforcement-learning environment (numpy arrays,
                    agents on the first axis); ParallelEnv the same as a PettingZoo ParallelEnv
    InputError      bad input, with the CLI's one line
    TestFailure     a test failed while it ran
"""

from ._behavior import Behavior, Param, Senses, World
from ._core import BatchRng, InputError, Session, TestFailure, WorldQueries
from ._core import register_behavior as _register_behavior
from ._core import version as _version
from ._env import Env
from ._parallel_env import ParallelEnv
from ._run import run
from ._validate import validate

__version__ = _version()
__all__ = ["BatchRng", "Behavior", "Env", "InputError", "ParallelEnv", "Param", "QueueResult", "Senses", "Session", "TestFailure",
           "TestResult", "TuneResult", "World", "WorldQueries", "behaviors", "load", "register", "run", "validate"]


_classes = {}  # name -> the class registered with salsa.register (salsa.run's processes import them again)


def register(cls):
    """Registers a salsa.Behavior subclass under its `name`: tests name it as a plugin's behavior, its
    params checked against its declared Params. Registering a name again replaces the earlier class
    (Sessions made before keep theirs); a C++ plugin's name is refused. Returns cls (a decorator)."""
    _register_behavior(cls)
    _classes[cls.name] = cls
    return cls


def behaviors():
    """Every behavior this process knows, the plugins' and the registered Python classes': name ->
    {brief, origin (the plugin file or the Python class), parameters (a list of Param)}."""
    from ._core import _behaviors

    return {name: {"brief": brief, "origin": origin, "parameters": [Param(*p) for p in params]}
            for name, brief, origin, params in _behaviors()}


for _name in ("BatchRng", "InputError", "Session", "TestFailure"):
    globals()[_name].__module__ = __name__  # salsa.InputError in messages and tracebacks, not salsa._core
del _name


def __getattr__(name):
    # load and its results need pandas (a quarter of a second to import): imported at their first use,
    # so a script that only steps Sessions starts without it.
    if name in ("QueueResult", "TestResult", "load"):
        from . import _results

        return getattr(_results, name)
    if name == "TuneResult":
        from ._tune import TuneResult

        return TuneResult
    raise AttributeError(f"module 'salsa' has no attribute {name!r}")
