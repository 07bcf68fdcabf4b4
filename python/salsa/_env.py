"""salsa.Env: one group of a test driven from Python by reinforcement-learning code, its drones on the
array axis (docs/python.md, "Reinforcement learning").

The group's behavior is an internal Python behavior that hands its perception batch over and waits
for the actions: a thread steps the Session and, inside that decide, parks while the caller's step()
computes the observations and sets the actions. So an observation is exactly what the drone perceives
for the decision its action becomes, and step(actions) is: that decide returns the actions, the step
runs on (act, physics, detection) and the next step runs to its decide of the group, whose batch is the
next observation. Nothing of the core changes: the same seed and the same actions give the same
episode, and a test run by `salsa run` with a behavior deciding as the actions did gives the same data.
"""

import atexit
import json
import math
import os
import threading
import weakref

import numpy as np

from . import _features
from ._behavior import Behavior, Param, Senses
from ._core import Session, register_behavior

ACTIONS = ("velocity", "steering")
_channels = {}  # channel number -> _Channel: how a behavior instance finds its Env
_next_channel = [1]
_registered = set()
_open = weakref.WeakSet()  # the Envs with an episode's thread, closed at exit before Python finalises


@atexit.register
def _close_all():
    # A stepping thread still parked at exit would be stopped inside C++ frames by the finalising
    # interpreter (std::terminate): end the episodes first.
    for env in list(_open):
        env.close()


class _Aborted(Exception):
    """Raised in the parked decide to unwind the stepping thread (reset, close)."""


def _agent_class(neighbours, targets):
    """The internal behavior for what the observation senses, registered once per process."""
    name = "rl_agent" + ("_neighbours" if neighbours else "") + ("_targets" if targets else "")

    class Agent(Behavior):
        brief = "Driven by salsa.Env's step(actions) from Python (internal)"
        parameters = [Param("channel", 0.0, (0.0, 1e9), "", "the Env that drives it (internal)", 1.0)]
        senses = Senses(neighbours=neighbours, targets=targets)

        def decide(self, group, rng):
            channel = _channels.get(int(self.params.channel))
            if channel is None:
                raise RuntimeError("no salsa.Env drives this group (the rl_agent behaviors are salsa.Env's own)")
            return channel.decide(group)

    Agent.name = name
    Agent.__qualname__ = Agent.__name__ = "Agent_" + name
    register_behavior(Agent)
    _registered.add(name)
    return name


def _agent_behavior(neighbours, targets):
    """The internal behavior's name; all four are registered at once, at the first Env, as registering
    is refused while a Session steps (and an Env's session is mid-step between two env steps)."""
    if not _registered:
        for n in (False, True):
            for t in (False, True):
                _agent_class(n, t)
    return "rl_agent" + ("_neighbours" if neighbours else "") + ("_targets" if targets else "")


class _Channel:
    """The hand-over between the caller's thread and the thread stepping the session: two locks, each
    released by one side and taken by the other, so exactly one side runs at a time."""

    def __init__(self, env, session):
        self._env, self.session = weakref.ref(env), session  # weak: a dropped Env closes its episode
        self.to_main, self.to_worker = threading.Lock(), threading.Lock()
        self.to_main.acquire()
        self.to_worker.acquire()
        self.abort = False
        self.group = None      # the batch of the parked decide
        self.steering = None   # what that decide returns
        self.decisions = 0
        self.ended = False     # the stepping stopped: no drone of the group flies any more
        self.error = None
        self.held = 0          # steps left of the current action (action_repeat)

    def decide(self, group):
        if self.abort:
            raise _Aborted("salsa.Env: episode closed")
        self.decisions += 1
        env = self._env()
        if env is None:
            raise _Aborted("salsa.Env: dropped")
        if self.held > 0 and group.time < env.end_time - group.dt / 2:
            # the same action held over another step, steered from this step's velocity
            self.held -= 1
            return env._steer(group)
        del env
        self.group = group
        self.session._park(True)
        self.to_main.release()
        self.to_worker.acquire()
        self.session._park(False)
        self.group = None
        if self.abort:
            raise _Aborted("salsa.Env: episode closed")
        return self.steering

    def run(self):
        try:
            while not self.abort:
                before = self.decisions
                self.session.step(1)
                if self.decisions == before:  # no decide: the group has no flying drone left
                    self.ended = True
                    break
        except BaseException as e:  # noqa: BLE001 - handed to the caller's thread
            if not self.abort:
                self.error = e
        finally:
            if not self.abort:
                self.to_main.release()

    def wait(self):
        """The caller's side: until the worker parks in the next decide, ends or fails."""
        self.to_main.acquire()
        if self.error is not None:
            raise self.error

    def go(self):
        self.to_worker.release()


def _read_test(test):
    """A test as a dict, its file paths absolute (a file's relative to its folder)."""
    if isinstance(test, dict):
        data, folder = json.loads(json.dumps(test)), os.getcwd()
    elif isinstance(test, (str, os.PathLike)):
        path = os.fsdecode(test)
        with open(path, encoding="utf-8") as f:
            data = json.load(f)
        if not isinstance(data, dict):
            raise ValueError(f"test: {path} holds no single test (allowed: a file holding one test object)")
        folder = os.path.dirname(os.path.abspath(path))
    else:
        raise TypeError(f"test: {type(test).__name__} (allowed: a test file's path, or a dict holding a test)")

    def absolute(value):
        return os.path.join(folder, value) if isinstance(value, str) and value and not os.path.isabs(value) else value

    if isinstance(data.get("map"), str) and data["map"].endswith(".json"):
        data["map"] = absolute(data["map"])
    elif isinstance(data.get("map"), dict) and "file" in data["map"]:
        data["map"] = {**data["map"], "file": absolute(data["map"]["file"])}
    if "drone_configs" in data:
        data["drone_configs"] = absolute(data["drone_configs"])
    return data


def _map_bounds(test):
    """((min x, min y), (max x, max y)) of the test's map: a generated square of side `size` from the
    origin (empty, forest), or a map file's bounds; None when the map is not one of these."""
    m = test.get("map", {"name": "empty"})
    if isinstance(m, dict) and "name" in m and m["name"] in ("empty", "forest"):
        size = float(m.get("params", {}).get("size", 500))
        return (0.0, 0.0), (size, size)
    file = m if isinstance(m, str) else m.get("file") if isinstance(m, dict) else None
    if isinstance(file, str) and os.path.isfile(file):
        with open(file, encoding="utf-8") as f:
            b = json.load(f).get("bounds", {})
        if "min" in b and "max" in b:
            return tuple(map(float, b["min"])), tuple(map(float, b["max"]))
    return None


class Env:
    """One group of a test as a batched RL environment: N agents (the group's drones at the start, in id
    order) on the first axis of every array (docs/python.md, "Reinforcement learning").

    Env(test, observation=["position", "velocity"], reward="found", group=None, action="velocity",
        action_repeat=1, bounds=None, threads=0, dtype=np.float32)

    reset(seed=None) -> observations (N, k)
    step(actions)    -> observations (N, k), rewards (N,), terminated (N,), truncated (N,), alive (N,), info
    """

    def __init__(self, test, observation=("position", "velocity"), reward="found", group=None, action="velocity",
                 action_repeat=1, bounds=None, threads=0, dtype=np.float32):
        self.test = _read_test(test)
        self.features = _features.parse(observation)
        self.reward_weights = self._parse_reward(reward)
        if action not in ACTIONS:
            raise ValueError(f"action: {action!r} (allowed: {', '.join(repr(a) for a in ACTIONS)})")
        self.action = action
        if isinstance(action_repeat, bool) or not isinstance(action_repeat, (int, np.integer)) or not 1 <= action_repeat <= 10000:
            raise ValueError(f"action_repeat: {action_repeat!r} (allowed: a whole number of steps in [1, 10000])")
        self.action_repeat = int(action_repeat)
        if isinstance(threads, bool) or not isinstance(threads, (int, np.integer)) or threads < 0:
            raise ValueError(f"threads: {threads!r} (allowed: a whole number >= 0; 0 means all cores)")
        self.threads = int(threads)
        self.dtype = np.dtype(dtype)
        if self.dtype not in (np.float32, np.float64):
            raise TypeError(f"dtype: {self.dtype} (allowed: float32 or float64)")

        groups = self.test.get("groups")
        names = [g.get("name") for g in groups] if isinstance(groups, list) else ["swarm"]
        if group is None:
            group = names[0]
        if group not in names:
            raise ValueError(f"group: {group!r} is not a group of the test (allowed: {', '.join(map(str, names))})")
        self.group, self.group_index = group, names.index(group)

        if bounds is None:
            bounds = _map_bounds(self.test)
            if bounds is None:
                raise ValueError("bounds: the map's bounds are not known from the test (allowed: ((min x, min y), (max x, max y)) in m)")
        try:
            lo, hi = (np.asarray(b, dtype=float).reshape(2) for b in bounds)
        except (TypeError, ValueError):
            raise ValueError(f"bounds: {bounds!r} (allowed: ((min x, min y), (max x, max y)) in m)") from None
        if not (hi > lo).all():
            raise ValueError(f"bounds: {bounds!r} (allowed: max greater than min in x and y)")
        self.centre, self.half = (lo + hi) / 2, (hi - lo) / 2

        neighbours = any("neighbours" in f.senses for f in self.features)
        targets = any("targets" in f.senses for f in self.features)
        self._behavior = _agent_behavior(neighbours, targets)
        self.observation_size = sum(f.width for f in self.features)
        self.columns = [c for f in self.features for c in f.columns]

        self._channel = None
        self._thread = None
        self._episodes = 0
        self.session = None
        self.agents = np.zeros(0, dtype=np.uint32)  # drone ids, in agent order
        self.alive = np.zeros(0, dtype=bool)
        self._over = True

    # ---- arguments ----

    @staticmethod
    def _parse_reward(reward):
        allowed = "'found' (targets found by the drone), a summary.csv column (its change, shared), or a dict of them -> weight"
        if isinstance(reward, str):
            reward = {reward: 1.0}
        if not isinstance(reward, dict) or not reward:
            raise TypeError(f"reward: {type(reward).__name__} (allowed: {allowed})")
        out = {}
        for name, weight in reward.items():
            if not isinstance(name, str):
                raise TypeError(f"reward: {name!r} (allowed: {allowed})")
            if isinstance(weight, bool) or not isinstance(weight, (int, float)) or not math.isfinite(weight):
                raise ValueError(f"reward: {name}: weight {weight!r} (allowed: a finite number)")
            out[name] = float(weight)
        return out

    # ---- episodes ----

    def group_drones(self):
        """The group's drone ids at the start (a Session made for it, not stepped): the agents of every
        episode, unless a group's size depends on the seed."""
        session = Session(self.test, threads=1)
        return np.flatnonzero(session.column("group") == self.group_index).astype(np.uint32)

    @property
    def num_agents(self):
        return len(self.agents)

    def reset(self, seed=None):
        """A new episode of the test with `seed` (None: the test's seed, then one more each reset), run to
        the group's first decide: the observations (N, k) the drones decide on at time 0."""
        self.close()
        if seed is None:
            seed = int(self.test.get("seed", 0)) + self._episodes
        if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or not 0 <= seed <= 2**53:
            raise ValueError(f"seed: {seed!r} (allowed: a whole number in [0, 2^53], or None)")
        self._episodes += 1
        test = dict(self.test, seed=int(seed))
        behavior = {"name": self._behavior, "params": {"channel": _next_channel[0]}}
        if isinstance(test.get("groups"), list):
            test["groups"] = [dict(g) for g in test["groups"]]
            test["groups"][self.group_index]["behavior"] = behavior
        else:
            test["behavior"] = behavior
        self.session = Session(test, threads=self.threads)
        groups = self.session.column("group")
        status = self.session.column("status")
        self.agents = np.flatnonzero((groups == self.group_index) & (status == 0)).astype(np.uint32)
        self.alive = np.ones(len(self.agents), dtype=bool)
        self._agent_of = np.full(len(groups), -1, dtype=np.intp)
        self._agent_of[self.agents] = np.arange(len(self.agents))
        self.end_time = self.session.end_time
        self._targets_found = None
        self._summary = None

        channel = _Channel(self, self.session)
        _channels[_next_channel[0]] = channel
        self._channel_number = _next_channel[0]
        _next_channel[0] += 1
        self._channel = channel
        self._actions = np.zeros((len(self.agents), 2))
        self._thread = threading.Thread(target=channel.run, name="salsa.Env", daemon=True)
        self._over = False
        _open.add(self)
        self._thread.start()
        obs, _, _, _, _, _ = self._advance()
        return obs

    def step(self, actions):
        """The actions (N, 2) become the steering of the decide the last observations came from; the
        session steps on to the group's next decide (action_repeat steps later). Returns observations
        (N, k), rewards (N,), terminated (N,), truncated (N,), alive (N,) and info."""
        if self._over:
            raise ValueError("step: the episode is over or not started (allowed: reset() first)")
        self._actions = self._check_actions(actions)
        g = self._channel.group
        self._channel.steering = self._steer(g)
        self._channel.held = self.action_repeat - 1
        self._channel.go()
        return self._advance()

    def _check_actions(self, actions):
        n = len(self.agents)
        allowed = f"a numpy float array of shape ({n}, 2), one row per agent, each in [-1, 1]"
        if not isinstance(actions, np.ndarray):
            raise TypeError(f"actions: {type(actions).__name__} (allowed: {allowed})")
        if actions.dtype.kind != "f":
            raise TypeError(f"actions: dtype {actions.dtype} (allowed: {allowed})")
        if actions.shape != (n, 2):
            raise ValueError(f"actions: shape {actions.shape} (allowed: {allowed})")
        bad = ~np.isfinite(actions).all(axis=1) & self.alive
        if bad.any():
            row = int(np.flatnonzero(bad)[0])
            raise ValueError(f"actions: row {row} is {actions[row].tolist()}, not finite (allowed: {allowed}; "
                             "rows of agents no longer alive are ignored)")
        return np.where(self.alive[:, None], np.clip(actions, -1.0, 1.0), 0.0).astype(np.float64)

    def _steer(self, g):
        """The steering (m/s) of the batch's rows from the agents' actions: a desired velocity of
        action × max speed ("velocity"), or a velocity change of action × max force ("steering"), the
        action clipped to the unit disc. Rows that are no agent (drones added later) hold still."""
        agent = self._agent_of[g.id]
        a = np.where((agent >= 0)[:, None], self._actions[np.maximum(agent, 0)], 0.0)
        norm = np.sqrt((a * a).sum(axis=1))
        a = np.where((norm > 1)[:, None], a / np.maximum(norm, 1)[:, None], a)
        if self.action == "steering":
            return np.ascontiguousarray(a * g.max_force)
        change = a * g.max_speed - g.velocity
        length = np.sqrt((change * change).sum(axis=1))
        scale = np.where(length > g.max_force, g.max_force / np.maximum(length, 1e-300), 1.0)
        return np.ascontiguousarray(change * scale[:, None])

    def _advance(self):
        """Waits for the next parked decide (or the end), then gathers what the caller gets."""
        channel = self._channel
        try:
            channel.wait()
        except BaseException:
            self._over = True
            raise
        n = len(self.agents)
        obs = np.zeros((n, self.observation_size), dtype=self.dtype)
        was = self.alive
        g = channel.group
        if channel.ended or g is None:
            alive = np.zeros(n, dtype=bool)
            time = self.session.time - self.session.dt  # the step whose decide found no drone to ask
        else:
            self._index(g)
            agent = self._agent_of[g.id]
            rows = agent >= 0
            alive = np.zeros(n, dtype=bool)
            alive[agent[rows]] = True
            ctx = _Context(self.centre, self.half, self.end_time)
            values = np.concatenate([f.compute(g, ctx).reshape(len(g), -1) for f in self.features], axis=1)
            obs[agent[rows]] = values[rows]
            time = g.time
        rewards = self._rewards(n)
        terminated = was & ~alive
        truncated = alive & (time >= self.end_time - self._dt() / 2)
        self.alive = alive & ~truncated
        if not self.alive.any():
            self._over = True
        info = {"time": time, "ids": self.agents}
        return obs, rewards, terminated, truncated, alive, info

    def _dt(self):
        return self.session.dt

    def _index(self, g):
        """drone id -> agent index (-1: no agent), grown when the drone count grew."""
        if len(g) and int(g.id.max()) >= len(self._agent_of):
            grown = np.full(int(g.id.max()) + 1, -1, dtype=np.intp)
            grown[: len(self._agent_of)] = self._agent_of
            self._agent_of = grown

    def _rewards(self, n):
        rewards = np.zeros(n, dtype=self.dtype)
        for name, weight in self.reward_weights.items():
            if name == "found":
                t = self.session.targets()
                found, by = t["found"], t["found_by"]
                before = self._targets_found
                if before is None or len(before) != len(found):  # the first decide, or targets changed
                    before = np.zeros_like(found) if before is None else found
                self._targets_found = found.copy()
                by = by[found & ~before]
                by = by[(by >= 0) & (by < len(self._agent_of))]
                agent = self._agent_of[by]
                np.add.at(rewards, agent[agent >= 0], weight)
            else:
                row = self.session.summary()
                if name not in row:
                    raise ValueError(f"reward: '{name}' is not a summary.csv column of this test (allowed: found, "
                                     f"{', '.join(row)})")
                value = row[name]
                last = self._summary.get(name, value) if self._summary is not None else value
                rewards += self.dtype.type(weight * (0.0 if math.isnan(value - last) else value - last))
                self._summary = {**(self._summary or {}), name: value}
        return rewards

    def close(self):
        """Ends the episode: its thread abandons the step it is parked in, and `session` is dropped (a
        step cut short is no state to go on from). reset calls it."""
        channel, thread = self._channel, self._thread
        self._channel = self._thread = None
        self._over = True
        if channel is None:
            return
        self.session = None
        channel.abort = True
        channel.go()
        thread.join()
        _open.discard(self)
        _channels.pop(self._channel_number, None)

    def __del__(self):
        try:
            self.close()
        except Exception:  # noqa: BLE001 - at interpreter exit
            pass

    def __repr__(self):
        return f"<salsa.Env group {self.group!r}: {len(self.agents)} agents, {self.observation_size} features>"


class _Context:
    __slots__ = ("centre", "half", "end_time")

    def __init__(self, centre, half, end_time):
        self.centre, self.half, self.end_time = centre, half, end_time
