// Metrics (docs/plugins.md, docs/output-format.md): each built-in against a hand-computed case, a
// metric plugin built by the test suite adding its columns through `salsa run`, and bad metric lists
// refused with one line.
#include "common.hpp"

#include <algorithm>
#include <cmath>

#include "salsa/core/run/metrics.hpp"
#include "salsa/core/experiments/test_spec.hpp"

using namespace salsa;
using namespace salsa_test;

namespace {

fs::path metric_plugin_dir() { return test_plugins_dir() / "metric"; }

/// The built-in plugins and the test suite's metric plugin.
std::unique_ptr<PluginHost> host_with_test_metric() {
  auto host = builtin_host();
  host->load({{metric_plugin_dir(), "test"}});
  return host;
}

/// A CSV file's rows, each split at commas (the header first).
QList<QStringList> csv_rows(const QString& file) {
  QList<QStringList> rows;
  for (const QString& line : non_empty_lines(QString::fromUtf8(read_file(file)))) rows << line.split(',');
  return rows;
}

/// Two drones on an empty 200 m map, as a metric sees them; the test moves them and sets their status.
class TwoDrones final : public MetricView {
 public:
  std::vector<Vec2> positions{{50, 100}, {150, 100}}, velocities{{}, {}};
  std::vector<std::uint32_t> groups{0, 0};
  std::vector<DroneStatus> status{DroneStatus::flying, DroneStatus::flying};
  Rect bounds() const override { return {{0, 0}, {200, 200}}; }
  double now = 0;  // s
  double time() const override { return now; }
  double dt() const override { return 1.0 / 60; }
  std::span<const Vec2> drone_positions() const override { return positions; }
  std::span<const Vec2> drone_velocities() const override { return velocities; }
  bool is_free(Vec2 p, double clearance) const override {
    return p.x - clearance >= 0 && p.y - clearance >= 0 && p.x + clearance <= 200 && p.y + clearance <= 200;
  }
  std::optional<ObstacleHit> ray_cast(Vec2, Vec2) const override { return std::nullopt; }
  const DroneProperties& drone(std::uint32_t) const override { return drone_; }
  std::span<const std::uint32_t> drone_groups() const override { return groups; }
  std::span<const DroneStatus> drone_status() const override { return status; }
  std::size_t group_count() const override { return 1; }
  Vec2 base(std::uint32_t) const override { return {100, 100}; }
  const MapData& map() const override { return map_; }
  std::span<const TargetState> targets() const override { return {}; }
  std::size_t targets_found() const override { return 0; }
  std::uint64_t collisions() const override { return 0; }

 private:
  MapData map_{{{0, 0}, {200, 200}}, {}, {}, {}, {100, 100}};
  DroneProperties drone_{15, 50.2, 134, 10, 0.3, 1, 1.5};
};

/// The field of `column` in `row` of a CSV file's rows.
QString field(const QList<QStringList>& rows, int row, const QString& column) {
  const int c = static_cast<int>(rows.at(0).indexOf(column));
  return c < 0 ? QString("<no column %1>").arg(column) : rows.at(row).value(c);
}

}  // namespace

class TestMetrics : public QObject {
  Q_OBJECT

  std::unique_ptr<PluginHost> host_ = host_with_test_metric();

 private Q_SLOTS:
  // One drone flies straight along +x at 10 m/s for 8 s on an empty 200 m map: its camera (15 m)
  // sweeps a stadium of π r² + 2 r L, its path is L = 80 m.
  void straight_line_coverage_and_distance_data() {
    QTest::addColumn<double>("cell_size");
    QTest::newRow("default cell (range / 4)") << 0.0;
    QTest::newRow("1 m cells") << 1.0;
    QTest::newRow("0.5 m cells") << 0.5;
  }
  void straight_line_coverage_and_distance() {
    QFETCH(double, cell_size);
    const std::string json = R"({"behavior": "test_straight", "drones": 1, "drone": {"base": "small", "max_force": 1000},
      "map": {"name": "empty", "params": {"size": 200}}, "decision_lag": 0, "time": 8,
      "metrics": [{"name": "area_coverage", "params": {"cell_size": )" + Parameter::format(cell_size) + R"(}}, "distance_flown"]})";
    const TestSpec t = parse_test(json, "t", *host_);
    Simulation sim(make_setup(t, *host_, 1));
    MetricSet metrics(t, *host_);
    QCOMPARE(metrics.step_columns(), (std::vector<std::string>{"coverage", "mean_distance"}));
    metrics.start(sim);
    const Vec2 from = sim.drone_positions()[0];
    for (std::size_t i = 0; i < t.steps(); ++i) {
      sim.step();
      metrics.after_step(sim);
    }
    const Vec2 to = sim.drone_positions()[0];
    const auto finals = metrics.finish(sim);
    QCOMPARE(finals.size(), std::size_t(2));
    QCOMPARE(finals[0].first, std::string("coverage"));
    QCOMPARE(finals[1].first, std::string("mean_distance"));

    const double r = 15, length = (to - from).length(), area = 200.0 * 200.0;
    QVERIFY2(std::abs(length - 80) < 0.01 && std::abs(to.y - from.y) < 1e-3, qPrintable(QString::number(length)));
    // distance = speed × time (3 decimals)
    QVERIFY2(std::abs(std::stod(finals[1].second) - 80) < 0.01, finals[1].second.c_str());

    // Coverage on a grid: cells near the stadium's rim, and near the map's edge (the free area), may
    // count either way: at most a cell's width along each perimeter.
    const double cell = cell_size > 0 ? cell_size : r / 4;
    const double stadium = pi * r * r + 2 * r * length, expected = stadium / area;
    const double tolerance = (2 * pi * r + 2 * length) * cell / area + expected * 4 * 200 * cell / area;
    const double coverage = std::stod(finals[0].second);
    QVERIFY2(std::abs(coverage - expected) <= tolerance,
             qPrintable(QString("coverage %1, swept stadium / area %2 ± %3").arg(coverage).arg(expected).arg(tolerance)));
  }

  // Coverage counts free area only: on a map half filled by one obstacle, 100 drones spread over the
  // free half see all of it (it would be at most about 0.5 if the obstacle's cells counted).
  void coverage_is_a_fraction_of_free_area() {
    QTemporaryDir dir;
    QVERIFY(write_file(dir.filePath("half.json"), R"({"bounds": {"min": [0, 0], "max": [60, 60]}, "spawn": [15, 30],
      "obstacles": [[[30, 0], [60, 0], [60, 60], [30, 60]]]})"));
    // (moc misreads a raw string that ends in a quote: plain strings here)
    const std::string json = "{\"behavior\": \"random_walk\", \"drones\": 100, \"spawn\": {\"mode\": \"uniform\"}, \"map\": \"" +
                             dir.filePath("half.json").toStdString() + "\", \"time\": 1, \"metrics\": [{\"name\": \"area_coverage\", \"params\": {\"cell_size\": 1}}]}";
    const TestSpec t = parse_test(json, "t", *host_);
    Simulation sim(make_setup(t, *host_, 1));
    MetricSet metrics(t, *host_);
    metrics.start(sim);
    sim.run_steps(t.steps());
    metrics.after_step(sim);
    QCOMPARE(metrics.finish(sim)[0].second, std::string("1.000000"));
  }

  // A drone that landed or failed flies no more and sees nothing: if something moves it (a collision),
  // neither area_coverage nor distance_flown counts it. The flying drone's moves count.
  void metrics_skip_drones_not_flying_data() {
    QTest::addColumn<int>("status");
    QTest::newRow("landed") << int(DroneStatus::landed);
    QTest::newRow("failed") << int(DroneStatus::failed);
  }
  void metrics_skip_drones_not_flying() {
    QFETCH(int, status);
    TwoDrones world;
    auto coverage = host_->metric("area_coverage").factory.create();
    auto distance = host_->metric("distance_flown").factory.create();
    coverage->reset(world), distance->reset(world);
    double before = 0, after = 0, flown = 0;
    coverage->observe(world, {&before, 1});
    world.status[1] = static_cast<DroneStatus>(status);
    for (int k = 1; k <= 40; ++k) {  // both drones move 40 m up
      world.positions = {{50, 100.0 + k}, {150, 100.0 + k}};
      coverage->step(world), distance->step(world);
    }
    coverage->observe(world, {&after, 1});
    distance->observe(world, {&flown, 1});
    // Seen: two camera discs at the start, then one 40 m stadium; the other drone adds nothing.
    const double r = 15, area = 200.0 * 200.0;
    const double expected = (2 * pi * r * r + 2 * r * 40) / area, tolerance = (4 * pi * r + 2 * 40) * (r / 4) / area;
    QVERIFY2(std::abs(before - 2 * pi * r * r / area) <= 4 * pi * r * (r / 4) / area, qPrintable(QString::number(before)));
    QVERIFY2(std::abs(after - expected) <= tolerance, qPrintable(QString("coverage %1, expected %2 ± %3").arg(after).arg(expected).arg(tolerance)));
    QCOMPARE(flown, 40.0 / 2);  // 40 m flown by one drone of two
  }

  // staleness is the mean over the free cells of the time since a flying drone's camera last covered
  // them: with hovering drones, t × (1 − the covered fraction, area_coverage's on the same grid); its time
  // average over N steps of dt is (1 − f) dt (N + 1) / 2; a drone that lands stops refreshing its disc,
  // whose cells then age from the landing.
  void staleness_is_the_age_of_the_area() {
    auto fraction = [&](bool second_flying) {  // area_coverage of drone 0's disc, or of both
      TwoDrones world;
      if (!second_flying) world.status[1] = DroneStatus::landed;
      auto coverage = host_->metric("area_coverage").factory.create();
      coverage->reset(world);
      double f = 0;
      coverage->observe(world, {&f, 1});
      return f;
    };
    const double both = fraction(true), first = fraction(false), second = both - first;
    QVERIFY(first > 0.01 && second > 0.01);
    TwoDrones world;
    auto staleness = host_->metric("staleness").factory.create();
    staleness->reset(world);
    const int steps = 600;
    for (int k = 1; k <= steps; ++k) {
      world.now = k * world.dt();
      staleness->step(world);
    }
    double row = 0;
    staleness->observe(world, {&row, 1});
    QVERIFY2(std::abs(row - world.now * (1 - both)) < 1e-9, qPrintable(QString::number(row)));
    double end[2] = {0, 0};
    staleness->finish(world, end);
    QVERIFY(std::abs(end[0] - row) < 1e-12);
    const double mean = (1 - both) * world.dt() * (steps + 1) / 2;
    QVERIFY2(std::abs(end[1] - mean) < 1e-9, qPrintable(QString("%1 vs %2").arg(end[1]).arg(mean)));
    // Drone 1 lands at 10 s; 10 s later its disc's cells are 10 s old, drone 0's still fresh.
    const double landed_at = world.now;
    world.status[1] = DroneStatus::landed;
    for (int k = 1; k <= steps; ++k) {
      world.now = landed_at + k * world.dt();
      staleness->step(world);
    }
    staleness->observe(world, {&row, 1});
    const double expected = world.now * (1 - both) + (world.now - landed_at) * second;
    QVERIFY2(std::abs(row - expected) < 1e-9, qPrintable(QString("%1 vs %2").arg(row).arg(expected)));
  }

  // time_to_50/90/100 are the ⌈f × n⌉-th found_time of targets.csv; empty when not reached.
  void time_to_found_matches_targets_csv_data() {
    QTest::addColumn<int>("targets");
    QTest::addColumn<int>("size");
    QTest::addColumn<QString>("filled");  // which of 50/90/100 are reached, as "yyn"
    QTest::newRow("all found") << 10 << 100 << "yyy";
    QTest::newRow("three: the 2nd is half") << 3 << 100 << "yyy";
    QTest::newRow("few found") << 300 << 1000 << "nnn";
    QTest::newRow("no targets") << 0 << 100 << "nnn";
  }
  void time_to_found_matches_targets_csv() {
    QFETCH(int, targets);
    QFETCH(int, size);
    QFETCH(QString, filled);
    QTemporaryDir dir;
    QVERIFY(write_file(dir.filePath("t.json"), QString(R"({"name": "t", "behavior": "random_walk", "drones": 5,
      "map": {"name": "empty", "params": {"size": %1}}, "targets": {"count": %2}, "time": 60, "seed": 4,
      "metrics": ["time_to_found"]})").arg(size).arg(targets).toUtf8()));
    const CliResult r = run_salsa({"run", "t.json", "--out", "out", "--quiet"}, dir.path());
    QVERIFY2(r.exit_code == 0, describe(r));
    std::vector<double> times;
    const auto target_rows = csv_rows(dir.filePath("out/t/targets.csv"));
    QCOMPARE(target_rows.size(), targets + 1);
    for (int i = 1; i < target_rows.size(); ++i)
      if (!field(target_rows, i, "found_time").isEmpty()) times.push_back(field(target_rows, i, "found_time").toDouble());
    std::sort(times.begin(), times.end());
    const auto outcome = csv_rows(dir.filePath("out/t/outcome.csv"));
    QCOMPARE(outcome.at(0).join(','), QString("targets,targets_found,fraction_found,time_to_50,time_to_90,time_to_100"));
    const int percents[] = {50, 90, 100};
    for (int i = 0; i < 3; ++i) {
      const auto needed = static_cast<std::size_t>((percents[i] * targets + 99) / 100);
      const QString expected = targets > 0 && times.size() >= needed ? QString::number(times[needed - 1], 'f', 4) : QString();
      QCOMPARE(field(outcome, 1, QString("time_to_%1").arg(percents[i])), expected);
      QCOMPARE(!expected.isEmpty(), filled[i] == 'y');
    }
  }

  // The final count equals the last running count of summary.csv's own column.
  void collisions_final_equals_the_running_count() {
    QTemporaryDir dir;
    QVERIFY(write_file(dir.filePath("t.json"), R"({"name": "t", "behavior": "random_walk", "drones": 30,
      "map": {"name": "empty", "params": {"size": 40}}, "time": 20, "metrics": ["collisions"]})"));
    const CliResult r = run_salsa({"run", "t.json", "--out", "out", "--quiet"}, dir.path());
    QVERIFY2(r.exit_code == 0, describe(r));
    const auto summary = csv_rows(dir.filePath("out/t/summary.csv"));
    const auto outcome = csv_rows(dir.filePath("out/t/outcome.csv"));
    QCOMPARE(summary.at(0).join(','), QString(summary_columns));  // no step column
    const QString running = field(summary, static_cast<int>(summary.size() - 1), "collisions");
    QVERIFY2(running.toInt() > 0, "30 drones on a 40 m map must collide");
    QCOMPARE(field(outcome, 1, "collisions"), running);
  }

  // A metric plugin built like a user's adds its columns to summary.csv and outcome.csv, and sees
  // every step up to each logged row.
  void user_metric_adds_its_columns() {
    QTemporaryDir dir;
    QVERIFY(write_file(dir.filePath("t.json"), R"({"name": "t", "behavior": "random_walk", "drones": 3, "time": 5,
      "metrics": ["test_metric", "area_coverage"]})"));
    const CliResult r = run_salsa({"run", "t.json", "--out", "out", "--quiet", "--plugin-dir", q(metric_plugin_dir())}, dir.path());
    QVERIFY2(r.exit_code == 0, describe(r));
    const auto summary = csv_rows(dir.filePath("out/t/summary.csv"));
    QCOMPARE(summary.at(0).join(','), QString(summary_columns) + ",test_steps,coverage");
    QCOMPARE(summary.size(), 7);  // header, t = 0..5
    for (int row = 1; row < summary.size(); ++row) {
      QCOMPARE(summary.at(row).size(), summary.at(0).size());
      QCOMPARE(field(summary, row, "test_steps"), QString::number(60 * (row - 1)));
    }
    const auto outcome = csv_rows(dir.filePath("out/t/outcome.csv"));
    QCOMPARE(outcome.size(), 2);
    QCOMPARE(outcome.at(0).join(','), QString("targets,targets_found,fraction_found,test_steps_total,test_never,coverage"));
    QCOMPARE(field(outcome, 1, "test_steps_total"), QString("300"));
    QCOMPARE(field(outcome, 1, "test_never"), QString());  // no value: an empty field
    QCOMPARE(field(outcome, 1, "coverage"), field(summary, 6, "coverage"));  // the last row is the end
    const QString config = QString::fromUtf8(read_file(dir.filePath("out/t/config.json")));
    QVERIFY2(config.contains("\"plugin\": \"test_metric\""), qPrintable(config));  // its version is recorded
  }

  void default_and_no_metrics_data() {
    QTest::addColumn<QString>("metrics");
    QTest::addColumn<QString>("step_columns");
    QTest::addColumn<QString>("final_columns");
    QTest::newRow("default: the built-ins") << "" << ",coverage,mean_distance"
                                            << ",coverage,time_to_50,time_to_90,time_to_100,mean_distance,collisions";
    QTest::newRow("none") << ", \"metrics\": []" << "" << "";
  }
  void default_and_no_metrics() {
    QFETCH(QString, metrics);
    QFETCH(QString, step_columns);
    QFETCH(QString, final_columns);
    QTemporaryDir dir;
    QVERIFY(write_file(dir.filePath("t.json"), QString(R"({"name": "t", "behavior": "flocking", "drones": 3, "time": 2%1})").arg(metrics).toUtf8()));
    const CliResult r = run_salsa({"run", "t.json", "--out", "out", "--quiet"}, dir.path());
    QVERIFY2(r.exit_code == 0, describe(r));
    QCOMPARE(csv_rows(dir.filePath("out/t/summary.csv")).at(0).join(','), QString(summary_columns) + step_columns);
    QCOMPARE(csv_rows(dir.filePath("out/t/outcome.csv")).at(0).join(','), QString(outcome_columns) + final_columns);
  }

  // Bad metric lists: exit 2, one line naming the file, metrics[i] and what is allowed; nothing runs.
  void bad_metric_lists_are_refused_data() {
    QTest::addColumn<QString>("metrics");
    QTest::addColumn<QStringList>("expected");
    QTest::newRow("unknown name") << R"(["nope"])" << QStringList{"t.json: metrics[0]: unknown metric 'nope' (known: test_metric, area_coverage, time_to_found, distance_flown, collisions, staleness)"};
    QTest::newRow("not a list") << R"("area_coverage")" << QStringList{"t.json: metrics: \"area_coverage\" must be a list"};
    QTest::newRow("out of range") << R"([{"name": "area_coverage", "params": {"cell_size": -1}}])"
                                  << QStringList{"t.json: metrics[0].params.cell_size: -1 is out of range (allowed: [0, 1000] m)"};
    QTest::newRow("unknown parameter") << R"(["collisions", {"name": "area_coverage", "params": {"size": 1}}])"
                                       << QStringList{"t.json: metrics[1].params.size: unknown parameter of metric 'area_coverage'"};
    QTest::newRow("no name") << R"([{"params": {}}])" << QStringList{"t.json: metrics[0].name: missing"};
    QTest::newRow("unknown key") << R"([{"name": "collisions", "weight": 1}])"
                                 << QStringList{"t.json: metrics[0].weight: unknown key (allowed: name, params)"};
    QTest::newRow("listed twice") << R"(["collisions", "distance_flown", "collisions"])"
                                  << QStringList{"t.json: metrics[2]: metric 'collisions' is listed twice (also metrics[0]"};
    QTest::newRow("clash with a metric") << R"(["area_coverage", {"name": "test_metric", "params": {"clash": 1}}])"
                                         << QStringList{"t.json: metrics[1]: metric 'test_metric' (", "libtest_metric.so)",
                                                        "summary.csv column \"coverage\" is already one of metric 'area_coverage''s columns"};
    QTest::newRow("clash with summary.csv") << R"([{"name": "test_metric", "params": {"clash": 2}}])"
                                            << QStringList{"t.json: metrics[0]: metric 'test_metric'",
                                                           "summary.csv column \"time\" is already one of summary.csv's own columns"};
    QTest::newRow("clash with outcome.csv") << R"([{"name": "test_metric", "params": {"clash": 3}}])"
                                            << QStringList{"outcome.csv column \"targets\" is already one of outcome.csv's own columns"};
    QTest::newRow("bad column name") << R"([{"name": "test_metric", "params": {"clash": 4}}])"
                                     << QStringList{"summary.csv column \"bad name\" is not a valid column name (allowed:"};
  }
  void bad_metric_lists_are_refused() {
    QFETCH(QString, metrics);
    QFETCH(QStringList, expected);
    QTemporaryDir dir;
    QVERIFY(write_file(dir.filePath("t.json"), QString(R"({"behavior": "flocking", "metrics": %1})").arg(metrics).toUtf8()));
    const CliResult r = run_salsa({"run", "t.json", "--out", "out", "--plugin-dir", q(metric_plugin_dir())}, dir.path());
    QVERIFY2(r.exit_code == 2, describe(r));
    QVERIFY2(non_empty_lines(r.err).size() == 1, describe(r));
    for (const QString& e : expected) QVERIFY2(r.err.contains(e), describe(r));
    QVERIFY2(!QFileInfo::exists(dir.filePath("out")), "nothing runs");
  }

  // A metric that throws fails its test with one line naming the test, the metric and its file.
  void throwing_metric_fails_its_test() {
    QTemporaryDir dir;
    QVERIFY(write_file(dir.filePath("t.json"), R"({"name": "t", "behavior": "flocking", "drones": 3, "time": 5,
      "metrics": [{"name": "test_metric", "params": {"throw_at": 2}}]})"));
    const CliResult r = run_salsa({"run", "t.json", "--out", "out", "--plugin-dir", q(metric_plugin_dir())}, dir.path());
    QVERIFY2(r.exit_code == 1 && !r.crashed, describe(r));
    QVERIFY2(non_empty_lines(r.err).size() == 1, describe(r));
    for (const char* e : {"test 't' (t.json)", "metric 'test_metric' (", "libtest_metric.so) failed in step at t = 2 s",
                          "test metric threw as asked"})
      QVERIFY2(r.err.contains(e), describe(r));
    QVERIFY2(!QFileInfo::exists(dir.filePath("out/t/config.json")), "a failed test is not complete");
  }

  // `salsa plugins` lists the metric kind; `salsa describe` a metric's columns with units.
  void listed_and_described() {
    const CliResult list = run_salsa({"plugins"});
    QVERIFY2(list.exit_code == 0, describe(list));
    for (const char* name : {"area_coverage", "time_to_found", "distance_flown", "collisions"})
      QVERIFY2(list.out.contains(QRegularExpression(QString("\\n\\s+metric\\s+%1\\s").arg(name))), describe(list));
    const CliResult d = run_salsa({"describe", "time_to_found"});
    QVERIFY2(d.exit_code == 0, describe(d));
    QVERIFY2(d.out.startsWith("metric 'time_to_found'"), describe(d));
    QVERIFY2(d.out.contains(QRegularExpression("time_to_90\\s+outcome.csv\\s+s\\s+time when 90 %")), describe(d));
    const CliResult c = run_salsa({"describe", "area_coverage"});
    QVERIFY2(c.out.contains(QRegularExpression("coverage\\s+summary.csv\\s+-\\s+fraction")), describe(c));
    QVERIFY2(c.out.contains("cell_size"), describe(c));
  }
};

QTEST_GUILESS_MAIN(TestMetrics)
#include "test_metrics.moc"
