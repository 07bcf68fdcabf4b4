#!/usr/bin/python3
"""numpy behaviors compared with the built-ins in one queue, from Python.

    PYTHONPATH=build/release/python /usr/bin/python3 examples/python/compare.py [--out results/compare] [--time 120] [--jobs 2]

Registers the numpy ports of examples/python/behaviors.py, runs a queue that sweeps them beside their
C++ originals on the forest of examples/flocking-forest.json (paired seeds: every behavior of a repeat
flies the same world), and prints salsa's paired comparison against the C++ flocking: a port's
difference from its original is zero in every repeat, as it follows it to rounding.
"""

import argparse
import json
import sys
from pathlib import Path

import salsa
from behaviors import PyFlocking, PyPheromoneAvoidance, PyRandomWalk

HERE = Path(__file__).resolve().parent


def queue(time, repeats):
    base = json.loads((HERE.parent / "flocking-forest.json").read_text())
    base.pop("behavior")
    for key in ("name", "seed"):  # the queue pairs the seeds
        base.pop(key, None)
    base["time"] = time
    return {"seed": 11, "repeats": repeats, "base": base, "reference": "flocking",
            "sweep": {"behaviors": ["flocking", "py_flocking", "random_walk", "py_random_walk",
                                    "pheromone_avoidance", "py_pheromone_avoidance"]}}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default="results/compare")
    parser.add_argument("--time", type=float, default=120.0, help="simulated seconds per test")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--jobs", type=int, default=None, help="tests at once (default: all cores)")
    args = parser.parse_args(argv)
    salsa.register(PyFlocking)
    salsa.register(PyRandomWalk)
    salsa.register(PyPheromoneAvoidance)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    file = out.parent / f"{out.name}-queue.json"
    file.write_text(json.dumps(queue(args.time, args.repeats), indent=2))
    result = salsa.run(str(file), out=out, jobs=args.jobs, force=True, plots=False)
    mean = result.summary.groupby("behavior", observed=True)["fraction_found"].agg(["mean", "std", "count"])
    print(mean.to_string(float_format=lambda v: f"{v:.4f}"))
    table = result.comparison[result.comparison["metric"] == "fraction_found"]
    print(table[["variant_a", "variant_b", "n", "mean_diff", "ci_low", "ci_high"]].to_string(index=False))
    return 0


if __name__ == "__main__":
    sys.exit(main())
