"""The observation features salsa.Env offers (docs/python.md, "Reinforcement learning"): each one a
fixed number of float columns per drone, computed in numpy from the group's perception batch (what
the drone perceives when it decides), scaled to about [-1, 1]. Lists are padded to a fixed count."""

import numpy as np

from ._core import _nearest  # a partial sort per row, in C++


class Feature:
    """One declared feature: `name`, `count` (items kept, for the lists), `width` (columns) and
    `columns` (their names)."""

    def __init__(self, name, count, columns, compute, senses=()):
        self.name, self.count, self.compute, self.senses = name, count, compute, tuple(senses)
        self.columns = list(columns)
        self.width = len(self.columns)

    def __repr__(self):
        return f"Feature({self.name!r}, count={self.count}, width={self.width})"


def _gather(index, width, fill):
    """(n, k, width) zeros, `fill(items, rows)` written where index >= 0 (items: the chosen items,
    rows: their drone's row)."""
    out = np.zeros(index.shape + (width,))
    has = index >= 0
    out[has] = fill(index[has], np.nonzero(has)[0])
    return out.reshape(len(index), -1)


def _position(g, ctx):
    return (g.position - ctx.centre) / ctx.half


def _velocity(g, ctx):
    return g.velocity / g.max_speed


def _battery(g, ctx):
    cap = g.battery_capacity
    if not np.isfinite(cap) or cap <= 0:
        return np.ones((len(g), 1))
    return np.clip(g.battery / cap, 0.0, 1.0)[:, None]


def _time(g, ctx):
    return np.full((len(g), 1), min(1.0, g.time / ctx.end_time) if ctx.end_time > 0 else 0.0)


def _neighbours(k):
    def compute(g, ctx):
        nb = g.neighbours
        index = _nearest(nb.offsets, nb.distance, k)  # (n, k), nearest first, -1 past the row's items
        reach = g.detection_range if g.detection_range > 0 else 1.0

        def fill(items, rows):
            return np.concatenate([(nb.position[items] - g.position[rows]) / reach,
                                   (nb.velocity[items] - g.velocity[rows]) / g.max_speed, np.ones((len(items), 1))], axis=1)
        return _gather(index, 5, fill)
    return compute


def _targets(k):
    def compute(g, ctx):
        t = g.targets
        index = _nearest(t.offsets, t.distance, k)
        reach = g.camera_range if g.camera_range > 0 else 1.0

        def fill(items, rows):
            return np.concatenate([(t.position[items] - g.position[rows]) / reach, t.found[items, None].astype(float),
                                   np.ones((len(items), 1))], axis=1)
        return _gather(index, 4, fill)
    return compute


def _obstacles(k):
    def compute(g, ctx):
        # The ray hits binned into k equal sectors of direction (sector 0 starts at +x, counter-clockwise):
        # per sector 1 − d / obstacle range of its nearest hit, 0 where nothing is in reach.
        hits = g.obstacles
        rows = hits.row
        out = np.zeros((len(g), k))
        if len(rows) == 0:
            return out
        away = hits.point - g.position[rows]
        angle = np.mod(np.arctan2(away[:, 1], away[:, 0]), 2 * np.pi)
        sector = np.minimum((angle / (2 * np.pi) * k).astype(np.intp), k - 1)
        reach = g.obstacle_range if g.obstacle_range > 0 else 1.0
        closeness = np.clip(1.0 - hits.distance / reach, 0.0, 1.0)
        np.maximum.at(out, (rows, sector), closeness)
        return out
    return compute


def _messages(g, ctx):
    m = g.messages
    n = len(g)
    rows = m.row
    count = m.counts.astype(float)
    reach = g.detection_range if g.detection_range > 0 else 1.0
    sums = np.stack([np.bincount(rows, m.offset[:, 0], minlength=n), np.bincount(rows, m.offset[:, 1], minlength=n)], axis=1)
    mean = sums / np.maximum(count, 1)[:, None] / reach
    return np.concatenate([(count / (count + 4))[:, None], mean], axis=1)  # 0 none, 0.5 at 4, towards 1


def _xy(prefix, count, fields):
    return [f"{prefix}{i}.{f}" for i in range(count) for f in fields]


# name -> (default count or None for a fixed feature, maker(count) -> Feature)
OPTIONS = {
    "position": (None, lambda k: Feature("position", 1, ["x", "y"], _position)),
    "velocity": (None, lambda k: Feature("velocity", 1, ["vx", "vy"], _velocity)),
    "battery": (None, lambda k: Feature("battery", 1, ["battery"], _battery)),
    "time": (None, lambda k: Feature("time", 1, ["time"], _time)),
    "messages": (None, lambda k: Feature("messages", 1, ["received", "mean_dx", "mean_dy"], _messages)),
    "neighbours": (4, lambda k: Feature("neighbours", k, _xy("neighbour", k, ("dx", "dy", "dvx", "dvy", "present")),
                                        _neighbours(k), senses=("neighbours",))),
    "targets": (3, lambda k: Feature("targets", k, _xy("target", k, ("dx", "dy", "found", "present")), _targets(k),
                                     senses=("targets",))),
    "obstacles": (8, lambda k: Feature("obstacles", k, [f"sector{i}" for i in range(k)], _obstacles(k))),
}

ALLOWED = ("position, velocity, battery, time, messages, neighbours, targets, obstacles "
           "(a list of them; the lists may be given with a count: ('neighbours', 4))")


def parse(observation):
    """The `observation` argument as a list of Features, or ValueError/TypeError naming what is allowed."""
    if isinstance(observation, str) or (isinstance(observation, tuple) and len(observation) == 2
                                        and isinstance(observation[1], (int, np.integer))):
        observation = [observation]  # one feature
    if not isinstance(observation, (list, tuple)) or not observation:
        raise TypeError(f"observation: {type(observation).__name__} (allowed: a non-empty list of {ALLOWED})")
    features, seen = [], set()
    for item in observation:
        count = None
        if isinstance(item, tuple):
            if len(item) != 2 or not isinstance(item[0], str):
                raise TypeError(f"observation: {item!r} (allowed: a name, or (name, count) for {ALLOWED})")
            item, count = item
        if not isinstance(item, str):
            raise TypeError(f"observation: {type(item).__name__} {item!r} (allowed: {ALLOWED})")
        if item not in OPTIONS:
            raise ValueError(f"observation: '{item}' is not a feature (allowed: {ALLOWED})")
        if item in seen:
            raise ValueError(f"observation: '{item}' given twice (allowed: each feature once)")
        seen.add(item)
        default, make = OPTIONS[item]
        if count is not None:
            if default is None:
                raise ValueError(f"observation: '{item}' takes no count (allowed a count: neighbours, targets, obstacles)")
            if isinstance(count, bool) or not isinstance(count, (int, np.integer)) or not 1 <= count <= 64:
                raise ValueError(f"observation: ('{item}', {count!r}): count out of range (allowed: a whole number in [1, 64])")
        features.append(make(int(count) if count is not None else default))
    return features
