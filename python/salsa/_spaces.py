"""Spaces for salsa.ParallelEnv: gymnasium.spaces.Box when gymnasium is importable, else a small Box with
the same attributes and methods that RL code uses (low, high, shape, dtype, sample, seed, contains)."""

import numpy as np


class Box:
    """A box [low, high] of float arrays of one shape and dtype (gymnasium.spaces.Box's contract for what
    salsa uses). `sample()` draws uniformly from the space's own generator, seeded by `seed(s)`."""

    def __init__(self, low, high, shape=None, dtype=np.float32):
        self.dtype = np.dtype(dtype)
        if shape is None:
            shape = np.shape(low) if np.ndim(low) else np.shape(high)
        self.shape = tuple(int(d) for d in shape)
        self.low = np.broadcast_to(np.asarray(low, dtype=self.dtype), self.shape).copy()
        self.high = np.broadcast_to(np.asarray(high, dtype=self.dtype), self.shape).copy()
        self.np_random = np.random.default_rng()

    def seed(self, seed=None):
        self.np_random = np.random.default_rng(seed)
        return [seed]

    def sample(self, mask=None):
        lo = np.where(np.isfinite(self.low), self.low, -1.0)
        hi = np.where(np.isfinite(self.high), self.high, 1.0)
        return self.np_random.uniform(lo, hi, size=self.shape).astype(self.dtype)

    def contains(self, x):
        if not isinstance(x, np.ndarray):
            try:
                x = np.asarray(x, dtype=self.dtype)
            except (TypeError, ValueError):
                return False
        return bool(x.shape == self.shape and np.can_cast(x.dtype, self.dtype, "same_kind")
                    and np.all(x >= self.low) and np.all(x <= self.high))

    __contains__ = contains

    def __eq__(self, other):
        return (isinstance(other, Box) and self.shape == other.shape and self.dtype == other.dtype
                and np.array_equal(self.low, other.low) and np.array_equal(self.high, other.high))

    def __repr__(self):
        return f"Box({self.low.min()}, {self.high.max()}, {self.shape}, {self.dtype})"


def box(low, high, shape, dtype):
    """gymnasium.spaces.Box(low, high, shape, dtype) when gymnasium is importable, else salsa's Box."""
    try:
        from gymnasium.spaces import Box as GymBox
    except ImportError:
        return Box(low, high, shape, dtype)
    return GymBox(low, high, shape, dtype)
