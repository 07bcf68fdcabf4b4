"""The units of every column salsa writes: the one table salsa.load reads them from.

The data files' own columns are as docs/output-format.md's tables give them; a test's numbers
(drone.*, the models' fields, plugin parameters) come from their declarations in the core and the
loaded plugins (salsa._core.input_units), so this file never repeats them. "" means a count, an id,
a fraction, a flag or a name.
"""

import re

from . import _core

_OUTCOME = {
    "targets": "", "targets_found": "", "fraction_found": "",
    # the built-in metrics' columns
    "coverage": "", "time_to_50": "s", "time_to_90": "s", "time_to_100": "s", "mean_distance": "m",
    "collisions": "",
    # the fleet, sensor noise and comm models' columns
    "alive": "", "energy_used_Wh": "Wh", "charging_s": "s", "false_detections": "",
    "messages_sent": "", "messages_delivered": "", "dropped_range": "", "dropped_obstacle": "",
    "dropped_loss": "", "dropped_cap": "",
}

# One table per data file, by file name; "queue" is a queue's summary.csv (one row per test).
FILES = {
    "summary.csv": {
        "time": "s", "targets_found": "", "fraction_found": "", "mean_speed": "m/s", "max_speed": "m/s",
        "mean_nn_distance": "m", "collisions": "", "coverage": "", "mean_distance": "m",
        **{k: v for k, v in _OUTCOME.items() if k not in ("targets", "time_to_50", "time_to_90", "time_to_100")},
    },
    "outcome.csv": _OUTCOME,
    "drones.csv": {"time": "s", "id": "", "x": "m", "y": "m", "vx": "m/s", "vy": "m/s", "group": "",
                   "status": "", "energy_used_Wh": "Wh", "charging_s": "s"},
    "targets.csv": {"id": "", "x": "m", "y": "m", "found_time": "s", "found_by": "", "observations": "", "found_x": "m", "found_y": "m"},
    "fleet.csv": {"id": "", "group": "", "status": "", "since": "s", "energy_used_Wh": "Wh", "battery_left": "", "charging_s": "s"},
    "timing.csv": {"name": "", "wall_seconds": "s"},
    "queue": {
        "name": "", "status": "", "error": "", "cell": "", "variant": "", "condition": "", "condition_label": "",
        "behavior": "", "repeat": "", "seed": "", "drones": "", "targets": "", "target": "", "map": "",
        "time": "s", "dt": "s", "log_interval": "s", "velocity_iterations": "", "position_iterations": "",
        "decision_lag": "", "spawn.mode": "", "spawn.radius": "m", "spawn.point": "m", "physics": "",
        "contact_handlers": "", "metrics": "", "drone.name": "", "wind.velocity": "m/s", "wind.field.name": "",
    },
    # comparison.csv, did.csv, condition_effects.csv and ranking.csv: the means and differences are in the unit of
    # the row's metric, which varies by row, so only the fixed columns have one.
    "comparison.csv": {"cell": "", "condition": "", "drones": "", "targets": "", "target": "", "map": "", "time": "s",
                       "metric": "", "variant_a": "", "variant_b": "", "n": "", "win_rate_a": ""},
    "did.csv": {"cell": "", "drones": "", "targets": "", "target": "", "map": "", "time": "s", "metric": "",
                "variant_a": "", "variant_b": "", "baseline": "", "condition": "", "n": ""},
    "condition_effects.csv": {"cell": "", "drones": "", "targets": "", "target": "", "map": "", "time": "s", "metric": "",
                              "variant": "", "baseline": "", "condition": "", "n": "", "win_rate": ""},
    "ranking.csv": {"cell": "", "condition": "", "drones": "", "targets": "", "target": "", "map": "", "time": "s", "metric": "",
                    "rank": "", "variant": "", "n": "", "repeats": "", "best_share": "", "n_vs_best": "", "differs_from_best": ""},
    # A tune's files: their other columns are the parameters (test keys) and the objectives (columns
    # of outcome.csv or summary.csv).
    "tune.csv": {"evaluation": "", "candidate": "", "phase": "", "world": "", "seed": "", "status": "", "test": ""},
    "candidates.csv": {"candidate": "", "generation": "", "status": "", "worlds": "", "evaluations": ""},
}

# A tune parameter's key (a test key, as timed changes write it) -> the key its unit is declared under.
_PARAMETER = [(re.compile(r"^groups\.[^.]+\."), ""), (re.compile(r"^(behavior|map)\.params\."), r"\1."),
              (re.compile(r"^targets\.params\."), "target.")]

_GROUP = re.compile(r"^groups\.[^.]+\.(.*)$")


def units(file, columns):
    """column -> unit for the columns of `file` (a key of FILES) whose unit is known."""
    table = FILES[file]
    declared = None
    out = {}
    for column in columns:
        name = column
        if file == "queue":
            name = column[len("outcome."):] if column.startswith("outcome.") else column
            group = _GROUP.match(name)
            if group:  # groups.<name>.<field>: the single form's field
                name = group.group(1)
        if name in table:
            out[column] = table[name]
            continue
        if file == "queue" and name in _OUTCOME:
            out[column] = _OUTCOME[name]
            continue
        if file in ("summary.csv", "outcome.csv", "queue") and name.endswith(".energy_used_Wh"):
            out[column] = "Wh"  # <group>.energy_used_Wh
            continue
        if file in ("summary.csv", "outcome.csv", "queue") and name.endswith(".charging_s"):
            out[column] = "s"  # <group>.charging_s (return to base)
            continue
        if file in ("summary.csv", "outcome.csv", "queue") and (name.endswith(".found") or name.endswith(".alive")):
            out[column] = ""
            continue
        if file == "drones.csv":  # --drone-columns: a state column, or <name>_x / <name>_y of a vector
            declared_columns = _core.declared_columns()
            base = name[:-2] if name.endswith(("_x", "_y")) else name
            for key in (name, base):
                if key in declared_columns and (key == name) == (declared_columns[key][1] == 1):
                    out[column] = declared_columns[key][0]
                    break
            continue
        if file in ("tune.csv", "candidates.csv"):
            column_name = name.split("@")[0]  # an objective read at a time: coverage@60
            objective = FILES["summary.csv"].get(column_name, _OUTCOME.get(column_name))
            if objective is not None:
                out[column] = objective
                continue
            if declared is None:
                declared = _core.input_units()
            key = name
            for pattern, replacement in _PARAMETER:
                key = pattern.sub(replacement, key)
            if key in declared:
                out[column] = declared[key]
            elif key == "drones":
                out[column] = ""
            continue
        if file == "queue":
            if declared is None:
                declared = _core.input_units()
            if name in declared:
                out[column] = declared[name]
            elif name.startswith("versions.") or name == "map.file":
                out[column] = ""
    return out
