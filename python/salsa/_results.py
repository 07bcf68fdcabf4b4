"""salsa.load: a test's, a queue's or a tune's output folder (docs/output-format.md) as typed pandas DataFrames."""

import json
import os
from functools import cached_property
from pathlib import Path

import pandas as pd

from . import _units
from ._core import InputError

STATUSES = ["flying", "camera_failed", "landed", "failed", "removed"]  # drones.csv, fleet.csv
QUEUE_STATUSES = ["ok", "incomplete", "failed", "missing"]  # a queue's summary.csv
# Each file's status categories (else a drone's: STATUSES), and a tune's phases.
_STATUSES = {"queue": QUEUE_STATUSES, "tune.csv": ["ok", "failed", "no value"],
             "candidates.csv": ["complete", "dropped", "failed", "cut"]}
_PHASES = ["tuning", "validation"]
ALLOWED = "allowed: a test's output folder OUT/<name>, a queue's output folder OUT or a tune's"
ARCHIVE, ARCHIVE_VERSION = "trajectories.nc", 1  # core/include/salsa/core/replay/archive.hpp

# Whole-number columns (counts and ids): int64, or pandas' nullable Int64 where a value may be empty.
_WHOLE = {"targets", "targets_found", "collisions", "alive", "false_detections", "messages_sent",
          "messages_delivered", "dropped_range", "dropped_obstacle", "dropped_loss", "dropped_cap",
          "id", "found_by", "observations", "repeat", "seed", "drones", "n", "velocity_iterations",
          "position_iterations", "decision_lag", "rank", "repeats", "n_vs_best"}
# Names: pandas categoricals.
_CATEGORIES = {"group", "status", "behavior", "condition", "variant", "target", "map", "metric",
               "variant_a", "variant_b", "baseline", "physics", "phase"}
# Text, never read as a number ("001" stays "001"; a cell's 12 hex digits may be all digits).
_TEXT = {"name", "cell", "error", "condition_label", "test"}
# A tune's files: only these are whole numbers; the other columns are the parameters' values and the
# objectives' (an aggregate over worlds in candidates.csv: 13.5 targets found), whatever their names.
_TUNE_WHOLE = {"tune.csv": {"evaluation", "candidate", "world", "seed"},
               "candidates.csv": {"candidate", "generation", "worlds", "evaluations"}}


def _is_whole(column, kind=None):
    if kind in _TUNE_WHOLE:
        return column in _TUNE_WHOLE[kind]
    name = column[len("outcome."):] if column.startswith("outcome.") else column
    return name in _WHOLE or name.endswith((".found", ".alive")) or (name.startswith("groups.") and name.endswith(".drones"))


def _read_csv(file, kind, groups=None):
    """One CSV file salsa wrote, typed: whole numbers as integers, names as categoricals, units in attrs."""
    try:
        frame = pd.read_csv(file, keep_default_na=False, na_values=[""], low_memory=False,
                            dtype={c: str for c in _CATEGORIES | _TEXT})
    except (pd.errors.ParserError, pd.errors.EmptyDataError, UnicodeDecodeError) as e:
        raise InputError(f"{file}: not a CSV file salsa wrote ({' '.join(str(e).split())})") from None
    if frame.empty:  # a header alone (a comparison with nothing to pair): numbers, as rows would make them
        frame = frame.astype({c: "float64" for c in frame.columns if c not in _CATEGORIES | _TEXT})
    for column in frame.columns:
        values = frame[column]
        if column in _CATEGORIES:
            categories = None
            if column == "status":
                categories = _STATUSES.get(kind, STATUSES)
            elif column == "phase":
                categories = _PHASES
            elif column == "group" and groups:
                categories = groups
            if categories is not None:  # a value outside the known ones is kept, never made NaN
                categories = list(categories) + [v for v in pd.unique(values.dropna()) if v not in categories]
            frame[column] = pd.Categorical(values, categories=categories)
        elif column in _TEXT:
            frame[column] = values.astype("string")
        elif _is_whole(column, kind) and pd.api.types.is_numeric_dtype(values):
            frame[column] = values.astype("int64" if not values.isna().any() else "Int64")
        elif kind in _TUNE_WHOLE and pd.api.types.is_numeric_dtype(values):
            frame[column] = values.astype("float64")  # a value or a score, whichever numbers this tune drew
        elif values.dtype == object:  # any other text (drone.name, versions.*, metrics): strings, as names are
            frame[column] = values.astype("string")
    frame.attrs["units"] = _units.units(kind, frame.columns)
    return frame


def _with_test(frames):
    """The tests' frames as one, with a `test` column first (a categorical in queue order)."""
    frames = [(name, frame) for name, frame in frames if frame is not None]
    if not frames:
        return None
    names = [name for name, _ in frames]
    parts = []
    for name, frame in frames:
        part = frame.copy()
        for column in part.columns:  # categories differ between tests: plain strings, typed again below
            if isinstance(part[column].dtype, pd.CategoricalDtype):
                part[column] = part[column].astype("string")
        part.insert(0, "test", name)
        parts.append(part)
    out = pd.concat(parts, ignore_index=True)
    out["test"] = pd.Categorical(out["test"], categories=names)
    for column in out.columns:
        if column in _CATEGORIES:  # drones.csv and fleet.csv: a drone's status
            categories = STATUSES if column == "status" else list(pd.unique(out[column].dropna()))
            out[column] = pd.Categorical(out[column], categories=categories)
    units = {}
    for _, frame in frames:
        units.update(frame.attrs.get("units", {}))
    out.attrs["units"] = {"test": "", **units}
    return out


class TestResult:
    """A finished test's output folder, OUT/<name>: its data files as DataFrames, each read on first use
    (None when the test has no such file: fleet.csv without the fleet model, drones.csv with
    --no-drones-csv). Units: df.attrs["units"]."""

    def __init__(self, folder):
        self.folder = Path(folder)
        self.name = self.folder.name
        try:
            self.config = json.loads((self.folder / "config.json").read_text())
        except (OSError, ValueError) as e:
            raise InputError(f"{self.folder / 'config.json'}: cannot be read as JSON ({e}) (allowed: the config.json salsa wrote)") from None
        groups = self.config.get("groups")
        self._groups = [g["name"] for g in groups] if isinstance(groups, list) else ["swarm"]

    def _file(self, name, kind=None):
        file = self.folder / name
        return _read_csv(file, kind or name, self._groups) if file.is_file() else None

    @cached_property
    def summary(self):
        """summary.csv: one row per logged step."""
        return self._file("summary.csv")

    @cached_property
    def outcome(self):
        """outcome.csv: the final values, one row."""
        return self._file("outcome.csv")

    @cached_property
    def drones(self):
        """drones.csv: one row per logged step and drone."""
        return self._file("drones.csv")

    @cached_property
    def targets(self):
        """targets.csv: one row per target."""
        return self._file("targets.csv")

    @cached_property
    def fleet(self):
        """fleet.csv: each drone at the end (with the fleet model only)."""
        return self._file("fleet.csv")

    @cached_property
    def trajectories(self):
        """trajectories.nc (salsa run --archive) as an xarray.Dataset over (time, drone[, xy]), lengths
        and speeds unpacked to metres; None without an archive. Needs xarray and netCDF4 (Debian:
        python3-xarray python3-netcdf4)."""
        file = self.folder / ARCHIVE
        if not file.is_file():
            return None
        import xarray  # only here: most uses of load never need it
        try:
            ds = xarray.open_dataset(file)
        except (OSError, ValueError) as e:
            raise InputError(f"{file}: cannot be read as a trajectory archive ({e}) (allowed: the trajectories.nc salsa run --archive wrote)") from None
        version = ds.attrs.get("salsa_archive_version")
        if version is None or int(version) > ARCHIVE_VERSION:
            ds.close()
            raise InputError(f"{file}: salsa_archive_version {version} is not one this package reads (allowed: 1 ... {ARCHIVE_VERSION})")
        return ds

    def __repr__(self):
        return f"<salsa test result {self.name!r} in {self.folder}>"


class QueueResult:
    """A queue's output folder, OUT: its summary.csv (one row per test), comparison files and timing,
    and every finished test's data as one DataFrame per file with a `test` column first. Each is read
    on first use; None when absent. `tests`: name -> TestResult, in queue order."""

    def __init__(self, folder):
        self.folder = Path(folder)
        order = _queue_order(self.folder)
        found = sorted(p.name for p in self.folder.iterdir() if _finished_test(p))
        names = [n for n in order if n in found] + [n for n in found if n not in order]
        self.tests = {name: TestResult(self.folder / name) for name in names}

    def _file(self, name):
        file = self.folder / name
        return _read_csv(file, "queue" if name == "summary.csv" else name) if file.is_file() else None

    @cached_property
    def summary(self):
        """The queue's summary.csv: one row per test, inputs and outcome (salsa summarize writes it)."""
        return self._file("summary.csv")

    @cached_property
    def comparison(self):
        """comparison.csv: the paired comparison of the variants."""
        return self._file("comparison.csv")

    @cached_property
    def did(self):
        """did.csv: the difference-in-differences (a queue with conditions)."""
        return self._file("did.csv")

    @cached_property
    def condition_effects(self):
        """condition_effects.csv: each variant under each condition against the baseline."""
        return self._file("condition_effects.csv")

    @cached_property
    def ranking(self):
        """ranking.csv: each cell and condition's variants by rank, how often each is best, against the best."""
        return self._file("ranking.csv")

    @cached_property
    def timing(self):
        """timing.csv: each test's wall time (s); differs between identical runs."""
        return self._file("timing.csv")

    @cached_property
    def test_summary(self):
        """The tests' summary.csv rows (one per logged step), with a `test` column."""
        return _with_test((n, t.summary) for n, t in self.tests.items())

    @cached_property
    def outcome(self):
        """The tests' outcome.csv rows, with a `test` column."""
        return _with_test((n, t.outcome) for n, t in self.tests.items())

    @cached_property
    def drones(self):
        """The tests' drones.csv rows, with a `test` column."""
        return _with_test((n, t.drones) for n, t in self.tests.items())

    @cached_property
    def targets(self):
        """The tests' targets.csv rows, with a `test` column."""
        return _with_test((n, t.targets) for n, t in self.tests.items())

    @cached_property
    def fleet(self):
        """The tests' fleet.csv rows, with a `test` column."""
        return _with_test((n, t.fleet) for n, t in self.tests.items())

    def __repr__(self):
        return f"<salsa queue result: {len(self.tests)} tests in {self.folder}>"


def _finished_test(path):
    return not path.name.startswith(".") and (path / ".salsa-test").is_file() and (path / "config.json").is_file()


def _queue_order(folder):
    """The test names of OUT/queue.json when salsa wrote it (it has configs_hash), else []."""
    try:
        record = json.loads((folder / "queue.json").read_text())
    except (OSError, ValueError):
        return []
    if not isinstance(record, dict) or "configs_hash" not in record or not isinstance(record.get("tests"), list):
        return []
    return [str(n) for n in record["tests"]]


def load(folder):
    """A salsa output folder: a test's (OUT/<name>: TestResult), a queue's (OUT: QueueResult) or a
    tune's (OUT of salsa tune: TuneResult).

    Raises salsa.InputError in one line for anything else."""
    if not isinstance(folder, (str, os.PathLike)):
        raise TypeError(f"folder: {type(folder).__name__} (allowed: a folder's path as str or os.PathLike)")
    path = Path(os.fspath(folder))
    if not path.exists():
        raise InputError(f"{path}: no such folder ({ALLOWED})")
    if not path.is_dir():
        raise InputError(f"{path}: a file, not a folder ({ALLOWED})")
    if (path / ".salsa-test").is_file():
        if not (path / "config.json").is_file():
            error = path / "error.txt"
            why = f": {error.read_text().strip()}" if error.is_file() else ""
            raise InputError(f"{path}: a test salsa has not finished (no config.json){why} ({ALLOWED}, of a finished test)")
        return TestResult(path)
    if (path / "tune.json").is_file():
        from ._tune import TuneResult  # it builds on this file's readers

        return TuneResult(path)
    if _queue_order(path) or any(_finished_test(p) for p in path.iterdir()):
        return QueueResult(path)
    raise InputError(f"{path}: not a salsa output folder (no .salsa-test marker, no queue.json salsa wrote, "
                     f"no finished test folder) ({ALLOWED})")
