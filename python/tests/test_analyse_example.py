"""examples/python/analyse.py: a queue's ranking per condition and its figure, checked against the
queue's own rows."""

import importlib.util
import json

import pandas as pd
import pytest

import salsa
from conftest import SOURCE

QUEUE = {
    "seed": 4,
    "repeats": 4,
    "base": {"map": {"name": "empty", "params": {"size": 300}}, "drones": 8, "time": 30, "log_interval": 5,
             "targets": {"kind": "tree", "count": 300}},
    "conditions": [{"name": "calm"}, {"name": "dropout", "changes": [{"time": 10, "set": {"drones": 3}}]}],
    "sweep": {"behaviors": ["random_walk", "pheromone_avoidance", "flocking"]},
    "reference": "random_walk",
}


@pytest.fixture(scope="module")
def analyse():
    spec = importlib.util.spec_from_file_location("analyse", SOURCE / "examples" / "python" / "analyse.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def queue(tmp_path_factory):
    folder = tmp_path_factory.mktemp("queue")
    file = folder / "queue.json"
    file.write_text(json.dumps(QUEUE))
    salsa.run(str(file), out=folder / "out", plots=False, drones_csv=False)
    return folder / "out"


def test_the_ranking_is_the_queues_numbers(analyse, queue, tmp_path, capsys):
    assert analyse.main([str(queue), "--out", str(tmp_path)]) == 0
    table = pd.read_csv(tmp_path / "ranking.csv")
    summary = salsa.load(queue).summary
    assert sorted(table["condition"].unique()) == ["calm", "dropout"]
    for condition, rows in table.groupby("condition"):
        tests = summary[summary["condition"] == condition]
        means = tests.groupby("variant", observed=True)["fraction_found"].mean()
        assert len(rows) == 3 and (rows["n"] == 4).all()
        for _, row in rows.iterrows():
            assert row["mean"] == pytest.approx(means[row["variant"]], abs=1e-12)
            assert row["ci_low"] <= row["mean"] <= row["ci_high"]
        # Rank 1 is the highest mean; the paired wins add up to every repeat once.
        assert rows.loc[rows["rank"] == 1, "mean"].iloc[0] == pytest.approx(means.max(), abs=1e-12)
        assert rows["best_share"].sum() == pytest.approx(1.0)
        share = dict.fromkeys(means.index, 0.0)
        for _, paired in tests.groupby("repeat"):
            best = paired[paired["fraction_found"] == paired["fraction_found"].max()]["variant"]
            for variant in best:
                share[variant] += 1 / len(best) / 4
        for _, row in rows.iterrows():
            assert row["best_share"] == pytest.approx(share[row["variant"]])
    # The dropout really is another condition: fewer drones find fewer trees.
    mean = table.groupby("condition")["mean"].mean()
    assert mean["dropout"] < mean["calm"]
    png = (tmp_path / "ranking.png").read_bytes()
    assert png.startswith(b"\x89PNG") and len(png) > 10_000
    assert "ranking.csv" in capsys.readouterr().out


def test_a_bad_metric_or_folder_is_one_line(analyse, queue, tmp_path, capsys):
    assert analyse.main([str(queue), "--metric", "speed", "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("analyse.py: --metric: speed is not a column") and "fraction_found" in err and err.count("\n") == 1
    assert analyse.main([str(tmp_path / "nothing")]) == 2
    assert capsys.readouterr().err.startswith("analyse.py: ")
