"""salsa.run: tests and queues run by the salsa program, the very engine of `salsa run`."""

import json
import os
import shutil
import subprocess
import sys
import tempfile
import warnings
from pathlib import Path

from . import _core
from ._core import InputError, TestFailure


def program():
    """The salsa program: the one of the module's build tree or install prefix, else `salsa` on PATH."""
    for root in (_core.build_tree(), _core.install_prefix()):
        if root is not None:
            built = Path(root) / "bin" / "salsa"
            if built.is_file() and os.access(built, os.X_OK):
                return str(built)
    found = shutil.which("salsa")
    if found is None:
        raise FileNotFoundError("salsa.run: no salsa program: neither beside the module (its build tree's or "
                                "install prefix's bin/salsa) nor on PATH")
    return found


def _runner(args):
    """The command that is `salsa` for this run, and its environment. With behaviors registered from
    Python, the salsa program cannot know them: this package's _program is the program with them
    (python -m salsa._program), each test in a process of its own (--isolate), the processes finding
    the classes through this process's sys.path."""
    from . import _classes
    from ._program import command, spec_of

    specs, hidden = [], {}
    for name, cls in _classes.items():
        try:
            specs.append(spec_of(cls))
        except ValueError as e:  # said if a test names it (_unknown)
            hidden[name] = str(e)
    if not specs:
        return [program()], None, [], hidden
    head = command(specs)
    path = [os.path.abspath(p) if p else os.getcwd() for p in sys.path]
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(dict.fromkeys(path))}
    return head, env, [] if "--isolate" in args else ["--isolate"], hidden


def _absolute_paths(test):
    """A test dict with its file paths absolute: they are relative to the working folder, as in a Session,
    while the program reads the dict from a temporary file elsewhere."""
    test = dict(test)

    def absolute(value):
        return os.path.abspath(value) if isinstance(value, str) and value else value

    if isinstance(test.get("map"), str) and test["map"].endswith(".json"):
        test["map"] = absolute(test["map"])
    elif isinstance(test.get("map"), dict) and "file" in test["map"]:
        test["map"] = {**test["map"], "file": absolute(test["map"]["file"])}
    if "drone_configs" in test:
        test["drone_configs"] = absolute(test["drone_configs"])
    return test


def _whole(name, value, allow_none=True):
    if value is None and allow_none:
        return None
    if isinstance(value, bool) or not isinstance(value, int):
        raise TypeError(f"{name}: {type(value).__name__} (allowed: a whole number >= 0{', or None' if allow_none else ''})")
    if value < 0:
        raise ValueError(f"{name}: {value} is negative (allowed: a whole number >= 0; 0 means all cores)")
    return value


def _flag(name, value):
    if not isinstance(value, bool):
        raise TypeError(f"{name}: {type(value).__name__} (allowed: True or False)")
    return value


def _terminal(stream):
    """The terminal's file descriptor when `stream` writes straight to one, else None."""
    try:
        return stream.fileno() if stream.isatty() else None
    except (AttributeError, OSError, ValueError):  # a notebook's or a test's stream
        return None


def _progress(command, errors, quiet, env=None):
    """Runs the program, its progress passed on to sys.stdout as it comes; its errors into `errors`.

    When sys.stdout is a terminal the program gets one of its own (a pseudo-terminal of the same
    width), so it draws its live bar as in a shell; anywhere else (a notebook, a file) it writes a line
    per finished test, each passed on when written. quiet: nothing written (the program has --quiet)."""
    fd = None if quiet else _terminal(sys.stdout)
    if fd is None:
        process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=errors, text=True, env=env)
        with process:
            for line in process.stdout:  # each line as the program flushes it
                if not quiet:
                    sys.stdout.write(line)
                    sys.stdout.flush()
        return process
    import codecs
    import fcntl
    import pty
    import termios

    leader, follower = pty.openpty()
    try:
        fcntl.ioctl(follower, termios.TIOCSWINSZ, fcntl.ioctl(fd, termios.TIOCGWINSZ, b"\0" * 8))
    except OSError:
        pass  # no size to copy: the bar is not cut to the width
    try:
        process = subprocess.Popen(command, stdout=follower, stderr=errors, env=env)
    finally:
        os.close(follower)
    decoder = codecs.getincrementaldecoder("utf-8")(errors="replace")
    with process:
        try:
            while True:
                try:
                    chunk = os.read(leader, 4096)
                except OSError:  # EIO: the program closed its terminal
                    break
                if not chunk:
                    break
                sys.stdout.write(decoder.decode(chunk))
                sys.stdout.flush()
        finally:
            os.close(leader)
    return process


def run(tests, out, jobs=None, force=False, resume=False, time=None, plots=True, drones_csv=True, quiet=True, args=()):
    """Runs tests with the salsa program (`salsa run`) into the folder `out` and returns salsa.load(out).

    tests: a test or queue file's path, a dict holding a test, or a list of them. jobs: tests at once
    (None: all cores). force, resume: as --force and --resume. time: simulated seconds per test (--time).
    plots: draw the PNG plots. drones_csv: write drones.csv. quiet: nothing printed; False: the
    program's progress on sys.stdout as it prints it (in a terminal its live bar, elsewhere a line per
    finished test). args: more options of `salsa run`, as strings.

    Raises salsa.InputError with the program's line when it refuses the input (exit status 2), and
    salsa.TestFailure naming the first failed test when a test failed (exit status 1; the others ran).
    """
    items = list(tests) if isinstance(tests, (list, tuple)) else [tests]
    if not items:
        raise ValueError("tests: an empty list (allowed: a file's path, a dict holding a test, or a list of them)")
    if not isinstance(out, (str, os.PathLike)):
        raise TypeError(f"out: {type(out).__name__} (allowed: a folder's path as str or os.PathLike)")
    jobs = _whole("jobs", jobs)
    for name, value in (("force", force), ("resume", resume), ("plots", plots), ("drones_csv", drones_csv), ("quiet", quiet)):
        _flag(name, value)
    if time is not None and (isinstance(time, bool) or not isinstance(time, (int, float))):
        raise TypeError(f"time: {type(time).__name__} (allowed: a number of seconds, or None for the tests' own)")
    if isinstance(args, str) or not all(isinstance(a, str) for a in args):
        raise TypeError("args: (allowed: a list of strings, each one option or value of salsa run)")

    with tempfile.TemporaryDirectory(prefix="salsa-run-") as scratch:
        files = []
        for i, item in enumerate(items):
            if isinstance(item, dict):
                # Named as the test is (its name, else "test"), so its output folder is the same as a file's.
                name = item.get("name") if isinstance(item.get("name"), str) and item.get("name") else "test"
                folder = Path(scratch) / str(i)
                folder.mkdir()
                file = folder / f"{os.path.basename(name)}.json"
                try:
                    file.write_text(json.dumps(_absolute_paths(item)))
                except (TypeError, ValueError) as e:
                    raise TypeError(f"tests[{i}]: the dict holds a value JSON cannot hold: {e} "
                                    "(allowed: dict, list, str, int, float, bool, None)") from None
                files.append(str(file))
            elif isinstance(item, (str, os.PathLike)):
                files.append(os.fsdecode(item))
            else:
                raise TypeError(f"tests[{i}]: {type(item).__name__} (allowed: a file's path as str or os.PathLike, or a dict holding a test)")
        head, env, isolate, hidden = _runner(args)
        command = [*head, "run", *files, "--out", os.fsdecode(out)]
        if jobs is not None:
            command += ["--jobs", str(jobs)]
        if time is not None:
            command += ["--time", repr(float(time))]
        command += ["--force"] * force + ["--resume"] * resume + ["--no-plots"] * (not plots)
        command += ["--no-drones-csv"] * (not drones_csv) + ["--quiet"] * quiet + isolate + list(args)
        with tempfile.TemporaryFile(mode="w+", dir=scratch) as errors:
            process = _progress(command, errors, quiet, env)
            errors.seek(0)
            lines = [line.rstrip("\n") for line in errors if line.strip()]
    problems = []
    for line in lines:
        if line.startswith("salsa: warning: "):
            warnings.warn(line[len("salsa: warning: "):], RuntimeWarning, stacklevel=2)
        else:
            problems.append(line[len("salsa: "):] if line.startswith("salsa: ") else line)
    status = process.returncode
    if status == 2:
        for name, why in hidden.items():
            if problems and f"unknown behavior '{name}'" in problems[0]:
                raise ValueError(f"tests: behavior '{name}' is a Python class salsa.run's processes cannot import: {why}")
        raise InputError(problems[0] if problems else f"salsa run refused the input (exit status 2): {' '.join(command)}")
    if status == 1:
        more = f" (and {len(problems) - 1} more)" if len(problems) > 1 else ""
        raise TestFailure((problems[0] if problems else "a test failed") + more + f"; the tests that ran are in {os.fsdecode(out)}")
    if status != 0:
        raise RuntimeError(f"salsa run ended with exit status {status}: {problems[0] if problems else ' '.join(command)}")
    from ._results import load  # pandas, imported when first needed

    return load(out)
