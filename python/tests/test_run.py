"""salsa.run: the salsa program runs tests given as files or dicts, then salsa.load reads them."""

import pytest

import salsa
from conftest import SMALL


def test_run_dicts_and_files(tmp_path, small_run):
    out = tmp_path / "out"
    q = salsa.run([{**SMALL, "name": "a", "seed": 1}, small_run[0]], out=out, jobs=2, plots=False, time=2)
    assert list(q.tests) == ["a", "small"]
    assert list(q.summary["time"]) == [2.0, 2.0]
    assert (q.summary["status"] == "ok").all()
    # The same test as the CLI's run, cut to 2 s: the same rows.
    cli_rows = salsa.load(small_run[1] / "small").drones
    rows = q.tests["small"].drones
    assert rows.equals(cli_rows[cli_rows["time"] <= 2].reset_index(drop=True))
    with pytest.raises(salsa.InputError, match=r"(allowed: .*--resume|--force)"):
        salsa.run(small_run[0], out=out, plots=False, time=2)  # its folder is there already
    again = salsa.run(small_run[0], out=out, plots=False, time=2, resume=True)
    assert list(again.tests) == ["small", "a"]  # the queue now recorded first, then the other folders
    assert again.tests["small"].drones.equals(rows)


def test_bad_arguments(tmp_path):
    with pytest.raises(ValueError, match=r"^jobs: -1 is negative"):
        salsa.run(SMALL, out=tmp_path, jobs=-1)
    with pytest.raises(TypeError, match=r"^jobs: str"):
        salsa.run(SMALL, out=tmp_path, jobs="2")
    with pytest.raises(TypeError, match=r"^force: int"):
        salsa.run(SMALL, out=tmp_path, force=1)
    with pytest.raises(TypeError, match=r"^out: NoneType"):
        salsa.run(SMALL, out=None)
    with pytest.raises(TypeError, match=r"^tests\[1\]: int"):
        salsa.run([SMALL, 3], out=tmp_path)
    with pytest.raises(ValueError, match=r"^tests: an empty list"):
        salsa.run([], out=tmp_path)
