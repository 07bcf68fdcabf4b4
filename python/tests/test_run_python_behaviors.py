"""salsa.run of queues naming behaviors written in Python: the salsa program with them (salsa._program),
each test in a process of its own, the same data as the C++ behaviors they port."""

import json
import os
import sys

import numpy as np
import pytest

import salsa
from conftest import SOURCE

sys.path.insert(0, str(SOURCE / "examples" / "python"))
from behaviors import PyRandomWalk  # noqa: E402


class PidWalk(PyRandomWalk):
    """PyRandomWalk that notes the process it runs in (a file per process in $PID_FOLDER)."""

    name = "pid_walk"

    def reset(self, drones):
        super().reset(drones)
        folder = os.environ.get("PID_FOLDER")
        if folder:
            open(os.path.join(folder, str(os.getpid())), "w").close()


class Broken(PyRandomWalk):
    name = "broken_walk"

    def decide(self, group, rng):
        if group.time > 1:
            raise ZeroDivisionError("the broken walk broke")
        return super().decide(group, rng)


def queue(tmp_path, behaviors, repeats=2):
    file = tmp_path / "queue.json"
    file.write_text(json.dumps({
        "seed": 3, "repeats": repeats,
        "base": {"map": {"name": "empty", "params": {"size": 300}}, "drones": 6, "time": 5,
                 "targets": {"kind": "tree", "count": 150}},
        "sweep": {"behaviors": behaviors}, "reference": behaviors[0]}))
    return file


def test_a_queue_runs_python_behaviors_beside_cpp_ones_each_test_in_its_process(tmp_path, monkeypatch):
    salsa.register(PyRandomWalk)
    salsa.register(PidWalk)
    pids = tmp_path / "pids"
    pids.mkdir()
    monkeypatch.setenv("PID_FOLDER", str(pids))
    result = salsa.run(queue(tmp_path, ["random_walk", "py_random_walk", "pid_walk"]), out=tmp_path / "out", jobs=2,
                       plots=False)
    summary = result.summary.set_index("name")
    assert (summary["status"] == "ok").all() and len(summary) == 6
    # The port flies as its original: the same drones' positions, the same trees found, in the same seeds.
    for r in (0, 1):
        cpp, py = result.tests[f"random_walk_r{r}"].drones, result.tests[f"py_random_walk_r{r}"].drones
        assert np.abs(cpp[["x", "y"]].to_numpy() - py[["x", "y"]].to_numpy()).max() < 1e-9
        assert summary.loc[f"random_walk_r{r}", "targets_found"] == summary.loc[f"py_random_walk_r{r}", "targets_found"]
    # Each test in a process of its own (--isolate), none in this one.
    seen = {int(p.name) for p in pids.iterdir()}
    assert len(seen) == 2 and os.getpid() not in seen
    # The queue's own files, as for any salsa run.
    assert (tmp_path / "out" / "comparison.csv").is_file() and (tmp_path / "out" / "queue.json").is_file()


def test_a_python_behavior_failing_is_a_test_failure_the_others_ran(tmp_path):
    salsa.register(Broken)
    with pytest.raises(salsa.TestFailure) as failed:
        salsa.run(queue(tmp_path, ["random_walk", "broken_walk"], repeats=1), out=tmp_path / "out", plots=False)
    line = str(failed.value)
    assert "broken_walk" in line and "ZeroDivisionError" in line and "the broken walk broke" in line
    assert (tmp_path / "out" / "random_walk_r0" / "summary.csv").is_file()


def test_a_class_no_process_can_import_is_said_so(tmp_path):
    def make():
        class Local(PyRandomWalk):
            name = "local_walk"
        return Local

    salsa.register(make())
    with pytest.raises(ValueError, match=r"^tests: behavior 'local_walk' is a Python class salsa.run's processes "
                                         r"cannot import: .*defined inside a function"):
        salsa.run(queue(tmp_path, ["random_walk", "local_walk"], repeats=1), out=tmp_path / "out", plots=False)
