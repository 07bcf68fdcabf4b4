// Timed changes in the test format: checked like every other field, applied by the runner right before
// the step that starts at their time, recorded in config.json, and equal to changing a live simulation
// by hand at the same steps (which is what the GUI's sandbox does, then saves as a test).
#include "common.hpp"

#include <QTemporaryDir>
#include <cmath>

#include "salsa/core/experiments/changes.hpp"
#include "salsa/core/run/runner.hpp"
#include "salsa/core/model/simulation.hpp"
#include "salsa/core/experiments/test_spec.hpp"

using namespace salsa;
using namespace salsa_test;

namespace {
const std::string base = R"("name": "chg", "behavior": "flocking", "drones": 8, "map": {"name": "forest", "params": {"size": 300}},
  "targets": {"kind": "tree", "count": 40}, "time": 3, "seed": 5, "metrics": [])";

std::string with_changes(const std::string& changes) { return "{" + base + R"(, "changes": )" + changes + "}"; }
}  // namespace

class TestChanges : public QObject {
  Q_OBJECT
  std::unique_ptr<PluginHost> host_ = builtin_host();

  QString refusal(const std::string& changes) {
    try {
      parse_test(with_changes(changes), "chg.json", *host_);
    } catch (const InputError& e) {
      return QString::fromStdString(e.what());
    }
    return "(accepted)";
  }

 private Q_SLOTS:
  void bad_changes_are_refused_naming_the_field_data() {
    QTest::addColumn<QString>("changes");
    QTest::addColumn<QString>("expected");
    QTest::newRow("drones 0") << R"([{"time": 1, "set": {"drones": 0}}])"
                              << "chg.json: changes[0].set.drones: 0 is out of range (allowed: whole number in [1, 1000000])";
    QTest::newRow("after the end") << R"([{"time": 5, "set": {"drones": 3}}])"
                                   << "chg.json: changes[0].time: 5 is out of range (allowed: [0, 3] s)";
    QTest::newRow("out of order") << R"([{"time": 2, "set": {"drones": 3}}, {"time": 1, "set": {"drones": 4}}])"
                                  << "chg.json: changes[1].time: 1 is out of range (allowed: [2, 3] s)";
    QTest::newRow("parameter range") << R"([{"time": 1, "set": {"behavior.params.cohesion_weight": 99}}])"
                                     << "chg.json: changes[0].set.behavior.params.cohesion_weight: 99 is out of range (allowed: [0, 10])";
    QTest::newRow("unknown parameter") << R"([{"time": 1, "set": {"behavior.params.nope": 1}}])"
                                       << "chg.json: changes[0].set.behavior.params.nope: unknown parameter of behavior 'flocking'";
    QTest::newRow("too fast") << R"([{"time": 1, "set": {"drone.max_speed": 500}}])"
                              << "chg.json: changes[0].set.drone.max_speed: 500 m/s × dt";
    // Checked against the test as the earlier changes left it: a larger radius first allows more speed.
    QTest::newRow("in order") << R"([{"time": 1, "set": {"drone.max_speed": 100}}, {"time": 1, "set": {"drone.radius": 2}}])"
                              << "chg.json: changes[0].set.drone.max_speed: 100 m/s × dt";
    QTest::newRow("unknown key") << R"([{"time": 1, "set": {"colour": 1}}])"
                                 << "chg.json: changes[0].set.colour: unknown key (allowed: behavior.params.<name>, drones, drone.<property>, "
                                    "groups.<name>.<any of those>, failures.<drone_mtbf, camera_mtbf>, comm.<range";
    QTest::newRow("no set") << R"([{"time": 1}])" << "chg.json: changes[0].set: missing";
    QTest::newRow("not a list") << R"({"time": 1})" << "chg.json: changes: {\"time\":1} must be a list";
  }
  void bad_changes_are_refused_naming_the_field() {
    QFETCH(QString, changes);
    QFETCH(QString, expected);
    const QString why = refusal(changes.toStdString());
    QVERIFY2(why.startsWith(expected), qPrintable(why));
  }

  void a_radius_change_first_allows_the_speed() {
    const TestSpec t = parse_test(with_changes(R"([{"time": 1, "set": {"drone.radius": 2}}, {"time": 1, "set": {"drone.max_speed": 100}}])"),
                                  "chg.json", *host_);
    QCOMPARE(t.changes.size(), std::size_t(2));
    QCOMPARE(t.changes[1].key, std::string("drone.max_speed"));
  }

  // The runner applies each change before the step that starts at its time: the same positions as a
  // simulation changed by hand at those steps (apply_change, the GUI's path), byte for byte.
  void runner_equals_changes_by_hand() {
    const std::string changes = R"([{"time": 0.5, "set": {"behavior.params.cohesion_weight": 3, "drones": 12}},
                                    {"time": 1.25, "set": {"drone.max_speed": 5}}, {"time": 2, "set": {"drones": 3}}])";
    const TestSpec test = parse_test(with_changes(changes), "chg.json", *host_);
    QTemporaryDir out;
    RunOptions options;
    options.out = out.path().toStdString();
    run_test(test, *host_, options);
    const QStringList rows = non_empty_lines(read_file(out.path() + "/chg/drones.csv"));

    TestSpec state = test;
    state.changes.clear();
    Simulation sim(make_setup(state, *host_));
    QStringList by_hand{"time,id,x,y,vx,vy"};
    auto log = [&] {
      for (std::size_t i = 0; i < sim.drone_count(); ++i) {
        if (sim.drone_status()[i] == DroneStatus::removed) continue;  // not in drones.csv
        const Vec2 p = sim.drone_positions()[i], v = sim.drone_velocities()[i];
        by_hand << QString::asprintf("%.4f,%zu,%.4f,%.4f,%.4f,%.4f", sim.time(), i, p.x, p.y, v.x, v.y);
      }
    };
    log();
    std::size_t next = 0;
    for (std::size_t step = 0; step < test.steps(); ++step) {
      for (; next < test.changes.size() && change_step(test.changes[next].time, test.dt) == step; ++next)
        apply_change(sim, state, test.changes[next], *host_);
      sim.step();
      if ((step + 1) % test.log_every() == 0) log();
    }
    QCOMPARE(next, test.changes.size());
    QCOMPARE(rows.size(), by_hand.size());
    for (int i = 0; i < rows.size(); ++i) QCOMPARE(rows[i], by_hand[i]);
    // The logged row at t = 1 still has 12 drones, the one at t = 3 has 3 (the change at t = 2).
    QCOMPARE(rows.filter(QRegularExpression("^1\\.0000,")).size(), 12);
    QCOMPARE(rows.filter(QRegularExpression("^3\\.0000,")).size(), 3);

    // config.json holds the changes; read back, it is the same test.
    const std::string config = read_file(out.path() + "/chg/config.json").toStdString();
    QVERIFY(config.find("\"changes\"") != std::string::npos);
    const TestSpec again = parse_test(config, "config.json", *host_);
    QVERIFY(again.changes == test.changes);
    QCOMPARE(resolved_json(again, *host_), resolved_json(test, *host_));
  }

  // A test without changes writes the config.json it always did: no "changes" key.
  void no_changes_no_key() {
    const TestSpec test = parse_test("{" + base + "}", "chg.json", *host_);
    QVERIFY(resolved_json(test, *host_).find("changes") == std::string::npos);
  }

  // A refused live change leaves the simulation and the test as they were.
  void refused_change_changes_nothing() {
    TestSpec test = parse_test("{" + base + "}", "chg.json", *host_);
    Simulation sim(make_setup(test, *host_));
    sim.run_steps(10);
    const TestSpec before = test;
    const std::vector<Vec2> positions(sim.drone_positions().begin(), sim.drone_positions().end());
    QVERIFY_THROWS_EXCEPTION(std::invalid_argument, apply_change(sim, test, {0, "drone.max_speed", 1000}, *host_));
    QVERIFY_THROWS_EXCEPTION(std::invalid_argument, apply_change(sim, test, {0, "behavior.params.cohesion_weight", -1}, *host_));
    QCOMPARE(resolved_json(test, *host_), resolved_json(before, *host_));
    QCOMPARE(sim.drone_config(), before.groups[0].drone);
    QCOMPARE(sim.behavior().param("cohesion_weight"), before.groups[0].behavior.params.get("cohesion_weight"));
    QVERIFY(std::equal(positions.begin(), positions.end(), sim.drone_positions().begin()));
  }
};

QTEST_GUILESS_MAIN(TestChanges)
#include "test_changes.moc"
