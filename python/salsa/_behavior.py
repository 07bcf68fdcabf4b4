"""Behaviors written in Python (docs/python.md, "Behaviors in Python"): the base class, the
declarations a behavior makes (its parameters and what it senses) and what `decide` is handed."""

import math
import numbers

import numpy as np


class Param:
    """A declared parameter, as a C++ plugin declares one: its name, default, allowed range
    (min, max), SI unit ("" for a plain number), meaning, and slider step (1: a whole number)."""

    __slots__ = ("name", "default", "range", "unit", "meaning", "step")

    def __init__(self, name, default, range, unit="", meaning="", step=0.0):
        if not isinstance(name, str):
            raise TypeError(f"Param name: {type(name).__name__} (allowed: str)")
        for what, v in (("default", default), ("step", step)):
            if not isinstance(v, numbers.Real) or isinstance(v, bool) or not math.isfinite(v):
                raise TypeError(f"Param {name!r}: {what} {v!r} (allowed: a finite number)")
        try:
            lo, hi = range
        except (TypeError, ValueError):
            raise TypeError(f"Param {name!r}: range {range!r} (allowed: (min, max))") from None
        for v in (lo, hi):
            if not isinstance(v, numbers.Real) or isinstance(v, bool):
                raise TypeError(f"Param {name!r}: range {range!r} (allowed: (min, max), two numbers)")
        if not isinstance(unit, str) or not isinstance(meaning, str):
            raise TypeError(f"Param {name!r}: unit and meaning are str")
        self.name, self.default, self.range = name, float(default), (float(lo), float(hi))
        self.unit, self.meaning, self.step = unit, meaning, float(step)

    def __repr__(self):
        return f"Param({self.name!r}, {self.default!r}, {self.range!r}, {self.unit!r}, {self.meaning!r})"


class Senses:
    """What `decide` reads besides the drone's own fields and obstacle hits (always there): the core
    gathers only these; a list not declared stays empty."""

    __slots__ = ("neighbours", "targets")

    def __init__(self, neighbours=True, targets=True):
        self.neighbours, self.targets = bool(neighbours), bool(targets)

    def __repr__(self):
        return f"Senses(neighbours={self.neighbours}, targets={self.targets})"


class Behavior:
    """Base of a behavior written in Python; register the class with salsa.register.

    Class attributes: `name` (how tests name it), `brief`, `parameters` (a list of Param), `senses`
    (a Senses), `shared_state` ("none", the default; "global": state built from all drones at once;
    "radio": shared only through messages; docs/plugins.md, Shared state; or a method shared_state(self)
    returning one from self.params), `message_size` (the most
    doubles one message holds, 0 to 64; 0, the default: its drones never broadcast). The core makes
    one instance per group that uses it, sets `params` (a Group-like namespace of the values) and
    calls:

      reset(drones)        drones (re)spawned: ids 0..drones-1, fresh memory (keep it in arrays by id)
      resize(drones)       the drone count changed, the others fly on (default: reset)
      prepare(world)       once per step before any decide: shared state from the whole World
                           (Behavior::prepare; default: nothing, and then not called)
      decide(group, rng)   once per step for the group's flying drones: return their steering, an
                           (N, 2) float64 array, m/s (Behavior::decide's velocity change), row r for
                           drone group.id[r]; group.broadcast(payload, where=None) sends row r's
                           message payload[r] ((N, K), K <= message_size) during the call
    """

    name = None
    brief = ""
    parameters = ()
    senses = Senses()
    shared_state = "none"
    message_size = 0

    def reset(self, drones):
        pass

    def resize(self, drones):
        self.reset(drones)

    def prepare(self, world):
        pass

    def decide(self, group, rng):
        raise NotImplementedError(f"{type(self).__name__}.decide")


class Rows:
    """One list per drone as flat arrays: row r's items are [offsets[r], offsets[r + 1])."""

    def __len__(self):
        return len(self.offsets) - 1

    @property
    def counts(self):
        """Items per row, (N,)."""
        return np.diff(self.offsets)

    @property
    def row(self):
        """Each item's row, (M,): index the drone's own arrays with it."""
        return np.repeat(np.arange(len(self), dtype=np.intp), self.counts)

    def __repr__(self):
        fields = ", ".join(k for k in self.__dict__ if k != "offsets")
        return f"<salsa.Rows: {len(self)} rows, {int(self.offsets[-1])} items: {fields}>"


class Group:
    """A group's flying drones this step, as `decide` gets them (docs/python.md lists the fields).
    Arrays are read-only views of what the core gathered, valid while referenced."""

    def __len__(self):
        return len(self.id)

    def __repr__(self):
        return f"<salsa.Group {self.group}: {len(self)} drones at t = {self.time} s>"


class World:
    """Every drone this step, as `prepare` gets it (docs/python.md lists the fields). The arrays are
    copies, indexed by drone id (yours to keep). Two questions to the map, during the prepare call
    only: is_free(points, clearance=0) and ray_cast(start, end) (salsa.WorldQueries)."""

    def __len__(self):
        return len(self.group)

    def __repr__(self):
        return f"<salsa.World: {len(self)} drones in {self.group_count} group(s) at t = {self.time} s>"
