// salsa suite through the CLI: the shipped suite's task files and committed references, a quick trial of
// new-plugin's behavior template on it, the report's paired numbers against a hand computation, the
// references written and checked on a small suite of the test's own, and bad input refused in one line.
#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <QtTest>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "common.hpp"

using namespace salsa_test;

namespace {

QString template_dir() { return q(test_plugins_dir() / "template-behavior"); }
QString shipped_suite() { return q(source_dir() / "suite" / "v1" / "suite.json"); }

/// The fields of one CSV line (RFC 4180 quotes; salsa's files hold no line break in a field).
QStringList fields(const QString& line) {
  QStringList out{""};
  bool quoted = false;
  for (qsizetype i = 0; i < line.size(); ++i) {
    const QChar c = line[i];
    if (quoted && c == '"' && i + 1 < line.size() && line[i + 1] == '"') out.back() += '"', ++i;
    else if (c == '"') quoted = !quoted;
    else if (c == ',' && !quoted) out << "";
    else out.back() += c;
  }
  return out;
}

/// A CSV file as rows of column → text.
QList<QMap<QString, QString>> csv_rows(const QString& file) {
  const QStringList lines = non_empty_lines(QString::fromUtf8(read_file(file)));
  QList<QMap<QString, QString>> rows;
  if (lines.isEmpty()) return rows;
  const QStringList header = fields(lines[0]);
  for (qsizetype i = 1; i < lines.size(); ++i) {
    const QStringList cells = fields(lines[i]);
    QMap<QString, QString> row;
    for (qsizetype k = 0; k < header.size(); ++k) row[header[k]] = cells.value(k);
    rows << row;
  }
  return rows;
}

/// "repeat/seed" → value of `variant` under `condition` in a summary.csv or references.csv.
std::map<QString, double> values_of(const QList<QMap<QString, QString>>& rows, const QString& variant, const QString& condition,
                                    const QString& column) {
  std::map<QString, double> out;
  for (const auto& r : rows)
    if (r["variant"] == variant && r["condition"] == condition) out[r["repeat"] + "/" + r["seed"]] = r[column].toDouble();
  return out;
}

struct Hand {
  int n = 0;
  double mean = 0, lo = 0, hi = 0;
};

/// The paired mean difference a − b and its 95 % t-interval, by hand (t quantiles for 2 to 5 pairs).
Hand paired(const std::map<QString, double>& a, const std::map<QString, double>& b) {
  std::vector<double> d;
  for (const auto& [k, v] : a)
    if (b.count(k)) d.push_back(v - b.at(k));
  Hand h;
  h.n = static_cast<int>(d.size());
  for (double x : d) h.mean += x / h.n;
  double ss = 0;
  for (double x : d) ss += (x - h.mean) * (x - h.mean);
  const std::map<int, double> t975{{2, 12.706205}, {3, 4.302653}, {4, 3.182446}, {5, 2.776445}};
  const double half = t975.at(h.n) * std::sqrt(ss / (h.n - 1)) / std::sqrt(h.n);
  h.lo = h.mean - half, h.hi = h.mean + half;
  return h;
}

bool close(const QString& text, double expected) {
  return std::abs(text.toDouble() - expected) <= 1e-5 * std::max(1.0, std::abs(expected));
}

/// A small suite of the test's own: one monitoring task of 20 s, two references, two conditions, 3 worlds.
QString write_mini_suite(const QTemporaryDir& dir) {
  QDir().mkpath(dir.filePath("tasks"));
  const QJsonObject task{{"behavior", "random_walk"},
                         {"map", QJsonObject{{"name", "empty"}, {"params", QJsonObject{{"size", 200}}}}},
                         {"drones", 3},
                         {"targets", QJsonObject{{"kind", "tree"}, {"count", 0}}},
                         {"metrics", QJsonArray{"staleness"}},
                         {"time", 20},
                         {"log_interval", 5}};
  write_file(dir.filePath("tasks/watch.json"), QJsonDocument(task).toJson());
  const QJsonObject suite{{"version", 1},
                          {"seed", 3},
                          {"repeats", 3},
                          {"references", QJsonArray{"random_walk", "flocking"}},
                          {"conditions", QJsonArray{QJsonObject{{"name", "nominal"}},
                                                    QJsonObject{{"name", "wind"}, {"wind", QJsonObject{{"velocity", QJsonArray{2, 0}}}}}}},
                          {"tasks", QJsonArray{QJsonObject{{"name", "watch"}, {"file", "tasks/watch.json"}, {"metric", "mean_staleness"}, {"better", "lower"}}}},
                          {"results", "references.csv"}};
  write_file(dir.filePath("suite.json"), QJsonDocument(suite).toJson());
  return dir.filePath("suite.json");
}

}  // namespace

class TestSuite : public QObject {
  Q_OBJECT

 private Q_SLOTS:
  /// Every task file is a test salsa validates, and the committed references hold one value for every
  /// reference behavior, task, condition and world of suite.json, every built-in survey behavior among
  /// them (abm_flocking, the ABM frameworks' speed model, surveys nothing and is no reference of v1).
  void shipped_suite_is_whole() {
    QStringList tasks;
    const QJsonObject suite = QJsonDocument::fromJson(read_file(shipped_suite())).object();
    for (const auto& t : suite["tasks"].toArray()) tasks << q(source_dir() / "suite" / "v1") + "/" + t.toObject()["file"].toString();
    QCOMPARE(tasks.size(), 4);
    const CliResult v = run_salsa(QStringList{"validate"} + tasks);
    QVERIFY2(v.exit_code == 0, describe(v).constData());

    std::set<QString> references;
    for (const auto& r : suite["references"].toArray()) references.insert(r.isString() ? r.toString() : r.toObject()["name"].toString());
    const auto host = builtin_host();  // kept alive: behaviors() is a view into it
    for (const auto& entry : host->behaviors())
      if (entry.factory.name != "abm_flocking") QVERIFY2(references.count(q(entry.factory.name)), entry.factory.name.c_str());
    QVERIFY(!references.count("abm_flocking"));

    const auto rows = csv_rows(q(source_dir() / "suite" / "v1" / "references.csv"));
    const qsizetype expected = tasks.size() * suite["conditions"].toArray().size() * suite["references"].toArray().size() * suite["repeats"].toInt();
    QCOMPARE(rows.size(), expected);
    for (const auto& r : rows) {
      QCOMPARE(r["version"], QString::number(suite["version"].toInt()));
      QVERIFY2(!r["value"].isEmpty(), qPrintable(r["task"] + " " + r["condition"] + " " + r["variant"]));
    }
  }

  /// A quick trial of new-plugin's behavior template on the shipped suite: the report places it among
  /// every reference, task and condition, and its numbers are the paired ones computed by hand.
  void quick_trial_of_a_template_plugin() {
    QTemporaryDir dir;
    const QString out = dir.filePath("trial");
    const CliResult r = run_salsa({"suite", "my_behavior", "--plugin-dir", template_dir(), "--time", "1", "--jobs", "2", "--out", out, "--quiet"});
    QVERIFY2(r.exit_code == 0, describe(r).constData());
    // Counted from suite.json: a reference or condition added there needs no change here.
    const QJsonObject suite = QJsonDocument::fromJson(read_file(shipped_suite())).object();
    const auto references = suite["references"].toArray().size(), conditions = suite["conditions"].toArray().size();
    const auto report = csv_rows(out + "/report.csv");
    QCOMPARE(report.size(), 4 * conditions * references);  // tasks × conditions × references
    for (const QString task : {"forest-health", "coverage", "search", "monitoring"}) {
      QVERIFY2(QFileInfo(out + "/plots/suite_" + task + ".png").size() > 1000, qPrintable(task));
      QVERIFY(read_file(out + "/plots/suite_" + task + ".png").startsWith("\x89PNG"));
    }
    QVERIFY(QString::fromUtf8(read_file(out + "/report.md")).contains("**my_behavior (defaults)**"));
    // The search task's people walk: its tests' targets.csv says where each was found.
    const QStringList searched = QDir(out + "/search").entryList(QDir::Dirs | QDir::NoDotAndDotDot);
    QVERIFY(!searched.isEmpty());
    for (const QString& test : searched)
      if (test != "plots")
        QVERIFY2(read_file(out + "/search/" + test + "/targets.csv").startsWith("id,x,y,found_time,found_by,observations,found_x,found_y\n"), qPrintable(test));

    // One difference by hand: forest-health under wind, the behavior against pheromone avoidance.
    const auto summary = csv_rows(out + "/forest-health/summary.csv");
    const auto mine = values_of(summary, "my_behavior (defaults)", "wind", "fraction_found");
    const auto theirs = values_of(summary, "pheromone_avoidance (defaults)", "wind", "fraction_found");
    QCOMPARE(mine.size(), std::size_t{5});
    const Hand h = paired(mine, theirs);
    QCOMPARE(h.n, 5);
    const auto row = std::find_if(report.begin(), report.end(), [](const auto& x) {
      return x["task"] == "forest-health" && x["condition"] == "wind" && x["reference"] == "pheromone_avoidance (defaults)";
    });
    QVERIFY(row != report.end());
    QCOMPARE((*row)["n"], QString("5"));
    QVERIFY2(close((*row)["mean_diff"], h.mean), qPrintable((*row)["mean_diff"] + " vs " + QString::number(h.mean, 'g', 10)));
    QVERIFY2(close((*row)["ci_low"], h.lo) && close((*row)["ci_high"], h.hi), qPrintable((*row)["ci_low"] + ", " + (*row)["ci_high"]));
    // Its rank: 1 + the variants with a strictly higher mean under that condition.
    std::set<QString> variants;
    for (const auto& s : summary) variants.insert(s["variant"]);
    QCOMPARE(static_cast<qsizetype>(variants.size()), references + 1);
    auto mean = [&](const QString& v) {
      double m = 0;
      const auto vals = values_of(summary, v, "wind", "fraction_found");
      for (const auto& [k, x] : vals) m += x / static_cast<double>(vals.size());
      return m;
    };
    int rank = 1;
    for (const QString& v : variants)
      if (mean(v) > mean("my_behavior (defaults)")) ++rank;
    QCOMPARE((*row)["rank"], QString::number(rank));
    QCOMPARE((*row)["ranked"], QString::number(references + 1));
  }

  /// --references writes the references of a suite and the table of their means; --check reruns them
  /// and says they are reproduced, or which value differs; a behavior is then compared with the
  /// committed values on the same seeds (a difference computed by hand, "lower is better" ranking).
  void references_written_checked_and_compared() {
    QTemporaryDir dir;
    const QString suite = write_mini_suite(dir);
    const CliResult made = run_salsa({"suite", "--references", "--suite", suite, "--out", dir.filePath("refs"), "--quiet"});
    QVERIFY2(made.exit_code == 0, describe(made).constData());
    const auto refs = csv_rows(dir.filePath("references.csv"));
    QCOMPARE(refs.size(), 2 * 2 * 3);
    QVERIFY(QString::fromUtf8(read_file(dir.filePath("references.md"))).contains("## watch (`mean_staleness`, lower is better)"));

    const CliResult check = run_salsa({"suite", "--check", "--suite", suite, "--out", dir.filePath("check"), "--quiet"});
    QVERIFY2(check.exit_code == 0, describe(check).constData());
    QCOMPARE(check.out.trimmed(), QString("watch: reproduced (12 values byte-equal)"));
    // One value changed in the committed file: --check names it and fails.
    const QByteArray good = read_file(dir.filePath("references.csv"));
    QByteArray bad = good;
    const QByteArray value = refs[4]["value"].toUtf8();
    bad.replace(bad.indexOf("," + value + "\n"), value.size() + 2, ",1" + value + "\n");
    write_file(dir.filePath("references.csv"), bad);
    const CliResult differs = run_salsa({"suite", "--check", "--suite", suite, "--out", dir.filePath("check"), "--resume", "--quiet"});
    QCOMPARE(differs.exit_code, 1);
    QVERIFY2(differs.out.startsWith("watch: DIFFERS: ") && differs.out.contains("1" + refs[4]["value"]), qPrintable(differs.out));
    write_file(dir.filePath("references.csv"), good);

    const QString out = dir.filePath("mine");
    const CliResult r = run_salsa({"suite", "my_behavior", "--params", R"({"turn_rate": 2})", "--plugin-dir", template_dir(), "--suite", suite,
                                   "--out", out, "--quiet"});
    QVERIFY2(r.exit_code == 0, describe(r).constData());
    const auto summary = csv_rows(out + "/watch/summary.csv");
    const QString me = "my_behavior: turn_rate = 2";
    QCOMPARE(summary.size(), 2 * 3);  // only the behavior ran: the references are the committed ones
    const auto report = csv_rows(out + "/report.csv");
    QCOMPARE(report.size(), 2 * 2);
    for (const QString condition : {"nominal", "wind"})
      for (const QString ref : {"random_walk (defaults)", "flocking (defaults)"}) {
        const Hand h = paired(values_of(summary, me, condition, "mean_staleness"), values_of(refs, ref, condition, "value"));
        QCOMPARE(h.n, 3);
        const auto row = std::find_if(report.begin(), report.end(), [&](const auto& x) { return x["condition"] == condition && x["reference"] == ref; });
        QVERIFY(row != report.end());
        QCOMPARE((*row)["behavior"], me);
        QVERIFY2(close((*row)["mean_diff"], h.mean), qPrintable(condition + " " + ref + ": " + (*row)["mean_diff"]));
        QVERIFY(close((*row)["ci_low"], h.lo) && close((*row)["ci_high"], h.hi));
        // Lower is better: better_share counts the worlds where the behavior's staleness was lower.
        const auto a = values_of(summary, me, condition, "mean_staleness");
        const auto b = values_of(refs, ref, condition, "value");
        double share = 0;
        for (const auto& [k, v] : a) share += (v < b.at(k) ? 1.0 : v == b.at(k) ? 0.5 : 0.0) / 3;
        QVERIFY(close((*row)["better_share"], share));
      }
  }

  /// Bad input: one line on stderr, exit status 2, nothing run.
  void bad_input_refused_in_one_line_data() {
    QTest::addColumn<QStringList>("args");
    QTest::addColumn<QString>("expected");
    const QStringList plugin{"--plugin-dir", template_dir()};
    QTest::newRow("unknown behavior") << QStringList{"nope"} << "BEHAVIOR: unknown behavior 'nope' (known:";
    QTest::newRow("out of range parameter") << QStringList{"my_behavior", "--params", R"({"turn_rate": 99})"} + plugin
                                            << "--params: behavior.params.turn_rate: 99 is out of range";
    QTest::newRow("unknown parameter") << QStringList{"my_behavior", "--params", R"({"speed": 1})"} + plugin << "--params: behavior.params.speed";
    QTest::newRow("params not JSON") << QStringList{"my_behavior", "--params", "{turn_rate"} + plugin << "--params";
    QTest::newRow("params not an object") << QStringList{"my_behavior", "--params", "[1]"} + plugin << "--params: [1] is not a JSON object";
    QTest::newRow("params file missing") << QStringList{"my_behavior", "--params", "/nonexistent/p.json"} + plugin << "--params: /nonexistent/p.json";
    QTest::newRow("jobs out of range") << QStringList{"my_behavior", "--jobs", "2000"} + plugin << "--jobs";
    QTest::newRow("negative time") << QStringList{"my_behavior", "--time", "-1"} + plugin << "--time";
    QTest::newRow("time with references") << QStringList{"--references", "--time", "5"} << "--time: not with --references";
    QTest::newRow("behavior with check") << QStringList{"random_walk", "--check"} << "--check: runs the reference behaviors only";
    QTest::newRow("nothing to do") << QStringList{} << "missing BEHAVIOR";
    QTest::newRow("no suite file") << QStringList{"random_walk", "--suite", "/nonexistent/suite.json"} << "/nonexistent/suite.json";
  }
  void bad_input_refused_in_one_line() {
    QFETCH(QStringList, args);
    QFETCH(QString, expected);
    QTemporaryDir dir;
    const QString out = dir.filePath("out");
    const CliResult r = run_salsa(QStringList{"suite"} + args + QStringList{"--out", out});
    QCOMPARE(r.exit_code, 2);
    QCOMPARE(non_empty_lines(r.err).size(), 1);
    QVERIFY2(r.err.contains(expected), qPrintable(r.err));
    QVERIFY(!QFileInfo::exists(out));
  }
};

QTEST_GUILESS_MAIN(TestSuite)
#include "test_suite.moc"
