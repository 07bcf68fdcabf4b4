"""Bad input raises salsa.InputError with the very line the CLI prints (without its "salsa: ")."""

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

import salsa
from salsa import _core
from conftest import SMALL, cli, in_process

BAD = {
    "out of range": {"behavior": "random_walk", "drones": -1},
    "unknown plugin": {"behavior": "nope"},
    "spawn outside": {"behavior": "random_walk", "map": {"name": "empty", "params": {"size": 100}}, "spawn": {"point": [500, 500]}},
    "no room for drones": {"behavior": "random_walk", "drones": 5000, "map": {"name": "empty", "params": {"size": 10}}},
    "plugin refuses": {"behavior": "random_walk", "targets": {"kind": "tree", "count": 100000}, "map": {"name": "empty", "params": {"size": 10}}},
}


def cli_line(program, command, file):
    status, _, err = cli(program, command, str(file))
    assert status == 2
    lines = err.splitlines()
    assert len(lines) == 1 and lines[0].startswith("salsa: ")
    return lines[0][len("salsa: "):]


@pytest.mark.parametrize("case", sorted(BAD))
def test_a_bad_test_gets_the_clis_line(tmp_path, program, case):
    file = tmp_path / "bad.json"
    file.write_text(json.dumps(BAD[case]))
    line = cli_line(program, "validate", file)
    assert line == cli_line(program, "run", file)
    with pytest.raises(salsa.InputError) as raised:
        salsa.Session(str(file))
    assert in_process(str(raised.value)) == line
    with pytest.raises(salsa.InputError) as raised:  # as a dict: the same line, naming <dict>
        salsa.Session(BAD[case])
    assert in_process(str(raised.value)) == line.replace(str(file), "<dict>")
    with pytest.raises(salsa.InputError) as raised:  # salsa.run passes the program's line on
        salsa.run(str(file), out=tmp_path / "out")
    assert in_process(str(raised.value)) == line  # with Python behaviors registered, the program knows them too


def test_bad_json_and_missing_files(tmp_path, program):
    file = tmp_path / "broken.json"
    file.write_text('{"behavior": "random_walk",')
    line = cli_line(program, "validate", file)
    assert "invalid JSON" in line
    with pytest.raises(salsa.InputError) as raised:
        salsa.Session(file)  # a pathlib.Path
    assert str(raised.value) == line
    missing = tmp_path / "missing.json"
    with pytest.raises(salsa.InputError) as raised:
        salsa.Session(missing)
    assert str(raised.value) == cli_line(program, "validate", missing)


def test_a_queue_is_not_one_session(tmp_path):
    file = tmp_path / "two.json"
    file.write_text(json.dumps([{**SMALL, "name": "a"}, {**SMALL, "name": "b", "seed": 8}]))
    with pytest.raises(salsa.InputError, match=r"two.json: holds 2 tests \(allowed: one test in a Session; salsa.run runs a queue\)$"):
        salsa.Session(file)


def test_input_error_is_its_own_class():
    assert issubclass(salsa.InputError, Exception) and not issubclass(salsa.InputError, ValueError)
    assert salsa.InputError.__module__ == "salsa" and issubclass(salsa.TestFailure, RuntimeError)


def test_a_plugin_throwing_while_stepping_raises_test_failure(tmp_path):
    # In a process of its own: the plugins are loaded once per process, and this one is a test plugin.
    folder = Path(_core.build_tree() or "/nonexistent") / "tests" / "test-plugins" / "crash"
    if not folder.is_dir():
        pytest.skip("the test plugins are built with the test suites (SALSA_BUILD_TESTS)")
    code = """if True:
        import salsa
        s = salsa.Session({"name": "crashing", "behavior": {"name": "test_crash", "params": {"mode": 3, "at": 0.5}},
                           "drones": 3, "time": 2})
        try:
            s.run_until()
        except salsa.TestFailure as e:
            print(s.time, e, sep="|")
        """
    env = {**os.environ, "SALSA_PLUGIN_PATH": str(folder)}
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    time, message = done.stdout.strip().split("|")
    assert float(time) == pytest.approx(0.5, abs=0.02)  # stopped at the failing step
    assert message.startswith(f"test 'crashing' (<dict>): behavior 'test_crash' ({folder}")
    assert message.endswith("failed at t = 0.5 s: crash plugin threw as asked")
