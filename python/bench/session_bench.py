#!/usr/bin/python3
"""Python's overheads, each as a ratio measured in one run (A and B alternated, medians):

1. a test stepped by salsa.Session from Python against `salsa run` of the same test (no plots, no
   drones.csv), each a fresh process, start-up and plugin loading included;
2. reading a drone state column from Python at 100,000 drones against 10 drones (a view, not a copy).

    PYTHONPATH=build/release/python /usr/bin/python3 python/bench/session_bench.py [TEST] [--time S] [--rounds 5]
"""

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
import timeit
from pathlib import Path

import salsa
from salsa import _run

SOURCE = Path(__file__).resolve().parents[2]


def timed(command, env=None):
    start = time.perf_counter()
    subprocess.run(command, check=True, stdout=subprocess.DEVNULL, env=env)
    return time.perf_counter() - start


def session_against_run(test, rounds):
    program = _run.program()
    env = {**os.environ, "PYTHONPATH": str(Path(salsa.__file__).parents[1])}
    step = [sys.executable, "-c", f"import salsa; salsa.Session({str(test)!r}).run_until()"]
    with tempfile.TemporaryDirectory() as out:
        run = [program, "run", str(test), "--out", out, "--force", "--quiet", "--no-plots", "--no-drones-csv"]
        a, b = [], []
        for _ in range(rounds):  # alternated, so a slow minute of the machine hits both alike
            a.append(timed(run))
            b.append(timed(step, env))
    return statistics.median(a), statistics.median(b)


def column_read(drones):
    test = {"behavior": "random_walk", "drones": drones, "time": 1, "physics": "light",
            "map": {"name": "empty", "params": {"size": 2000}}}
    session = salsa.Session(test)
    session.step()
    n = 20000
    return min(timeit.repeat(lambda: session.column("position"), number=n, repeat=5)) / n


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("test", nargs="?", default=str(SOURCE / "examples" / "flocking-forest.json"))
    parser.add_argument("--time", type=float, help="simulated seconds (default: the test's)")
    parser.add_argument("--rounds", type=int, default=5)
    args = parser.parse_args()
    test = json.loads(Path(args.test).read_text())
    if args.time:
        test["time"] = args.time
    with tempfile.TemporaryDirectory() as folder:
        file = Path(folder) / Path(args.test).name
        file.write_text(json.dumps(test))
        if "map_file" in test or isinstance(test.get("map"), str):
            raise SystemExit("session_bench.py: a test with a map file: run it from its folder")
        measure(args, test, file)


def measure(args, test, file):
    print(f"salsa {salsa.__version__ if hasattr(salsa, '__version__') else ''} on {os.cpu_count()} cores; "
          f"test {args.test}: {test.get('drones')} drones, {test.get('time')} s simulated")
    run, step = session_against_run(file, args.rounds)
    print(f"salsa run: {run:.3f} s   salsa.Session from Python: {step:.3f} s   ratio (Session / run): {step / run:.3f}"
          f"   (medians of {args.rounds}, alternated)")
    small, large = column_read(10), column_read(100_000)
    print(f"column('position'): 10 drones {small * 1e6:.2f} us, 100,000 drones {large * 1e6:.2f} us, "
          f"ratio {large / small:.2f}")


if __name__ == "__main__":
    main()
