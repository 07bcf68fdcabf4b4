// Test files as docs/test-format.md describes them: defaults, the shorthands, named drone
// configurations from a JSON file, and config.json rereading to the very same test.
#include "common.hpp"

#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>

#include <cmath>

#include "salsa/core/experiments/queue.hpp"
#include "salsa/core/model/simulation.hpp"
#include "salsa/core/experiments/test_spec.hpp"

using namespace salsa;
using namespace salsa_test;

namespace {

fs::path contact_plugin_dir() { return test_plugins_dir() / "contact"; }

/// One drone whose camera covers the whole 100 m map, so it has all 3 targets in view from the first
/// step on; dt 0.1 s. `handlers` is the test's "contact_handlers" value.
std::string dwell_test(const std::string& handlers) {
  return R"({"name": "dwell", "behavior": "random_walk", "drones": 1, "drone": {"base": "small", "camera_range": 500},
             "map": {"name": "empty", "params": {"size": 100}}, "targets": {"count": 3}, "dt": 0.1, "time": 2,
             "seed": 4, "contact_handlers": )" + handlers + "}";
}

}  // namespace

class TestTestFormat : public QObject {
  Q_OBJECT

  std::unique_ptr<PluginHost> host_ = builtin_host();

 private Q_SLOTS:
  // The drone is described once (drone_schema): every property it declares is read with its range,
  // written to config.json, set by a timed change and part of the world key that pairs seeds. A
  // property added to the schema is covered here without touching this test.
  void every_drone_property_goes_through_the_schema() {
    QVERIFY(drone_schema().size() >= 8);
    const TestSpec base = parse_test(R"({"behavior": "flocking"})", "t.json", *host_);
    for (const DroneProperty& p : drone_schema()) {
      const Parameter& spec = p.spec;
      const QString name = QString::fromStdString(spec.name);
      QCOMPARE(p.get(base.groups[0].drone), spec.value);  // the default drone is the schema's defaults
      // A value in range, not the default; small enough that check_drone's step limit holds.
      const double v = spec.is_integer() ? spec.value + 1
                       : spec.value == 0       ? 1
                       : (spec.name == "max_speed" || spec.value * 1.5 > spec.max ? spec.value / 2 : spec.value * 1.5);
      const std::string value = Parameter::format(v);
      // The energy model's properties are written once there is a battery; return to base's once it is
      // on, which needs a base that charges.
      const bool returning = p.section == DroneSection::returning;
      const std::string battery = returning ? std::string(", \"battery_capacity\": 10, \"charge_power\": 100") +
                                                  (spec.name == "return_to_base" ? "" : ", \"return_to_base\": 1")
                                  : p.shapes_world || spec.name == "battery_capacity" ? ""
                                                                                      : ", \"battery_capacity\": 10";
      auto with = [&](const std::string& text) {
        return "{\"behavior\": \"flocking\", \"drone\": {\"" + spec.name + "\": " + text + battery + "}}";
      };
      const TestSpec t = parse_test(with(value), "t.json", *host_);
      QCOMPARE(p.get(t.groups[0].drone), v);
      QVERIFY2(resolved_json(t, *host_).find("\"" + spec.name + "\": " + value) != std::string::npos, qPrintable(name));
      // The world key pairs seeds over what shapes the world, not over batteries.
      QVERIFY2((world_key(t) != world_key(base)) == p.shapes_world, qPrintable(name));
      // Out of range: refused with the schema's range, in one line.
      try {
        parse_test(with(Parameter::format(spec.max * 2 + 1)), "t.json", *host_);
        QFAIL(qPrintable(name + ": out of range accepted"));
      } catch (const InputError& e) {
        QVERIFY2(std::string(e.what()).find("t.json: drone." + spec.name + ": ") == 0 && std::string(e.what()).find(spec.range()) != std::string::npos,
                 e.what());
      }
      // A timed change of it (return to base's on a drone that may return).
      const Change change{1, "drone." + spec.name, v};
      const TestSpec from = returning ? parse_test("{\"behavior\": \"flocking\", \"drone\": {\"battery_capacity\": 10, \"charge_power\": 100}}", "t.json", *host_) : base;
      QCOMPARE(check_change(from, change, *host_), std::string());
      TestSpec changed = from;
      apply_to_test(changed, change);
      QCOMPARE(p.get(changed.groups[0].drone), v);
      QVERIFY(!check_change(from, {1, "drone." + spec.name, spec.max * 2 + 1}, *host_).empty());
    }
    QVERIFY(check_change(base, {1, "drone.wingspan", 1}, *host_).find(drone_schema().names()) != std::string::npos);
  }

  void defaults_are_filled_in() {
    const TestSpec t = parse_test(R"({"behavior": "flocking"})", "t.json", *host_);
    QCOMPARE(t.groups[0].drones, std::size_t(10));
    QCOMPARE(t.groups[0].drone.name, std::string("small"));
    QCOMPARE(t.map.name, std::string("empty"));
    QCOMPARE(t.contact_handlers.size(), std::size_t(1));
    QCOMPARE(t.contact_handlers[0].name, std::string("detect_targets"));
    QCOMPARE(t.dt, 1.0 / 60);
    QCOMPARE(t.decision_lag, 0);  // the paper's sequential definition, the default everywhere
    QCOMPARE(t.groups[0].behavior.params.get("alignment_weight"), 1.6);  // declared default
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
    const DroneConfig& d = tests[0].groups[0].drone;
    QCOMPARE(d.name, std::string("heavy"));
    QCOMPARE(d.max_speed, 6.0);
    QCOMPARE(d.mass, 30.0);
    QCOMPARE(d.camera_range, 40.0);  // from "large"
    QCOMPARE(d.obstacle_rays, 12);

    // A configuration edited inline on top of a named one.
    const TestSpec t = parse_test(R"({"behavior": "random_walk", "drone": {"base": "small", "radius": 0.5}})", "t", *host_);
    QCOMPARE(t.groups[0].drone.radius, 0.5);
    QCOMPARE(t.groups[0].drone.detection_range, 134.0);
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

  // A contact handler's parameters come from the test file (its "dwell" s in view before a target counts
  // as found), and those not given get their defaults.
  void contact_handler_parameters_reach_the_handler_data() {
    QTest::addColumn<QString>("handlers");
    QTest::addColumn<double>("dwell");
    QTest::addColumn<double>("found_time");  // the end of the step in which the dwell is reached
    QTest::newRow("default (1 s)") << R"(["test_dwell"])" << 1.0 << 1.0;
    QTest::newRow("0.5 s") << R"([{"name": "test_dwell", "params": {"dwell": 0.5}}])" << 0.5 << 0.5;
    QTest::newRow("0: the first step") << R"([{"name": "test_dwell", "params": {"dwell": 0}}])" << 0.0 << 0.1;
    QTest::newRow("1.5 s, given twice") << R"([{"name": "test_dwell", "params": {"dwell": 1.5}}, {"name": "test_dwell", "params": {"dwell": 1.5}}])"
                                        << 1.5 << 1.5;
  }
  void contact_handler_parameters_reach_the_handler() {
    QFETCH(QString, handlers);
    QFETCH(double, dwell);
    QFETCH(double, found_time);
    PluginHost host;
    host.load({{plugin_dir(), "test"}, {contact_plugin_dir(), "test"}});
    const TestSpec t = parse_test(dwell_test(handlers.toStdString()), "t.json", host);
    QVERIFY(!t.contact_handlers.empty());
    QCOMPARE(t.contact_handlers[0].name, std::string("test_dwell"));
    QCOMPARE(t.contact_handlers[0].params.get("dwell"), dwell);
    QCOMPARE(t.contact_handlers[0].params.get("drones_at_least"), 0.0);  // the default filled in
    Simulation sim(make_setup(t, host, 1));
    sim.run_steps(t.steps());
    QCOMPARE(sim.targets().size(), std::size_t(3));
    for (const TargetState& target : sim.targets()) {
      QVERIFY2(target.found(), qPrintable(QString("dwell %1 s").arg(dwell)));
      QVERIFY2(std::abs(target.found_time - found_time) < 1e-9,
               qPrintable(QString("found at %1 s, expected %2 s").arg(target.found_time).arg(found_time)));
    }
    // config.json holds every handler with all its values, and rereads to the same test.
    const std::string config = resolved_json(t, host);
    QCOMPARE(resolved_json(parse_test(config, "config.json", host), host), config);
  }

  // `salsa run` records a handler's parameters in config.json (and its plugin's version), and the
  // targets it found after the dwell time in targets.csv.
  void contact_handler_parameters_in_config_json() {
    QTemporaryDir dir;
    QVERIFY(write_file(dir.filePath("t.json"), QByteArray::fromStdString(dwell_test(
        R"(["detect_targets", {"name": "test_dwell", "params": {"dwell": 0.7, "drones_at_least": 1}}])"))));
    const CliResult r = run_salsa({"run", "t.json", "--out", "out", "--quiet", "--plugin-dir", q(contact_plugin_dir())}, dir.path());
    QVERIFY2(r.exit_code == 0, describe(r));
    const QJsonObject config = QJsonDocument::fromJson(read_file(dir.filePath("out/dwell/config.json"))).object();
    const QJsonArray handlers = config["contact_handlers"].toArray();
    QCOMPARE(handlers.size(), 2);
    QCOMPARE(handlers[0].toObject()["name"].toString(), QString("detect_targets"));
    QCOMPARE(handlers[0].toObject()["params"].toObject().size(), 0);
    QCOMPARE(handlers[1].toObject()["name"].toString(), QString("test_dwell"));
    const QJsonObject params = handlers[1].toObject()["params"].toObject();
    QCOMPARE(params.size(), 2);
    QCOMPARE(params["dwell"].toDouble(), 0.7);
    QCOMPARE(params["drones_at_least"].toDouble(), 1.0);
    const QJsonArray versions = config["versions"].toObject()["contact_handlers"].toArray();
    QCOMPARE(versions.size(), 2);
    QCOMPARE(versions[1].toObject()["plugin"].toString(), QString("test_contact"));
    // The queue summary: names joined, each parameter its own column.
    const QStringList summary = non_empty_lines(QString::fromUtf8(read_file(dir.filePath("out/summary.csv"))));
    QCOMPARE(summary.size(), 2);
    const QStringList header = summary[0].split(','), row = summary[1].split(',');
    QCOMPARE(row.value(static_cast<int>(header.indexOf("contact_handlers"))), QString("detect_targets;test_dwell"));
    QCOMPARE(row.value(static_cast<int>(header.indexOf("contact_handler.test_dwell.dwell"))), QString("0.7"));
    // detect_targets comes first and finds every target in the first step, before test_dwell's turn.
    const QStringList targets = non_empty_lines(QString::fromUtf8(read_file(dir.filePath("out/dwell/targets.csv"))));
    QCOMPARE(targets.size(), 4);
    const int found_time = static_cast<int>(targets[0].split(',').indexOf("found_time"));
    QVERIFY(found_time >= 0);
    for (int i = 1; i < targets.size(); ++i) QCOMPARE(targets[i].split(',').value(found_time).toDouble(), 0.1);
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
    QCOMPARE(again.groups[0].spawn_mode, SpawnMode::uniform);
    QCOMPARE(again.target.params.get("radius"), 3.0);
    QVERIFY(config.find("\"versions\"") != std::string::npos);
    QVERIFY(config.find(salsa_version()) != std::string::npos);
  }
};

QTEST_GUILESS_MAIN(TestTestFormat)
#include "test_test_format.moc"
