"""salsa from Python (docs/python.md).

    Session(test)   one test stepped in this process, its drones' state as numpy views
    load(folder)    a test's, a queue's or a tune's output folder as pandas DataFrames
    run(tests, out) tests run by the salsa program into `out`, then load(out)
    validate(tests) tests, queues and maps checked as `salsa validate` checks them
    InputError      bad input, with the CLI's one line
    TestFailure     a test failed while it ran
"""

from ._core import InputError, Session, TestFailure
from ._core import version as _version
from ._run import run
from ._validate import validate

__version__ = _version()
__all__ = ["InputError", "QueueResult", "Session", "TestFailure", "TestResult", "TuneResult", "load", "run", "validate"]

for _name in ("InputError", "Session", "TestFailure"):
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
