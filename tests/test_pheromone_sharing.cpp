// Pheromone avoidance's two sharing modes on whole runs: over a perfect radio that reaches everyone
// (no loss, no latency, no walls in the way) `messages` finds what `global` finds within noise, and
// every drone's marks reach every other drone. (test_builtin_behaviors checks the merge itself.)
#include <QTemporaryDir>
#include <QtTest>

#include <cmath>
#include <string>
#include <vector>

#include "common.hpp"
#include "salsa/core/files/csv_reader.hpp"
#include "salsa/core/run/runner.hpp"
#include "salsa/core/experiments/test_spec.hpp"

using namespace salsa;
using namespace salsa_test;

class TestPheromoneSharing : public QObject {
  Q_OBJECT

  std::unique_ptr<PluginHost> host_ = builtin_host();

  /// fraction_found at the end of the test, in percent; `delivered`: messages_delivered then.
  double found(int seed, int sharing, const std::string& comm, double* delivered = nullptr) {
    const std::string json = R"({"name": "p", "behavior": {"name": "pheromone_avoidance", "params": {"sharing": )" +
                             std::to_string(sharing) + R"(}}, "drones": 6, "map": {"name": "empty", "params": {"size": 400}},
        "targets": {"count": 2000}, "time": 150, "seed": )" + std::to_string(seed) + comm + "}";
    const TestSpec test = parse_test(json, "sharing.json", *host_);
    QTemporaryDir out;
    RunOptions options;
    options.out = out.path().toStdString();
    options.drones_csv = false;
    run_test(test, *host_, options);
    CsvReader outcome((out.path() + "/p/outcome.csv").toStdString());
    const std::size_t column = outcome.column("fraction_found");
    double last = -1;
    while (outcome.next()) last = outcome.number(column);
    if (delivered) {
      CsvReader summary((out.path() + "/p/summary.csv").toStdString());
      const std::size_t c = summary.column("messages_delivered");
      while (summary.next()) *delivered = summary.number(c);
    }
    return 100 * last;
  }

 private Q_SLOTS:
  void messages_over_a_perfect_radio_find_what_the_global_field_finds() {
    const std::string perfect = R"(, "comm": {"range": 100000, "line_of_sight": false})";
    std::vector<double> same;
    for (int seed = 1; seed <= 8; ++seed) {
      double delivered = 0;
      same.push_back(found(seed, 1, perfect, &delivered) - found(seed, 0, ""));
      // 6 drones broadcast every step of 150 s at dt 1/60; each message reaches the 5 others (the
      // last step's are still in flight when the test ends).
      QCOMPARE(delivered, 6.0 * 5 * (9000 - 1));
    }
    auto mean = [](const std::vector<double>& d) { double s = 0; for (double x : d) s += x; return s / static_cast<double>(d.size()); };
    auto half = [&](const std::vector<double>& d) {  // 95 % paired interval: t(0.975, 7 df) × sd / √n
      const double m = mean(d);
      double ss = 0;
      for (double x : d) ss += (x - m) * (x - m);
      const auto n = static_cast<double>(d.size());
      return 2.365 * std::sqrt(ss / (n - 1) / n);
    };
    qInfo("messages over a perfect radio − global: %+.2f ± %.2f points", mean(same), half(same));
    // Within noise: the interval of the paired difference holds 0, or the difference is under 1 point.
    QVERIFY2(std::abs(mean(same)) <= std::max(half(same), 1.0), "a perfect radio should share what the global field shares");
  }
};

QTEST_GUILESS_MAIN(TestPheromoneSharing)
#include "test_pheromone_sharing.moc"
