"""numpy ports of three built-in behaviors, written as salsa.Behavior classes (docs/python.md, "Behaviors
in Python"): PyRandomWalk (random_walk), PyFlocking (flocking) and PyPheromoneAvoidance
(pheromone_avoidance with the paper's shared field, built in prepare), with the same parameters, the
same formulas and the same draws in the same order from each drone's own stream, so a test run with
either follows its C++ original to rounding.

    import salsa, behaviors
    salsa.register(behaviors.PyFlocking)
    salsa.Session({..., "behavior": {"name": "py_flocking", "params": {"separation_distance": 60}}})
"""

import math

import numpy as np

import salsa


# ---- The SDK's steering helpers (salsa/behavior.hpp) over whole groups: rows of vectors ----

def length(v):
    """Vec2::length: sqrt(x² + y²) (not hypot, which rounds differently)."""
    return np.sqrt(v[:, 0] * v[:, 0] + v[:, 1] * v[:, 1])


def normalized(v):
    """Vec2::normalized: unit vectors, zero stays zero."""
    n = length(v)
    safe = np.where(n > 0, n, 1.0)
    return np.where((n > 0)[:, None], v / safe[:, None], 0.0)


def clamped(v, max_length):
    """Vec2::clamped: longer than max_length scaled down to it."""
    l2 = v[:, 0] * v[:, 0] + v[:, 1] * v[:, 1]
    over = l2 > max_length * max_length
    scale = np.where(over, max_length / np.sqrt(np.where(over, l2, 1.0)), 1.0)
    return np.where(over[:, None], v * scale[:, None], v)


def ground_speed_along(g, d):
    """ground_speed_along: the fastest ground speed along unit vectors d in each drone's wind."""
    w = g.wind
    across = d[:, 0] * w[:, 1] - d[:, 1] * w[:, 0]
    room = g.max_speed * g.max_speed - across * across
    along = d[:, 0] * w[:, 0] + d[:, 1] * w[:, 1]
    return np.where(room > 0, np.maximum(0.0, along + np.sqrt(np.maximum(room, 0.0))), 0.0)


def full_speed_heading(g, heading):
    """full_speed(me, heading): polar(max_speed, heading) without wind."""
    d = np.stack([np.cos(heading), np.sin(heading)], axis=1)
    calm = (g.wind == 0).all(axis=1)
    return np.where(calm[:, None], g.max_speed * d, d * ground_speed_along(g, d)[:, None])


def full_speed_direction(g, direction):
    """full_speed(me, direction): direction.with_length(max_speed) without wind."""
    d = normalized(direction)
    calm = (g.wind == 0).all(axis=1)
    return np.where(calm[:, None], d * g.max_speed, d * ground_speed_along(g, d)[:, None])


def steer_towards(g, desired):
    return clamped(desired - g.velocity, g.max_force)


def steer_along(g, direction):
    """Full speed along direction; zero where the direction is zero."""
    zero = (direction == 0).all(axis=1)
    return np.where(zero[:, None], 0.0, steer_towards(g, full_speed_direction(g, direction)))


def row_sums(rows, values, n):
    """Per row, the sum of its items' vectors, added in item order (as the C++ loops add them)."""
    return np.stack([np.bincount(rows, values[:, 0], minlength=n), np.bincount(rows, values[:, 1], minlength=n)], axis=1)


def avoid_obstacles(g):
    """Away from the ray hits, each weighted by 1/d: (p − q) / d²."""
    hits = g.obstacles
    rows = hits.row
    d = hits.distance
    keep = d > 0
    safe = np.where(keep, d * d, 1.0)
    away = np.where(keep[:, None], (g.position[rows] - hits.point) / safe[:, None], 0.0)
    return steer_along(g, row_sums(rows, away, len(g)))


def avoid_near_obstacles(g, fade=0.5):
    """avoid_obstacles faded in as the nearest hit gets closer."""
    nearest = np.full(len(g), g.obstacle_range)
    np.minimum.at(nearest, g.obstacles.row, g.obstacles.distance)
    reach = fade * g.obstacle_range
    closeness = np.maximum(0.0, 1 - nearest / reach) if reach > 0 else np.zeros(len(g))
    return (closeness * closeness)[:, None] * avoid_obstacles(g)


# ---- The behaviors ----

class PyRandomWalk(salsa.Behavior):
    """random_walk in numpy: full speed along a random heading for a random time, then a new one;
    obstacle hits close ahead make the drone turn away."""

    name = "py_random_walk"
    brief = "Random headings for random times, no communication (numpy port of random_walk)"
    parameters = [
        salsa.Param("min_duration", 2.0, (0.1, 600.0), "s", "shortest time a heading is kept"),
        salsa.Param("max_duration", 10.0, (0.1, 600.0), "s", "longest time a heading is kept"),
        salsa.Param("turn_distance", 0.33, (0.0, 1.0), "",
                    "obstacle hits closer than this fraction of obstacle range make the drone turn away"),
        salsa.Param("obstacle_avoidance_weight", 4.0, (0.0, 10.0), "", "weight of flying away from obstacle hits"),
    ]
    senses = salsa.Senses(neighbours=False, targets=False)  # obstacles only

    def reset(self, drones):
        self.heading = np.zeros(drones)
        self.time_left = np.zeros(drones)
        self.started = np.zeros(drones, dtype=bool)

    def resize(self, drones):
        old = len(self.heading)
        for name in ("heading", "time_left", "started"):
            a = getattr(self, name)
            grown = np.zeros(drones, dtype=a.dtype)
            grown[: min(old, drones)] = a[: min(old, drones)]
            setattr(self, name, grown)

    def duration(self, g, rng, where):
        """Uniform in [min_duration, max(min, max)] (Rng::uniform(lo, hi)), drawn where asked."""
        return rng.uniform(g.min_duration, max(g.min_duration, g.max_duration), where=where)

    def decide(self, g, rng):
        ids = g.id
        heading, time_left = self.heading[ids], self.time_left[ids]

        # The first step keeps the spawn velocity's heading (a random one from rest): angle, then duration.
        new = ~self.started[ids]
        if new.any():
            still = new & (g.velocity == 0).all(axis=1)
            drawn = rng.angle(where=still)
            heading = np.where(new, np.where(still, drawn, np.arctan2(g.velocity[:, 1], g.velocity[:, 0])), heading)
            time_left = np.where(new, self.duration(g, rng, new), time_left)
            self.started[ids] = True

        time_left = time_left - g.dt
        turn = time_left <= 0
        if turn.any():
            heading = np.where(turn, rng.angle(where=turn), heading)
            time_left = np.where(turn, self.duration(g, rng, turn), time_left)

        # Close hits ahead: a new heading within ±60° of straight away.
        hits = g.obstacles
        close = hits.distance < g.turn_distance * g.obstacle_range
        rows = hits.row
        away = row_sums(rows[close], normalized(g.position[rows[close]] - hits.point[close]), len(g))
        ahead = np.cos(heading) * away[:, 0] + np.sin(heading) * away[:, 1]
        flee = ~(away == 0).all(axis=1) & (ahead < 0)
        if flee.any():
            offset = rng.uniform(-np.pi / 3, np.pi / 3, where=flee)
            heading = np.where(flee, np.arctan2(away[:, 1], away[:, 0]) + offset, heading)
            time_left = np.where(flee, self.duration(g, rng, flee), time_left)

        self.heading[ids], self.time_left[ids] = heading, time_left
        return steer_towards(g, full_speed_heading(g, heading)) + g.obstacle_avoidance_weight * avoid_near_obstacles(g)


class PyFlocking(salsa.Behavior):
    """flocking in numpy: alignment, separation, cohesion and obstacle avoidance, each a steering term
    of at most max force, summed with weights."""

    name = "py_flocking"
    brief = "Reynolds boids: alignment, separation, cohesion, obstacle avoidance (numpy port of flocking)"
    parameters = [
        salsa.Param("separation_distance", 250.0, (0.0, 1000.0), "m", "neighbours closer than this push the drone away"),
        salsa.Param("alignment_weight", 1.6, (0.0, 10.0), "", "weight of matching the neighbours' mean velocity"),
        salsa.Param("cohesion_weight", 1.0, (0.0, 10.0), "", "weight of flying towards the neighbours' centre"),
        salsa.Param("separation_weight", 3.0, (0.0, 10.0), "", "weight of keeping the separation distance"),
        salsa.Param("obstacle_avoidance_weight", 4.0, (0.0, 10.0), "", "weight of flying away from obstacle hits"),
    ]
    senses = salsa.Senses(neighbours=True, targets=False)

    def decide(self, g, rng):
        n = len(g)
        nb = g.neighbours
        rows = nb.row
        count = nb.counts
        d = nb.distance
        near = (d > 0) & (d < g.separation_distance)
        safe = np.where(near, d * d, 1.0)
        push = np.where(near[:, None], (g.position[rows] - nb.position) / safe[:, None], 0.0)
        velocities = row_sums(rows, nb.velocity, n)
        positions = row_sums(rows, nb.position, n)
        away = row_sums(rows, push, n)
        alone = count == 0
        centre = positions / np.where(alone, 1, count)[:, None] - g.position
        alignment = steer_along(g, velocities)
        cohesion = steer_along(g, centre)
        separation = steer_along(g, away)
        boids = (g.alignment_weight * alignment + g.separation_weight * separation) + g.cohesion_weight * cohesion
        boids = np.where(alone[:, None], 0.0, boids)
        return boids + g.obstacle_avoidance_weight * avoid_obstacles(g)


class PyPheromoneAvoidance(salsa.Behavior):
    """pheromone_avoidance in numpy: drones mark the cells they fly over in a field that evaporates and
    steer towards the least-marked of `directions` headings ahead. `sharing` 0 (the paper's shared
    list): prepare marks every flying drone's cell in one field the group shares. `sharing` 1: each
    drone marks its own field and broadcasts where it is; what the comm model delivers is marked in
    the receiver's field."""

    name = "py_pheromone_avoidance"
    brief = "Steer towards the least-marked ground in an evaporating field (numpy port of pheromone_avoidance)"
    parameters = [
        salsa.Param("cell_size", 10.0, (1.0, 1000.0), "m", "side of one cell of the pheromone field"),
        salsa.Param("deposit", 1.0, (0.001, 1000.0), "", "pheromone a drone adds to its cell each step"),
        salsa.Param("evaporation_rate", 0.01, (0.0, 10.0), "1/s", "exponential decay rate of the pheromone"),
        salsa.Param("look_ahead", 30.0, (1.0, 1000.0), "m", "how far ahead the field is sampled"),
        salsa.Param("directions", 8, (3, 64), "", "directions sampled around the current heading", step=1),
        salsa.Param("turn_cost", 2.0, (0.0, 20.0), "",
                    "penalty of a 90 degree turn against log(1 + marks / deposit): higher flies straighter"),
        salsa.Param("obstacle_avoidance_weight", 4.0, (0.0, 10.0), "", "weight of flying away from obstacle hits"),
        salsa.Param("sharing", 0, (0, 1), "",
                    "0: one field shared by the group (global, the paper's); 1: each drone's own, merged from the messages the comm model delivers",
                    step=1),
    ]
    senses = salsa.Senses(neighbours=False, targets=False)  # obstacles only
    message_size = 2  # where the sender marked: x, y (sharing 1)
    MAX_CELLS, MAX_CELLS_PER_DRONE = 1 << 22, 1 << 18
    BLOCKED = 1e9

    def shared_state(self):
        return "radio" if self.params.sharing else "global"

    def reset(self, drones):
        self.bounds = None  # a fresh run starts with clean fields

    def resize(self, drones):
        pass  # fields outlive drones that come and go

    def evaporate(self, value, elapsed):
        rate = self.params.evaporation_rate
        return value * np.exp(-rate * elapsed) if rate > 0 else value

    def prepare(self, world):
        own = self.params.sharing == 1
        if self.bounds != world.bounds or self.built != (self.params.cell_size, own):
            self.build(world.bounds, own)
        ids = np.flatnonzero((world.group == world.own_group) & (world.status == 0))
        if own:  # each drone its own cell in its own field
            self.grow(len(world))
            self.mark(ids, self.index(world.position[ids]), world.time)
        else:  # every drone's cell in the group's field (row 0), in id order as the C++ marks them
            cells = self.index(world.position[ids])
            touched = np.unique(cells)
            self.mark(np.zeros(len(touched), dtype=np.int64), touched, world.time, deposit=0.0)
            np.add.at(self.value[0], cells, self.params.deposit)

    def build(self, bounds, own):
        x0, y0, x1, y1 = bounds
        w, h = x1 - x0, y1 - y0
        most = self.MAX_CELLS_PER_DRONE if own else self.MAX_CELLS
        self.cell = max(self.params.cell_size, math.sqrt(w * h / most), max(w, h) / most)
        self.cols, self.rows = int(math.ceil(w / self.cell)) + 1, int(math.ceil(h / self.cell)) + 1
        self.value = np.zeros((0 if own else 1, self.cols * self.rows))  # one row per field
        self.time = np.zeros_like(self.value)
        self.bounds, self.built = bounds, (self.params.cell_size, own)

    def grow(self, drones):
        """Own fields (sharing 1): one row per drone id, clean when first made."""
        if len(self.value) < drones:
            more = np.zeros((drones - len(self.value), self.cols * self.rows))
            self.value, self.time = np.vstack([self.value, more]), np.vstack([self.time, more])

    def field(self, ids):
        """The row of the field each drone reads and marks: its own, or the group's."""
        return ids if self.built[1] else np.zeros(len(ids), dtype=np.int64)

    def mark(self, rows, cells, t, deposit=None):
        """`deposit` at cells[i] of field rows[i] at times t (distinct (row, cell) pairs): a mark older
        than the cell's last update (a late message) is added as what is left of it now."""
        deposit = self.params.deposit if deposit is None else deposit
        value, time = self.value[rows, cells], self.time[rows, cells]
        late = t < time
        age = np.abs(t - time)  # both branches are computed: neither may evaporate backwards (overflow)
        self.value[rows, cells] = np.where(late, value + self.evaporate(deposit, age), self.evaporate(value, age) + deposit)
        self.time[rows, cells] = np.where(late, time, t)

    def index(self, p):
        x0, y0 = self.bounds[:2]
        x = np.clip(((p[:, 0] - x0) / self.cell).astype(np.int64), 0, self.cols - 1)
        y = np.clip(((p[:, 1] - y0) / self.cell).astype(np.int64), 0, self.rows - 1)
        return y * self.cols + x

    def marks(self, rows, p, t):
        c = self.index(p)
        value = self.value[rows, c]
        return np.where(value > 0, self.evaporate(value, t - self.time[rows, c]), 0.0)

    def receive(self, g):
        """sharing 1: each drone marks what its messages say, in their order, then broadcasts where it is."""
        m = g.messages
        at = m.payload_offsets[:-1]
        use = (m.group == g.group) & (np.diff(m.payload_offsets) == 2)
        points = np.stack([m.payload[np.where(use, at, 0)], m.payload[np.where(use, at + 1, 0)]], axis=1)
        rank = np.arange(len(m.sender)) - m.offsets[m.row]  # each message's place among its drone's
        for k in range(int(m.counts.max(initial=0))):  # the k-th message of every drone at once
            now = use & (rank == k)
            self.mark(g.id[m.row[now]], self.index(points[now]), m.time[now])
        g.broadcast(g.position)

    def decide(self, g, rng):
        if self.built[1]:
            self.receive(g)
        n = int(g.directions)
        turns = [(math.cos(2 * math.pi * k / n), math.sin(2 * math.pi * k / n)) for k in range(n)]
        cone, margin = math.cos(2 * math.pi / n), g.look_ahead / 3
        x0, y0, x1, y1 = self.bounds
        fields = self.field(g.id)
        still = (g.velocity == 0).all(axis=1)
        drawn = rng.angle(where=still)
        heading = np.where(still[:, None], np.stack([np.cos(drawn), np.sin(drawn)], axis=1), normalized(g.velocity))
        hits, rows = g.obstacles, g.obstacles.row
        best_score, best = np.zeros(len(g)), np.zeros((len(g), 2))
        for k, (c, s) in enumerate(turns):
            d = np.stack([heading[:, 0] * c - heading[:, 1] * s, heading[:, 0] * s + heading[:, 1] * c], axis=1)
            # Sample short of any obstacle that way; blocked right ahead, or out of the area: maximally marked.
            reach = np.full(len(g), g.look_ahead)
            to_hit = hits.point - g.position[rows]
            blocking = d[rows, 0] * to_hit[:, 0] + d[rows, 1] * to_hit[:, 1] > cone * hits.distance
            np.minimum.at(reach, rows[blocking], hits.distance[blocking] - margin)
            ahead = g.position + d * reach[:, None]
            inside = (reach >= margin) & (ahead[:, 0] >= x0) & (ahead[:, 0] <= x1) & (ahead[:, 1] >= y0) & (ahead[:, 1] <= y1)
            score = np.where(inside, np.log1p(self.marks(fields, ahead, g.time) / g.deposit), self.BLOCKED)
            score = score + (g.turn_cost * (1 - c) + rng.uniform(0, 0.1))  # jitter breaks symmetric ties
            better = (score < best_score) | (k == 0)
            best_score, best = np.where(better, score, best_score), np.where(better[:, None], d, best)
        return steer_along(g, best) + g.obstacle_avoidance_weight * avoid_near_obstacles(g)
