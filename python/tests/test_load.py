"""salsa.load: test and queue folders as typed DataFrames with their units."""

import json

import numpy as np
import pandas as pd
import pytest

import salsa
from conftest import SMALL, SOURCE, cli


def test_a_test_folder(small_result):
    r = small_result
    assert isinstance(r, salsa.TestResult) and r.name == "small" and r.config["time"] == 5
    assert r.fleet is None  # no fleet model in this test
    assert list(r.summary["time"]) == [0, 1, 2, 3, 4, 5]
    assert r.summary["targets_found"].dtype == np.int64 and r.summary["collisions"].dtype == np.int64
    assert r.summary.attrs["units"]["mean_speed"] == "m/s" and r.summary.attrs["units"]["mean_distance"] == "m"
    assert len(r.outcome) == 1 and r.outcome["targets"].iloc[0] == 500
    assert r.outcome.attrs["units"]["time_to_50"] == "s"
    d = r.drones
    assert len(d) == 6 * 30 and d["id"].dtype == np.int64
    assert list(d.columns) == ["time", "id", "x", "y", "vx", "vy"]
    assert d.attrs["units"] == {"time": "s", "id": "", "x": "m", "y": "m", "vx": "m/s", "vy": "m/s"}
    t = r.targets
    assert len(t) == 500 and t["id"].dtype == np.int64 and t["observations"].dtype == np.int64
    assert t["found_by"].dtype == "Int64"  # empty until found
    assert t["found_by"].notna().sum() == r.outcome["targets_found"].iloc[0]
    assert t["found_time"].dtype == np.float64 and t.attrs["units"]["found_time"] == "s"


def test_the_fleet_and_drone_columns(tmp_path, program):
    out = tmp_path / "out"
    test = json.loads((SOURCE / "examples" / "groups-forest.json").read_text())
    file = tmp_path / "groups.json"
    file.write_text(json.dumps({**test, "time": 3}))
    status, _, err = cli(program, "run", str(file), "--out", str(out), "--no-plots", "-q", "--drone-columns", "battery_left,air_velocity")
    assert status == 0, err
    r = salsa.load(out / "groups-forest")
    d = r.drones
    assert isinstance(d["group"].dtype, pd.CategoricalDtype) and list(d["group"].cat.categories) == ["surveyors", "inspectors"]
    assert list(d["status"].cat.categories) == ["flying", "camera_failed", "landed", "failed", "removed"]
    assert d.attrs["units"]["battery_left"] == "J" and d.attrs["units"]["air_velocity_x"] == "m/s"
    assert d.attrs["units"]["energy_used_Wh"] == "Wh"
    f = r.fleet
    assert f["id"].dtype == np.int64 and isinstance(f["status"].dtype, pd.CategoricalDtype)
    assert f.attrs["units"]["since"] == "s" and len(f) == 18
    assert r.summary.attrs["units"]["surveyors.energy_used_Wh"] == "Wh"


def test_a_queue_folder(tmp_path, program):
    file = tmp_path / "queue.json"
    base = {k: v for k, v in SMALL.items() if k != "seed"}  # paired seeds: one per repeat
    file.write_text(json.dumps({"repeats": 2, "tests": [{**base, "name": "walk", "time": 2},
                                                        {**base, "name": "flock", "behavior": "flocking", "time": 2}]}))
    out = tmp_path / "out"
    status, _, err = cli(program, "run", str(file), "--out", str(out), "--no-plots", "-q")
    assert status == 0, err
    q = salsa.load(out)
    assert isinstance(q, salsa.QueueResult)
    names = ["walk_r0", "flock_r0", "walk_r1", "flock_r1"]
    assert list(q.tests) == names  # queue order
    s = q.summary
    assert list(s["name"]) == names and s["name"].dtype == "string"
    assert list(s["status"].cat.categories) == ["ok", "incomplete", "failed", "missing"] and (s["status"] == "ok").all()
    assert isinstance(s["behavior"].dtype, pd.CategoricalDtype) and set(s["behavior"]) == {"random_walk", "flocking"}
    assert s["seed"].dtype == np.int64 and s["repeat"].dtype == np.int64 and s["drones"].dtype == np.int64
    assert s.attrs["units"]["time"] == "s" and s.attrs["units"]["drone.max_speed"] == "m/s"
    assert s.attrs["units"]["map.size"] == "m"
    c = q.comparison
    assert len(c) == 1 and c["n"].iloc[0] == 2 and isinstance(c["variant_a"].dtype, pd.CategoricalDtype)
    o = q.outcome
    assert list(o["test"]) == names and list(o["test"].cat.categories) == names
    assert o["targets_found"].dtype == np.int64
    d = q.drones
    assert len(d) == 4 * 3 * 30 and list(d.columns[:3]) == ["test", "time", "id"]
    assert d.attrs["units"]["x"] == "m"
    assert len(q.test_summary) == 4 * 3 and q.fleet is None
    # A test's folder inside it loads alone.
    assert salsa.load(out / "walk_r0").summary.equals(q.tests["walk_r0"].summary)


def test_not_salsa_output(tmp_path):
    with pytest.raises(salsa.InputError, match=r"^.*: not a salsa output folder \(no \.salsa-test marker, .*\(allowed: a test's output folder"):
        salsa.load(tmp_path)
    with pytest.raises(salsa.InputError, match=r"no such folder"):
        salsa.load(tmp_path / "missing")
    (tmp_path / "file.csv").write_text("a,b\n")
    with pytest.raises(salsa.InputError, match=r"file.csv: a file, not a folder"):
        salsa.load(tmp_path / "file.csv")
    (tmp_path / "tune").mkdir()
    (tmp_path / "tune" / "tune.json").write_text("{}")
    with pytest.raises(salsa.InputError, match=r"tune.json: not the tune file salsa tune writes"):
        salsa.load(tmp_path / "tune")
    (tmp_path / "tune" / "tune.json").write_text("{")
    with pytest.raises(salsa.InputError, match=r"tune.json: cannot be read as JSON"):
        salsa.load(tmp_path / "tune")
    with pytest.raises(TypeError, match=r"^folder: int"):
        salsa.load(3)
