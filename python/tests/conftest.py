"""Shared fixtures: the salsa program of the build tree and one small test run by it."""

import json
import subprocess
from pathlib import Path

import pytest

import salsa
from salsa import _run

SOURCE = Path(__file__).resolve().parents[2]

# examples/random-walk-forest.json cut to 5 s: 30 drones, 500 trees, a forest map.
SMALL = {**json.loads((SOURCE / "examples" / "random-walk-forest.json").read_text()), "name": "small", "time": 5}


@pytest.fixture(scope="session")
def program():
    return _run.program()


def cli(program, *args, cwd=None):
    """The salsa program's exit status, stdout and stderr."""
    done = subprocess.run([program, *args], capture_output=True, text=True, cwd=cwd)
    return done.returncode, done.stdout, done.stderr


@pytest.fixture(scope="session")
def small_run(tmp_path_factory, program):
    """SMALL written to small.json and run by `salsa run` (no plots): (test file, OUT)."""
    folder = tmp_path_factory.mktemp("small")
    file = folder / "small.json"
    file.write_text(json.dumps(SMALL))
    out = folder / "out"
    status, _, err = cli(program, "run", str(file), "--out", str(out), "--no-plots", "--quiet")
    assert status == 0, err
    return file, out


@pytest.fixture(scope="session")
def small_result(small_run):
    return salsa.load(small_run[1] / "small")


def in_process(line):
    """A Session's line as the program prints it: a Session also knows the Python behaviors registered in
    this process (other tests' and salsa.Env's), listed after the plugins' in an unknown name's line."""
    for name, b in salsa.behaviors().items():
        if b["origin"].startswith("Python class "):
            line = line.replace(", " + name + ",", ",").replace(", " + name + ")", ")")
    return line
