"""examples/python/compare.py: numpy ports beside their C++ originals in one queue run from Python."""

import importlib.util
import sys

import salsa
from conftest import SOURCE


def test_the_ports_tie_their_originals_in_every_paired_repeat(tmp_path, capsys, monkeypatch):
    folder = SOURCE / "examples" / "python"
    monkeypatch.syspath_prepend(str(folder))  # as when the script runs: its folder first on sys.path
    spec = importlib.util.spec_from_file_location("compare", folder / "compare.py")
    compare = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(compare)
    assert compare.main(["--out", str(tmp_path / "out"), "--time", "15", "--repeats", "2", "--jobs", "2"]) == 0
    printed = capsys.readouterr().out
    assert "py_flocking" in printed and "py_random_walk" in printed and "py_pheromone_avoidance" in printed
    result = salsa.load(tmp_path / "out")
    summary = result.summary.set_index("name")
    assert len(summary) == 12 and (summary["status"] == "ok").all()
    for r in (0, 1):
        for original in ("flocking", "random_walk", "pheromone_avoidance"):
            assert summary.loc[f"{original}_r{r}", "targets_found"] == summary.loc[f"py_{original}_r{r}", "targets_found"]
    rows = result.comparison[(result.comparison["metric"] == "fraction_found")
                             & (result.comparison["variant_a"] == "py_flocking (defaults)")]
    assert len(rows) == 1 and rows["mean_diff"].iloc[0] == 0
    assert sys.modules.get("behaviors") is not None
