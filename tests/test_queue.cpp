// Queues as docs/test-format.md describes them: sweeps multiplied out (counts, ranges), every bad input
// refused with one line naming the position, paired seeds (the same world for every behavior of a
// repeat; no seed moves when tests are added or reordered), interleaved order, names fit for folders,
// and `salsa queue expand` / `salsa validate` through the CLI.
#include "common.hpp"

#include <nlohmann/json.hpp>

#include <map>
#include <set>

#include "salsa/core/files/names.hpp"
#include "salsa/core/results/comparison.hpp"
#include "salsa/core/experiments/queue.hpp"
#include "salsa/core/results/queue_summary.hpp"
#include "salsa/core/run/output_folder.hpp"
#include "salsa/core/run/runner.hpp"

using namespace salsa;
using namespace salsa_test;

class TestQueue : public QObject {
  Q_OBJECT

  std::unique_ptr<PluginHost> host_ = builtin_host();
  QTemporaryDir dir_;

  std::string file(const QString& name, const QByteArray& json) {
    const QString path = dir_.filePath(name);
    if (!write_file(path, json)) qFatal("cannot write %s", qPrintable(path));
    return path.toStdString();
  }
  /// The queue, or a failed test (not an abort) when it is refused.
  Queue load(const QByteArray& json, QueueOptions options = {}) {
    try {
      return load_queue(file("q.json", json), *host_, options);
    } catch (const InputError& e) {
      QTest::qFail(e.what(), __FILE__, __LINE__);
      return {};
    }
  }
  QString error_of(const QByteArray& json, QueueOptions options = {}) {
    try {
      load_queue(file("q.json", json), *host_, options);
    } catch (const InputError& e) {
      return QString::fromStdString(e.what());
    }
    return "(accepted)";
  }
  /// A sweep's test objects before the test reader (expand_sweep), or a failed test when refused.
  std::vector<std::pair<nlohmann::json, SweptTest>> swept(const QByteArray& json) {
    std::vector<std::pair<nlohmann::json, SweptTest>> out;
    try {
      for (SweptTest& t : expand_sweep(file("q.json", json), *host_)) out.emplace_back(nlohmann::json::parse(t.json), std::move(t));
    } catch (const InputError& e) {
      QTest::qFail(e.what(), __FILE__, __LINE__);
    }
    return out;
  }
  static std::string number(double v) { return Parameter::format(v); }
  static std::map<std::string, std::uint64_t> seeds_by_name(const Queue& q) {
    std::map<std::string, std::uint64_t> out;
    for (const auto& t : q.tests) out[t.name] = t.seed;
    return out;
  }

 private Q_SLOTS:
  void initTestCase() {
    QVERIFY(dir_.isValid());
    file("w.json", read_file(q(source_dir() / "examples/maps/warehouse.json")));  // a map file beside the queues
  }

  // ---- Expansion

  // Finding a repeated test looks at every field a queue varies: 10,000 conditions, 10,000 values of a
  // sweep.set key or 10,000 explicit tests that differ only in the wind are 10,000 tests, and a repeat
  // among 10,001 is still found, naming both (a check that compared every pair of one world took
  // minutes here).
  void large_queues_find_the_repeated_test() {
    const int n = 10000;
    QStringList conditions, values, tests;
    for (int i = 0; i < n; ++i) {
      const QString wind = QString::fromStdString(number(i * 1e-4));
      conditions << QString(R"({"name": "c%1", "wind": {"velocity": [%2, 0]}})").arg(i).arg(wind);
      values << wind;
      tests << QString(R"({"name": "t%1", "wind": {"velocity": [%2, 0]}})").arg(i).arg(wind);
    }
    const QString base = R"({"behavior": "random_walk", "drones": 2, "time": 1})";
    QCOMPARE(load(QString(R"({"base": %1, "conditions": [%2], "tests": [{"name": "t"}]})").arg(base, conditions.join(", ")).toUtf8()).tests.size(),
             std::size_t(n));
    QCOMPARE(load(QString(R"({"sweep": {"test": %1, "set": {"wind.velocity.x": [%2]}}})").arg(base, values.join(", ")).toUtf8()).tests.size(),
             std::size_t(n));
    QCOMPARE(load(QString(R"({"base": %1, "tests": [%2]})").arg(base, tests.join(", ")).toUtf8()).tests.size(), std::size_t(n));
    tests << R"({"name": "again", "wind": {"velocity": [0.5, 0]}})";  // t5000's
    QueueOptions more;
    more.max_tests = 20000;
    const QString error = error_of(QString(R"({"base": %1, "tests": [%2]})").arg(base, tests.join(", ")).toUtf8(), more);
    QVERIFY2(error.contains("q.json: tests[10000]: the same test as ") && error.contains("q.json: tests[5000] (the same world"), qPrintable(error));
  }

  void expansion_counts_data() {
    QTest::addColumn<QByteArray>("queue");
    QTest::addColumn<int>("count");
    QTest::newRow("one test") << QByteArray(R"({"behavior": "flocking"})") << 1;
    QTest::newRow("a list") << QByteArray(R"([{"behavior": "flocking"}, {"behavior": "random_walk"}, {"behavior": "flocking", "drones": 3}])") << 3;
    QTest::newRow("tests object") << QByteArray(R"({"tests": [{"behavior": "flocking"}, {"behavior": "random_walk"}]})") << 2;
    QTest::newRow("four behaviors")
        << QByteArray(R"({"sweep": {"behaviors": ["random_walk", "flocking", "pheromone_avoidance", "dynamic_space_partitioning"]}})") << 4;
    QTest::newRow("a behavior's parameter product")
        << QByteArray(R"({"sweep": {"behaviors": ["random_walk", {"name": "flocking", "params": {"cohesion_weight": [1, 2],
                         "alignment_weight": {"from": 0.5, "to": 2, "step": 0.5}}}]}})")
        << 1 + 2 * 4;
    QTest::newRow("behaviors x drones x maps")
        << QByteArray(R"({"sweep": {"behaviors": ["random_walk", {"name": "flocking", "params": {"cohesion_weight": [1, 2]}}],
                         "drones": [10, 20, 30], "maps": ["empty", {"name": "forest", "params": {"clusters": [5, 10]}}]}})")
        << 3 * 3 * 3;
    QTest::newRow("x repeats")
        << QByteArray(R"({"repeats": 4, "sweep": {"behaviors": ["random_walk", "flocking"], "drones": {"from": 10, "to": 50, "step": 10}}})")
        << 4 * 2 * 5;
    QTest::newRow("tests and a sweep, repeated")
        << QByteArray(R"({"repeats": 3, "tests": [{"name": "a", "behavior": "flocking"}, {"name": "b", "behavior": "random_walk", "drones": 4}],
                         "sweep": {"test": {"drones": 20}, "behaviors": ["random_walk", "flocking", "pheromone_avoidance"]}})")
        << 3 * (2 + 3);
    QTest::newRow("targets x drone configurations")
        << QByteArray(R"({"sweep": {"test": {"behavior": "random_walk"}, "targets": [0, 100, {"kind": "tree", "count": 50, "params": {"radius": 2}}],
                         "drone": ["small", "medium", {"name": "fast", "base": "small", "max_speed": 15}]}})")
        << 3 * 3;
    QTest::newRow("count form") << QByteArray(R"({"sweep": {"behaviors": [{"name": "flocking", "params": {"cohesion_weight": {"from": 0, "to": 1, "count": 5}}}]}})") << 5;
    QTest::newRow("float step reaches its end") << QByteArray(R"({"sweep": {"behaviors": [{"name": "flocking", "params": {"cohesion_weight": {"from": 0.1, "to": 0.7, "step": 0.2}}}]}})") << 4;
    QTest::newRow("step past the end stops") << QByteArray(R"({"sweep": {"test": {"behavior": "flocking"}, "drones": {"from": 1, "to": 10, "step": 4}}})") << 3;
    QTest::newRow("map files") << QByteArray(R"({"sweep": {"behaviors": ["flocking", "random_walk"], "maps": ["w.json", {"name": "empty", "params": {"size": [200, 300]}}]}})") << 2 * 3;
  }
  void expansion_counts() {
    QFETCH(QByteArray, queue);
    QFETCH(int, count);
    QCOMPARE(load(queue).tests.size(), std::size_t(count));
  }

  void range_values_data() {
    QTest::addColumn<QByteArray>("range");
    QTest::addColumn<QList<double>>("values");
    QTest::newRow("step 0.1: 0.3, not 0.30000000000000004") << QByteArray(R"({"from": 0.1, "to": 0.5, "step": 0.1})") << QList<double>{0.1, 0.2, 0.3, 0.4, 0.5};
    QTest::newRow("step 0.5") << QByteArray(R"({"from": 0.5, "to": 2, "step": 0.5})") << QList<double>{0.5, 1, 1.5, 2};
    QTest::newRow("count 4") << QByteArray(R"({"from": 0.5, "to": 2, "count": 4})") << QList<double>{0.5, 1, 1.5, 2};
    QTest::newRow("count 4, thirds") << QByteArray(R"({"from": 0, "to": 1, "count": 4})") << QList<double>{0, 1.0 / 3, 2.0 / 3, 1};
    QTest::newRow("step short of the end") << QByteArray(R"({"from": 1, "to": 2, "step": 0.3})") << QList<double>{1, 1.3, 1.6, 1.9};
    QTest::newRow("from = to") << QByteArray(R"({"from": 2, "to": 2, "step": 1})") << QList<double>{2};
    QTest::newRow("count 1, from = to") << QByteArray(R"({"from": 2, "to": 2, "count": 1})") << QList<double>{2};
    QTest::newRow("a list") << QByteArray("[3, 0, 2.5]") << QList<double>{3, 0, 2.5};
    QTest::newRow("one number") << QByteArray("7") << QList<double>{7};
  }
  void range_values() {
    QFETCH(QByteArray, range);
    QFETCH(QList<double>, values);
    const Queue q = load(R"({"sweep": {"behaviors": [{"name": "flocking", "params": {"cohesion_weight": )" + range + "}}]}}");
    QList<double> got;
    for (const auto& t : q.tests) got << t.groups[0].behavior.params.get("cohesion_weight");
    QCOMPARE(got, values);  // exactly: the ends as given, the steps without float noise where it matters
  }

  // ---- sweep.set: any number of the test by its dotted key, one axis per key

  void queues_without_set_expand_as_before_data() {
    QTest::addColumn<QString>("queue");
    QTest::newRow("examples/sweep-queue.json") << "sweep-queue";
    QTest::newRow("every other axis, tests, repeats, a prefix") << "every-axis";
  }
  void queues_without_set_expand_as_before() {
    // tests/data/queue/*.expand: `salsa queue expand` of the commit before sweep.set existed, cut to
    // name and seed. The count, every name and seed and their order must not move.
    QFETCH(QString, queue);
    const fs::path folder = source_dir() / "tests/data/queue";
    const Queue got = load_queue(folder / (queue.toStdString() + ".json"), *host_, {});
    QStringList lines{QString::number(got.tests.size()) + " tests"};
    for (const TestSpec& t : got.tests) lines << q(t.name) + " seed=" + QString::number(t.seed);
    const QStringList expected = non_empty_lines(read_file(q(folder / (queue.toStdString() + ".expand"))));
    QVERIFY(expected.size() > 10);
    QCOMPARE(lines, expected);
  }

  void set_axes_multiply_in_key_order() {
    // Keys sorted (behavior.params..., drone.max_speed, drones), the last fastest; a named drone becomes
    // {"base": name}, a named behavior {"name", "params"}.
    const auto tests = swept(R"({"sweep": {"test": {"behavior": "flocking", "drone": "large", "time": 5},
                                 "set": {"drones": {"from": 2, "to": 4, "count": 2}, "drone.max_speed": [5, 10],
                                         "behavior.params.cohesion_weight": {"from": 1, "to": 2, "step": 0.5}}}})");
    QCOMPARE(tests.size(), std::size_t(3 * 2 * 2));
    std::size_t i = 0;
    for (const double cw : {1.0, 1.5, 2.0})
      for (const double speed : {5.0, 10.0})
        for (const int drones : {2, 4}) {
          const nlohmann::json& t = tests[i].first;
          QCOMPARE(t["behavior"], (nlohmann::json{{"name", "flocking"}, {"params", {{"cohesion_weight", cw}}}}));
          QCOMPARE(t["drone"], (nlohmann::json{{"base", "large"}, {"max_speed", speed}}));
          QCOMPARE(t["drones"], nlohmann::json(drones));
          QCOMPARE(t["time"], nlohmann::json(5));  // sweep.test's other keys stay
          const std::string name = "flocking_cohesion_weight" + number(cw) + "_max_speed" + number(speed) + "_drones" + std::to_string(drones);
          QCOMPARE(tests[i].second.name, name);
          QCOMPARE(tests[i].second.at, "set.behavior.params.cohesion_weight[" + std::to_string(i / 4) + "], set.drone.max_speed[" +
                                           std::to_string(i / 2 % 2) + "], set.drones[" + std::to_string(i % 2) + "]");
          ++i;
        }
  }

  void set_axes_reach_groups_by_name() {
    // A group is found by its name wherever it stands in the list; the other group is left as it was.
    const auto tests = swept(R"({"sweep": {"test": {"name": "mix", "groups": [
                                   {"name": "scouts", "drones": 2, "drone": "small", "behavior": "random_walk"},
                                   {"name": "lifters", "drone": {"base": "large", "radius": 3}, "behavior": {"name": "flocking", "params": {"cohesion_weight": 1}}}]},
                                 "set": {"groups.lifters.drones": [1, 3], "groups.scouts.drone.max_speed": 4,
                                         "groups.lifters.behavior.params.alignment_weight": [0.5, 1], "failures.drone_mtbf": [600]}}})");
    QCOMPARE(tests.size(), std::size_t(2 * 2));
    std::size_t i = 0;
    for (const double aw : {0.5, 1.0})
      for (const int drones : {1, 3}) {
        const nlohmann::json& t = tests[i++].first;
        QCOMPARE(t["failures"], (nlohmann::json{{"drone_mtbf", 600}}));
        QCOMPARE(t["groups"][0], (nlohmann::json{{"name", "scouts"}, {"drones", 2}, {"drone", {{"base", "small"}, {"max_speed", 4}}}, {"behavior", "random_walk"}}));
        QCOMPARE(t["groups"][1], (nlohmann::json{{"name", "lifters"}, {"drones", drones}, {"drone", {{"base", "large"}, {"radius", 3}}},
                                                 {"behavior", {{"name", "flocking"}, {"params", {{"cohesion_weight", 1}, {"alignment_weight", aw}}}}}}));
        QCOMPARE(t.size(), std::size_t(3));  // name, groups, failures: no top-level drone, drones or behavior appears
      }
    QCOMPARE(tests[1].second.name, std::string("mix_random_walk_flocking_drone_mtbf600_alignment_weight0.5_drones3_max_speed4"));
  }

  void set_keys_that_end_alike_are_told_apart_in_names() {
    const auto tests = swept(R"({"sweep": {"test": {"groups": [{"name": "a", "behavior": "flocking"}, {"name": "b", "behavior": "random_walk"}]},
                                 "set": {"groups.b.drones": [3], "groups.a.drones": [1, 2]}}})");
    QCOMPARE(tests.size(), std::size_t(2));
    QCOMPARE(tests[0].second.name, std::string("flocking_random_walk_a.drones1_b.drones3"));
    QCOMPARE(tests[1].second.name, std::string("flocking_random_walk_a.drones2_b.drones3"));
    QCOMPARE(tests[1].first["groups"][0]["drones"], nlohmann::json(2));
    QCOMPARE(tests[1].first["groups"][1]["drones"], nlohmann::json(3));
  }

  void set_axes_through_the_test_reader() {
    // Keys the reader knows: drone.<property> of a named drone, a behavior's and a map's parameters, a
    // metric's parameter (a list entered by name), crossed with the other axes and repeated.
    const Queue q = load(R"({"repeats": 2, "sweep": {"test": {"drone": "medium", "map": "forest", "time": 5, "metrics": ["collisions", "area_coverage"]},
                             "behaviors": ["random_walk", "flocking"],
                             "set": {"drone.max_speed": [6, 12], "map.params.clusters": {"from": 2, "to": 4, "step": 2},
                                     "metrics.area_coverage.params.cell_size": [2.5]}}})");
    QCOMPARE(q.tests.size(), std::size_t(2 * 2 * 2 * 2));
    const DroneConfig medium = builtin_drone_configs()[1];
    QCOMPARE(medium.name, std::string("medium"));
    std::map<std::pair<std::string, std::size_t>, std::set<std::uint64_t>> seeds;  // (world, repeat) -> seeds
    std::set<std::string> names;
    for (std::size_t i = 0; i < q.tests.size(); ++i) {
      const TestSpec& t = q.tests[i];
      const nlohmann::json config = nlohmann::json::parse(resolved_json(t, *host_));  // the test as read, as config.json holds it
      const double speed = i / 4 % 2 ? 12 : 6, clusters = i / 2 % 2 ? 4 : 2;
      QCOMPARE(t.repeat, i / 8);
      QCOMPARE(config.at("behavior").at("name"), nlohmann::json(i % 2 ? "flocking" : "random_walk"));
      QCOMPARE(config.at("drone").at("max_speed").get<double>(), speed);
      QCOMPARE(config.at("drone").at("radius").get<double>(), medium.radius);  // the rest of the named configuration
      QCOMPARE(config.at("drone").at("detection_range").get<double>(), medium.detection_range);
      QCOMPARE(config.at("map").at("name"), nlohmann::json("forest"));
      QCOMPARE(config.at("map").at("params").at("clusters").get<double>(), clusters);
      QCOMPARE(config.at("metrics").size(), std::size_t(2));
      QCOMPARE(config.at("metrics")[0].at("name"), nlohmann::json("collisions"));
      QCOMPARE(config.at("metrics")[1].at("params").at("cell_size").get<double>(), 2.5);
      QCOMPARE(config.at("time").get<double>(), 5.0);
      QCOMPARE(t.name, std::string(i % 2 ? "flocking" : "random_walk") + "_max_speed" + number(speed) + "_clusters" +
                           number(clusters) + "_cell_size2.5_r" + std::to_string(t.repeat));
      QVERIFY(names.insert(t.name).second);
      seeds[{world_key(t), t.repeat}].insert(t.seed);
    }
    // Both behaviors of a world and repeat share its seed; the drone's speed and the map's clusters are the world.
    QCOMPARE(seeds.size(), std::size_t(2 * 2 * 2));
    for (const auto& [world, one] : seeds) QCOMPARE(one.size(), std::size_t(1));
  }

  void set_axes_of_groups_through_the_test_reader() {
    const QByteArray queue = R"({"sweep": {"test": {"time": 5, "groups": [
                                  {"name": "scouts", "drones": 3, "drone": "small", "behavior": "random_walk"},
                                  {"name": "lifters", "drone": "large", "behavior": "flocking"}]},
                                "set": {"groups.lifters.drones": [2, 4], "groups.scouts.drone.max_speed": [6],
                                        "groups.lifters.behavior.params.cohesion_weight": [1, 3], "failures.camera_mtbf": [900]}}})";
    const Queue q = load(queue);
    QCOMPARE(q.tests.size(), std::size_t(2 * 2));
    for (std::size_t i = 0; i < q.tests.size(); ++i) {
      const nlohmann::json config = nlohmann::json::parse(resolved_json(q.tests[i], *host_));  // config.json writes the groups back
      const nlohmann::json& groups = config.at("groups");
      QCOMPARE(groups.size(), std::size_t(2));
      QCOMPARE(groups[0].at("name"), nlohmann::json("scouts"));
      QCOMPARE(groups[0].at("drones"), nlohmann::json(3));
      QCOMPARE(groups[0].at("drone").at("max_speed").get<double>(), 6.0);
      QCOMPARE(groups[1].at("drones").get<int>(), i % 2 ? 4 : 2);
      QCOMPARE(groups[1].at("drone").at("radius").get<double>(), builtin_drone_configs()[2].radius);  // the rest of "large"
      QCOMPARE(groups[1].at("behavior").at("params").at("cohesion_weight").get<double>(), i / 2 ? 3.0 : 1.0);
      QCOMPARE(config.at("failures").at("camera_mtbf").get<double>(), 900.0);
    }
    QCOMPARE(q.tests[0].seed, q.tests[2].seed);  // a behavior parameter is not the world
    QVERIFY(q.tests[0].seed != q.tests[1].seed);  // a group's drone count is
  }

  void set_axes_give_each_behavior_parameter_value_the_same_world() {
    const Queue q = load(R"({"sweep": {"test": {"behavior": "pheromone_avoidance"},
                             "set": {"behavior.params.directions": [4, 8, 16], "drones": [4, 6]}}})");
    QCOMPARE(q.tests.size(), std::size_t(6));
    for (std::size_t i = 0; i < q.tests.size(); ++i) {
      const nlohmann::json config = nlohmann::json::parse(resolved_json(q.tests[i], *host_));
      QCOMPARE(config.at("behavior").at("params").at("directions").get<double>(), double(4 << (i / 2)));
      QCOMPARE(config.at("drones").get<int>(), i % 2 ? 6 : 4);
      QCOMPARE(q.tests[i].seed, q.tests[i % 2].seed);  // the parameter is not the world: paired
    }
    QVERIFY(q.tests[0].seed != q.tests[1].seed);
  }

  // ---- Bad input: one line naming the file, the position, the value and what is allowed.

  // ---- Base and conditions

  void base_is_inherited_by_every_test() {
    // Explicit tests and sweep.test lay their fields over the base; objects merge key by key, and a
    // plugin object of another kind replaces the base's.
    const Queue q = load(R"({"base": {"drones": 7, "time": 30, "targets": {"kind": "tree", "count": 40, "params": {"radius": 2}},
                                      "behavior": {"name": "flocking", "params": {"cohesion_weight": 2}}},
                             "tests": [{"name": "own", "targets": {"count": 10}}, {"name": "walk", "behavior": {"name": "random_walk"}, "drones": 3}],
                             "sweep": {"test": {"time": 20}, "set": {"behavior.params.alignment_weight": [0.5]}}})");
    QCOMPARE(q.tests.size(), std::size_t(3));
    QCOMPARE(q.tests[0].drone_total(), std::size_t(7));
    QCOMPARE(q.tests[0].time, 30.0);
    QCOMPARE(q.tests[0].targets, std::size_t(10));
    QCOMPARE(q.tests[0].target.params.get("radius"), 2.0);
    QCOMPARE(q.tests[0].groups[0].behavior.params.get("cohesion_weight"), 2.0);
    QCOMPARE(q.tests[1].groups[0].behavior.name, std::string("random_walk"));
    QCOMPARE(q.tests[1].drone_total(), std::size_t(3));
    QCOMPARE(q.tests[2].time, 20.0);
    QCOMPARE(q.tests[2].targets, std::size_t(40));
    QCOMPARE(q.tests[2].groups[0].behavior.params.get("cohesion_weight"), 2.0);
    QCOMPARE(q.tests[2].groups[0].behavior.params.get("alignment_weight"), 0.5);
  }

  void conditions_cross_every_test() {
    const QByteArray conditions = R"("conditions": [{"name": "baseline"}, {"name": "dropout", "changes": [{"time": 20, "set": {"drones": 7}}]},
                                                    {"name": "windy", "set": {"wind.velocity.x": 2}}, {"name": "big", "drones": 14}])";
    const QByteArray rest = R"("repeats": 2, "base": {"drones": 10, "time": 30, "targets": {"count": 20}},
                               "tests": [{"name": "solo", "behavior": "dynamic_space_partitioning"}],
                               "sweep": {"behaviors": ["flocking", "random_walk"]})";
    const Queue q = load("{" + rest + ", " + conditions + "}");
    QCOMPARE(q.tests.size(), std::size_t(3 * 4 * 2));
    std::vector<std::string> names;
    for (std::size_t i = 0; i < 12; ++i) names.push_back(q.tests[i].name);
    // Each test under each condition; in the sweep, conditions vary just slower than behaviors.
    QCOMPARE(names, (std::vector<std::string>{"solo_baseline_r0", "solo_dropout_r0", "solo_windy_r0", "solo_big_r0",
                                              "flocking_baseline_r0", "random_walk_baseline_r0", "flocking_dropout_r0", "random_walk_dropout_r0",
                                              "flocking_windy_r0", "random_walk_windy_r0", "flocking_big_r0", "random_walk_big_r0"}));
    std::map<std::string, const TestSpec*> by_name;
    for (const TestSpec& t : q.tests) by_name[t.name] = &t;
    const TestSpec& dropout = *by_name["flocking_dropout_r1"];
    QCOMPARE(dropout.changes, (std::vector<Change>{{20, "drones", 7}}));
    QCOMPARE(dropout.condition, std::string("dropout"));
    QCOMPARE(dropout.condition_label, std::string("drones → 7 at 20 s"));
    QCOMPARE(by_name["random_walk_windy_r0"]->wind.velocity.x, 2.0);
    QCOMPARE(by_name["random_walk_windy_r0"]->condition_label, std::string("wind.velocity.x = 2"));
    QCOMPARE(by_name["solo_big_r0"]->drone_total(), std::size_t(14));
    QCOMPARE(by_name["solo_big_r0"]->condition_label, std::string("drones = 14"));
    QCOMPARE(by_name["solo_baseline_r0"]->condition_label, std::string("no change"));
    QCOMPARE(by_name["solo_baseline_r0"]->drone_total(), std::size_t(10));
    // Only what changes the world moves the seed: a change at 20 s and the wind keep the baseline's
    // worlds (the comparison across conditions is paired too), a larger swarm gets others. And the
    // baseline's seeds are those of the queue without conditions.
    const Queue plain = load("{" + rest + "}");
    for (int r = 0; r < 2; ++r) {
      const std::string k = "_r" + std::to_string(r);
      const std::uint64_t seed = by_name["flocking_baseline" + k]->seed;
      for (const char* name : {"random_walk_baseline", "flocking_dropout", "random_walk_windy", "solo_dropout"})
        QCOMPARE(by_name[name + k]->seed, seed);
      QVERIFY(by_name["flocking_big" + k]->seed != seed);
      QCOMPARE(seeds_by_name(plain)["flocking" + k], seed);
    }
    // config.json holds the condition, and reads back to the same test.
    const std::string config = resolved_json(dropout, *host_);
    QVERIFY2(config.find(R"("condition": {)") != std::string::npos && config.find("drones → 7 at 20 s") != std::string::npos, config.c_str());
    TestSpec back = parse_test(config, "config.json", *host_);
    back.source = dropout.source, back.seed_given = dropout.seed_given;  // config.json gives the seed it ran with
    QVERIFY(back == dropout);
  }

  void conditions_reach_any_test_field() {
    // Failures, energy, comm, noise and wind settings, as fields or dotted keys; a drone given by name
    // keeps its name's values under a condition's key.
    const Queue q = load(R"({"base": {"behavior": "flocking", "drones": 6, "time": 20, "drone": "small"},
      "tests": [{"name": "t"}],
      "conditions": [{"name": "fail", "failures": {"drone_mtbf": 600}},
                     {"name": "battery", "set": {"drone.battery_capacity": 50}},
                     {"name": "radio", "comm": {"range": 40}},
                     {"name": "gusty", "wind": {"gusts": {"strength": 1}}},
                     {"name": "half", "changes": [{"time": 10, "set": {"fail.fraction": 0.5}}]}]})");
    QCOMPARE(q.tests.size(), std::size_t(5));
    QCOMPARE(q.tests[0].failures.drone_mtbf, 600.0);
    QCOMPARE(q.tests[1].groups[0].drone.battery_capacity, 50.0);
    QCOMPARE(q.tests[1].groups[0].drone.max_speed, builtin_drone_configs()[0].max_speed);
    QVERIFY(q.tests[2].comm.on);
    QCOMPARE(q.tests[3].wind.gust_strength, 1.0);
    QCOMPARE(q.tests[4].condition_label, std::string("fail.fraction → 0.5 at 10 s"));
  }

  void reference_is_a_variant() {
    const QByteArray sweep = R"("sweep": {"test": {"time": 10}, "behaviors": ["random_walk", {"name": "flocking", "params": {"cohesion_weight": [1, 2]}}]})";
    QCOMPARE(load("{" + sweep + R"(, "reference": "random_walk"})").reference, std::string("random_walk (defaults)"));
    QCOMPARE(load("{" + sweep + R"(, "reference": "flocking: cohesion_weight = 2"})").reference, std::string("flocking: cohesion_weight = 2"));
    QCOMPARE(load("{" + sweep + R"(, "reference": "flocking"})").reference, std::string("flocking (defaults)"));  // cohesion_weight 1 is its default
    QCOMPARE(load("{" + sweep + "}").reference, std::string());
    const QString error = error_of("{" + sweep + R"(, "reference": "pheromone_avoidance"})");
    QVERIFY2(error.contains("q.json: reference: \"pheromone_avoidance\" names no variant of the queue (allowed: random_walk (defaults); flocking (defaults); "
                            "flocking: cohesion_weight = 2; or a behavior's name for its defaults)"),
             qPrintable(error));
  }

  // "top": a whole number from 2 to the queue's variants; not with "reference" (each picks the pairs).
  void top_is_checked() {
    const QByteArray sweep = R"("sweep": {"test": {"time": 10}, "behaviors": ["random_walk", "pheromone_avoidance", {"name": "flocking", "params": {"cohesion_weight": [1, 2]}}]})";
    QCOMPARE(load("{" + sweep + R"(, "top": 2})").top, std::size_t(2));
    QCOMPARE(load("{" + sweep + R"(, "top": 4})").top, std::size_t(4));
    QCOMPARE(load("{" + sweep + "}").top, std::size_t(0));
    auto error = [&](const QByteArray& json) {  // from the file's name on: the folder is a temporary one
      const QString e = error_of(json);
      return e.mid(e.indexOf("q.json: "));
    };
    QCOMPARE(error("{" + sweep + R"(, "top": 5})"), QString("q.json: top: 5 is out of range (allowed: whole number in [2, 4])"));
    QCOMPARE(error("{" + sweep + R"(, "top": 1})"), QString("q.json: top: 1 is out of range (allowed: whole number in [2, 4])"));
    QCOMPARE(error("{" + sweep + R"(, "top": 0})"), QString("q.json: top: 0 is out of range (allowed: whole number in [2, 4])"));
    QCOMPARE(error("{" + sweep + R"(, "top": 2.5})"), QString("q.json: top: 2.5 is not a whole number (allowed: whole number in [2, 4])"));
    QCOMPARE(error("{" + sweep + R"(, "top": "3"})"), QString("q.json: top: \"3\" is not a whole number (allowed: whole number in [2, 4])"));
    QCOMPARE(error("{" + sweep + R"(, "top": 3, "reference": "random_walk"})"),
             QString("q.json: top: 3 given with \"reference\" (allowed: one of them; \"top\" compares the best variants with each other, "
                     "\"reference\" every variant with one)"));
    QCOMPARE(error(R"({"tests": [{"behavior": "flocking", "time": 10}], "top": 2})"),
             QString("q.json: top: 2: the queue has one variant, nothing to compare (allowed: leave it out)"));
  }

  // The pairs "top" picks, on a summary whose order is known: in cell c1 the means of v0..v5 are
  // .3 .9 .1 .7 .5 .8, so the top 3 are v1, v5, v3 (in that order); in cell c2 v2 leads and only two
  // variants ran, so "top 3" pairs both. Each pair once, the better ranked first.
  void top_pairs_the_best_variants() {
    using P = std::vector<std::pair<std::size_t, std::size_t>>;
    const std::vector<std::string> six{"v0", "v1", "v2", "v3", "v4", "v5"};
    QCOMPARE(compared_pairs(six, "", 3, {.3, .9, .1, .7, .5, .8}), (P{{1, 5}, {1, 3}, {5, 3}}));
    QCOMPARE(compared_pairs(six, "", 2, {.5, .5, .5, .5, .5, .5}), (P{{0, 1}}));  // ties: first appearance first
    QCOMPARE(compared_pairs({"a", "b", "c"}, "", 3, {std::nan(""), .2, .1}), (P{{1, 2}, {1, 0}, {2, 0}}));  // no value ranks last
    QCOMPARE(compared_pairs({"a", "b"}, "", 5, {.1, .2}), (P{{1, 0}}));
    const QString out = dir_.filePath("top");
    QByteArray summary = "name,status,error,cell,variant,behavior,repeat,seed,drones,targets,target,map,time,fraction_found\n";
    const double means[] = {.3, .9, .1, .7, .5, .8};
    for (int v = 0; v < 6; ++v)
      for (int r = 0; r < 2; ++r)  // ± .05 around the mean
        summary += "t" + QByteArray::number(v) + "_" + QByteArray::number(r) + ",ok,,c1,v" + QByteArray::number(v) + ",f," + QByteArray::number(r) +
                   "," + QByteArray::number(r + 1) + ",10,50,tree,forest,60," + QByteArray::number(means[v] + (r ? .05 : -.05)) + "\n";
    summary += "u0,ok,,c2,v0,f,0,7,20,50,tree,forest,60,0.2\nu2,ok,,c2,v2,f,0,7,20,50,tree,forest,60,0.6\n";
    QVERIFY(write_file(out + "/summary.csv", summary));
    QVERIFY(write_file(out + "/queue.json", R"({"tests": [], "configs_hash": "0123456789abcdef", "command": [], "top": 3})"));
    write_comparison(out.toStdString());
    QStringList pairs;
    for (const QString& line : non_empty_lines(QString::fromUtf8(read_file(out + "/comparison.csv"))).mid(1))
      pairs << line.section(',', 0, 0) + ":" + line.section(',', 8, 9);
    QCOMPARE(pairs, (QStringList{"c1:v1,v5", "c1:v1,v3", "c1:v5,v3", "c2:v2,v0"}));
  }

  void variants_in_words() {
    const Queue q = load(R"({"sweep": {"test": {"time": 10}, "behaviors": ["random_walk", {"name": "flocking", "params": {"cohesion_weight": [1.4], "alignment_weight": [2]}}]}})");
    QCOMPARE(variant(q.tests[0], *host_), std::string("random_walk (defaults)"));
    QCOMPARE(variant(q.tests[1], *host_), std::string("flocking: alignment_weight = 2, cohesion_weight = 1.4"));
  }

  void errors_data() {
    QTest::addColumn<QByteArray>("queue");
    QTest::addColumn<QStringList>("expect");
    QTest::newRow("unknown behavior")
        << QByteArray(R"({"sweep": {"behaviors": ["random_walk", "flocking", "flokking"]}})")
        << QStringList{"q.json: sweep.behaviors[2]: unknown behavior 'flokking' (known: ", "flocking"};
    QTest::newRow("unknown behavior in an object")
        << QByteArray(R"({"sweep": {"behaviors": [{"name": "flokking"}]}})") << QStringList{"q.json: sweep.behaviors[0].name: unknown behavior 'flokking'"};
    QTest::newRow("unknown parameter")
        << QByteArray(R"({"sweep": {"behaviors": ["random_walk", {"name": "flocking", "params": {"cohesion": [1, 2]}}]}})")
        << QStringList{"q.json: sweep.behaviors[1].params.cohesion: unknown parameter of behavior 'flocking' (declared: ", "cohesion_weight"};
    QTest::newRow("value out of range")
        << QByteArray(R"({"sweep": {"behaviors": ["random_walk", {"name": "flocking", "params": {"cohesion_weight": [1, 20]}}]}})")
        << QStringList{"q.json: sweep.behaviors[1].params.cohesion_weight[1]: 20 is out of range (allowed: [0, 10])"};
    QTest::newRow("range out of range")
        << QByteArray(R"({"sweep": {"behaviors": [{"name": "flocking", "params": {"cohesion_weight": {"from": 0, "to": 20, "step": 5}}}]}})")
        << QStringList{"q.json: sweep.behaviors[0].params.cohesion_weight: {\"from\":0,\"to\":20,\"step\":5} gives 15, which is out of range (allowed: [0, 10])"};
    QTest::newRow("whole-number parameter")
        << QByteArray(R"({"sweep": {"behaviors": [{"name": "pheromone_avoidance", "params": {"directions": {"from": 4, "to": 8, "count": 4}}}]}})")
        << QStringList{"q.json: sweep.behaviors[0].params.directions: {\"from\":4,\"to\":8,\"count\":4} gives 5.333333333333333, which is out of range (allowed: whole number in [3, 64])"};
    QTest::newRow("mistyped value")
        << QByteArray(R"({"sweep": {"behaviors": [{"name": "flocking", "params": {"cohesion_weight": ["1"]}}]}})")
        << QStringList{"q.json: sweep.behaviors[0].params.cohesion_weight[0]: \"1\" is not a number (allowed: [0, 10])"};
    QTest::newRow("a value twice")
        << QByteArray(R"({"sweep": {"behaviors": [{"name": "flocking", "params": {"cohesion_weight": [1, 2, 1]}}]}})")
        << QStringList{"q.json: sweep.behaviors[0].params.cohesion_weight[2]: 1 is already in the list"};
    QTest::newRow("map parameter")
        << QByteArray(R"({"sweep": {"behaviors": ["flocking"], "maps": ["empty", {"name": "forest", "params": {"clusters": [10, 2.5]}}]}})")
        << QStringList{"q.json: sweep.maps[1].params.clusters[1]: 2.5 is out of range (allowed: whole number in [0, 20000])"};
    QTest::newRow("unknown map") << QByteArray(R"({"sweep": {"behaviors": ["flocking"], "maps": ["empty", "forrest"]}})")
                                 << QStringList{"q.json: sweep.maps[1]: unknown map 'forrest'"};
    QTest::newRow("drones out of range") << QByteArray(R"({"sweep": {"behaviors": ["flocking"], "drones": [10, 0]}})")
                                         << QStringList{"q.json: sweep.drones[1]: 0 is out of range (allowed: whole number in [1, 1000000])"};
    QTest::newRow("drones not whole")
        << QByteArray(R"({"sweep": {"behaviors": ["flocking"], "drones": {"from": 1, "to": 10, "step": 1.5}}})")
        << QStringList{"q.json: sweep.drones: {\"from\":1,\"to\":10,\"step\":1.5} gives 2.5, which is out of range (allowed: whole number in [1, 1000000])"};
    QTest::newRow("drones not a list") << QByteArray(R"({"sweep": {"behaviors": ["flocking"], "drones": 10}})")
                                       << QStringList{"q.json: sweep.drones: 10 must be a list, e.g. [10, 20, 30]"};
    QTest::newRow("targets count") << QByteArray(R"({"sweep": {"behaviors": ["flocking"], "targets": [10, -1]}})")
                                   << QStringList{"q.json: sweep.targets[1]: -1 is out of range (allowed: whole number in [0, 10000000])"};
    QTest::newRow("target kind") << QByteArray(R"({"sweep": {"behaviors": ["flocking"], "targets": [{"kind": "rock", "count": 3}]}})")
                                 << QStringList{"q.json: sweep.targets[0].kind: unknown target 'rock' (known: tree, walker)"};
    QTest::newRow("drone configuration")
        << QByteArray(R"({"sweep": {"behaviors": ["flocking"], "drone": ["small", {"name": "x", "max_speed": 5000}]}})")
        << QStringList{"q.json: sweep.drone[1].max_speed: 5000 is out of range (allowed: [0.001, 1000] m/s)"};
    QTest::newRow("unnamed drone configuration")
        << QByteArray(R"({"sweep": {"behaviors": ["flocking"], "drone": ["small", {"max_speed": 5}]}})")
        << QStringList{"q.json: sweep.drone[1].name: missing"};
    QTest::newRow("unknown drone configuration") << QByteArray(R"({"sweep": {"behaviors": ["flocking"], "drone": ["tiny"]}})")
                                                 << QStringList{"q.json: sweep.drone[0]: unknown drone configuration 'tiny' (known: small, medium, large)"};
    QTest::newRow("empty axis") << QByteArray(R"({"sweep": {"behaviors": ["flocking"], "maps": []}})")
                                << QStringList{"q.json: sweep.maps: [] is an empty list (allowed: at least one entry"};
    QTest::newRow("empty behaviors") << QByteArray(R"({"sweep": {"behaviors": []}})") << QStringList{"q.json: sweep.behaviors: [] is an empty list"};
    QTest::newRow("empty parameter list") << QByteArray(R"({"sweep": {"behaviors": [{"name": "flocking", "params": {"cohesion_weight": []}}]}})")
                                          << QStringList{"q.json: sweep.behaviors[0].params.cohesion_weight: [] is an empty list (allowed: values in [0, 10]"};
    QTest::newRow("empty tests") << QByteArray(R"({"tests": []})") << QStringList{"q.json: tests holds no tests"};
    QTest::newRow("unknown sweep key") << QByteArray(R"({"sweep": {"behaviours": ["flocking"]}})")
                                       << QStringList{"q.json: sweep.behaviours: unknown key (allowed: test, behaviors, maps, drones, targets, drone, set)"};
    QTest::newRow("unknown queue key") << QByteArray(R"({"sweep": {"behaviors": ["flocking"]}, "repeat": 3})")
                                       << QStringList{"q.json: repeat: unknown key (allowed: seed, repeats, base, conditions, reference, top, tests, sweep)"};
    QTest::newRow("unknown range key") << QByteArray(R"({"sweep": {"behaviors": ["flocking"], "drones": {"from": 1, "to": 5, "by": 1}}})")
                                       << QStringList{"q.json: sweep.drones.by: unknown key (allowed: from, to, step, count)"};
    QTest::newRow("range without step or count") << QByteArray(R"({"sweep": {"behaviors": ["flocking"], "drones": {"from": 1, "to": 5}}})")
                                                 << QStringList{"q.json: sweep.drones: {\"from\":1,\"to\":5} needs \"from\", \"to\" and either \"step\" or \"count\""};
    QTest::newRow("range backwards") << QByteArray(R"({"sweep": {"behaviors": ["flocking"], "drones": {"from": 5, "to": 1, "step": 1}}})")
                                     << QStringList{"q.json: sweep.drones.to: 1 is below \"from\" 5 (allowed: to ≥ from)"};
    QTest::newRow("step zero") << QByteArray(R"({"sweep": {"behaviors": ["flocking"], "drones": {"from": 1, "to": 5, "step": 0}}})")
                               << QStringList{"q.json: sweep.drones.step: 0 is not positive (allowed: a step > 0)"};
    QTest::newRow("count 1 with two ends") << QByteArray(R"({"sweep": {"behaviors": ["flocking"], "drones": {"from": 1, "to": 5, "count": 1}}})")
                                           << QStringList{"q.json: sweep.drones.count: 1 gives one value, but \"from\" 1 and \"to\" 5 differ"};
    QTest::newRow("a range of a trillion")
        << QByteArray(R"({"sweep": {"behaviors": [{"name": "flocking", "params": {"cohesion_weight": {"from": 0, "to": 10, "step": 1e-11}}}]}})")
        << QStringList{"q.json: sweep.behaviors[0].params.cohesion_weight: ", " values (allowed: at most 1,000,000 in one range)"};
    QTest::newRow("too many without --yes")
        << QByteArray(R"({"repeats": 3, "sweep": {"behaviors": ["random_walk", "flocking"], "drones": {"from": 1, "to": 2000, "step": 1}}})")
        << QStringList{"q.json: the queue expands to 12,000 tests (4,000 × 3 repeats; allowed: 10,000 without --yes): check the sweep, or pass --yes to run them all"};
    QTest::newRow("past the limit even with --yes")
        << QByteArray(R"({"repeats": 1000, "sweep": {"behaviors": ["random_walk", "flocking"], "drones": {"from": 1, "to": 1000, "step": 1}}})")
        << QStringList{"q.json: the queue expands to 2,000,000 tests (2,000 × 1,000 repeats; allowed: at most 1,000,000 in one queue, even with --yes): split it"};
    QTest::newRow("the same map twice")
        << QByteArray(R"({"sweep": {"behaviors": ["flocking"], "maps": ["empty", "w.json", {"file": "w.json", "name": "json"}]}})")
        << QStringList{"q.json: sweep (behaviors[0], maps[2]): the same test as ", "q.json: sweep (behaviors[0], maps[1]) (the same world"};
    QTest::newRow("a key in sweep.test and an axis") << QByteArray(R"({"sweep": {"test": {"drones": 5}, "behaviors": ["flocking"], "drones": [1, 2]}})")
                                                     << QStringList{"q.json: sweep.test.drones: also swept by sweep.drones (allowed: one or the other)"};
    QTest::newRow("bad field in sweep.test") << QByteArray(R"({"sweep": {"test": {"time": 0}, "behaviors": ["flocking"]}})")
                                             << QStringList{"q.json: sweep.test: time: 0 is out of range (allowed: [0.016666666666666666, 10000000] s)"};
    QTest::newRow("no behavior anywhere") << QByteArray(R"({"sweep": {"drones": [1, 2]}})") << QStringList{"q.json: sweep.test: behavior: missing"};
    QTest::newRow("bad explicit test") << QByteArray(R"({"tests": [{"behavior": "flocking"}, {"behavior": "flocking", "drones": 0}]})")
                                       << QStringList{"q.json: tests[1]: drones: 0 is out of range (allowed: whole number in [1, 1000000])"};
    QTest::newRow("the same test twice") << QByteArray(R"({"tests": [{"name": "a", "behavior": "flocking"}, {"name": "b", "behavior": "flocking"}]})")
                                         << QStringList{"q.json: tests[1]: the same test as ", "q.json: tests[0] (the same world, seed and behavior give the same data"};
    QTest::newRow("a sweep repeating an explicit test")
        << QByteArray(R"({"tests": [{"name": "a", "behavior": "flocking", "drones": 20}], "sweep": {"behaviors": ["flocking"], "drones": [10, 20]}})")
        << QStringList{"q.json: sweep (behaviors[0], drones[1]): the same test as ", "q.json: tests[0] (the same world"};
    QTest::newRow("explicit seed with repeats") << QByteArray(R"({"repeats": 3, "tests": [{"behavior": "flocking", "seed": 4}]})")
                                                << QStringList{"q.json: tests[0]: seed: 4 would be the seed of every repeat (\"repeats\": 3)"};
    QTest::newRow("repeat with repeats") << QByteArray(R"({"repeats": 2, "tests": [{"behavior": "flocking", "repeat": 1}]})")
                                         << QStringList{"q.json: tests[0]: repeat: 1 is given, and the queue has \"repeats\": 2 (allowed: one or the other)"};
    QTest::newRow("repeats zero") << QByteArray(R"({"repeats": 0, "tests": [{"behavior": "flocking"}]})")
                                  << QStringList{"q.json: repeats: 0 is out of range (allowed: whole number in [1, 1000000])"};
    QTest::newRow("queue seed") << QByteArray(R"({"seed": -1, "tests": [{"behavior": "flocking"}]})")
                                << QStringList{"q.json: seed: -1 is out of range (allowed: whole number in [0, 9007199254740992])"};
    // sweep.set
    const QByteArray groups = R"("groups": [{"name": "scouts", "behavior": "flocking"}, {"name": "lifters", "behavior": "random_walk"}])";
    QTest::newRow("set: a key an axis sweeps") << QByteArray(R"({"sweep": {"behaviors": ["flocking"], "drones": [1, 2], "set": {"drones": [3]}}})")
                                               << QStringList{"q.json: sweep.set.drones: also swept by sweep.drones (allowed: one or the other)"};
    QTest::newRow("set: a key inside an axis")
        << QByteArray(R"({"sweep": {"behaviors": ["flocking"], "set": {"behavior.params.cohesion_weight": [1]}}})")
        << QStringList{"q.json: sweep.set.behavior.params.cohesion_weight: also swept by sweep.behaviors (allowed: one or the other)"};
    QTest::newRow("set: a key sweep.test gives")
        << QByteArray(R"({"sweep": {"test": {"behavior": {"name": "flocking", "params": {"cohesion_weight": 2}}}, "set": {"behavior.params.cohesion_weight": [1, 3]}}})")
        << QStringList{"q.json: sweep.test.behavior.params.cohesion_weight: also swept by sweep.set.behavior.params.cohesion_weight (allowed: one or the other)"};
    QTest::newRow("set: a key inside another") << QByteArray(R"({"sweep": {"test": {"behavior": "flocking"}, "set": {"drone.max_speed": [2], "drone": [1]}}})")
                                               << QStringList{"q.json: sweep.set.drone.max_speed: inside sweep.set.drone, also swept (allowed: one or the other)"};
    QTest::newRow("set: an unknown group") << QByteArray(R"({"sweep": {"test": {)" + groups + R"(}, "set": {"groups.scout.drones": [1, 2]}}})")
                                           << QStringList{"q.json: sweep.set.groups.scout.drones: no 'scout' in sweep.test.groups (allowed: scouts, lifters)"};
    QTest::newRow("set: a group without groups") << QByteArray(R"({"sweep": {"test": {"behavior": "flocking"}, "set": {"groups.scouts.drones": [1, 2]}}})")
                                                 << QStringList{"q.json: sweep.set.groups.scouts.drones: sweep.test has no \"groups\" (allowed: groups.<name>.<key>"};
    QTest::newRow("set: a single-form key with groups")
        << QByteArray(R"({"sweep": {"test": {)" + groups + R"(}, "set": {"drone.max_speed": [5]}}})")
        << QStringList{"q.json: sweep.set.drone.max_speed: sweep.test has \"groups\", each with its own (allowed: groups.<name>.drone.max_speed, <name> one of: scouts, lifters)"};
    QTest::newRow("set: not a number") << QByteArray(R"({"sweep": {"test": {"behavior": "flocking"}, "set": {"drone.max_speed": "fast"}}})")
                                       << QStringList{"q.json: sweep.set.drone.max_speed: \"fast\" is not a number, a list of numbers or a range {\"from\", \"to\", \"step\" or \"count\"} (allowed: numbers)"};
    QTest::newRow("set: a list item not a number") << QByteArray(R"({"sweep": {"test": {"behavior": "flocking"}, "set": {"drone.max_speed": [5, "6"]}}})")
                                                   << QStringList{"q.json: sweep.set.drone.max_speed[1]: \"6\" is not a number (allowed: numbers)"};
    QTest::newRow("set: an empty list") << QByteArray(R"({"sweep": {"test": {"behavior": "flocking"}, "set": {"drones": []}}})")
                                        << QStringList{"q.json: sweep.set.drones: [] is an empty list (allowed: at least one number; or leave the key out)"};
    QTest::newRow("set: a range without step") << QByteArray(R"({"sweep": {"test": {"behavior": "flocking"}, "set": {"drones": {"from": 1, "to": 5}}}})")
                                               << QStringList{"q.json: sweep.set.drones: {\"from\":1,\"to\":5} needs \"from\", \"to\" and either \"step\" or \"count\""};
    QTest::newRow("set: a value twice") << QByteArray(R"({"sweep": {"test": {"behavior": "flocking"}, "set": {"drones": [1, 2, 1]}}})")
                                        << QStringList{"q.json: sweep.set.drones[2]: 1 is already in the list (allowed: each value once)"};
    QTest::newRow("set: not a dotted key") << QByteArray(R"({"sweep": {"test": {"behavior": "flocking"}, "set": {"drone..max_speed": [1]}}})")
                                           << QStringList{"q.json: sweep.set.drone..max_speed: not a dotted key of letters, digits, '_' and '-' (allowed: a dotted path to a number of the test: drones, drone.<property>, behavior.params.<p>, groups.<name>.drones"};
    QTest::newRow("set: a key naming no number") << QByteArray(R"({"sweep": {"test": {"behavior": "flocking"}, "set": {"behavior": [1]}}})")
                                                 << QStringList{"q.json: sweep.set.behavior: sweep.test.behavior is \"flocking\", not a number (allowed: a dotted path to a number"};
    QTest::newRow("set: a path through a number") << QByteArray(R"({"sweep": {"test": {"behavior": "flocking", "time": 5}, "set": {"time.x": [1]}}})")
                                                  << QStringList{"q.json: sweep.set.time.x: sweep.test.time is 5, which holds no x (allowed: a dotted path to a number"};
    QTest::newRow("set: not an object") << QByteArray(R"({"sweep": {"test": {"behavior": "flocking"}, "set": ["drones"]}})")
                                        << QStringList{"q.json: sweep.set: [\"drones\"] must be an object of keys and their values, e.g. {\"drone.max_speed\": [5, 10]"};
    QTest::newRow("set: a value out of the key's range")
        << QByteArray(R"({"repeats": 2, "sweep": {"test": {"behavior": "flocking"}, "set": {"drone.max_speed": [5, 2000]}}})")
        << QStringList{"q.json: sweep (set.drone.max_speed[1]): drone.max_speed: 2000 is out of range (allowed: [0.001, 1000] m/s)"};
    QTest::newRow("set: a count out of range") << QByteArray(R"({"sweep": {"behaviors": ["flocking", "random_walk"], "set": {"drones": [0]}}})")
                                               << QStringList{"q.json: sweep (behaviors[0], set.drones[0]): drones: 0 is out of range (allowed: whole number in [1, 1000000])"};
    QTest::newRow("set: a key the test does not have") << QByteArray(R"({"sweep": {"test": {"behavior": "flocking"}, "set": {"drone.speed": [3]}}})")
                                                       << QStringList{"q.json: sweep (set.drone.speed[0]): drone.speed: unknown key (allowed: name, base, camera_range"};
  }
  void errors() {
    QFETCH(QByteArray, queue);
    QFETCH(QStringList, expect);
    const QString message = error_of(queue);
    QVERIFY2(!message.contains('\n'), qPrintable(message));
    for (const QString& e : expect) QVERIFY2(message.contains(e), qPrintable("expected \"" + e + "\" in\n" + message));
  }

  void yes_allows_a_large_queue() {
    const QByteArray queue = R"({"repeats": 3, "sweep": {"behaviors": ["random_walk", "flocking"], "drones": {"from": 1, "to": 2000, "step": 1}}})";
    QueueOptions options;
    options.yes = true;
    QCOMPARE(load(queue, options).tests.size(), std::size_t(12000));
    options = {};
    options.max_tests = 5;
    QVERIFY(error_of(R"({"sweep": {"behaviors": ["random_walk", "flocking", "pheromone_avoidance"], "drones": [1, 2]}})", options)
                .contains("q.json: the queue expands to 6 tests (allowed: 5 without --yes): check the sweep"));
  }

  // The queue record's configs are built once per group of repeats: the same text as test_config.
  void record_configs_are_the_tests_configs() {
    const Queue q = load(R"({"repeats": 4, "sweep": {"test": {"time": 2},
                             "behaviors": ["random_walk", {"name": "flocking", "params": {"cohesion_weight": [1, 2]}}],
                             "drones": [5, 10]}})");
    QCOMPARE(q.tests.size(), std::size_t(24));
    std::size_t calls = 0;
    for_each_test_config(q.tests, *host_, [&](std::size_t i, const std::string& config) {
      QCOMPARE(i, calls++);
      QCOMPARE(config, test_config(q.tests[i], *host_));
    });
    QCOMPARE(calls, q.tests.size());
  }

  // A list of 10^6 values is checked for repeats in one pass (it took 372 s in Release when each value
  // was compared with all before it): a repeat at its end is found. No wall-clock assertion (a loaded
  // machine is not a slow algorithm): sized so that the quadratic check, about 10× slower under the
  // sanitizers, cannot finish the two lists within the suite's 1,800 s; the time is printed.
  void long_sweep_lists_are_checked_fast() {
    for (const char* axis : {"behaviors\": [{\"name\": \"flocking\", \"params\": {\"cohesion_weight\": ", "drones\": "}) {
      QByteArray list = "[";
      const bool weights = QByteArray(axis).startsWith("behaviors");
      for (int i = 0; i < 1'000'000; ++i) list += QByteArray::number(weights ? 1 + i * 1e-6 : 1.0 + i, 'g', 12) + ",";
      list += weights ? "1.5]}}]" : "500]";
      QElapsedTimer timer;
      timer.start();
      const QString message = error_of("{\"sweep\": {\"" + QByteArray(axis) + list + "}}");
      qInfo("%s: %lld ms", axis, static_cast<long long>(timer.elapsed()));
      QVERIFY2(message.contains("[1000000]: ") && message.contains("is already in the list (allowed: each value once)"), qPrintable(message.left(300)));
    }
  }

  // ---- Seeds: the paired rule

  void reordering_tests_or_adding_a_behavior_changes_no_seed() {
    const Queue before = load(R"({"tests": [{"name": "a", "behavior": "flocking", "drones": 6}, {"name": "b", "behavior": "random_walk", "drones": 4}],
                                  "sweep": {"behaviors": ["random_walk", "flocking"], "drones": [10, 20]}})");
    const Queue after = load(R"({"tests": [{"name": "c", "behavior": "flocking", "drones": 7},
                                           {"name": "b", "behavior": "random_walk", "drones": 4}, {"name": "a", "behavior": "flocking", "drones": 6}],
                                 "sweep": {"behaviors": ["pheromone_avoidance", "flocking", "random_walk"], "drones": [30, 20, 10]}})");
    const auto old_seeds = seeds_by_name(before), new_seeds = seeds_by_name(after);
    QCOMPARE(old_seeds.size(), std::size_t(6));
    QCOMPARE(new_seeds.size(), std::size_t(12));
    for (const auto& [name, seed] : old_seeds) {
      QVERIFY2(new_seeds.count(name), name.c_str());  // the names did not change either
      QCOMPARE(new_seeds.at(name), seed);
    }
  }

  void behaviors_in_one_repeat_share_their_world_data() {
    QTest::addColumn<QByteArray>("queue");
    QTest::newRow("behaviors x drones x maps, 3 repeats")
        << QByteArray(R"({"repeats": 3, "sweep": {"behaviors": ["random_walk", "pheromone_avoidance",
                         {"name": "flocking", "params": {"cohesion_weight": [1, 2]}}], "drones": [10, 20],
                         "maps": ["empty", {"name": "forest", "params": {"clusters": [5, 10]}}]}})");
    QTest::newRow("explicit tests and a sweep")
        << QByteArray(R"({"repeats": 2, "tests": [{"name": "x", "behavior": "dynamic_space_partitioning", "drones": 20, "map": "forest",
                         "time": 30}], "sweep": {"test": {"map": "forest"}, "behaviors": ["random_walk", "flocking"], "drones": [10, 20]}})");
    QTest::newRow("drone configurations and targets")
        << QByteArray(R"({"repeats": 2, "sweep": {"behaviors": ["random_walk", "flocking"], "drone": ["small", "large"], "targets": [0, 50]}})");
  }
  void behaviors_in_one_repeat_share_their_world() {
    QFETCH(QByteArray, queue);
    const Queue q = load(queue);
    std::map<std::pair<std::string, std::size_t>, std::uint64_t> by_world;  // (world, repeat) -> seed
    std::map<std::string, std::set<std::string>> behaviors;                   // world -> behaviors seen
    for (const auto& t : q.tests) {
      const auto [it, fresh] = by_world.emplace(std::pair{world_key(t), t.repeat}, t.seed);
      QVERIFY2(fresh || it->second == t.seed, t.name.c_str());  // every behavior of a world and repeat: one seed
      behaviors[world_key(t)].insert(variant(t, *host_));
    }
    for (const auto& [world, seen] : behaviors) QVERIFY2(seen.size() >= 2, world.c_str());  // the rule was put to the test
    // Other repeats and other worlds: other seeds.
    std::set<std::uint64_t> distinct;
    for (const auto& [key, seed] : by_world) distinct.insert(seed);
    QCOMPARE(distinct.size(), by_world.size());
  }

  void world_key_holds_the_world_only() {
    const TestSpec a = parse_test(R"({"name": "a", "behavior": "flocking", "drones": 30, "map": "forest", "time": 10})", "t", *host_);
    const TestSpec b = parse_test(R"({"name": "b", "behavior": {"name": "random_walk", "params": {"max_duration": 3}}, "drones": 30,
                                      "map": {"name": "forest", "params": {"size": 500}}, "time": 99, "log_interval": 2, "decision_lag": 0})",
                                  "t", *host_);
    QCOMPARE(world_key(a), world_key(b));
    QCOMPARE(a.seed, b.seed);  // the paired seed of queue seed 1, repeat 0
    for (const char* other : {R"({"behavior": "flocking", "drones": 31, "map": "forest"})",
                              R"({"behavior": "flocking", "drones": 30, "map": {"name": "forest", "params": {"clusters": 13}}})",
                              R"({"behavior": "flocking", "drones": 30, "map": "forest", "targets": {"count": 1}})",
                              R"({"behavior": "flocking", "drones": 30, "map": "forest", "drone": "medium"})",
                              R"({"behavior": "flocking", "drones": 30, "map": "forest", "spawn": {"mode": "uniform"}})"}) {
      const TestSpec c = parse_test(other, "t", *host_);
      QVERIFY2(world_key(c) != world_key(a), other);
      QVERIFY2(c.seed != a.seed, other);
    }
    // A map file is known by its name, not the folder it was reached from.
    const std::string warehouse = (source_dir() / "examples/maps/warehouse.json").string();
    const TestSpec by_path = parse_test("{\"behavior\": \"flocking\", \"map\": \"" + warehouse + "\"}", "t", *host_);
    const TestSpec relative = parse_test(R"({"behavior": "flocking", "map": "maps/warehouse.json"})", "t", *host_, source_dir() / "examples");
    QCOMPARE(world_key(by_path), world_key(relative));
  }

  void paired_seed_is_stable() {
    // The rule as documented (queue.hpp, docs/test-format.md), computed apart from salsa: a queue
    // expanded by another version must get the same seeds.
    QCOMPARE(paired_seed(1, 0, "{}"), std::uint64_t(7101787162266751));
    QCOMPARE(paired_seed(7, 2, "{\"drones\":30}"), std::uint64_t(5596072146341897));
    std::set<std::uint64_t> seeds;
    for (std::uint64_t s = 0; s < 100; ++s)
      for (std::size_t r = 0; r < 100; ++r) {
        const std::uint64_t seed = paired_seed(s, r, "{\"drones\":30}");
        QVERIFY(seed < (std::uint64_t{1} << 53));
        seeds.insert(seed);
      }
    QCOMPARE(seeds.size(), std::size_t(10000));
  }

  void explicit_seed_wins() {
    const Queue q = load(R"({"seed": 9, "tests": [{"name": "fixed", "behavior": "flocking", "seed": 42}, {"name": "paired", "behavior": "flocking", "drones": 5}],
                             "sweep": {"test": {"seed": 43}, "behaviors": ["random_walk", "flocking"], "drones": [3, 4]}})");
    QCOMPARE(q.tests.size(), std::size_t(6));
    QCOMPARE(q.tests[0].seed, std::uint64_t(42));
    QVERIFY(q.tests[0].seed_given);
    QCOMPARE(q.tests[1].seed, paired_seed(9, 0, world_key(q.tests[1])));
    QVERIFY(!q.tests[1].seed_given);
    for (std::size_t i = 2; i < q.tests.size(); ++i) QCOMPARE(q.tests[i].seed, std::uint64_t(43));
  }

  void command_line_seed_changes_all() {
    const QByteArray queue = R"({"seed": 9, "repeats": 2, "tests": [{"name": "a", "behavior": "flocking"}],
                                 "sweep": {"behaviors": ["random_walk", "flocking"], "drones": [3, 4]}})";
    const Queue plain = load(queue);
    QueueOptions options;
    options.seed = 5;
    const Queue seeded = load(queue, options);
    QCOMPARE(seeded.seed, std::uint64_t(5));
    QCOMPARE(seeded.tests.size(), plain.tests.size());
    for (std::size_t i = 0; i < plain.tests.size(); ++i) {
      QCOMPARE(seeded.tests[i].name, plain.tests[i].name);
      QVERIFY(seeded.tests[i].seed != plain.tests[i].seed);
      QCOMPARE(seeded.tests[i].seed, paired_seed(5, seeded.tests[i].repeat, world_key(seeded.tests[i])));
    }
    // Over the seeds in the file too: a fixed-seed queue gets new worlds, repeats included.
    const QByteArray fixed = R"({"repeats": 2, "tests": [{"name": "a", "behavior": "flocking", "seed": 42}]})";
    QVERIFY(error_of(fixed).contains("seed: 42 would be the seed of every repeat"));
    const Queue over = load(fixed, options);
    QCOMPARE(over.tests[0].seed, paired_seed(5, 0, world_key(over.tests[0])));
    QCOMPARE(over.tests[1].seed, paired_seed(5, 1, world_key(over.tests[1])));
  }

  void plain_test_files_keep_working() {
    const Queue one = load_queue(file("fast.json", R"({"behavior": "flocking", "drones": 5})"), *host_, {});
    QCOMPARE(one.tests.size(), std::size_t(1));
    QCOMPARE(one.tests[0].name, std::string("fast"));
    QCOMPARE(one.tests[0].repeat, std::size_t(0));
    QCOMPARE(one.tests[0].seed, paired_seed(1, 0, world_key(one.tests[0])));
    const auto list = load_tests(file("list.json", R"([{"behavior": "flocking"}, {"behavior": "random_walk", "drones": 4}])"), *host_);
    QCOMPARE(list.size(), std::size_t(2));
    QCOMPARE(list[0].name, std::string("list-1"));
    QCOMPARE(list[1].name, std::string("list-2"));
  }

  // ---- Order and names

  void interleaved_order() {
    const Queue q = load(R"({"repeats": 3, "tests": [{"name": "a", "behavior": "flocking"}, {"name": "b", "behavior": "random_walk"}],
                             "sweep": {"behaviors": ["random_walk", "flocking"], "drones": [3, 4]}})");
    QCOMPARE(q.tests.size(), std::size_t(3 * 6));
    const std::vector<std::string> one_repeat{"a", "b", "random_walk_d3", "flocking_d3", "random_walk_d4", "flocking_d4"};
    for (std::size_t i = 0; i < q.tests.size(); ++i) {
      const std::size_t repeat = i / one_repeat.size();
      QCOMPARE(q.tests[i].repeat, repeat);
      QCOMPARE(q.tests[i].name, one_repeat[i % one_repeat.size()] + "_r" + std::to_string(repeat));
    }
  }

  void names_are_unique_and_fit_for_folders_data() {
    QTest::addColumn<QByteArray>("queue");
    QTest::addColumn<QStringList>("some_names");
    QTest::newRow("parameters, counts, maps")
        << QByteArray(R"({"sweep": {"behaviors": [{"name": "flocking", "params": {"cohesion_weight": [2], "alignment_weight": [0.5, 1e-9]}}],
                         "drones": [30], "targets": [100], "maps": [{"name": "forest", "params": {"size": [1000]}}]}})")
        << QStringList{"flocking_aw0.5_cw2_d30_t100_forest_size1000_r0", "flocking_aw1e-09_cw2_d30_t100_forest_size1000_r0"};
    QTest::newRow("look-alike initials spelled out")
        << QByteArray(R"({"sweep": {"behaviors": [{"name": "random_walk", "params": {"min_duration": [1], "max_duration": [5], "turn_distance": [0.5]}}]}})")
        << QStringList{"random_walk_min_duration1_max_duration5_td0.5_r0"};
    QTest::newRow("a prefix, drone configurations, map files, target objects")
        << QByteArray(R"({"sweep": {"test": {"name": "study"}, "behaviors": ["flocking"], "maps": ["w.json"],
                         "drone": ["small", {"name": "fast one", "max_speed": 15}], "targets": [{"kind": "tree", "count": 5, "params": {"radius": 2}}]}})")
        << QStringList{"study_flocking_tree5_radius2_w_small_r0", "study_flocking_tree5_radius2_w_fast_one_r0"};
    QTest::newRow("explicit names with repeats")
        << QByteArray(R"({"repeats": 2, "tests": [{"name": "mine", "behavior": "flocking"}, {"behavior": "random_walk"}]})")
        << QStringList{"mine_r0", "q-2_r0", "mine_r1", "q-2_r1"};
    QTest::newRow("long names get a hash")
        << QByteArray(R"({"sweep": {"test": {"name": ")" + QByteArray(100, 'x') + R"("}, "behaviors": [{"name": "flocking",
                         "params": {"cohesion_weight": [1, 2], "alignment_weight": [0.25], "separation_weight": [0.125]}}]}})")
        << QStringList{};
  }
  void names_are_unique_and_fit_for_folders() {
    QFETCH(QByteArray, queue);
    QFETCH(QStringList, some_names);
    file("w.json", read_file(q(source_dir() / "examples/maps/warehouse.json")));
    const Queue q = load(queue);
    std::set<std::string> names;
    for (const auto& t : q.tests) {
      QVERIFY2(name_problem(t.name).empty(), name_problem(t.name).c_str());
      QVERIFY2(names.insert(t.name).second, t.name.c_str());
    }
    for (const QString& n : some_names) QVERIFY2(names.count(n.toStdString()), qPrintable(n + " not among the names"));
    if (some_names.isEmpty())
      for (const auto& name : names) {
        QCOMPARE(name.size(), max_name_length);
        QVERIFY2(name.ends_with("_r0") && name.starts_with(std::string(100, 'x') + "_flocking_"), name.c_str());
      }
  }

  void config_json_holds_the_repeat_and_reruns_it() {
    const Queue q = load(R"({"repeats": 2, "sweep": {"behaviors": ["flocking"], "drones": [3]}})");
    const std::string config = resolved_json(q.tests[1], *host_);
    QVERIFY(config.find("\"repeat\": 1") != std::string::npos);
    const TestSpec again = parse_test(config, "config.json", *host_);
    QCOMPARE(again.repeat, std::size_t(1));
    QCOMPARE(again.seed, q.tests[1].seed);
    QCOMPARE(resolved_json(again, *host_), config);
  }

  // ---- Through the CLI

  void cli_queue_expand() {
    const std::string path = file("cli.json", R"({"seed": 4, "repeats": 2, "tests": [{"name": "base", "behavior": "random_walk", "drones": 5}],
                                                  "sweep": {"behaviors": ["random_walk", {"name": "flocking", "params": {"cohesion_weight": [2]}}],
                                                            "drones": [10], "maps": [{"name": "forest", "params": {"clusters": [5]}}]}})");
    const CliResult r = run_salsa({"queue", "expand", q(path)});
    QVERIFY2(r.exit_code == 0 && r.err.isEmpty(), describe(r));
    const QStringList lines = non_empty_lines(r.out);
    QCOMPARE(lines.value(0), QString("6 tests"));
    QCOMPARE(lines.size(), 7);
    const Queue queue = load_queue(path, *host_, {});
    for (std::size_t i = 0; i < queue.tests.size(); ++i) {
      const TestSpec& t = queue.tests[i];
      const QStringList fields = lines[qsizetype(i) + 1].split(' ', Qt::SkipEmptyParts);
      QCOMPARE(fields.value(0), q(t.name));
      QVERIFY2(fields.contains("seed=" + QString::number(t.seed)) && fields.contains("repeat=" + QString::number(t.repeat)),
               qPrintable(lines[qsizetype(i) + 1]));
    }
    QVERIFY2(lines[2].split(' ', Qt::SkipEmptyParts) ==
                 QStringList({"random_walk_d10_forest_clusters5_r0", "random_walk", "(defaults)", "drones=10", "targets=0", "map=forest(clusters=5)",
                              "drone=small", "repeat=0", "seed=" + QString::number(queue.tests[1].seed)}),
             qPrintable(lines[2]));
    QVERIFY2(lines[3].contains(" flocking: cohesion_weight = 2 "), qPrintable(lines[3]));

    // --seed changes every seed; the names stay.
    const CliResult seeded = run_salsa({"queue", "expand", q(path), "--seed", "5"});
    QVERIFY2(seeded.exit_code == 0, describe(seeded));
    const QStringList other = non_empty_lines(seeded.out);
    QCOMPARE(other.size(), lines.size());
    for (qsizetype i = 1; i < lines.size(); ++i) {
      QCOMPARE(other[i].section(' ', 0, 0), lines[i].section(' ', 0, 0));
      QVERIFY(other[i].section("seed=", 1) != lines[i].section("seed=", 1));
    }
  }

  void cli_queue_expand_names_the_condition() {
    const std::string path = file("cond.json", R"({"base": {"drones": 5, "time": 10}, "sweep": {"behaviors": ["flocking"]},
                                                   "conditions": [{"name": "calm"}, {"name": "big", "drones": 6}]})");
    const CliResult r = run_salsa({"queue", "expand", q(path)});
    QVERIFY2(r.exit_code == 0 && r.err.isEmpty(), describe(r));
    const QStringList lines = non_empty_lines(r.out);
    QCOMPARE(lines.size(), 3);
    QVERIFY2(lines[1].startsWith("flocking_calm_r0 ") && lines[1].contains(" condition=calm ") && lines[1].contains("drones=5"), qPrintable(lines[1]));
    QVERIFY2(lines[2].startsWith("flocking_big_r0 ") && lines[2].contains(" condition=big ") && lines[2].contains("drones=6"), qPrintable(lines[2]));
  }

  void cli_validate_and_yes() {
    const std::string small = file("small.json", R"({"sweep": {"behaviors": ["random_walk", "flocking"], "drones": [3, 4]}})");
    CliResult r = run_salsa({"validate", q(small)});
    QVERIFY2(r.exit_code == 0 && r.out.trimmed() == q(small) + ": ok (4 tests)", describe(r));

    const std::string big = file("big.json", R"({"sweep": {"behaviors": ["random_walk", "flocking"], "drones": {"from": 1, "to": 5001, "step": 1}}})");
    r = run_salsa({"queue", "expand", q(big)});
    QVERIFY2(r.exit_code == 2 && non_empty_lines(r.err).size() == 1 && r.out.isEmpty(), describe(r));
    QVERIFY2(r.err.contains("big.json: the queue expands to 10,002 tests (allowed: 10,000 without --yes): check the sweep, or pass --yes"), describe(r));
    r = run_salsa({"queue", "expand", q(big), "--yes"});
    QVERIFY2(r.exit_code == 0 && r.out.startsWith("10002 tests\n"), qPrintable(r.err));

    r = run_salsa({"queue", "list", q(small)});
    QVERIFY2(r.exit_code == 2 && r.err.contains("queue: unknown action 'list' (allowed: expand)"), describe(r));
  }

  void cli_run_writes_the_seeds_it_expanded() {
    const std::string path = file("run.json", R"({"repeats": 2, "sweep": {"test": {"time": 1, "targets": {"count": 5}},
                                                  "behaviors": ["random_walk", "flocking"], "drones": [3]}})");
    QTemporaryDir out;
    const CliResult r = run_salsa({"run", q(path), "--out", out.path(), "--no-drones-csv"});
    QVERIFY2(r.exit_code == 0, describe(r));
    for (const TestSpec& t : load_queue(path, *host_, {}).tests) {
      const QByteArray config = read_file(out.filePath(q(t.name) + "/config.json"));
      QVERIFY2(config.contains("\"seed\": " + QByteArray::number(quint64(t.seed)) + ",") &&
                   config.contains("\"repeat\": " + QByteArray::number(quint64(t.repeat)) + ","),
               config.constData());
    }
  }
};

QTEST_GUILESS_MAIN(TestQueue)
#include "test_queue.moc"
