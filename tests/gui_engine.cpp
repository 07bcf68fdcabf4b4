// The sandbox's engine, driven as the window drives it: live changes are applied and recorded, "save
// as test" replays byte for byte with `salsa run`, a drone-count change re-spawns, a refused start
// state changes nothing, any number of stepping threads gives the same bytes, and a behavior that throws stops the run with a message naming the plugin.
#include "common.hpp"

#include <QTemporaryDir>
#include <cmath>
#include <cstring>
#include <fstream>

#include "engine.hpp"
#include "salsa/core/experiments/test_spec.hpp"

using namespace salsa;
using namespace salsa::gui;
using namespace salsa_test;

namespace {

const std::string small_test = R"({"name": "sandbox", "behavior": "flocking", "drones": 12,
  "map": {"name": "forest", "params": {"size": 300}}, "targets": {"kind": "tree", "count": 60}, "time": 60, "seed": 11})";

/// Steps the paused engine `n` times, exactly.
void steps(Engine& engine, int n) {
  for (int i = 0; i < n; ++i) QCOMPARE(engine.step_once().get(), std::string());
}

/// The drones.csv rows the runner writes for a snapshot (the runner's "%.4f" fields).
QStringList rows_of(const Snapshot& s) {
  QStringList rows;
  for (std::uint32_t i = 0; i < s.positions.size(); ++i) {
    if (s.status_of(i) == DroneStatus::removed) continue;  // in no output
    const Vec2 p = s.positions[i], v = s.velocities[i];
    rows << QString::asprintf("%.4f,%u,%.4f,%.4f,%.4f,%.4f", s.time, i, p.x, p.y, v.x, v.y);
  }
  return rows;
}

}  // namespace

class GuiEngine : public QObject {
  Q_OBJECT
  std::unique_ptr<PluginHost> host_ = builtin_host();
  std::unique_ptr<PluginHost> bad_host_ = [] {
    auto host = std::make_unique<PluginHost>();
    host->load({{plugin_dir(), "test"}, {test_plugins_dir() / "bad-behavior", "test"}});
    return host;
  }();

  TestSpec spec(const std::string& json = small_test) { return parse_test(json, "sandbox", *host_); }

 private Q_SLOTS:
  void live_parameter_change_is_applied_and_recorded() {
    Engine engine(*host_);
    QCOMPARE(engine.load(spec()).get(), std::string());
    steps(engine, 30);
    QCOMPARE(engine.set("behavior.params.cohesion_weight", 2.5).get(), std::string());
    const auto timeline = engine.timeline();
    QCOMPARE(timeline.size(), std::size_t(1));
    QCOMPARE(timeline[0].key, std::string("behavior.params.cohesion_weight"));
    QCOMPARE(timeline[0].value, 2.5);
    QCOMPARE(change_step(timeline[0].time, 1.0 / 60), std::uint64_t(30));
    QCOMPARE(engine.current_test()->groups[0].behavior.params.get("cohesion_weight"), 2.5);
    // Refused: out of the declared range; nothing recorded, nothing changed.
    const std::string why = engine.set("behavior.params.cohesion_weight", 99).get();
    QVERIFY2(why.starts_with("behavior.params.cohesion_weight: 99 is out of range (allowed: [0, 10])"), why.c_str());
    QCOMPARE(engine.timeline().size(), std::size_t(1));
    QCOMPARE(engine.current_test()->groups[0].behavior.params.get("cohesion_weight"), 2.5);
  }

  // The whole point of the timeline: a tuning session saved as a test replays byte for byte headless.
  void save_as_test_replays_byte_for_byte() {
    Engine engine(*host_);
    QCOMPARE(engine.load(spec()).get(), std::string());
    steps(engine, 45);
    QCOMPARE(engine.set("behavior.params.separation_weight", 3).get(), std::string());
    QCOMPARE(engine.set("drones", 20).get(), std::string());
    steps(engine, 40);
    QCOMPARE(engine.set("drone.max_speed", 6).get(), std::string());
    steps(engine, 20);
    QCOMPARE(engine.set("drones", 7).get(), std::string());
    steps(engine, 15);  // 120 steps: t = 2 s, a logged row
    const auto snap = engine.snapshot();
    QCOMPARE(snap->step, std::uint64_t(120));
    QCOMPARE(snap->positions.size(), std::size_t(20));  // ids are never reused: 13 of them removed
    QCOMPARE(rows_of(*snap).size(), 7);

    std::string why;
    const auto test = engine.as_test(&why);
    QVERIFY2(test, why.c_str());
    QCOMPARE(test->changes.size(), std::size_t(4));
    QTemporaryDir dir;
    {
      std::ofstream out((dir.path() + "/saved.json").toStdString());
      out << resolved_json(*test, *host_);
    }
    const CliResult r = run_salsa({"run", "saved.json", "--out", "out", "--no-plots", "-q"}, dir.path());
    QVERIFY2(r.exit_code == 0, describe(r));
    const QStringList rows = non_empty_lines(read_file(dir.path() + "/out/sandbox/drones.csv"));
    const QStringList last = rows.filter(QRegularExpression("^2\\.0000,"));
    QCOMPARE(last, rows_of(*snap));
    // The found targets too: the CLI's targets.csv marks exactly the ones the sandbox found.
    const QStringList targets = non_empty_lines(read_file(dir.path() + "/out/sandbox/targets.csv"));
    std::size_t found = 0;
    for (int i = 1; i < targets.size(); ++i) {
      const bool cli_found = !targets[i].split(',')[3].isEmpty();
      QCOMPARE(cli_found, snap->found[static_cast<std::size_t>(i - 1)] != 0);
      found += cli_found;
    }
    QCOMPARE(found, snap->targets_found);
  }

  // The sandbox and `salsa run` step through one core Session: a test's own timed changes play in the
  // sandbox, its metrics run there (the coverage line is the area_coverage metric's column), and the
  // live rows equal summary.csv's. A sandbox that bypassed the Session would miss the changes and have
  // no coverage; a CLI that did would disagree on the rows.
  void sandbox_and_salsa_run_step_the_same_session() {
    const std::string timed = R"({"name": "timed", "behavior": "flocking", "drones": 12,
      "map": {"name": "forest", "params": {"size": 300}}, "targets": {"kind": "tree", "count": 60}, "time": 3, "seed": 5,
      "changes": [{"time": 0.5, "set": {"behavior.params.cohesion_weight": 3}}, {"time": 1, "set": {"drones": 18}},
                  {"time": 2, "set": {"drone.max_speed": 5}}]})";
    Engine engine(*host_);
    QCOMPARE(engine.load(spec(timed)).get(), std::string());
    QCOMPARE(engine.timeline().size(), std::size_t(3));
    steps(engine, 90);  // t = 1.5 s: two changes applied
    QCOMPARE(engine.snapshot()->positions.size(), std::size_t(18));
    QCOMPARE(engine.current_test()->groups[0].behavior.params.get("cohesion_weight"), 3.0);
    QCOMPARE(engine.current_test()->groups[0].drone.max_speed, 10.0);  // not yet
    steps(engine, 90);  // t = 3 s
    QCOMPARE(engine.current_test()->groups[0].drone.max_speed, 5.0);
    const auto snap = engine.snapshot();
    QTemporaryDir dir;
    QVERIFY(write_file(dir.path() + "/timed.json", QByteArray::fromStdString(timed)));
    const CliResult r = run_salsa({"run", "timed.json", "--out", "out", "--no-plots", "-q"}, dir.path());
    QVERIFY2(r.exit_code == 0, describe(r));
    const QStringList rows = non_empty_lines(read_file(dir.path() + "/out/timed/summary.csv"));
    const QStringList header = rows[0].split(',');
    QCOMPARE(rows.size() - 1, static_cast<int>(snap->stats->size()));  // t = 0, 1, 2, 3
    for (int i = 1; i < rows.size(); ++i) {
      const QStringList f = rows[i].split(',');
      const StatsRow& live = (*snap->stats)[static_cast<std::size_t>(i - 1)];
      QCOMPARE(QString::asprintf("%.4f", live.time), f[header.indexOf("time")]);
      QCOMPARE(QString::asprintf("%.6f", live.found_percent / 100), f[header.indexOf("fraction_found")]);
      QCOMPARE(QString::asprintf("%.4f", live.mean_speed), f[header.indexOf("mean_speed")]);
      QCOMPARE(QString::asprintf("%.6f", live.coverage_percent / 100), f[header.indexOf("coverage")]);
    }
    QCOMPARE(non_empty_lines(read_file(dir.path() + "/out/timed/drones.csv")).filter(QRegularExpression("^3\\.0000,")), rows_of(*snap));
  }

  // The sandbox steps on every core; a person's run must not depend on how many the machine has.
  void any_thread_count_steps_the_same_bytes() {
    const std::string big = R"({"name": "threads", "behavior": "flocking", "drones": 2000, "physics": "light",
      "map": {"name": "empty", "params": {"size": 600}}, "targets": {"kind": "tree", "count": 500}, "time": 60, "seed": 3})";
    auto run = [&](int threads) {
      Engine engine(*host_);
      engine.set_threads(threads);
      [&] { QCOMPARE(engine.load(spec(big)).get(), std::string()); }();
      steps(engine, 30);
      return engine.snapshot();
    };
    const auto one = run(1), many = run(4);
    QCOMPARE(many->step, one->step);
    QCOMPARE(many->positions.size(), one->positions.size());
    QVERIFY(std::memcmp(many->positions.data(), one->positions.data(), one->positions.size() * sizeof(Vec2)) == 0);
    QVERIFY(std::memcmp(many->velocities.data(), one->velocities.data(), one->velocities.size() * sizeof(Vec2)) == 0);
    QCOMPARE(many->targets_found, one->targets_found);
  }

  void drone_count_change_respawns() {
    Engine engine(*host_);
    QCOMPARE(engine.load(spec()).get(), std::string());
    steps(engine, 120);
    const auto before = engine.snapshot();
    QCOMPARE(engine.set("drones", 30).get(), std::string());
    auto snap = engine.snapshot();
    QCOMPARE(snap->positions.size(), std::size_t(30));
    for (std::size_t i = 0; i < 12; ++i) QCOMPARE(snap->positions[i], before->positions[i]);  // the old ones stay
    const Vec2 spawn = snap->scene->bases.at(0);
    for (std::size_t i = 12; i < 30; ++i)  // new ones come in around the spawn point
      QVERIFY2(distance(snap->positions[i], spawn) < 100, qPrintable(QString("drone %1 far from spawn").arg(i)));
    // A lower count removes the highest ids (never reused): they stay in the spans, marked removed.
    QCOMPARE(engine.set("drones", 5).get(), std::string());
    snap = engine.snapshot();
    QCOMPARE(snap->positions.size(), std::size_t(30));
    for (std::uint32_t i = 0; i < 30; ++i) QCOMPARE(snap->status_of(i) == DroneStatus::removed, i >= 5);
    QCOMPARE(engine.set("drones", 0).get().substr(0, 9), std::string("drones: 0"));
  }

  void refused_load_keeps_the_simulation() {
    Engine engine(*host_);
    QCOMPARE(engine.load(spec()).get(), std::string());
    steps(engine, 10);
    const auto before = engine.snapshot();
    QTemporaryDir dir;
    write_file(dir.path() + "/bad-map.json", R"({"bounds": {"min": [0, 0], "max": [100, 100]}, "obstacles": [[[10, 10], [20, 10], [500, 20]]]})");
    TestSpec bad = spec();
    bad.map.name = "json";
    bad.map.params = ParameterValues(host_->map("json").factory.parameters);
    bad.map_file = (dir.path() + "/bad-map.json").toStdString();
    const std::string why = engine.load(bad).get();
    QVERIFY2(why.find("bad-map.json") != std::string::npos && why.find("obstacles[0][2]") != std::string::npos, why.c_str());
    const auto after = engine.snapshot();
    QCOMPARE(after->step, before->step);
    QCOMPARE(after->positions, before->positions);
    QCOMPARE(after->scene, before->scene);
    steps(engine, 1);  // and it still runs
    QCOMPARE(engine.snapshot()->step, before->step + 1);
  }

  void throwing_behavior_stops_with_the_plugin_named() {
    Engine engine(*bad_host_);
    const TestSpec t = parse_test(R"({"behavior": {"name": "test_nan", "params": {"at": 0.2}}, "drones": 3, "seed": 1})", "bad", *bad_host_);
    QCOMPARE(engine.load(t).get(), std::string());
    engine.start();
    QTRY_VERIFY_WITH_TIMEOUT(engine.snapshot()->state == RunState::failed, 20000);
    const std::string error = engine.snapshot()->error;
    QVERIFY2(error.find("behavior 'test_nan'") != std::string::npos && error.find("bad-behavior") != std::string::npos, error.c_str());
    QVERIFY(!engine.step_once().get().empty());  // stays stopped until reset
    QCOMPARE(engine.reset().get(), std::string());
    QCOMPARE(engine.snapshot()->state, RunState::paused);
  }

  // The sandbox names the plugin that threw, not the behavior: a contact handler's on_contact while
  // running, its reset when the test is loaded, a target kind's in_view.
  void throwing_plugin_of_any_kind_is_named() {
    PluginHost host;
    host.load({{plugin_dir(), "build"}, {test_plugins_dir() / "blame", "test"}});
    const std::string head = R"({"behavior": "blame_behavior", "drones": 30, "seed": 1, )";
    for (const auto& [rest, named] : std::vector<std::pair<std::string, std::string>>{
             {R"("targets": {"count": 2000}, "contact_handlers": ["detect_targets", {"name": "blame_handler", "params": {"mode": 1}}]})",
              "contact handler 'blame_handler' ("},
             {R"("targets": {"kind": "blame_target", "count": 2000, "params": {"mode": 1}}})", "target kind 'blame_target' ("}}) {
      Engine engine(host);
      QCOMPARE(engine.load(parse_test(head + rest, "blame", host)).get(), std::string());
      engine.start();
      QTRY_VERIFY_WITH_TIMEOUT(engine.snapshot()->state == RunState::failed, 20000);
      const std::string error = engine.snapshot()->error;
      QVERIFY2(error.starts_with("test 'test' (blame): " + named) && error.find("libtest_blame.so) failed at t = ") != std::string::npos &&
                   error.find("first line second line third line") != std::string::npos,
               error.c_str());
    }
    {  // the inspector asks the behavior between steps: a throw is shown there, the desktop goes on
      Engine engine(host);
      QCOMPARE(engine.load(parse_test(R"({"behavior": {"name": "blame_behavior", "params": {"inspect_throws": 1}}, "drones": 3})",
                                      "blame", host))
                   .get(),
               std::string());
      engine.select(0);
      QCOMPARE(engine.step_once().get(), std::string());
      QTRY_VERIFY_WITH_TIMEOUT(engine.snapshot()->selected.has_value(), 5000);
      const std::string memory = engine.snapshot()->selected->memory;
      QVERIFY2(memory.starts_with("behavior 'blame_behavior' (") &&
                   memory.find("failed in inspect: first line second line third line") != std::string::npos,
               memory.c_str());
    }
    Engine engine(host);
    const std::string why =
        engine.load(parse_test(head + R"("contact_handlers": [{"name": "blame_handler", "params": {"mode": 2}}]})", "blame", host)).get();
    QVERIFY2(why.starts_with("test 'test' (blame): could not start: contact handler 'blame_handler' (") && why.find("failed: first line second line third line") != std::string::npos,
             why.c_str());
  }

  void running_publishes_snapshots_and_rows() {
    Engine engine(*host_);
    QCOMPARE(engine.load(spec()).get(), std::string());
    QCOMPARE(engine.set_pacing({Pacing::fastest, 1, 1}).get(), std::string());
    engine.start();
    QTRY_VERIFY_WITH_TIMEOUT(engine.snapshot()->time >= 3, 60000);
    engine.pause();
    engine.sync();
    const auto snap = engine.snapshot();
    QVERIFY(snap->stats->size() >= 4);  // one row per logged second, and t = 0
    QCOMPARE(snap->stats->front().time, 0.0);
    QVERIFY(snap->stats->back().coverage_percent > 0);
    QVERIFY(snap->heat && !snap->heat->values.empty());
    QCOMPARE(*std::max_element(snap->heat->values.begin(), snap->heat->values.end()), 100.f);
    // The larger step is marked inexact and cannot be saved as a test.
    QCOMPARE(engine.set_pacing({Pacing::fastest, 1, 2}).get(), std::string());
    QVERIFY(engine.step_once().get().empty());
    QVERIFY(engine.snapshot()->inexact);
    std::string why;
    QVERIFY(!engine.as_test(&why));
    QVERIFY2(why.find("inexact") != std::string::npos, why.c_str());
    // Too large for the physics: refused, the step stays as it was.
    QVERIFY(!engine.set_pacing({Pacing::fastest, 1, 100}).get().empty());
  }
};

QTEST_GUILESS_MAIN(GuiEngine)
#include "gui_engine.moc"
