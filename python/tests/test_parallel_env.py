"""salsa.ParallelEnv against PettingZoo's ParallelEnv contract: the checks of PettingZoo's parallel API
test and parallel seed test, written for salsa (pettingzoo is not imported)."""

import numpy as np
import pytest

import salsa

SMALL = {"name": "rl", "behavior": "random_walk", "drones": 5, "map": {"name": "empty", "params": {"size": 200}},
         "targets": {"kind": "tree", "count": 100}, "time": 2, "seed": 3, "physics": "light",
         "spawn": {"mode": "uniform"}, "changes": [{"time": 0.5, "set": {"fail.drone": 1}}]}


def make(**args):
    return salsa.ParallelEnv(SMALL, observation=["position", "velocity", "neighbours", "obstacles"], threads=1, **args)


def equivalent(a, b):
    """Same types, keys, dtypes and values, recursively (gymnasium's data_equivalence)."""
    if type(a) is not type(b):
        return False
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(equivalent(a[k], b[k]) for k in a)
    if isinstance(a, (list, tuple)):
        return len(a) == len(b) and all(equivalent(x, y) for x, y in zip(a, b))
    if isinstance(a, np.ndarray):
        return a.shape == b.shape and a.dtype == b.dtype and np.array_equal(a, b)
    return a == b


def test_parallel_api():
    env = make()
    env.max_cycles = 1000  # the API test sets it
    assert env.unwrapped is env
    assert env.possible_agents == [f"swarm_{i}" for i in range(5)]
    env.reset(seed=0, options={"options": 1})  # reset takes seed and options
    for _ in range(2):
        obs, infos = env.reset()
        assert isinstance(obs, dict) and isinstance(infos, dict)
        assert set(env.agents) <= set(obs) and set(env.agents) <= set(infos)
        live, finished = set(env.agents), set()
        terminated = dict.fromkeys(env.agents, False)
        for _ in range(1000):
            actions = {a: env.action_space(a).sample() for a in env.agents if not terminated[a]}
            obs, rew, terminated, truncated, info = env.step(actions)
            for a in env.agents:
                assert a not in finished, "an agent came back"
            for d in (obs, rew, terminated, truncated, info):
                assert isinstance(d, dict) and set(d) == live  # every live agent, no other
            assert set(env.agents) <= set(env.possible_agents)
            for a in obs:
                assert env.observation_space(a).contains(obs[a]), a
                assert isinstance(rew[a], float) and isinstance(terminated[a], bool) and isinstance(truncated[a], bool)
            finished |= {a for a in live if terminated[a] or truncated[a]}
            for a in env.agents:
                assert env.observation_space(a) is env.observation_space(a)
                assert env.action_space(a) is env.action_space(a)
            live -= {a for a in live if terminated[a] or truncated[a]}
            assert set(env.agents) == live
            if not live:
                break
        assert finished == set(env.possible_agents)  # no agent left while some never finished
        assert not env.agents
    env.close()


def test_failed_drone_leaves_for_good():
    # Drone 1 fails at 0.5 s (a timed change): terminated once, then absent from agents and every dict.
    env = make()
    env.reset(seed=4)
    ended = 0
    while env.agents:
        _, _, terminated, truncated, _ = env.step({a: np.zeros(2, np.float32) for a in env.agents})
        if "swarm_1" in terminated:
            assert ended == 0
            if terminated["swarm_1"]:
                ended += 1
                assert "swarm_1" not in env.agents and env.env.session.time == pytest.approx(0.5)
    assert ended == 1 and "swarm_1" not in truncated and len(truncated) == 4 and all(truncated.values())


def test_parallel_seed():
    def run(env):
        env.reset(seed=42)
        for i, a in enumerate(env.agents):
            env.action_space(a).seed(42 + i)
            env.observation_space(a).seed(42 + i)
        first = env.reset(seed=42)
        for i, a in enumerate(env.agents):
            env.action_space(a).seed(42 + i)
        out = [first]
        while env.agents:
            actions = {a: env.action_space(a).sample() for a in env.agents}
            out.append(actions)
            out.append(env.step(actions))
        env.close()
        return out

    one, two = run(make()), run(make())
    assert len(one) > 10 and equivalent(one, two)
    three = make()
    three.reset(seed=43)
    assert not equivalent(three.reset(seed=43)[0], one[0][0])


def test_spaces():
    env = make()
    space = env.action_space("swarm_0")
    assert space.shape == (2,) and space.dtype == np.float32
    assert (space.low == -1).all() and (space.high == 1).all()
    space.seed(1)
    x = space.sample()
    assert x.shape == (2,) and x.dtype == np.float32 and space.contains(x)
    space.seed(1)
    assert np.array_equal(space.sample(), x)
    assert not space.contains(np.array([2.0, 0.0], np.float32)) and not space.contains(np.zeros(3, np.float32))
    obs_space = env.observation_space("swarm_4")
    assert obs_space.shape == (4 + 4 * 5 + 8,) and obs_space is not env.observation_space("swarm_3")
    with pytest.raises(ValueError, match=r"^agent: 'swarm_9' is not an agent of this env \(allowed: swarm_0, swarm_1, ..., swarm_4\)"):
        env.observation_space("swarm_9")


def test_render():
    if hasattr(salsa.Session, "render"):
        env = make(render_mode="rgb_array")
        env.reset(seed=1)
        image = env.render()
        assert image.ndim == 3 and image.shape[2] == 3 and image.dtype == np.uint8
        env.close()
    else:
        with pytest.raises(ValueError, match=r"^render_mode: 'rgb_array' \(allowed: None, none in this build"):
            make(render_mode="rgb_array")
    assert make().render() is None


@pytest.mark.parametrize("actions, error, match", [
    ([0, 0], TypeError, r"^actions: list \(allowed: a dict agent -> action"),
    ({"swarm_0": [0, 0]}, ValueError, r"^actions: no action for 'swarm_1' and 3 more \(allowed: an action for every agent"),
    ({"bee": [0, 0]}, ValueError, r"^actions: 'bee' is not an agent of this env"),
    ({**{f"swarm_{i}": [0, 0] for i in range(5)}, "swarm_2": [0, 0, 0]}, ValueError, r"^actions\['swarm_2'\]: shape \(3,\)"),
    ({**{f"swarm_{i}": [0, 0] for i in range(5)}, "swarm_2": [np.nan, 0]}, ValueError, r"^actions\['swarm_2'\]: \[nan, 0.0\] is not finite"),
    ({**{f"swarm_{i}": [0, 0] for i in range(5)}, "swarm_2": "up"}, TypeError, r"^actions\['swarm_2'\]: str"),
])
def test_bad_actions(actions, error, match):
    env = make()
    env.reset(seed=1)
    with pytest.raises(error, match=match):
        env.step(actions)
    env.close()


def test_step_before_reset_and_bad_options():
    env = make()
    with pytest.raises(ValueError, match=r"^step: no agent is live \(allowed: reset\(\) first\)"):
        env.step({})
    with pytest.raises(TypeError, match=r"^options: list \(allowed: a dict, or None\)"):
        env.reset(seed=1, options=[1])
    with pytest.raises(ValueError, match=r"^max_cycles: 0"):
        make(max_cycles=0)


def test_max_cycles_truncates():
    env = make(max_cycles=3)
    env.reset(seed=1)
    for _ in range(2):
        env.step({a: [0.0, 0.0] for a in env.agents})
    _, _, _, truncated, _ = env.step({a: [0.0, 0.0] for a in env.agents})
    assert all(truncated.values()) and not env.agents
