"""Learns where to fly to find targets: a linear policy over salsa.Env's observations, trained by an
evolution strategy in numpy, then compared with random actions on held-out seeds (docs/python.md,
"Reinforcement learning").

    PYTHONPATH=build/release/python /usr/bin/python3 examples/python/train.py --budget 110

The task: 4 small drones on an empty 300 m square with 400 trees for 20 s; each decides every 10
steps (1/6 s) on its position, velocity, its 2 nearest neighbours and 4 obstacle sectors (the walls), an
action being the desired velocity as a fraction of the top speed; the reward is the trees each drone
finds. Random actions jitter around the start; a learned policy flies out, keeps apart and turns at
the walls. The last line printed is a JSON summary (the test reads it).
"""

import argparse
import json
import time
from concurrent.futures import ProcessPoolExecutor

import numpy as np

import salsa

TEST = {"name": "train", "behavior": "random_walk", "drones": 4, "physics": "light",
        "map": {"name": "empty", "params": {"size": 300}}, "targets": {"kind": "tree", "count": 400}, "time": 20}
OBSERVATION = ["position", "velocity", ("neighbours", 2), ("obstacles", 4)]
REPEAT = 10

_env = None


def env():
    """One Env per process (a worker's own)."""
    global _env
    if _env is None:
        _env = salsa.Env(TEST, observation=OBSERVATION, reward="found", action_repeat=REPEAT, threads=1)
    return _env


def act(theta, obs):
    """The policy: tanh(obs · W + b), W (k, 2) and b (2,) packed in theta."""
    k = obs.shape[1]
    w, b = theta[: 2 * k].reshape(k, 2), theta[2 * k:]
    return np.tanh(obs @ w + b)


def episode(theta, seed):
    """Targets found per drone in one episode: the policy theta, or random actions when theta is None."""
    e = env()
    obs = e.reset(seed=seed)
    rng = np.random.default_rng(seed)
    found = 0.0
    while e.alive.any():
        actions = rng.uniform(-1, 1, (e.num_agents, 2)) if theta is None else act(theta, obs.astype(np.float64))
        obs, rewards, *_ = e.step(actions)
        found += float(rewards.sum())
    return found / e.num_agents


def score(job):
    theta, seeds = job
    return float(np.mean([episode(theta, s) for s in seeds]))


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--budget", type=float, default=110, help="training time, s (the evaluation comes after)")
    p.add_argument("--generations", type=int, default=1000, help="at most this many (the budget stops earlier)")
    p.add_argument("--population", type=int, default=8, help="antithetic pairs per generation")
    p.add_argument("--train-seeds", type=int, default=2, help="episodes per candidate (seeds change each generation)")
    p.add_argument("--eval-seeds", type=int, default=8, help="held-out seeds, each flown by both policies")
    p.add_argument("--workers", type=int, default=2)
    p.add_argument("--sigma", type=float, default=0.5)
    p.add_argument("--lr", type=float, default=0.3)
    p.add_argument("--seed", type=int, default=0)
    args = p.parse_args()

    k = env().observation_size
    rng = np.random.default_rng(args.seed)
    theta = rng.normal(0, 0.1, 2 * k + 2)
    start = time.perf_counter()
    generation = 0
    with ProcessPoolExecutor(args.workers) as pool:
        while generation < args.generations and time.perf_counter() - start < args.budget:
            seeds = [int(s) for s in rng.integers(0, 10**6, args.train_seeds)]  # training seeds: below 10^6
            noise = rng.normal(0, 1, (args.population, theta.size))
            candidates = [theta + args.sigma * n for n in noise] + [theta - args.sigma * n for n in noise]
            scores = np.array(list(pool.map(score, [(c, seeds) for c in candidates])))
            # Centred ranks: the step does not depend on the scores' scale.
            ranks = np.empty(len(scores))
            ranks[np.argsort(scores)] = np.arange(len(scores))
            ranks = ranks / (len(scores) - 1) - 0.5
            weights = ranks[: args.population] - ranks[args.population:]
            theta = theta + args.lr / (args.population * args.sigma) * (weights @ noise)
            generation += 1
            print(f"generation {generation}: mean {scores.mean():.2f}, best {scores.max():.2f} targets per drone, "
                  f"{time.perf_counter() - start:.0f} s", flush=True)
        trained = time.perf_counter() - start
        held_out = [10**6 + i for i in range(args.eval_seeds)]  # never trained on
        learned = list(pool.map(score, [(theta, [s]) for s in held_out]))
        random = list(pool.map(score, [(None, [s]) for s in held_out]))
    diff = np.array(learned) - np.array(random)
    print(json.dumps({"generations": generation, "train_seconds": round(trained, 1), "held_out_seeds": held_out,
                      "learned": learned, "random": random, "learned_mean": float(np.mean(learned)),
                      "random_mean": float(np.mean(random)), "paired_difference_mean": float(diff.mean()),
                      "paired_difference_min": float(diff.min())}))


if __name__ == "__main__":
    main()
