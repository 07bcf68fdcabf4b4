"""Every example's output, and a tune's, loads with typed columns and a unit for each column."""

import json

import numpy as np
import pandas as pd
import pytest

import salsa
from conftest import SOURCE, cli

EXAMPLES = sorted((SOURCE / "examples").glob("*.json"))
TUNE_FILE = SOURCE / "examples" / "tune" / "flocking-forest-tune.json"


# The comparison files' means and differences are in the unit of their row's metric: no one unit.
PER_METRIC = {"mean_a", "mean_b", "mean_diff", "ci_low", "ci_high", "diff_baseline", "diff_condition", "did",
              "mean_baseline", "baseline_ci_low", "baseline_ci_high", "mean_condition", "mean", "diff_vs_best",
              "ci_low_vs_best", "ci_high_vs_best"}


def check_frame(frame, where):
    """No untyped column (object), names and categories typed as documented, and a unit for each column."""
    units = frame.attrs.get("units", {})
    for column in frame.columns:
        dtype = frame[column].dtype
        assert dtype != object, f"{where}: {column} is untyped (object)"
        assert column in units or column in PER_METRIC, f"{where}: {column} has no unit"
        if column in ("status", "group", "behavior", "variant", "condition", "phase", "test", "map", "target"):
            assert isinstance(dtype, pd.CategoricalDtype) or (column == "test" and dtype == "string"), f"{where}: {column} {dtype}"
        if column in ("id", "seed", "repeat", "candidate", "evaluation", "world", "generation", "drones", "found_by"):
            assert pd.api.types.is_integer_dtype(dtype), f"{where}: {column} {dtype}"
        if column in ("name", "cell", "error"):
            assert dtype == "string", f"{where}: {column} {dtype}"


def frames(result):
    """Every DataFrame a result has, by name."""
    names = {salsa.TestResult: ["summary", "outcome", "drones", "targets", "fleet"],
             salsa.QueueResult: ["summary", "comparison", "did", "condition_effects", "ranking", "timing", "test_summary",
                                 "outcome", "drones", "targets", "fleet"],
             salsa.TuneResult: ["evaluations", "candidates", "best", "front", "summary", "timing"]}[type(result)]
    return {n: getattr(result, n) for n in names if getattr(result, n) is not None}


@pytest.mark.parametrize("example", EXAMPLES, ids=[e.stem for e in EXAMPLES])
def test_every_example_loads_typed(tmp_path, program, example):
    status, out, _ = cli(program, "validate", str(example))
    count = int(out.split("(")[1].split()[0])
    out_dir = tmp_path / "out"
    # 0.5 s each (at least one step of a test's own dt); of a queue of more than 60 tests (the
    # forest-health ones: 50,000 trees each) a share of 4.
    shard = ["--shard", f"0/{count // 4}"] if count > 60 else []
    seconds = max(0.5, json.loads(example.read_text()).get("dt", 0))
    status, _, err = cli(program, "run", str(example), "--out", str(out_dir), "--time", str(seconds), "--no-plots", "-q", "--jobs", "2", *shard)
    assert status == 0, err
    result = salsa.load(out_dir)
    assert isinstance(result, salsa.QueueResult) and result.tests
    got = frames(result)
    assert {"outcome", "drones", "targets", "test_summary"} <= set(got)
    if not shard:
        assert "summary" in got and len(got["summary"]) == count
    for name, frame in got.items():
        check_frame(frame, f"{example.name}: {name}")
    for test in result.tests.values():
        for name, frame in frames(test).items():
            check_frame(frame, f"{example.name}: {test.name}: {name}")


def run_tune(tmp_path, program, **changes):
    """examples/tune/flocking-forest-tune.json cut to a dozen 3 s evaluations, with `changes` laid over it."""
    tune = json.loads(TUNE_FILE.read_text())
    tune["test"]["time"] = 3
    tune.update({"budget": {"evaluations": 12}, "worlds": 2, "validation": {"worlds": 2, "candidates": 2},
                 "racing": {"level": 0.05, "first_test": 2}, **changes})
    file = tmp_path / "tune.json"
    file.write_text(json.dumps({k: v for k, v in tune.items() if v is not None}))
    out = tmp_path / "out"
    status, _, err = cli(program, "tune", str(file), "--out", str(out), "--no-plots", "-q", "--jobs", "2")
    assert status == 0, err
    return out


def test_the_tune_example_loads(tmp_path, program):
    r = salsa.load(run_tune(tmp_path, program))
    assert isinstance(r, salsa.TuneResult)
    assert r.objectives == {"targets_found": "max"} and r.parameters == list(json.loads(TUNE_FILE.read_text())["parameters"])
    e, c = r.evaluations, r.candidates
    evaluations = e[e["phase"] == "tuning"]
    assert len(evaluations) == 12 and list(e["evaluation"]) == list(range(len(e)))
    assert list(e["phase"].cat.categories) == ["tuning", "validation"] and (e["phase"] == "validation").any()
    assert list(e["status"].cat.categories) == ["ok", "failed", "no value"] and (e["status"] == "ok").all()
    assert list(c["status"].cat.categories) == ["complete", "dropped", "failed", "cut"]
    # An objective is a number per evaluation and an aggregate per candidate: floats in both, whatever it counts.
    assert e["targets_found"].dtype == np.float64 and c["targets_found"].dtype == np.float64
    assert e.attrs["units"]["behavior.params.separation_distance"] == "m" and e.attrs["units"]["targets_found"] == ""
    assert c.attrs["units"]["behavior.params.cohesion_weight"] == "" and c.attrs["units"]["worlds"] == ""
    for name, frame in frames(r).items():
        check_frame(frame, f"tune: {name}")
    # The winner: the complete candidate with the highest score, best.json's values.
    best = r.best
    complete = c[c["status"] == "complete"]
    assert len(best) == 1 and best["targets_found"].iloc[0] == complete["targets_found"].max()
    params = r.best_test["tests"][0]["behavior"]["params"]
    assert params["cohesion_weight"] == pytest.approx(best["behavior.params.cohesion_weight"].iloc[0])
    assert r.front is None and r.front_tests == []
    # Its tests: every evaluation's folder, in tune.csv's order.
    assert list(r.tests) == list(e["test"])
    first = r.tests[e["test"].iloc[0]]
    assert first.outcome["targets_found"].iloc[0] == e["targets_found"].iloc[0]
    assert set(r.summary["name"]) == set(e["test"]) and r.summary["seed"].dtype == np.int64
    assert "salsa tune" in r.report


def test_a_pareto_front_loads(tmp_path, program):
    objectives = [{"column": "targets_found", "goal": "max"}, {"column": "mean_speed", "goal": "min"}]
    r = salsa.load(run_tune(tmp_path, program, objective=None, objectives=objectives, algorithm="random", racing=None))
    assert r.objectives == {"targets_found": "max", "mean_speed": "min"}
    front = r.front
    assert list(front.columns[:2]) == ["rank", "candidate"] and front["rank"].dtype == np.int64
    assert list(front["rank"]) == list(range(1, len(front) + 1)) and len(front) == len(r.front_tests) >= 1
    assert front.attrs["units"]["mean_speed"] == "m/s" and r.evaluations.attrs["units"]["mean_speed"] == "m/s"
    assert front["candidate"].iloc[0] == r.best["candidate"].iloc[0]  # front/1.json is best.json's candidate
    for rank, test in enumerate(r.front_tests, start=1):
        assert test["tests"][0]["name"].startswith(f"front_{rank}")
        member = front[front["rank"] == rank].iloc[0]
        assert test["tests"][0]["behavior"]["params"]["separation_distance"] == pytest.approx(member["behavior.params.separation_distance"])
    # No member is dominated by a complete candidate.
    complete = r.candidates[r.candidates["status"] == "complete"]
    for _, m in front.iterrows():
        better = (complete["targets_found"] >= m["targets_found"]) & (complete["mean_speed"] <= m["mean_speed"])
        strictly = (complete["targets_found"] > m["targets_found"]) | (complete["mean_speed"] < m["mean_speed"])
        assert not (better & strictly).any()
