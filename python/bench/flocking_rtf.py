"""The numpy flocking (examples/python/behaviors.py's PyFlocking) against the C++ flocking at 1,000
drones: the real-time factor (wall time of stepping / simulated time, lower is faster) of the same test,
the two run in turn (A/B alternated) so that a busy machine slows both alike. Not a test: figures only.

    PYTHONPATH=build/release/python /usr/bin/python3 python/bench/flocking_rtf.py [--drones 1000] [--time 20] [--rounds 3] [--threads 0]
"""

import argparse
import statistics
import sys
import time
from pathlib import Path

import salsa

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "examples" / "python"))
import behaviors  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--drones", type=int, default=1000)
    ap.add_argument("--time", type=float, default=20, help="simulated seconds per run")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--threads", type=int, default=0, help="decide threads (0: all cores)")
    args = ap.parse_args()
    salsa.register(behaviors.PyFlocking)

    def spec(name):
        # The paper's flocking (Table I's parameters) in a 2 km forest.
        return {"name": f"{name}-{args.drones}", "behavior": {"name": name, "params": {"separation_distance": 250}},
                "drone": "small", "drones": args.drones, "map": {"name": "forest", "params": {"size": 2000}},
                "targets": {"kind": "tree", "count": 1000}, "time": args.time, "log_interval": 10, "seed": 1}

    rtf = {"flocking": [], "py_flocking": []}
    found = {}
    for r in range(args.rounds):
        for name in (("flocking", "py_flocking") if r % 2 == 0 else ("py_flocking", "flocking")):
            s = salsa.Session(spec(name), threads=args.threads)
            start = time.perf_counter()
            s.run_until()
            rtf[name].append((time.perf_counter() - start) / s.time)
            found[name] = s.summary()["targets_found"]
            print(f"round {r + 1} {name:12s} RTF {rtf[name][-1]:.4f}  targets found {found[name]}", flush=True)
    cpp, py = statistics.median(rtf["flocking"]), statistics.median(rtf["py_flocking"])
    print(f"median RTF: flocking {cpp:.4f}, py_flocking {py:.4f}: {py / cpp:.2f}x")


if __name__ == "__main__":
    main()
