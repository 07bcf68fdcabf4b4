"""python -m salsa._program [--behavior SPEC]... COMMAND ARGS...: the salsa program with behaviors
written in Python.

salsa.run starts it when this process has registered Python behaviors: the `salsa` program cannot
know them, so this process is the program with them registered (the same code: its output folder,
resume, summary, comparison and plots), and each test of a queue runs in a process of its own
(--isolate; the child is this module again). SPEC names a registered class where a new process can
import it: "module:QualName", or "/path/to/script.py:QualName" for a class of a script run as
__main__ (imported again under another name, so its `if __name__ == "__main__":` part does not run).
"""

import importlib
import importlib.util
import os
import sys

from . import _core, register


def spec_of(cls):
    """Where a new process finds `cls` again, or a ValueError saying why it cannot."""
    module = sys.modules.get(cls.__module__)
    if "<locals>" in cls.__qualname__:
        raise ValueError(f"{cls.__qualname__}: a class defined inside a function cannot be run by salsa.run's "
                         "processes (allowed: a class at the top of a module or script)")
    if cls.__module__ != "__main__":
        return f"{cls.__module__}:{cls.__qualname__}"
    file = getattr(module, "__file__", None)
    if not file:
        raise ValueError(f"{cls.__qualname__}: defined in an interactive session, which salsa.run's processes cannot "
                         "import (allowed: a class in a module or a script file)")
    return f"{os.path.abspath(file)}:{cls.__qualname__}"


def load(spec):
    where, _, qualname = spec.rpartition(":")
    if where.endswith(".py"):
        name = "_salsa_script_" + os.path.splitext(os.path.basename(where))[0]
        module = sys.modules.get(name)
        if module is None:
            found = importlib.util.spec_from_file_location(name, where)
            module = importlib.util.module_from_spec(found)
            sys.modules[name] = module
            found.loader.exec_module(module)
    else:
        module = importlib.import_module(where)
    cls = module
    for part in qualname.split("."):
        cls = getattr(cls, part)
    return cls


def command(specs):
    """This module's command line, before the salsa command's own arguments."""
    line = [sys.executable, "-m", "salsa._program"]
    for spec in specs:
        line += ["--behavior", spec]
    return line


def main(argv):
    specs = []
    while len(argv) >= 2 and argv[0] == "--behavior":
        specs.append(argv[1])
        argv = argv[2:]
    for spec in specs:
        try:
            register(load(spec))
        except Exception as e:  # the program's own way of refusing: one line, exit status 2
            print(f"salsa: --behavior {spec}: {type(e).__name__}: {e}", file=sys.stderr)
            return 2
    sys.stdout.flush()
    return _core._cli(command(specs), ["salsa", *argv])


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
