"""examples/python/train.py with a small budget: the learned policy finds more targets per drone than
random actions on every held-out seed (each seed flown by both)."""

import json
import os
import subprocess
import sys
from pathlib import Path

import salsa

SOURCE = Path(__file__).resolve().parents[2]


def test_learned_policy_beats_random_actions():
    env = {**os.environ, "PYTHONPATH": str(Path(salsa.__file__).resolve().parents[1])}
    # A fixed number of generations (the time budget out of reach): the same run on any machine.
    done = subprocess.run([sys.executable, str(SOURCE / "examples" / "python" / "train.py"), "--generations", "5",
                           "--budget", "600", "--eval-seeds", "6"], capture_output=True, text=True, env=env, timeout=300)
    assert done.returncode == 0, done.stderr
    result = json.loads(done.stdout.strip().splitlines()[-1])
    assert result["generations"] == 5
    learned, random = result["learned"], result["random"]
    assert len(learned) == len(random) == 6
    # Random actions jitter around the start (about 5 trees per drone); 5 generations fly out (about 18).
    assert result["paired_difference_min"] > 0
    assert result["learned_mean"] >= 2 * result["random_mean"] and result["paired_difference_mean"] >= 5
