// Test files as docs/test-format.md describes them: defaults, the shorthands, named drone
// configurations from a JSON file, and config.json rereading to the very same test.
#include "common.hpp"

#include "salsa/core/queue.hpp"
#include "salsa/core/test_spec.hpp"

using namespace salsa;
using namespace salsa_test;

class TestTestFormat : public QObject {
  Q_OBJECT

  std::unique_ptr<PluginHost> host_ = builtin_host();

 private Q_SLOTS:
  void defaults_are_filled_in() {
    const TestSpec t = parse_test(R"({"behavior": "flocking"})", "t.json", *host_);
    QCOMPARE(t.drones, std::size_t(10));
    QCOMPARE(t.drone.name, std::string("small"));
    QCOMPARE(t.map.name, std::string("empty"));
    QCOMPARE(t.contact_handlers, std::vector<std::string>{"detect_targets"});
    QCOMPARE(t.dt, 1.0 / 60);
    QCOMPARE(t.decision_lag, 1);
    QCOMPARE(t.behavior.params.get("alignment_weight"), 1.6);  // declared default
    QCOMPARE(t.steps(), std::size_t(3600));
    QCOMPARE(t.log_every(), std::size_t(60));
  }

  void named_drone_configurations_from_a_file() {
    QTemporaryDir dir;
    QVERIFY(write_file(dir.filePath("fleet.json"),
                       R"({"heavy": {"base": "large", "max_speed": 6, "mass": 30},
                           "scout": {"camera_range": 40, "max_speed": 25}})"));
    const QByteArray test = R"({"behavior": "random_walk", "drone_configs": "fleet.json", "drone": "heavy"})";
    QVERIFY(write_file(dir.filePath("t.json"), test));
    const auto tests = load_tests(dir.filePath("t.json").toStdString(), *host_);
    QCOMPARE(tests.size(), std::size_t(1));
    const DroneConfig& d = tests[0].drone;
    QCOMPARE(d.name, std::string("heavy"));
    QCOMPARE(d.max_speed, 6.0);
    QCOMPARE(d.mass, 30.0);
    QCOMPARE(d.camera_range, 40.0);  // from "large"
    QCOMPARE(d.obstacle_rays, 12);

    // A configuration edited inline on top of a named one.
    const TestSpec t = parse_test(R"({"behavior": "random_walk", "drone": {"base": "small", "radius": 0.5}})", "t", *host_);
    QCOMPARE(t.drone.radius, 0.5);
    QCOMPARE(t.drone.detection_range, 134.0);
  }

  void map_shorthands() {
    const std::string warehouse = (source_dir() / "examples/maps/warehouse.json").string();
    const std::string json = "{\"behavior\": \"flocking\", \"map\": \"" + warehouse + "\"}";
    const TestSpec by_file = parse_test(json, "t", *host_);
    QCOMPARE(by_file.map.name, std::string("json"));
    QCOMPARE(by_file.map_file, warehouse);
    const TestSpec by_name = parse_test(R"({"behavior": "flocking", "map": "forest"})", "t", *host_);
    QCOMPARE(by_name.map.name, std::string("forest"));
    QCOMPARE(by_name.map.params.get("size"), 500.0);
  }

  void lists_get_names_by_index_and_paired_seeds() {
    QTemporaryDir dir;
    QVERIFY(write_file(dir.filePath("queue.json"),
                       R"({"tests": [{"behavior": "flocking"}, {"behavior": "random_walk", "seed": 99}]})"));
    const auto tests = load_tests(dir.filePath("queue.json").toStdString(), *host_);
    QCOMPARE(tests.size(), std::size_t(2));
    QCOMPARE(tests[0].name, std::string("queue-1"));
    QCOMPARE(tests[0].seed, paired_seed(1, 0, world_key(tests[0])));  // not the position: docs/test-format.md
    QCOMPARE(tests[1].name, std::string("queue-2"));
    QCOMPARE(tests[1].seed, std::uint64_t(99));
  }

  // config.json is the whole test: read back, it resolves to the same JSON, byte for byte.
  void config_json_rereads_to_the_same_test() {
    const TestSpec t = parse_test(
        R"({"name": "x", "behavior": {"name": "pheromone_avoidance", "params": {"deposit": 2}}, "drones": 7,
            "drone": "medium", "map": {"name": "forest", "params": {"size": 300}}, "spawn": {"mode": "uniform"},
            "targets": {"count": 50, "params": {"radius": 3}}, "time": 12, "log_interval": 0.5,
            "decision_lag": 0, "seed": 5})",
        "t", *host_);
    const std::string config = resolved_json(t, *host_);
    const TestSpec again = parse_test(config, "config.json", *host_);
    QCOMPARE(resolved_json(again, *host_), config);
    QCOMPARE(again.spawn_mode, SpawnMode::uniform);
    QCOMPARE(again.target.params.get("radius"), 3.0);
    QVERIFY(config.find("\"versions\"") != std::string::npos);
    QVERIFY(config.find(salsa_version()) != std::string::npos);
  }
};

QTEST_GUILESS_MAIN(TestTestFormat)
#include "test_test_format.moc"
