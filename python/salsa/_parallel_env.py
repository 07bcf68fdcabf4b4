"""salsa.ParallelEnv: salsa.Env behind PettingZoo's ParallelEnv contract (docs/python.md, "Reinforcement
learning"), without importing pettingzoo: dicts keyed by agent ids "{group}_{i}" (the group's i-th drone),
agents leaving `agents` once they fail, land, are removed or the episode is truncated, never to return."""

import numpy as np

from . import _spaces
from ._core import Session
from ._env import Env

RENDER_MODES = ["rgb_array"] if hasattr(Session, "render") else []


class ParallelEnv:
    """ParallelEnv(test, render_mode=None, max_cycles=None, **env_args): the group `group` of `test` as
    PettingZoo parallel agents. `env_args` are salsa.Env's (observation, reward, group, action,
    action_repeat, bounds, threads, dtype); `max_cycles` truncates every agent after that many steps.

    reset(seed=None, options=None) -> (observations, infos)
    step(actions)                  -> (observations, rewards, terminations, truncations, infos)
    """

    metadata = {"name": "salsa_v0", "render_modes": RENDER_MODES, "is_parallelizable": True}

    def __init__(self, test, render_mode=None, max_cycles=None, **env_args):
        if render_mode is not None and render_mode not in RENDER_MODES:
            allowed = ", ".join(repr(m) for m in RENDER_MODES) or "none in this build: Session.render is missing"
            raise ValueError(f"render_mode: {render_mode!r} (allowed: None, {allowed})")
        if max_cycles is not None and (isinstance(max_cycles, bool) or not isinstance(max_cycles, (int, np.integer))
                                       or max_cycles < 1):
            raise ValueError(f"max_cycles: {max_cycles!r} (allowed: a whole number >= 1, or None)")
        self.render_mode = render_mode
        self.max_cycles = max_cycles
        self.env = Env(test, **env_args)
        count = len(self.env.group_drones())
        self.possible_agents = [f"{self.env.group}_{i}" for i in range(count)]
        self._index = {agent: i for i, agent in enumerate(self.possible_agents)}
        self.agents = []
        dtype = self.env.dtype
        # One object per agent, the same on every call (seeding one agent's space seeds that agent's only).
        self._observation_spaces = {a: _spaces.box(-np.inf, np.inf, (self.env.observation_size,), dtype)
                                    for a in self.possible_agents}
        self._action_spaces = {a: _spaces.box(-1.0, 1.0, (2,), dtype) for a in self.possible_agents}
        self._cycles = 0

    @property
    def unwrapped(self):
        return self

    @property
    def num_agents(self):
        return len(self.agents)

    @property
    def max_num_agents(self):
        return len(self.possible_agents)

    def observation_space(self, agent):
        return self._space(self._observation_spaces, agent)

    def action_space(self, agent):
        return self._space(self._action_spaces, agent)

    def _space(self, spaces, agent):
        try:
            return spaces[agent]
        except (KeyError, TypeError):
            raise ValueError(f"agent: {agent!r} is not an agent of this env (allowed: {self._allowed()})") from None

    def _allowed(self):
        a = self.possible_agents
        return ", ".join(a) if len(a) <= 4 else f"{a[0]}, {a[1]}, ..., {a[-1]}"

    def reset(self, seed=None, options=None):
        """A new episode (salsa.Env.reset(seed)); `options` is accepted and unused. Returns
        (observations, infos), one entry per agent."""
        if options is not None and not isinstance(options, dict):
            raise TypeError(f"options: {type(options).__name__} (allowed: a dict, or None)")
        obs = self.env.reset(seed)
        if len(self.env.agents) != len(self.possible_agents):
            raise ValueError(f"test: the group {self.env.group!r} has {len(self.env.agents)} drones at the start, not "
                             f"{len(self.possible_agents)} as when the env was made (allowed: a test whose group size does not vary)")
        self._cycles = 0
        self.agents = list(self.possible_agents)
        ids = self.env.agents
        return ({a: obs[i] for i, a in enumerate(self.agents)},
                {a: {"drone": int(ids[i])} for i, a in enumerate(self.agents)})

    def step(self, actions):
        """One step: `actions` maps every agent in `agents` to its action (2,) in [-1, 1]. Returns five
        dicts over the agents that were live: observations, rewards, terminations, truncations, infos;
        those terminated or truncated leave `agents`."""
        if not self.agents:
            raise ValueError("step: no agent is live (allowed: reset() first)")
        if not isinstance(actions, dict):
            raise TypeError(f"actions: {type(actions).__name__} (allowed: a dict agent -> action of shape (2,))")
        n = len(self.possible_agents)
        array = np.zeros((n, 2))
        for agent, action in actions.items():
            i = self._index.get(agent)
            if i is None:
                raise ValueError(f"actions: {agent!r} is not an agent of this env (allowed: {self._allowed()})")
            if agent not in self.agents:
                continue  # finished agents' actions are ignored, as PettingZoo's envs do
            try:
                a = np.asarray(action, dtype=np.float64)
            except (TypeError, ValueError):
                raise TypeError(f"actions[{agent!r}]: {type(action).__name__} (allowed: 2 numbers in [-1, 1])") from None
            if a.shape != (2,):
                raise ValueError(f"actions[{agent!r}]: shape {a.shape} (allowed: (2,), 2 numbers in [-1, 1])")
            if not np.isfinite(a).all():
                raise ValueError(f"actions[{agent!r}]: {a.tolist()} is not finite (allowed: 2 numbers in [-1, 1])")
            array[i] = a
        missing = [a for a in self.agents if a not in actions]
        if missing:
            raise ValueError(f"actions: no action for {missing[0]!r}" + (f" and {len(missing) - 1} more" if len(missing) > 1 else "")
                             + " (allowed: an action for every agent in env.agents)")
        obs, rewards, terminated, truncated, alive, info = self.env.step(array)
        self._cycles += 1
        if self.max_cycles is not None and self._cycles >= self.max_cycles:
            truncated = truncated | (alive & ~truncated)
        live = self.agents
        index = [self._index[a] for a in live]
        ids = self.env.agents
        out = ({a: obs[i] for a, i in zip(live, index)},
               {a: float(rewards[i]) for a, i in zip(live, index)},
               {a: bool(terminated[i]) for a, i in zip(live, index)},
               {a: bool(truncated[i]) for a, i in zip(live, index)},
               {a: {"drone": int(ids[i])} for a, i in zip(live, index)})
        self.agents = [a for a, i in zip(live, index) if alive[i] and not truncated[i]]
        if not self.agents:
            self.env.close()
        return out

    def render(self):
        """The swarm as an RGB array (Session.render) in render_mode 'rgb_array'; None without a render mode."""
        if self.render_mode is None:
            return None
        if self.env.session is None:
            raise ValueError("render: no episode (allowed: after reset())")
        return self.env.session.render()

    def close(self):
        self.env.close()

    def __repr__(self):
        return f"<salsa.ParallelEnv {self.env.group!r}: {len(self.agents)} of {len(self.possible_agents)} agents live>"
