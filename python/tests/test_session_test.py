"""Session.test(): the session as a test dict that `salsa run`, and a Session of it, replay exactly."""

import json

import numpy as np
import pytest

import salsa
from conftest import SMALL

TIMES = (1, 2, 3, 4, 5)


def changed_session():
    """SMALL stepped to its end with live changes of the drone count, a behavior parameter and the
    wind made on the way; the positions and summary rows at each whole second."""
    s = salsa.Session({**SMALL, "changes": [{"time": 4, "set": {"behavior.params.min_duration": 1}}]})
    positions, rows = {}, {}
    live = {1: ("drones", 40), 2: ("behavior.params.max_duration", 3), 3: ("wind.velocity.x", 2.5)}
    for t in TIMES:
        s.run_until(t)
        positions[t], rows[t] = s.column("position").copy(), s.summary()
        if t in live:
            s.change(*live[t])
    s.run_until(2.5 + 5)  # past the test's time: the test keeps the time reached
    return s, positions, rows


@pytest.fixture(scope="module")
def changed():
    return changed_session()


def test_the_dict_holds_every_change_at_its_time(changed):
    s, _, _ = changed
    test = s.test()
    assert test["name"] == "small" and test["drones"] == 30  # the start state, not the current one
    assert test["time"] == pytest.approx(7.5)
    assert [(c["time"], c["set"]) for c in test["changes"]] == [
        (pytest.approx(1), {"drones": 40}), (pytest.approx(2), {"behavior.params.max_duration": 3}),
        (pytest.approx(3), {"wind.velocity.x": 2.5}), (pytest.approx(4), {"behavior.params.min_duration": 1})]
    assert json.loads(json.dumps(test)) == test  # JSON through and through
    # A session with no change made gives its test back with its own time.
    fresh = salsa.Session(SMALL).test()
    assert fresh["time"] == 5 and "changes" not in fresh


def test_a_session_of_the_dict_replays_it_bit_for_bit(changed):
    s, positions, rows = changed
    again = salsa.Session(s.test())
    for t in TIMES:
        again.run_until(t)
        assert np.array_equal(again.column("position"), positions[t]), t
        assert again.summary() == pytest.approx(rows[t], nan_ok=True), t
    assert again.drones == 40
    again.run_until(7.5)
    assert np.array_equal(again.column("position"), s.column("position"))
    assert np.array_equal(again.column("wind"), s.column("wind"))


def test_salsa_run_of_the_file_replays_it(changed, tmp_path):
    s, positions, rows = changed
    file = tmp_path / "small.json"
    file.write_text(json.dumps(s.test(), indent=2))
    result = salsa.run(file, out=tmp_path / "out", plots=False).tests["small"]
    drones, summary = result.drones, result.summary
    for t in TIMES:
        at = drones[np.isclose(drones["time"], t)].sort_values("id")
        assert len(at) == len(positions[t])
        np.testing.assert_allclose(positions[t][at["id"]], at[["x", "y"]].to_numpy(), rtol=0, atol=1e-4)
        row = summary[np.isclose(summary["time"], t)].iloc[0]
        for column, value in rows[t].items():
            assert value == pytest.approx(row[column], abs=1e-3, nan_ok=True), (t, column)
    # The test the run wrote down (config.json) is the file's: running it again is running the same test.
    assert json.loads((tmp_path / "out" / "small" / "config.json").read_text()) == s.test()
    salsa.run(tmp_path / "out" / "small" / "config.json", out=tmp_path / "again", plots=False)
    for name in ("drones.csv", "summary.csv", "outcome.csv", "targets.csv", "config.json"):
        assert (tmp_path / "again" / "small" / name).read_bytes() == (tmp_path / "out" / "small" / name).read_bytes(), name
