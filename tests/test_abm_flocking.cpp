// abm_flocking, the ABM frameworks' flocking model: its velocity is the declared rule's, hand-computed
// for a scripted neighbourhood; one step moves a bird `speed` along a unit heading at any dt; and both
// shipped examples run their 100 steps with every bird at that speed, flocking (aligning) as they go.
#include <salsa/sdk.hpp>
#include <salsa/testing.hpp>

#include <QTemporaryDir>
#include <QtTest>

#include <cmath>

#include "common.hpp"

using namespace salsa_test;
using salsa::Vec2;

namespace {

std::shared_ptr<salsa::Behavior> make(const salsa::PluginHost& host, double visual_distance = 5) {
  const auto& registered = host.behavior("abm_flocking");
  salsa::ParameterValues params(registered.factory.parameters);
  params.set("visual_distance", visual_distance);
  return salsa::PluginHost::create(registered, params);
}

/// The scripted neighbourhood at time scale `k` (dt = 1 / k s, velocities k times theirs): the bird
/// at (10, 10) heading (1, 0); a neighbour 0.5 m east (inside separation) heading north, one 5 m away
/// at (13, 14) (exactly the visual distance: counted) heading east, and one 6 m north (not seen).
salsa::testing::Scene scene(double k) {
  salsa::testing::Scene s;
  s.me().dt = 1 / k;
  s.me().max_speed = 2 * k;
  s.at({10, 10}, Vec2{1, 0} * k).neighbour({10.5, 10}, Vec2{0, 1} * k).neighbour({13, 14}, Vec2{1, 0} * k).neighbour({10, 16}, Vec2{0, -1} * k);
  return s;
}

}  // namespace

class TestAbmFlocking : public QObject {
  Q_OBJECT

 private Q_SLOTS:
  void velocity_is_the_declared_rule() {
    // N = 2: cohere = ((0.5, 0) + (3, 4)) / 2 × 0.03, separate = −(0.5, 0) / 2 × 0.015,
    // match = ((0, 1) + (1, 0)) / 2 × 0.05; vel = ((1, 0) + cohere + separate + match) / 2, normalised:
    // (1.07375, 0.085) / 1.0771091... = (0.99688135, 0.07891494).
    const auto host = builtin_host();
    for (const double k : {1.0, 2.0, 60.0}) {
      auto behavior = make(*host);
      auto s = scene(k);
      const Vec2 steering = s.step(*behavior);
      const Vec2 v = s.me().velocity / k;  // their unit velocity
      QVERIFY2(std::abs(v.x - 0.9968813532757407) < 1e-12 && std::abs(v.y - 0.07891493832683395) < 1e-12,
               qPrintable(QString("k %1: velocity (%2, %3)").arg(k).arg(v.x).arg(v.y)));
      QVERIFY(std::abs((steering + Vec2{1, 0} * k - s.me().velocity).length()) < 1e-12);
      // one step of theirs: `speed` (1) along the heading, whatever dt
      QVERIFY(std::abs(distance(s.me().position, Vec2{10, 10}) - 1) < 1e-12);
    }
  }

  void parameters_enter_as_declared() {
    // separate_factor 0: the push is gone; cohere and match as above.
    const auto host = builtin_host();
    const auto& registered = host->behavior("abm_flocking");
    salsa::ParameterValues params(registered.factory.parameters);
    params.set("separate_factor", 0);
    params.set("speed", 0.5);
    auto behavior = salsa::PluginHost::create(registered, params);
    auto s = scene(1);
    s.step(*behavior);
    // Velocities are read as v × dt / speed, twice theirs: own (2, 0), match ((0, 2) + (2, 0)) / 2 × 0.05;
    // ((2, 0) + (0.0525, 0.06) + (0.05, 0.05)) / 2, normalised, flown at 0.5 m per step.
    const Vec2 sum{2.1025, 0.11};
    const Vec2 expect = sum / sum.length() * 0.5;
    QVERIFY2((s.me().velocity - expect).length() < 1e-12, qPrintable(QString("(%1, %2)").arg(s.me().velocity.x).arg(s.me().velocity.y)));
  }

  void alone_it_keeps_its_heading_and_at_rest_it_draws_one() {
    const auto host = builtin_host();
    auto behavior = make(*host);
    salsa::testing::Scene alone;
    alone.me().dt = 1;
    alone.at({50, 50}, {0.6, 0.8});
    alone.step(*behavior);
    QVERIFY((alone.me().velocity - Vec2{0.6, 0.8}).length() < 1e-12);
    // At rest (a salsa drone's start) it draws a heading as their birds start, and flies it at speed.
    for (std::uint64_t seed : {1, 2}) {
      auto b = make(*host);
      salsa::testing::Scene rest;
      rest.me().dt = 1;
      rest.at({50, 50});
      rest.step(*b, seed);
      QVERIFY(std::abs(rest.me().velocity.length() - 1) < 1e-12);
    }
  }

  void examples_run_and_flock_data() {
    QTest::addColumn<QString>("name");
    QTest::newRow("small") << "abm-flocking-small";
    QTest::newRow("large") << "abm-flocking-large";
  }
  void examples_run_and_flock() {
    QFETCH(QString, name);
    QTemporaryDir out;
    QVERIFY(out.isValid());
    const CliResult r = run_salsa({"run", q(source_dir() / "examples") + "/" + name + ".json", "--out", out.path(), "--no-plots"});
    QVERIFY2(!r.crashed && r.exit_code == 0, describe(r));
    const auto rows = rows_of(out.filePath(name + "/drones.csv"));
    const std::size_t t = column(rows, "time"), vx = column(rows, "vx"), vy = column(rows, "vy");
    // Polarisation |mean of the unit velocities| at the first and last logged step: measured 0.10 → 0.26
    // (small, seed 1) and 0.03 → 0.41 (large): the birds align.
    auto polarisation = [&](double time) {
      Vec2 sum;
      std::size_t n = 0;
      for (std::size_t i = 1; i < rows.size(); ++i)
        if (std::stod(rows[i][t]) == time) {
          const Vec2 v{std::stod(rows[i][vx]), std::stod(rows[i][vy])};
          sum += v / v.length(), ++n;
        }
      return n ? sum.length() / static_cast<double>(n) : -1.0;
    };
    std::size_t birds = 0, at_speed = 0;
    for (std::size_t i = 1; i < rows.size(); ++i)
      if (std::stod(rows[i][t]) == 100) {
        ++birds;
        // 1 m per step, give or take what the contacts of birds 2 m apart (their bodies' radii) changed
        if (std::abs(std::hypot(std::stod(rows[i][vx]), std::stod(rows[i][vy])) - 1) < 0.15) ++at_speed;
      }
    QCOMPARE(birds, static_cast<std::size_t>(name.endsWith("small") ? 200 : 400));
    QVERIFY2(at_speed > birds * 9 / 10, qPrintable(QString("%1 of %2 at speed").arg(at_speed).arg(birds)));
    const double start = polarisation(10), end = polarisation(100);
    qInfo("%s: polarisation %.3f at 10 steps, %.3f at 100", qPrintable(name), start, end);
    QVERIFY2(end > 2 * start, qPrintable(QString("polarisation %1 → %2").arg(start).arg(end)));
  }

  // The benchmark refuses a seed count out of range in one line, before running anything.
  void bench_refuses_bad_seeds() {
    for (const char* seeds : {"0", "1001"}) {
      const CliResult r = run_salsa({"bench", "abm-flocking", "--seeds", seeds});
      QVERIFY2(!r.crashed && r.exit_code == 2, describe(r));
      QCOMPARE(non_empty_lines(r.err).size(), 1);
      QVERIFY2(r.err.contains(QString("--seeds: %1 is out of range (allowed: 1 to 1000)").arg(seeds)), describe(r));
    }
  }

  // It always runs light physics on one thread by the CPU clock: an option of another workload is
  // refused by name, not silently ignored (a figure taken with "--physics box2d" would not be Box2D's).
  void bench_refuses_other_workloads_options() {
    for (const QStringList& extra : {QStringList{"--physics", "box2d"}, QStringList{"--floor"}, QStringList{"--threads", "2"}}) {
      const CliResult r = run_salsa(QStringList{"bench", "abm-flocking", "--seeds", "1"} + extra);
      QVERIFY2(!r.crashed && r.exit_code == 2, describe(r));
      QCOMPARE(non_empty_lines(r.err).size(), 1);
      QVERIFY2(r.err.contains(extra.front() + " does not apply to this workload (allowed: --seeds, --json, --plugin-dir)"), describe(r));
      QVERIFY2(!r.out.contains("agent-steps"), describe(r));
    }
  }
};

QTEST_GUILESS_MAIN(TestAbmFlocking)
#include "test_abm_flocking.moc"
