"""Agent-steps per second of salsa.Env with a numpy policy (docs/python.md, "Reinforcement learning").

    PYTHONPATH=build/release/python /usr/bin/python3 python/bench/env_steps.py --drones 1000 --steps 600

The test: `drones` drones on an empty square map with light physics, 2,000 trees, observations of own
state, the 4 nearest neighbours and 8 obstacle sectors; the policy a random linear map with tanh.
"""

import argparse
import time

import numpy as np

import salsa


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--drones", type=int, default=1000)
    p.add_argument("--steps", type=int, default=600, help="env steps timed (after a warm-up of 20)")
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--size", type=float, default=2000, help="map side, m")
    p.add_argument("--observation", default="position,velocity,neighbours,obstacles")
    args = p.parse_args()
    test = {"name": "bench", "behavior": "random_walk", "drones": args.drones, "physics": "light", "spawn": {"mode": "uniform"},
            "map": {"name": "empty", "params": {"size": args.size}}, "targets": {"kind": "tree", "count": 2000},
            "time": 3600, "seed": 1}
    env = salsa.Env(test, observation=args.observation.split(","), threads=args.threads)
    obs = env.reset(seed=1)
    w = np.random.default_rng(0).normal(size=(env.observation_size, 2)) / np.sqrt(env.observation_size)
    for _ in range(20):
        obs, *_ = env.step(np.tanh(obs @ w).astype(np.float64))
    agent_steps = 0
    start = time.perf_counter()
    for _ in range(args.steps):
        obs, rewards, terminated, truncated, alive, info = env.step(np.tanh(obs @ w).astype(np.float64))
        agent_steps += int(alive.sum())
    elapsed = time.perf_counter() - start
    env.close()
    print(f"{args.drones} drones, {env.observation_size} features, {args.threads} threads: {args.steps} steps in "
          f"{elapsed:.2f} s, {agent_steps / elapsed:,.0f} agent-steps/s ({elapsed / args.steps * 1e3:.2f} ms per step)")


if __name__ == "__main__":
    main()
