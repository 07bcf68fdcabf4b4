"""salsa.load of a tune's output folder (`salsa tune`, docs/tuning.md) as a TuneResult."""

import json
from functools import cached_property
from pathlib import Path

import pandas as pd

from ._core import InputError
from ._results import TestResult, _finished_test, _read_csv


def _json(file, what):
    try:
        return json.loads(file.read_text())
    except (OSError, ValueError) as e:
        raise InputError(f"{file}: cannot be read as JSON ({e}) (allowed: {what} salsa tune wrote)") from None


class TuneResult:
    """A tune's output folder (salsa tune --out OUT): its evaluations and candidates as DataFrames, the
    winner and the Pareto front, its tests. Each file is read on first use; None when absent (a tune
    that has not finished a generation yet). Units: df.attrs["units"]."""

    def __init__(self, folder):
        self.folder = Path(folder)
        self.config = _json(self.folder / "tune.json", "the tune.json")
        if not isinstance(self.config, dict) or not isinstance(self.config.get("parameters"), dict):
            raise InputError(f"{self.folder / 'tune.json'}: not the tune file salsa tune writes (no \"parameters\" object) "
                             "(allowed: a tune's output folder)")
        plots = self.folder / "tune_plots.json"
        self._plots = _json(plots, "the tune_plots.json") if plots.is_file() else None

    @property
    def objectives(self):
        """The objectives' columns in tune.csv and candidates.csv, and their goals: name -> "max" or "min"."""
        if self._plots is not None:
            return {o["name"]: o["goal"] for o in self._plots["objectives"]}
        objectives = self.config.get("objectives") or [self.config.get("objective", {})]
        return {o.get("column", "") + (f"@{o['at']:g}" if "at" in o else ""): o.get("goal", "max") for o in objectives}

    @property
    def parameters(self):
        """The tuned parameters' keys, in the files' order."""
        return list(self.config["parameters"])

    @cached_property
    def evaluations(self):
        """tune.csv: one row per evaluation (a candidate on a world), in the order they were scheduled."""
        return self._csv("tune.csv")

    @cached_property
    def candidates(self):
        """candidates.csv: one row per candidate: its values, status, worlds run and score."""
        return self._csv("candidates.csv")

    @cached_property
    def best(self):
        """The winner's row of candidates.csv (one row), or None before the tune has one."""
        if self._plots is None or self.candidates is None or self._plots.get("winner") is None:
            return None
        return self._rows([self._plots["winner"]])

    @cached_property
    def front(self):
        """With two or more objectives, the Pareto front's rows of candidates.csv by rank (front/<rank>.json:
        rank 1 first, best's candidate), with a `rank` column first; None with one objective."""
        if self._plots is None or self.candidates is None or len(self._plots.get("objectives", [])) < 2:
            return None
        front = self._rows(self._plots.get("front", []))
        front.insert(0, "rank", pd.Series(range(1, len(front) + 1), dtype="int64"))
        front.attrs["units"] = {"rank": "", **self.candidates.attrs["units"]}
        return front

    @cached_property
    def best_test(self):
        """best.json as a dict: the winner as a queue that `salsa run` (or salsa.run) replays."""
        file = self.folder / "best.json"
        return _json(file, "the best.json") if file.is_file() else None

    @cached_property
    def front_tests(self):
        """front/<rank>.json as dicts, rank 1 first (empty with one objective)."""
        files = sorted((self.folder / "front").glob("*.json"), key=lambda f: int(f.stem) if f.stem.isdigit() else 0)
        return [_json(f, "a front/<rank>.json") for f in files]

    @cached_property
    def summary(self):
        """summary.csv: one row per evaluation's test, as a queue's."""
        file = self.folder / "summary.csv"
        return _read_csv(file, "queue") if file.is_file() else None

    @cached_property
    def timing(self):
        """timing.csv: each test's wall time (s); differs between identical runs."""
        file = self.folder / "timing.csv"
        return _read_csv(file, "timing.csv") if file.is_file() else None

    @cached_property
    def tests(self):
        """name -> TestResult of each finished evaluation's test folder (c0012_w03), in tune.csv's order."""
        found = {p.name for p in self.folder.iterdir() if _finished_test(p)}
        order = list(self.evaluations["test"]) if self.evaluations is not None else []
        names = [n for n in order if n in found] + sorted(found - set(order))
        return {name: TestResult(self.folder / name) for name in names}

    @cached_property
    def report(self):
        """report.txt: the tune's report as `salsa tune` printed it."""
        file = self.folder / "report.txt"
        return file.read_text() if file.is_file() else None

    def _csv(self, name):
        file = self.folder / name
        return _read_csv(file, name) if file.is_file() else None

    def _rows(self, candidates):
        c = self.candidates
        rows = pd.concat([c[c["candidate"] == k] for k in candidates]) if candidates else c.iloc[0:0]
        rows = rows.reset_index(drop=True)
        rows.attrs["units"] = dict(c.attrs["units"])
        return rows

    def __repr__(self):
        n = 0 if self.evaluations is None else len(self.evaluations)
        return f"<salsa tune result: {n} evaluations in {self.folder}>"
