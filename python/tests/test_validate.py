"""salsa.validate: the checks of `salsa validate`, in this process, with its lines."""

import json

import pytest

import salsa
from conftest import SMALL, SOURCE, cli, in_process

# A million drones on a 2 km forest for an hour: `salsa validate` warns it would take days.
HUGE = {**SMALL, "name": "huge", "drones": 1000000, "time": 3600, "map": {"name": "forest", "params": {"size": 2000}}}


def test_good_input_has_no_warnings():
    assert salsa.validate(SMALL) is None
    assert salsa.validate([SOURCE / "examples" / "comparison-queue.json", str(SOURCE / "examples" / "maps" / "warehouse.json"),
                           SOURCE / "examples" / "sweep-queue.json"]) is None
    base = {k: v for k, v in SMALL.items() if k != "seed"}  # paired seeds: one per repeat
    queue = {"repeats": 2, "tests": [{**base, "name": "a"}, {**base, "name": "b", "behavior": "flocking"}]}
    assert salsa.validate(queue) is None


def test_the_warnings_are_the_clis(tmp_path, program):
    file = tmp_path / "huge.json"
    file.write_text(json.dumps(HUGE))
    status, out, err = cli(program, "validate", str(file))
    assert status == 0 and out.startswith(f"{file}: ok")
    line = err.strip()
    assert line.startswith("salsa: warning: ") and "expect days" in line
    assert salsa.validate(file) == [line[len("salsa: warning: "):]]
    # A dict is named <dict>; each test of a list warns once, in order.
    warnings = salsa.validate([HUGE, SMALL, {"tests": [HUGE, {**HUGE, "name": "other", "drones": 500000}]}])
    assert len(warnings) == 3 and warnings[0] == line[len("salsa: warning: "):].replace(str(file), "<dict>")
    assert all(w.startswith("<dict>: ") for w in warnings) and "500,000 drones" in warnings[2]


@pytest.mark.parametrize("content", [
    {**SMALL, "drones": -1},
    {"tests": [SMALL, {**SMALL, "behavior": "nope"}]},
    {"tests": [SMALL], "sweep": 3},
    {"bounds": [0, 0, 10, 10], "obstacles": [{"polygon": [[1, 1], [2, 1]]}]},  # a map file
])
def test_bad_input_is_the_clis_line(tmp_path, program, content):
    file = tmp_path / "bad.json"
    file.write_text(json.dumps(content))
    status, _, err = cli(program, "validate", str(file))
    assert status == 2 and err.startswith("salsa: ")
    line = err.strip()[len("salsa: "):]
    with pytest.raises(salsa.InputError) as e:
        salsa.validate(file)
    assert in_process(str(e.value)) == line
    if "bounds" not in content:  # a dict is a test or a queue, named <dict>
        with pytest.raises(salsa.InputError) as e:
            salsa.validate(content)
        assert in_process(str(e.value)) == line.replace(str(file), "<dict>")


def test_bad_arguments(tmp_path):
    with pytest.raises(salsa.InputError, match=r"missing.json: cannot open file"):
        salsa.validate([SMALL, tmp_path / "missing.json"])
    with pytest.raises(TypeError, match=r"^tests\[1\]: int"):
        salsa.validate([SMALL, 3])
    with pytest.raises(TypeError, match=r"^tests: NoneType"):
        salsa.validate(None)
    with pytest.raises(ValueError, match=r"^tests: an empty list"):
        salsa.validate([])
    with pytest.raises(TypeError, match=r"^tests\[0\]: the dict holds a value JSON cannot hold"):
        salsa.validate([{**SMALL, "time": object()}])
