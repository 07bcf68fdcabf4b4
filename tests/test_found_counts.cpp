// summary.csv and targets.csv tell the same story: every summary row's targets_found is the number of
// targets whose found_time is at or before the row's time, from the row at t = 0 (drones spawn among
// trees, so some are in view at once) to the last. Through the real CLI, for both decision lags and for
// rows every step as well as every second.
#include <QtTest>

#include <algorithm>
#include <vector>

#include "common.hpp"

using namespace salsa_test;

class TestFoundCounts : public QObject {
  Q_OBJECT

 private Q_SLOTS:
  void summary_rows_agree_with_targets_csv_data() {
    QTest::addColumn<QString>("behavior");
    QTest::addColumn<int>("lag");
    QTest::addColumn<QString>("log_interval");
    for (const char* behavior : {"flocking", "random_walk"})
      for (int lag : {0, 1})
        for (const char* interval : {"0.016666666666666666", "1"})
          QTest::newRow(qPrintable(QString("%1, lag %2, log every %3 s").arg(behavior).arg(lag).arg(interval)))
              << behavior << lag << interval;
  }
  void summary_rows_agree_with_targets_csv() {
    QFETCH(QString, behavior);
    QFETCH(int, lag);
    QFETCH(QString, log_interval);
    QTemporaryDir dir;
    QVERIFY(dir.isValid());
    // 30 drones in a 30 m disc over 4,000 trees on 400 m × 400 m: dozens of trees in view at t = 0.
    QVERIFY(write_file(dir.filePath("t.json"),
                       QString(R"({"name": "t", "behavior": "%1", "drones": 30, "map": {"name": "empty", "params": {"size": 400}},
                                   "targets": {"kind": "tree", "count": 4000}, "time": 8, "log_interval": %3,
                                   "decision_lag": %2, "seed": 3})")
                           .arg(behavior)
                           .arg(lag)
                           .arg(log_interval)
                           .toUtf8()));
    const CliResult r = run_salsa({"run", dir.filePath("t.json"), "--out", dir.filePath("out")});
    QVERIFY2(r.exit_code == 0 && !r.crashed, describe(r));

    std::vector<double> found_times;  // targets.csv: id,x,y,found_time,found_by,observations
    const QStringList targets = non_empty_lines(QString::fromUtf8(read_file(dir.filePath("out/t/targets.csv"))));
    QCOMPARE(targets.value(0), QString("id,x,y,found_time,found_by,observations"));
    for (qsizetype i = 1; i < targets.size(); ++i)
      if (const QString t = targets[i].split(',').value(3); !t.isEmpty()) found_times.push_back(t.toDouble());
    std::sort(found_times.begin(), found_times.end());

    const QStringList summary = non_empty_lines(QString::fromUtf8(read_file(dir.filePath("out/t/summary.csv"))));
    QVERIFY(summary.value(0).startsWith("time,targets_found,"));
    QVERIFY2(summary.size() > 8, "one row per logged step");
    for (qsizetype i = 1; i < summary.size(); ++i) {
      const QStringList row = summary[i].split(',');
      const double time = row.value(0).toDouble();
      const auto by_then = std::upper_bound(found_times.begin(), found_times.end(), time) - found_times.begin();
      QVERIFY2(row.value(1).toLongLong() == by_then,
               qPrintable(QString("t = %1 s: summary.csv says %2 found, targets.csv %3").arg(row[0], row[1]).arg(by_then)));
    }
    // Meaningful: trees were in view from the start (found in the first step), and more were found later.
    QVERIFY2(!found_times.empty() && found_times.front() < 0.02, "no tree found in the first step");
    QVERIFY2(found_times.back() > 1, "no tree found after the first second");
    QCOMPARE(summary.value(1).split(',').value(0), QString("0.0000"));
  }
};

QTEST_GUILESS_MAIN(TestFoundCounts)
#include "test_found_counts.moc"
