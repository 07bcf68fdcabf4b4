"""salsa.Session: stepping, the state columns as views of the simulation's memory, live changes, and
the same numbers as `salsa run` of the same test."""

import json
import threading
import time
import tracemalloc

import numpy as np
import pytest

import salsa
from conftest import SMALL, cli


def rows_at(frame, t):
    return frame[np.isclose(frame["time"], t)].sort_values("id")


def test_views_share_the_simulations_memory(small_run):
    s = salsa.Session(small_run[0])
    a, b = s.column("position"), s.column("position")
    assert np.shares_memory(a, b)
    assert a.__array_interface__["data"][0] == s.columns()["position"]["address"]
    assert a.base is s  # the view keeps the session alive
    assert a.shape == (30, 2) and a.dtype == np.float64
    assert s.column("status").dtype == np.uint8 and s.column("group").dtype == np.uint32
    assert not np.shares_memory(s.column("position"), s.column("velocity"))


def test_a_view_outlives_every_other_reference_to_its_session():
    view = salsa.Session(SMALL).column("position")
    assert view.shape == (30, 2) and np.isfinite(view).all()


def test_views_are_read_only():
    s = salsa.Session(SMALL)
    v = s.column("position")
    with pytest.raises(ValueError, match="read-only"):
        v[0, 0] = 1.0
    with pytest.raises(ValueError):
        v.flags.writeable = True
    assert not v.flags.writeable and not v.flags.owndata


def test_positions_and_summary_equal_the_clis(small_run):
    file, out = small_run
    result = salsa.load(out / "small")
    s = salsa.Session(file)
    for t in (0, 1, 5):
        s.run_until(t)
        assert s.time == pytest.approx(t)
        rows = rows_at(result.drones, t)
        position = s.column("position")  # taken again after stepping
        velocity = s.column("velocity")
        np.testing.assert_allclose(position[rows["id"]], rows[["x", "y"]].to_numpy(), rtol=0, atol=1e-4)
        np.testing.assert_allclose(velocity[rows["id"]], rows[["vx", "vy"]].to_numpy(), rtol=0, atol=1e-4)
        row = result.summary[np.isclose(result.summary["time"], t)].iloc[0]
        summary = s.summary()
        assert list(summary) == list(result.summary.columns)
        for column, value in summary.items():
            assert value == pytest.approx(row[column], abs=1e-3), column  # the file rounds to 3 to 6 decimals
    assert s.finished
    targets = s.targets()
    file_targets = result.targets.sort_values("id")
    np.testing.assert_allclose(targets["position"], file_targets[["x", "y"]].to_numpy(), atol=1e-4)
    assert (targets["found"] == file_targets["found_by"].notna().to_numpy()).all()
    np.testing.assert_allclose(targets["found_time"], file_targets["found_time"].to_numpy(), atol=1e-4)
    assert (targets["found_by"] == file_targets["found_by"].fillna(-1).to_numpy()).all()


def test_the_view_follows_the_simulation_when_taken_again():
    s = salsa.Session(SMALL)
    before = s.column("position").copy()
    s.step(30)
    after = s.column("position")
    assert s.steps == 30 and s.time == pytest.approx(0.5)
    assert not np.allclose(before, after)
    # 30 steps of at most max_speed: every drone within 0.5 s x 10 m/s of where it was
    assert (np.linalg.norm(after - before, axis=1) <= 5 + 1e-9).all()


def test_a_large_column_is_a_view_not_a_copy():
    n = 100_000
    s = salsa.Session({"behavior": "random_walk", "drones": n, "map": {"name": "empty", "params": {"size": 5000}},
                       "spawn": {"mode": "uniform"}, "physics": "light", "metrics": [], "time": 1})
    s.step()
    tracemalloc.start()
    try:
        tracemalloc.reset_peak()
        view = s.column("velocity")
        _, peak_view = tracemalloc.get_traced_memory()
        tracemalloc.reset_peak()
        copy = view.copy()  # the measure sees numpy's allocations: a copy shows
        _, peak_copy = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert view.shape == (n, 2) and view.nbytes == n * 16
    assert peak_copy >= n * 16
    assert peak_view < n * 16 // 100
    assert np.shares_memory(view, s.column("velocity")) and not np.shares_memory(view, copy)


def test_change_applies_as_a_timed_change(tmp_path, program):
    s = salsa.Session(SMALL)
    s.run_until(2)
    s.change("drones", 40)
    assert s.drones == 40 and s.column("position").shape == (40, 2)
    s.change("drones", 20)  # ids are never reused: the highest 20 are removed
    status = s.column("status")
    assert s.drones == 40 and (status[:20] == 0).all() and (status[20:] == 3).all()
    with pytest.raises(ValueError, match=r"^drones: 0 is out of range \(allowed: whole number in \[1, 1000000\]\)$"):
        s.change("drones", 0)
    with pytest.raises(ValueError, match="behavior.params.nope"):
        s.change("behavior.params.nope", 1)
    assert s.drones == 40
    s.run_until(5)
    # The same changes as a test's timeline, run by the CLI: the same positions.
    file = tmp_path / "changed.json"
    file.write_text(json.dumps({**SMALL, "name": "changed", "changes": [{"time": 2, "set": {"drones": 40}}, {"time": 2, "set": {"drones": 20}}]}))
    status_code, _, err = cli(program, "run", str(file), "--out", str(tmp_path / "out"), "--no-plots", "-q")
    assert status_code == 0, err
    drones = salsa.load(tmp_path / "out" / "changed").drones
    rows = rows_at(drones, 5)
    assert list(rows["id"]) == list(range(20))
    np.testing.assert_allclose(s.column("position")[:20], rows[["x", "y"]].to_numpy(), atol=1e-4)


def test_stepping_releases_the_gil_and_refuses_reads_meanwhile():
    s = salsa.Session({**SMALL, "drones": 300, "time": 10}, threads=1)  # about 0.7 s of stepping
    thread = threading.Thread(target=s.run_until)
    refused = []
    spins = 0
    thread.start()
    while thread.is_alive():
        spins += 1
        try:
            s.column("position")
        except ValueError as e:
            refused.append(str(e))
        time.sleep(0.001)
    thread.join()
    assert s.finished and s.time == pytest.approx(10)
    assert spins > 1  # this thread ran while the other stepped
    assert refused and refused[0] == "column: the session is stepping in another thread (allowed: once step or run_until returns)"


def test_bad_arguments_name_the_argument():
    s = salsa.Session(SMALL)
    with pytest.raises(ValueError, match=r"^n: -1 is negative"):
        s.step(-1)
    with pytest.raises(TypeError):
        s.step(1.5)
    with pytest.raises(ValueError, match="^t: "):
        s.run_until(float("nan"))
    with pytest.raises(ValueError, match=r"^name: 'nope' is not a drone state column \(allowed now: position, velocity"):
        s.column("nope")
    with pytest.raises(ValueError, match=r"^name: 'wind' is the wind model's"):
        s.column("wind")
    with pytest.raises(TypeError):
        s.column(3)
    with pytest.raises(TypeError, match=r"^test: int \(allowed: a test file's path"):
        salsa.Session(3)
    with pytest.raises(TypeError, match="^test: the dict holds a value JSON cannot hold"):
        salsa.Session({**SMALL, "drones": np.int64(3)})
    with pytest.raises(ValueError, match="^threads: -1 is negative"):
        salsa.Session(SMALL, threads=-1)
    s.step(0)
    assert s.steps == 0


def test_columns_describe_each_column():
    meta = salsa.Session(SMALL).columns()
    assert meta["position"] == {**meta["position"], "unit": "m", "model": "drone", "dtype": "float64", "width": 2, "rows": 30}
    assert meta["battery_left"]["unit"] == "J" and meta["status"]["dtype"] == "uint8"
    assert "wind" not in meta  # the wind's columns once the test has had wind
    windy = salsa.Session({**SMALL, "wind": {"velocity": [1, 0]}}).columns()
    assert windy["wind"]["unit"] == "m/s" and windy["wind"]["width"] == 2
