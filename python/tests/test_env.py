"""salsa.Env: observations are what the core perceives at the decide the actions go to, episodes are
the same for the same seed and actions, finished drones leave, bad arguments are refused in one line."""

import numpy as np
import pytest

import salsa

# 6 drones on a 200 m empty square, 150 trees, 3 s (180 steps), light physics.
SMALL = {"name": "rl", "behavior": "random_walk", "drones": 6, "map": {"name": "empty", "params": {"size": 200}},
         "targets": {"kind": "tree", "count": 150}, "time": 3, "seed": 3, "physics": "light",
         "spawn": {"mode": "uniform"}}


def episode(env, seed, policy_seed=0):
    """Every array of one episode with random actions from `policy_seed`."""
    rng = np.random.default_rng(policy_seed)
    out = [env.reset(seed=seed).copy()]
    while True:
        obs, r, term, trunc, alive, info = env.step(rng.uniform(-1, 1, (env.num_agents, 2)))
        out += [obs.copy(), r.copy(), term.copy(), trunc.copy(), alive.copy()]
        if not env.alive.any():
            return out


def same(a, b):
    return len(a) == len(b) and all(x.dtype == y.dtype and np.array_equal(x, y) for x, y in zip(a, b))


def test_same_seed_same_episode_other_seed_other_episode():
    env = salsa.Env(SMALL, observation=["position", "velocity", "neighbours", "targets", "obstacles"], threads=2)
    first, again = episode(env, 5), episode(env, 5)
    assert same(first, again)
    assert not same(first, episode(env, 6))
    # Another Env, one thread: the same episode (the core's results do not depend on the thread count).
    assert same(first, episode(salsa.Env(SMALL, observation=["position", "velocity", "neighbours", "targets", "obstacles"],
                                         threads=1), 5))


def test_observation_is_what_the_core_holds_at_the_decide():
    env = salsa.Env(SMALL, observation=["position", "velocity", ("neighbours", 3)], dtype=np.float64, threads=1)
    obs = env.reset(seed=1)
    rng = np.random.default_rng(0)
    for step in range(40):
        s = env.session
        assert s.time == pytest.approx(step * s.dt)
        pos, vel = s.column("position")[env.agents], s.column("velocity")[env.agents]
        np.testing.assert_allclose(obs[:, :2] * env.half + env.centre, pos, rtol=0, atol=1e-9)
        np.testing.assert_allclose(obs[:, 2:4] * 10.0, vel, rtol=0, atol=1e-12)  # small drone: 10 m/s
        # The nearest neighbours, brute force over the columns: relative positions within detection range.
        for a in range(env.num_agents):
            d = np.sqrt(((pos - pos[a]) ** 2).sum(axis=1))
            d[a] = np.inf
            near = np.argsort(d)[:3]
            near = near[d[near] < 134]
            got = obs[a, 4:].reshape(3, 5)
            np.testing.assert_allclose(got[: len(near), :2] * 134, pos[near] - pos[a], atol=1e-9)
            assert (got[: len(near), 4] == 1).all() and (got[len(near):] == 0).all()
        obs, *_ = env.step(rng.uniform(-1, 1, (env.num_agents, 2)))
    env.close()


class Ahead(salsa.Behavior):
    """What Env's "velocity" actions do for the constant action (1, 0.5)/|.|, as a behavior."""
    name = "test_env_ahead"
    senses = salsa.Senses(neighbours=False, targets=False)

    def decide(self, g, rng):
        desired = np.array([1.0, 0.5]) / np.hypot(1.0, 0.5) * g.max_speed
        change = desired - g.velocity
        length = np.sqrt((change * change).sum(axis=1))
        scale = np.where(length > g.max_force, g.max_force / np.maximum(length, 1e-300), 1.0)
        return np.ascontiguousarray(change * scale[:, None])


def test_actions_steer_the_decide_they_answer():
    # The same steering from a registered behavior and from Env's actions: the same flight, step by step.
    salsa.register(Ahead)
    plain = salsa.Session({**SMALL, "behavior": "test_env_ahead"}, threads=1)
    env = salsa.Env(SMALL, dtype=np.float64, threads=1)
    env.reset(seed=SMALL["seed"])
    for _ in range(30):
        env.step(np.tile([1.0, 0.5], (env.num_agents, 1)))
        plain.step()
        assert env.session.time == plain.time
        np.testing.assert_array_equal(env.session.column("position")[env.agents], plain.column("position"))
    env.close()


def test_rewards_are_the_targets_each_drone_found():
    env = salsa.Env(SMALL, reward="found", threads=1)
    env.reset(seed=2)
    total = np.zeros(env.num_agents)
    steps = 0
    while env.alive.any():
        _, r, _, trunc, _, info = env.step(np.tile([1.0, 0.0], (env.num_agents, 1)))
        total += r
        steps += 1
    assert steps == round(SMALL["time"] / env.session.dt)  # truncated at the test's time
    assert trunc.all() and info["time"] == pytest.approx(SMALL["time"])
    t = env.session.targets()
    by = t["found_by"][t["found"]]
    expected = np.array([(by == i).sum() for i in env.agents])
    assert expected.sum() > 0
    np.testing.assert_array_equal(total, expected)
    env.close()


def test_summary_reward_is_the_change_of_the_column():
    env = salsa.Env(SMALL, reward={"targets_found": 0.5}, threads=1)
    env.reset(seed=2)
    total = 0.0
    while env.alive.any():
        _, r, *_ = env.step(np.tile([1.0, 0.0], (env.num_agents, 1)))
        assert (r == r[0]).all()  # shared
        total += r[0]
    assert total == pytest.approx(0.5 * env.session.summary()["targets_found"])


def test_failed_drones_terminate_and_leave():
    test = {**SMALL, "changes": [{"time": 0.5, "set": {"fail.drone": 2}}, {"time": 1, "set": {"fail.drone": 4}}]}
    env = salsa.Env(test, threads=1)
    env.reset(seed=1)
    when = {}
    while env.alive.any():
        actions = np.tile([0.0, 1.0], (env.num_agents, 1))
        actions[~env.alive] = np.nan  # ignored for finished agents
        obs, r, term, trunc, alive, info = env.step(actions)
        for a in np.flatnonzero(term):
            when[int(env.agents[a])] = info["time"]
        assert (obs[~alive] == 0).all()
    assert set(when) == {2, 4}
    # A timed change applies at the start of its step: the decide at that time no longer has the drone.
    assert when[2] == pytest.approx(0.5) and when[4] == pytest.approx(1)


def test_all_gone_ends_the_episode():
    test = {**SMALL, "drones": 2, "changes": [{"time": 0.2, "set": {"fail.fraction": 1}}]}
    env = salsa.Env(test, threads=1)
    env.reset(seed=1)
    steps = 0
    while env.alive.any():
        *_, term, trunc, alive, info = env.step(np.zeros((2, 2)))
        steps += 1
    assert term.all() and not trunc.any() and steps == round(0.2 / env.session.dt)
    assert info["time"] == pytest.approx(0.2)
    with pytest.raises(ValueError, match=r"^step: the episode is over"):
        env.step(np.zeros((2, 2)))


def test_other_groups_keep_their_behavior():
    test = {k: v for k, v in SMALL.items() if k not in ("behavior", "drones", "spawn")}
    test["groups"] = [{"name": "walkers", "behavior": "random_walk", "drones": 3},
                      {"name": "learners", "behavior": "random_walk", "drones": 4}]
    env = salsa.Env(test, group="learners", threads=1)
    env.reset(seed=1)
    assert env.agents.tolist() == [3, 4, 5, 6]
    start = env.session.column("position").copy()
    for _ in range(20):
        env.step(np.zeros((4, 2)))
    moved = np.sqrt(((env.session.column("position") - start) ** 2).sum(axis=1))
    assert (moved[:3] > 1).all()  # the walkers fly on
    env.close()


@pytest.mark.parametrize("actions, error, match", [
    (np.zeros((5, 2)), ValueError, r"^actions: shape \(5, 2\) \(allowed: a numpy float array of shape \(6, 2\)"),
    (np.zeros((6, 3)), ValueError, r"^actions: shape \(6, 3\)"),
    (np.zeros((6, 2), dtype=int), TypeError, r"^actions: dtype int64 \(allowed: a numpy float array"),
    ([[0.0, 0.0]] * 6, TypeError, r"^actions: list \(allowed: a numpy float array"),
    (np.full((6, 2), np.nan), ValueError, r"^actions: row 0 is \[nan, nan\], not finite"),
])
def test_bad_actions(actions, error, match):
    env = salsa.Env(SMALL, threads=1)
    env.reset(seed=1)
    with pytest.raises(error, match=match):
        env.step(actions)
    env.step(np.zeros((6, 2)))  # still usable
    env.close()


@pytest.mark.parametrize("args, error, match", [
    ({"observation": ["position", "lidar"]}, ValueError, r"^observation: 'lidar' is not a feature \(allowed: position, velocity"),
    ({"observation": [("neighbours", 0)]}, ValueError, r"^observation: \('neighbours', 0\): count out of range"),
    ({"observation": [("position", 2)]}, ValueError, r"^observation: 'position' takes no count"),
    ({"observation": 3}, TypeError, r"^observation: int \(allowed"),
    ({"action": "thrust"}, ValueError, r"^action: 'thrust' \(allowed: 'velocity', 'steering'\)"),
    ({"group": "nope"}, ValueError, r"^group: 'nope' is not a group of the test \(allowed: swarm\)"),
    ({"action_repeat": 0}, ValueError, r"^action_repeat: 0 \(allowed"),
    ({"reward": 3}, TypeError, r"^reward: int \(allowed: 'found'"),
    ({"dtype": np.int32}, TypeError, r"^dtype: int32 \(allowed: float32 or float64\)"),
    ({"bounds": ((0, 0), (0, 5))}, ValueError, r"^bounds: .* \(allowed: max greater than min"),
])
def test_bad_arguments(args, error, match):
    with pytest.raises(error, match=match):
        salsa.Env(SMALL, **args)


def test_bad_reset_and_reward_column():
    env = salsa.Env(SMALL, reward="nope", threads=1)
    with pytest.raises(ValueError, match=r"^seed: -1 \(allowed: a whole number in \[0, 2\^53\], or None\)"):
        env.reset(seed=-1)
    with pytest.raises(ValueError, match=r"^reward: 'nope' is not a summary.csv column of this test \(allowed: found, time"):
        env.reset(seed=1)
    env.close()


def test_action_repeat_holds_the_action():
    env = salsa.Env(SMALL, action_repeat=4, threads=1)
    env.reset(seed=1)
    _, _, _, _, _, info = env.step(np.zeros((6, 2)))
    assert info["time"] == pytest.approx(4 * env.session.dt)
    steps = 1
    while env.alive.any():
        env.step(np.zeros((6, 2)))
        steps += 1
    assert steps == round(SMALL["time"] / env.session.dt / 4)


def test_the_session_is_read_only_between_steps():
    env = salsa.Env(SMALL, threads=1)
    env.reset(seed=1)
    s = env.session
    assert s.summary()["time"] == 0 and len(s.targets()["found"]) == 150  # reads: allowed while parked
    with pytest.raises(ValueError, match=r"^step: the session is inside a step \(allowed: once step or run_until returns\)"):
        s.step()
    with pytest.raises(ValueError, match=r"^change: the session is inside a step"):
        s.change("drones", 3)
    with pytest.raises(ValueError, match=r"^_park: only the thread stepping the session parks it"):
        s._park(False)
    env.close()  # the episode's step is abandoned: its session goes with it
    assert env.session is None


def test_nearest_items_per_row():
    from salsa._core import _nearest
    offsets = np.array([0, 3, 3, 5], dtype=np.int64)
    distance = np.array([5.0, 1.0, 3.0, 2.0, 2.0])
    np.testing.assert_array_equal(_nearest(offsets, distance, 2), [[1, 2], [-1, -1], [3, 4]])  # ties: item order
    with pytest.raises(ValueError, match=r"^_nearest: offsets run from 0 to 5 \(allowed: 0 to the 4 items\)"):
        _nearest(offsets, distance[:4], 2)


def test_every_feature():
    test = {k: v for k, v in SMALL.items() if k not in ("behavior", "drones", "spawn")}
    test["groups"] = [{"name": "others", "behavior": "pheromone_avoidance", "drones": 4},
                      {"name": "learners", "behavior": "random_walk", "drones": 3,
                       "drone": {"base": "small", "battery_capacity": 7}}]
    test["comm"] = {"range": 150}
    env = salsa.Env(test, group="learners", observation=["position", "velocity", ("neighbours", 2), ("targets", 2),
                                                         ("obstacles", 4), "battery", "messages", "time"], threads=1)
    assert env.columns[:4] == ["x", "y", "vx", "vy"] and env.columns[-5:] == ["battery", "received", "mean_dx", "mean_dy", "time"]
    obs = env.reset(seed=1)
    assert obs.shape == (3, 4 + 10 + 8 + 4 + 1 + 3 + 1) == (3, env.observation_size) and obs.dtype == np.float32
    received = 0.0
    for _ in range(60):
        obs, _, _, _, alive, info = env.step(np.tile([0.5, 0.5], (3, 1)))
        assert np.isfinite(obs).all() and (np.abs(obs) <= 2.01).all()  # relative velocities reach ±2
        battery = obs[:, env.columns.index("battery")]
        assert ((0 < battery) & (battery < 1)).all()  # drawn from a 7 Wh battery
        assert obs[0, -1] == pytest.approx(info["time"] / 3, abs=1e-6)
        received += obs[:, env.columns.index("received")].sum()
    assert received == 0  # no built-in behavior broadcasts: the radio stays silent
    env.close()


class Still(salsa.Behavior):
    name = "test_env_still"

    def decide(self, g, rng):
        return np.zeros((len(g), 2))


def test_a_dropped_env_ends_its_episode():
    env = salsa.Env(SMALL, threads=1)
    env.reset(seed=1)
    with pytest.raises(ValueError, match=r"a Session is stepping in another thread"):
        salsa.register(Still)  # refused while the episode's thread is inside a step
    del env  # closes the episode: nothing steps any more
    salsa.register(Still)
