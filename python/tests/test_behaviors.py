"""Behaviors written in Python: the numpy ports of examples/python/behaviors.py follow their C++
originals, the batch the core hands decide, the drones' own random streams, and every bad return,
declaration and parameter refused with its line."""

import json
import math
import sys

import numpy as np
import pytest

import salsa
from conftest import SOURCE

sys.path.insert(0, str(SOURCE / "examples" / "python"))
import behaviors  # noqa: E402  (examples/python/behaviors.py)

salsa.register(behaviors.PyRandomWalk)
salsa.register(behaviors.PyFlocking)
salsa.register(behaviors.PyPheromoneAvoidance)

FOREST = json.loads((SOURCE / "examples" / "random-walk-forest.json").read_text())  # 30 drones, 500 trees
FLOCKING = {"separation_distance": 60}
PORTS = [("random_walk", "py_random_walk", {}), ("flocking", "py_flocking", FLOCKING),
         ("pheromone_avoidance", "py_pheromone_avoidance", {})]


def spec_of(behavior, params=None, **fields):
    return {**FOREST, "behavior": {"name": behavior, "params": params or {}}, **fields}


def tracks(a, b, steps):
    """The largest distance (m) between the two sessions' drones, per drone per step, over `steps` steps."""
    worst = 0.0
    for _ in range(steps):
        a.step()
        b.step()
        assert a.column("status").tolist() == b.column("status").tolist()
        worst = max(worst, float(np.abs(a.column("position") - b.column("position")).max()))
    return worst


@pytest.mark.parametrize("cpp, py, params", PORTS)
def test_a_port_tracks_its_cpp_original_over_the_first_second(cpp, py, params):
    a = salsa.Session(spec_of(cpp, params))
    b = salsa.Session(spec_of(py, params), threads=1)
    assert tracks(a, b, round(1 / a.dt)) < 1e-9
    assert a.steps == b.steps == 60 and a.drones == 30


@pytest.mark.parametrize("cpp, py, params", PORTS)
def test_a_port_tracks_its_original_with_sensor_noise(cpp, py, params):
    drone = {"base": "small", "position_noise": 2, "neighbour_noise": 1, "obstacle_noise": 0.5}
    a = salsa.Session(spec_of(cpp, params, drone=drone))
    b = salsa.Session(spec_of(py, params, drone=drone))
    assert tracks(a, b, 60) < 1e-9


@pytest.mark.parametrize("params, comm", [({}, None), ({"sharing": 1}, {"range": 150, "latency": 3})])
def test_the_pheromone_port_follows_its_original_as_the_field_fills(params, comm):
    # 20 s: marks laid in prepare (and, sharing 1, sent, delayed and marked by the receivers), evaporated
    # and read back many times; the same bits throughout.
    extra = {"comm": comm} if comm else {}
    a = salsa.Session(spec_of("pheromone_avoidance", params, **extra))
    b = salsa.Session(spec_of("py_pheromone_avoidance", params, **extra))
    assert tracks(a, b, 1200) == 0.0


def test_the_pheromone_ports_marks_compose_in_any_order():
    # A message may arrive after newer marks of its cell (latency): the port adds what is left of it
    # now, as the original does. Every order of the same marks then reads deposit × e^(-rate × age)
    # summed, even 100 s late at rate 10/s, where evaporating forwards would overflow.
    import itertools
    import types
    port = behaviors.PyPheromoneAvoidance()
    port.params = types.SimpleNamespace(cell_size=10.0, deposit=1.5, evaporation_rate=10.0, sharing=1)
    port.build((0.0, 0.0, 100.0, 100.0), own=True)
    port.grow(1)
    times, now = [0.0, 0.5, 100.0, 100.25], 100.5
    expected = 1.5 * sum(math.exp(-10.0 * (now - t)) for t in times)
    point = np.array([[55.0, 45.0]])
    for order in itertools.permutations(times):
        port.value[:], port.time[:] = 0.0, 0.0
        for t in order:
            port.mark(np.array([0]), port.index(point), np.array([t]))
        assert port.marks(np.array([0]), point, now)[0] == pytest.approx(expected, rel=1e-12), order
        assert port.time[0].max() == 100.25  # the cell's time is its newest mark's


def test_groups_mix_python_and_cpp_behaviors():
    # Batteries, failures, two groups: the Python group decides after the C++ one, drones land and fail.
    spec = json.loads((SOURCE / "examples" / "groups-forest.json").read_text())
    spec["failures"] = {"drone_mtbf": 20, "camera_mtbf": 20}
    ported = json.loads(json.dumps(spec))
    ported["groups"][1]["behavior"]["name"] = "py_random_walk"
    a, b = salsa.Session(spec), salsa.Session(ported)
    assert tracks(a, b, 600) < 1e-9
    assert (a.column("status") == 2).any()  # some failed meanwhile: the batch holds flying drones only


def test_the_batch_gathers_in_chunks_whatever_the_threads():
    # 300 drones: several chunks gathered in parallel, one batch in id order.
    spec = spec_of("py_flocking", FLOCKING, drones=300, time=2)
    one, two = salsa.Session(spec, threads=1), salsa.Session(spec, threads=2)
    one.run_until(1)
    two.run_until(1)
    assert np.array_equal(one.column("position"), two.column("position"))


def paired_interval(differences, t=2.262):  # Student's t, 9 degrees of freedom, 95 %
    d = np.asarray(differences, dtype=float)
    half = t * d.std(ddof=1) / math.sqrt(len(d))
    return d.mean() - half, d.mean() + half


# The pheromone port is held bit for bit over 20 s instead (10 × 60 s of it cost over a minute).
@pytest.mark.parametrize("cpp, py, params", PORTS[:2])
def test_a_port_finds_as_many_targets_as_its_original(cpp, py, params):
    differences = []
    for seed in range(1, 11):
        found = []
        for name in (cpp, py):
            s = salsa.Session(spec_of(name, params, seed=seed, time=60))
            s.run_until()
            found.append(s.summary()["targets_found"])
        differences.append(found[1] - found[0])
    low, high = paired_interval(differences)
    assert low <= 0 <= high, differences


# ---- What decide gets ----

class Recorder(salsa.Behavior):
    name = "py_recorder"
    brief = "keeps what decide got"
    parameters = [salsa.Param("gain", 0.5, (0.0, 2.0), "", "a parameter decide reads")]
    senses = salsa.Senses(neighbours=True, targets=True)
    seen = []

    def reset(self, drones):
        type(self).resets = drones

    def decide(self, group, rng):
        type(self).seen.append(group)
        return np.zeros((len(group), 2))


salsa.register(Recorder)


def test_decide_gets_the_groups_perceptions_as_flat_arrays():
    Recorder.seen.clear()
    s = salsa.Session(spec_of("py_recorder", {"gain": 1.5}, drones=20))
    s.step(30)
    g = Recorder.seen[-1]
    assert Recorder.resets == 20 and len(Recorder.seen) == 30
    assert g.id.tolist() == list(range(20)) and g.id.dtype == np.uint32
    assert g.position.shape == (20, 2) and g.position.dtype == np.float64 and not g.position.flags.writeable
    assert g.gain == 1.5 and g.dt == pytest.approx(1 / 60) and g.time == pytest.approx(29 / 60)
    assert g.max_speed > 0 and g.detection_range > 0 and g.battery.tolist() == [1.0] * 20
    # Before the step the group saw, the positions were what this step's decide perceived.
    for rows in (g.neighbours, g.targets, g.obstacles, g.messages):
        assert rows.offsets.shape == (21,) and rows.offsets[0] == 0 and (np.diff(rows.offsets) >= 0).all()
    nb = g.neighbours
    assert nb.offsets[-1] > 0 and len(nb.id) == nb.offsets[-1]
    me = nb.row
    np.testing.assert_allclose(nb.distance, np.sqrt(((g.position[me] - nb.position) ** 2).sum(axis=1)), rtol=1e-12)
    assert (nb.distance < g.detection_range).all() and (nb.id != g.id[me]).all()
    assert len(g.targets.id) == g.targets.offsets[-1] and g.targets.found.dtype == np.bool_
    assert len(g.messages.sender) == 0  # no comm in this test
    # Views of each step's own memory: what an earlier step's decide got is still there, unchanged.
    first = Recorder.seen[0]
    assert first.time == 0 and not np.array_equal(first.position, g.position)
    assert not np.shares_memory(first.position, g.position)


def test_only_what_senses_declares_is_gathered():
    class Blind(Recorder):
        name = "py_blind"
        senses = salsa.Senses(neighbours=False, targets=False)
        seen = []

    salsa.register(Blind)
    s = salsa.Session(spec_of("py_blind", drones=20))
    s.step(5)
    g = Blind.seen[-1]
    assert g.neighbours.offsets[-1] == 0 and g.targets.offsets[-1] == 0 and g.neighbours.position.shape == (0, 2)


def test_the_rng_draws_from_each_drones_stream_where_asked():
    draws = {}

    class Draws(salsa.Behavior):
        name = "py_draws"
        senses = salsa.Senses(neighbours=False, targets=False)
        masked = False

        def decide(self, group, rng):
            if group.time == 0:
                odd = group.id % 2 == 1
                first = rng.uniform(where=odd) if self.masked else None
                draws[self.masked] = (first, rng.uniform(), rng.angle(), rng.normal(), rng.chance(0.5), rng.index(7))
            return np.zeros((len(group), 2))

    class Masked(Draws):
        name = "py_draws_masked"
        masked = True

    salsa.register(Draws)
    salsa.register(Masked)
    salsa.Session(spec_of("py_draws", drones=10)).step()
    salsa.Session(spec_of("py_draws_masked", drones=10)).step()
    plain, masked = draws[False], draws[True]
    odd = np.arange(10) % 2 == 1
    assert np.isnan(masked[0][~odd]).all() and (masked[0][odd] >= 0).all()
    # Rows the mask left out drew nothing: their next draw is the plain run's first.
    assert np.array_equal(masked[1][~odd], plain[1][~odd])
    # Rows it drew for are one draw on: their first is the plain run's first.
    assert np.array_equal(masked[0][odd], plain[1][odd])
    assert len(set(plain[1].tolist())) == 10  # a stream per drone
    assert ((plain[2] >= 0) & (plain[2] < 2 * np.pi)).all()
    assert plain[4].dtype == np.bool_ and plain[5].dtype == np.int64 and ((plain[5] >= 0) & (plain[5] < 7)).all()


def test_the_rng_refuses_use_outside_its_call_and_a_bad_mask():
    kept = []

    class Keeper(salsa.Behavior):
        name = "py_keeper"

        def decide(self, group, rng):
            kept.append(rng)
            if group.time > 0:
                rng.uniform(where=np.ones(3, dtype=bool))
            return np.zeros((len(group), 2))

    salsa.register(Keeper)
    s = salsa.Session(spec_of("py_keeper", drones=5))
    s.step()
    with pytest.raises(ValueError, match="outside the decide call"):
        kept[0].uniform()
    with pytest.raises(salsa.TestFailure, match=r"where: bool of shape \(3,\) \(allowed: a numpy bool array of shape \(5,\)"):
        s.step()


# ---- Bad returns stop the test with one line ----

def bad(name, result):
    class Bad(salsa.Behavior):
        def decide(self, group, rng):
            if group.time > 0.04:
                return result(len(group))
            return np.zeros((len(group), 2))

    Bad.name = name
    salsa.register(Bad)
    return Bad


def fail_line(name, steps=10):
    s = salsa.Session(spec_of(name, drones=4))
    with pytest.raises(salsa.TestFailure) as e:
        s.step(steps)
    assert "\n" not in str(e.value)
    return s, str(e.value)


@pytest.mark.parametrize("name, result, why", [
    ("py_bad_shape", lambda n: np.zeros((n, 3)), r"decide returned float64 of shape \(4, 3\) \(allowed: a numpy float64 array of shape \(4, 2\)"),
    ("py_bad_rows", lambda n: np.zeros((n + 1, 2)), r"decide returned float64 of shape \(5, 2\)"),
    ("py_bad_dtype", lambda n: np.zeros((n, 2), dtype=np.float32), r"decide returned float32 of shape \(4, 2\)"),
    ("py_bad_type", lambda n: [[0.0, 0.0]] * n, r"decide returned list \(allowed"),
    ("py_bad_nan", lambda n: np.full((n, 2), np.nan), r"decide returned a steering that is not finite, \(nan, nan\) at row 0"),
    ("py_bad_inf", lambda n: np.array([[0.0, 0.0]] * (n - 1) + [[np.inf, 0.0]]), r"not finite, \(inf, 0\) at row 3"),
])
def test_a_bad_return_stops_the_test_with_one_line(name, result, why):
    bad(name, result)
    s, line = fail_line(name)
    assert line.startswith(f"test 'random-walk-forest' (<dict>): behavior '{name}' (Python class test_behaviors.bad.<locals>.Bad) failed at t = ")
    assert f"Python behavior '{name}': " in line
    import re
    assert re.search(why, line), line
    assert s.steps == 3  # what was stepped before stays; the session can still be read
    assert s.column("position").shape == (4, 2)


def test_an_exception_in_decide_is_named_with_where_it_was_raised():
    def boom(n):
        raise ZeroDivisionError("the drones divided by zero")

    bad("py_raises", boom)
    _, line = fail_line("py_raises")
    assert "Python behavior 'py_raises': decide raised ZeroDivisionError: the drones divided by zero (" in line
    assert "test_behaviors.py:" in line


def test_params_out_of_range_are_refused_with_the_cores_line():
    with pytest.raises(salsa.InputError, match=r"behavior.params.min_duration: 0.01 is out of range \(allowed: \[0.1, 600\] s\)"):
        salsa.Session(spec_of("py_random_walk", {"min_duration": 0.01}))
    with pytest.raises(salsa.InputError, match="unknown"):
        salsa.Session(spec_of("py_random_walk", {"nope": 1}))


def test_registration_refuses_what_it_cannot_use():
    class NoName(salsa.Behavior):
        pass

    with pytest.raises(ValueError, match=r"name: None \(allowed: a str"):
        salsa.register(NoName)
    with pytest.raises(TypeError, match="allowed: a subclass of salsa.Behavior"):
        salsa.register(object)

    class Taken(salsa.Behavior):
        name = "random_walk"

    with pytest.raises(ValueError, match="the name is taken by .*random_walk"):
        salsa.register(Taken)

    class Clash(salsa.Behavior):
        name = "py_clash"
        parameters = [salsa.Param("position", 1.0, (0.0, 2.0))]

    with pytest.raises(ValueError, match="parameter 'position' has the name of a field"):
        salsa.register(Clash)

    class Wrong(salsa.Behavior):
        name = "py_wrong"
        parameters = [salsa.Param("gain", 5.0, (0.0, 2.0))]

    with pytest.raises(ValueError, match="py_wrong"):
        salsa.register(Wrong)
    with pytest.raises(TypeError, match="range"):
        salsa.Param("gain", 1.0, 2.0)


def test_a_declared_shared_state_is_checked_and_warned_about_beside_a_radio():
    class Bad(salsa.Behavior):
        name = "py_bad_sharing"
        shared_state = "everyone"

    with pytest.raises(ValueError, match=r"shared_state: 'everyone' \(allowed: \"none\", \"global\", \"radio\", or a method returning one\)"):
        salsa.register(Bad)

    class Oracle(salsa.Behavior):
        name = "py_oracle"
        shared_state = "global"

        def decide(self, group, rng):
            return np.zeros((len(group.id), 2))

    salsa.register(Oracle)
    queue = {"repeats": 1, "base": {"drones": 3, "time": 1, "targets": {"count": 5}},
             "tests": [{"name": "o", "behavior": "py_oracle", "comm": {"range": 50}}, {"name": "w", "behavior": "py_random_walk"}]}
    warnings = salsa.validate(queue) or []
    assert any("compares global knowledge with a radio: py_oracle" in w for w in warnings), warnings
    # A Python behavior without the attribute declares none: no warning beside the same radio.
    queue["tests"][0]["behavior"] = "py_random_walk"
    queue["tests"][1]["behavior"] = "py_flocking"
    assert not any("global knowledge" in w for w in salsa.validate(queue) or []), warnings


def warns_of_global_knowledge(behavior, params):
    queue = {"repeats": 1, "base": {"drones": 3, "time": 1, "targets": {"count": 5}, "comm": {"range": 50}},
             "tests": [{"name": "t", "behavior": {"name": behavior, "params": params}}]}
    return any("compares global knowledge with a radio" in w for w in salsa.validate(queue) or [])


def test_a_shared_state_method_says_it_from_the_parameters_as_its_cpp_original():
    # The pheromone port's method: "global" for sharing 0, "radio" for 1, as pheromone_avoidance's.
    for sharing in (0, 1):
        assert warns_of_global_knowledge("py_pheromone_avoidance", {"sharing": sharing}) == \
            warns_of_global_knowledge("pheromone_avoidance", {"sharing": sharing}) == (sharing == 0)

    class Says(salsa.Behavior):
        name = "py_says_sharing"
        parameters = [salsa.Param("word", 0, (0, 3), "", "0 none, 1 global, 2 radio, 3 a wrong word", step=1)]

        def shared_state(self):
            return ["none", "global", "radio", "all of them"][int(self.params.word)]

        def decide(self, group, rng):
            return np.zeros((len(group.id), 2))

    class Fails(salsa.Behavior):
        name = "py_fails_sharing"

        def shared_state(self):
            raise KeyError("sharing")

    salsa.register(Says)
    salsa.register(Fails)
    assert [warns_of_global_knowledge("py_says_sharing", {"word": w}) for w in (0, 1, 2)] == [False, True, False]
    with pytest.raises(Exception, match=r"behavior 'py_says_sharing' \(Python class test_behaviors\..*Says\) shared_state\(\): returned 'all of them' "
                                        r"\(allowed: \"none\", \"global\", \"radio\"\)"):
        warns_of_global_knowledge("py_says_sharing", {"word": 3})
    with pytest.raises(Exception, match=r"behavior 'py_fails_sharing' \(Python class .*Fails\) shared_state\(\): raised KeyError: 'sharing' \(.*test_behaviors.py:\d+\)"):
        warns_of_global_knowledge("py_fails_sharing", {})


def test_registered_classes_are_listed_beside_the_plugins():
    listed = salsa.behaviors()
    assert "flocking" in listed and listed["flocking"]["origin"].endswith(".so")
    walk = listed["py_random_walk"]
    assert walk["origin"] == "Python class behaviors.PyRandomWalk"
    assert [p.name for p in walk["parameters"]] == ["min_duration", "max_duration", "turn_distance", "obstacle_avoidance_weight"]
    assert walk["parameters"][0].range == (0.1, 600.0) and walk["parameters"][0].unit == "s"
    # The same parameters as the C++ original.
    assert [(p.name, p.default, p.range) for p in listed["random_walk"]["parameters"]] == \
        [(p.name, p.default, p.range) for p in walk["parameters"]]
    for cpp, py, _ in PORTS[1:]:
        assert [(p.name, p.default, p.range, p.unit, p.step) for p in listed[cpp]["parameters"]] == \
            [(p.name, p.default, p.range, p.unit, p.step) for p in listed[py]["parameters"]]


def test_a_live_change_of_a_param_reaches_decide():
    Recorder.seen.clear()
    s = salsa.Session(spec_of("py_recorder", drones=3))
    s.step()
    s.change("behavior.params.gain", 2.0)
    s.step()
    assert Recorder.seen[0].gain == 0.5 and Recorder.seen[-1].gain == 2.0
    with pytest.raises(ValueError, match="out of range"):
        s.change("behavior.params.gain", 3.0)


# ---- prepare: the whole world once a step ----

WAREHOUSE = SOURCE / "examples" / "maps" / "warehouse.json"  # a rack spans (40..100, 120..126), a wall y = 100 for x in 35..60


def two_groups(python_behavior, python_drones=6, others=4):
    return {"groups": [{"name": "py", "drones": python_drones, "behavior": python_behavior, "spawn": {"point": [150, 60]}},
                       {"name": "cpp", "drones": others, "behavior": "random_walk"}],
            "map": str(WAREHOUSE), "time": 10, "seed": 3}


def test_prepare_sees_every_drone_once_a_step_before_any_decide():
    calls = []

    class Watcher(salsa.Behavior):
        name = "py_watcher"
        senses = salsa.Senses(neighbours=False, targets=False)

        def prepare(self, world):
            calls.append(("prepare", world))

        def decide(self, group, rng):
            calls.append(("decide", group))
            return np.zeros((len(group), 2))

    salsa.register(Watcher)
    s = salsa.Session(two_groups("py_watcher"))
    s.step(3)
    before = (s.time, s.column("position").copy(), s.column("velocity").copy(), s.column("status").copy(), s.column("group").copy())
    s.step()
    assert [c[0] for c in calls] == ["prepare", "decide"] * 4
    world = calls[-2][1]
    assert world.time == pytest.approx(before[0]) and world.dt == pytest.approx(1 / 60) and len(world) == 10
    # Every drone of both groups, exactly the state the step began with, by id.
    np.testing.assert_array_equal(world.position, before[1])
    np.testing.assert_array_equal(world.velocity, before[2])
    assert world.status.dtype == np.uint8 and world.status.tolist() == before[3].tolist() == [0] * 10
    assert world.group.dtype == np.uint32 and world.group.tolist() == before[4].tolist() == [0] * 6 + [1] * 4
    assert world.own_group == 0 and world.group_count == 2 and world.bounds == (0.0, 0.0, 300.0, 200.0)
    assert world.bases.shape == (2, 2) and world.bases[0].tolist() == [150.0, 60.0]
    # Copies: the core's arrays step on, what prepare kept does not.
    assert not np.shares_memory(world.position, s.column("position"))
    assert not np.array_equal(world.position, s.column("position"))


def test_prepare_builds_the_shared_state_decide_reads():
    """The fixture's Scatter in Python: prepare finds the centre of the group's flying drones once a
    step, every drone flies straight away from it at full speed; the other group is not counted."""
    centres = []

    class Scatter(salsa.Behavior):
        name = "py_scatter"
        shared_state = "global"
        senses = salsa.Senses(neighbours=False, targets=False)

        def prepare(self, world):
            mine = (world.group == world.own_group) & (world.status == 0)
            self.centre = world.position[mine].mean(axis=0)
            centres.append(self.centre)

        def decide(self, group, rng):
            away = group.position - self.centre
            away /= np.linalg.norm(away, axis=1, keepdims=True)
            return group.max_speed * away - group.velocity

    salsa.register(Scatter)
    s = salsa.Session(two_groups("py_scatter", python_drones=12))
    mine = s.column("group") == 0

    def spread():
        p = s.column("position")[mine]
        return float(np.linalg.norm(p - p.mean(axis=0), axis=1).mean())

    spreads = [spread()]
    for _ in range(4):
        s.step(15)
        spreads.append(spread())
    assert all(b > a for a, b in zip(spreads, spreads[1:])), spreads
    # Each centre was the group's own mean then: the last one, against the positions before that step.
    s2 = salsa.Session(two_groups("py_scatter", python_drones=12))
    s2.step(59)
    expected = s2.column("position")[mine].mean(axis=0)
    s2.step()
    np.testing.assert_allclose(centres[-1], expected, rtol=0, atol=1e-12)


def test_prepare_asks_the_map():
    answers = {}

    class Surveyor(salsa.Behavior):
        name = "py_surveyor"

        def prepare(self, world):
            answers["free"] = world.is_free([[70, 110], [70, 123], [-5, 50], [299, 50]])
            answers["clear"] = world.is_free([[70, 110], [70, 110]], 11)
            answers["rays"] = world.ray_cast([[70, 110], [45, 90], [250, 60]], [[70, 140], [45, 110], [260, 60]])
            answers["none"] = world.ray_cast(np.zeros((0, 2)), np.zeros((0, 2)))
            answers["world"] = world

        def decide(self, group, rng):
            return np.zeros((len(group), 2))

    salsa.register(Surveyor)
    s = salsa.Session(two_groups("py_surveyor"))
    s.step()
    assert answers["free"].tolist() == [True, False, False, True]  # open floor, inside a rack, outside the hall, by its wall
    assert answers["clear"].tolist() == [False, False]  # 10 m from the rack: a disc of 11 m touches it
    hit, point, distance = answers["rays"]
    assert hit.tolist() == [True, True, False]
    np.testing.assert_allclose(point[:2], [[70, 120], [45, 100]], atol=1e-6)
    np.testing.assert_allclose(distance[:2], [10, 10], atol=1e-6)
    assert np.isnan(point[2]).all() and np.isnan(distance[2])
    assert [a.shape for a in answers["none"]] == [(0,), (0, 2), (0,)]
    # The map is asked during prepare only; the arrays stay.
    with pytest.raises(ValueError, match=r"is_free: asked outside the prepare call its world was handed to \(allowed: during that call\)"):
        answers["world"].is_free([[1, 1]])
    assert answers["world"].position.shape == (10, 2)


@pytest.mark.parametrize("ask, why", [
    (lambda w: w.is_free([1, 2]), r"points: an array of shape \(2,\) \(allowed: points of shape \(M, 2\), m\)"),
    (lambda w: w.is_free("here"), r"points: str \(allowed: points of shape \(M, 2\), m\)"),
    (lambda w: w.is_free([[np.nan, 1]]), r"points: a coordinate that is not finite \(allowed: finite m\) \(.*test_behaviors.py:\d+\)"),
    (lambda w: w.is_free([[1, 1]], -1), r"clearance: -1 \(allowed: a finite number of m >= 0\)"),
    (lambda w: w.ray_cast([[0, 0]], [[1, 1], [2, 2]]), r"end: 2 rows \(allowed: as many as start, 1\)"),
    (lambda w: 1 / 0, r"ZeroDivisionError: division by zero \(.*test_behaviors.py:\d+\)"),
])
def test_a_bad_question_or_an_exception_in_prepare_stops_the_test_with_one_line(ask, why):
    class Asker(salsa.Behavior):
        name = "py_asker"

        def prepare(self, world):
            if world.time > 0.04:
                ask(world)

        def decide(self, group, rng):
            return np.zeros((len(group), 2))

    salsa.register(Asker)
    s = salsa.Session(two_groups("py_asker"))
    with pytest.raises(salsa.TestFailure) as e:
        s.step(10)
    line = str(e.value)
    assert "\n" not in line and "behavior 'py_asker' of group 'py' (Python class test_behaviors." in line
    assert "Python behavior 'py_asker': prepare raised " in line
    import re
    assert re.search(why, line), line
    assert s.steps == 3  # the steps before stay


# ---- broadcast: messages from Python ----

def talk_and_listen(where_even=False, comm=True):
    """A Python talker group broadcasting [id, x, y] and a listener group recording its messages."""
    sent, heard = {}, []

    class Talker(salsa.Behavior):
        name = "py_talker"
        message_size = 3
        senses = salsa.Senses(neighbours=False, targets=False)

        def decide(self, group, rng):
            sent[round(group.time, 9)] = {int(i): p.copy() for i, p in zip(group.id, group.position)}
            payload = np.column_stack([group.id.astype(float), group.position])
            even = np.repeat(group.id % 2 == 0, 2)[::2]  # a strided view: read by its strides
            group.broadcast(payload, where=even if where_even else None)
            return full_circle(group, rng)

    class Listener(salsa.Behavior):
        name = "py_listener"

        def decide(self, group, rng):
            heard.append(group)
            return full_circle(group, rng)

    salsa.register(Talker)
    salsa.register(Listener)
    test = {"groups": [{"name": "talkers", "drones": 10, "behavior": "py_talker"},
                       {"name": "listeners", "drones": 10, "behavior": "py_listener"}],
            "map": {"name": "empty", "params": {"size": 300}}, "time": 10, "seed": 4}
    if comm:
        test["comm"] = {"range": 120}
    s = salsa.Session(test)
    s.step(60)
    return s, sent, heard


def full_circle(group, rng):
    a = rng.angle()
    return group.max_force * np.column_stack([np.cos(a), np.sin(a)])


def test_a_python_broadcast_arrives_as_sent():
    s, sent, heard = talk_and_listen()
    received = 0
    for g in heard:
        m = g.messages
        for k in range(len(m.sender)):
            payload = m.payload[m.payload_offsets[k]:m.payload_offsets[k + 1]]
            sender = int(m.sender[k])
            assert sender < 10 and m.group[k] == 0 and m.time[k] < g.time
            # The sender's id and its position as it decided at the time it sent.
            assert payload[0] == sender
            np.testing.assert_array_equal(payload[1:], sent[round(float(m.time[k]), 9)][sender])
            received += 1
    assert received > 100


def test_broadcast_sends_only_where_asked_and_nothing_without_comm():
    _, _, heard = talk_and_listen(where_even=True)
    senders = np.concatenate([g.messages.sender for g in heard])
    assert len(senders) > 50 and (senders % 2 == 0).all()
    _, _, heard = talk_and_listen(comm=False)
    assert sum(len(g.messages.sender) for g in heard) == 0


@pytest.mark.parametrize("payload, where, why", [
    (lambda n: np.zeros((n, 4)), None, r"payload: 4 doubles a message \(allowed: at most message_size = 3\)"),
    (lambda n: np.zeros((n + 1, 2)), None, r"payload: an array of shape \(11, 2\) \(allowed: numbers of shape \(10, K\), row r the message of drone group.id\[r\]\)"),
    (lambda n: "hello", None, r"payload: str \(allowed: numbers of shape"),
    (lambda n: np.zeros((n, 2)), lambda n: np.ones(n), r"where: float64 of shape \(10,\) \(allowed: a numpy bool array of shape \(10,\)"),
])
def test_a_bad_broadcast_stops_the_test_with_one_line(payload, where, why):
    class Shouter(salsa.Behavior):
        name = "py_shouter"
        message_size = 3

        def decide(self, group, rng):
            if group.time > 0.04:
                group.broadcast(payload(len(group)), where=None if where is None else where(len(group)))
            return np.zeros((len(group), 2))

    salsa.register(Shouter)
    s = salsa.Session({**spec_of("py_shouter", drones=10), "comm": {"range": 100}})
    with pytest.raises(salsa.TestFailure) as e:
        s.step(10)
    line = str(e.value)
    import re
    assert "\n" not in line and "Python behavior 'py_shouter': decide raised ValueError: " in line and "test_behaviors.py:" in line
    assert re.search(why, line), line


def test_broadcast_is_refused_outside_its_call_and_message_size_is_checked():
    kept = []

    class Keeper(salsa.Behavior):
        name = "py_outbox_keeper"
        message_size = 1

        def decide(self, group, rng):
            kept.append(group)
            return np.zeros((len(group), 2))

    salsa.register(Keeper)
    salsa.Session(spec_of("py_outbox_keeper", drones=3)).step()
    with pytest.raises(ValueError, match=r"broadcast: called outside the decide call its group was handed to \(allowed: during that call\)"):
        kept[0].broadcast(np.zeros((3, 1)))
    for size in (65, -1, 2.5, True, "3"):
        class Wrong(salsa.Behavior):
            name = "py_wrong_size"
            message_size = size
        with pytest.raises(ValueError, match=r"message_size: .* \(allowed: a whole number of doubles in \[0, 64\]\)"):
            salsa.register(Wrong)
