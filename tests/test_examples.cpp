// Every shipped example is a test, so none goes stale unnoticed: each test file under examples/
// validates and runs (shortened to 5 s) through the salsa CLI and writes its data (a queue, every test
// it expands to), byte for byte the data of the committed digests; each map file validates.
#include <QCryptographicHash>
#include <QDirIterator>
#include <QJsonDocument>
#include <QJsonObject>
#include <QtTest>

#include <cmath>

#include "common.hpp"

using namespace salsa_test;

namespace {

/// The names of the tests in a test or queue file, as salsa names their output folders: the first
/// column of `salsa queue expand` (the count, then a line per test).
QStringList test_names(const QString& file) {
  const CliResult r = run_salsa({"queue", "expand", file});
  const QStringList lines = non_empty_lines(r.out);
  QStringList names;
  for (qsizetype i = 1; i < lines.size(); ++i) names << lines[i].section(' ', 0, 0);
  if (r.exit_code != 0 || lines.value(0) != QString::number(names.size()) + (names.size() == 1 ? " test" : " tests")) return {};
  return names;
}

/// Every example's data files as they were when the digests were committed (tests/data/
/// example-digests.txt: "<example>/<test>/<file> <sha-256>"), so a change that was to change no result
/// is shown to change none. SALSA_UPDATE_DIGESTS=1 writes the digests of this run instead.
const char* const data_files[] = {"summary.csv", "outcome.csv", "drones.csv", "targets.csv", "map.json"};
/// The radio studies set the global variants beside radio-bound ones on purpose (the idealised
/// baseline): their stderr is the one warning that says so, and nothing else. Returns what is left.
QString other_warnings(const QString& file, const QString& err) {
  QStringList left = non_empty_lines(err);
  if (file.endsWith("dsp-radio-queue.json") || file.endsWith("pheromone-radio-queue.json")) {
    const qsizetype said = left.removeIf([](const QString& l) { return l.contains("salsa: warning: ") && l.contains("compares global knowledge with a radio"); });
    if (said != 1) left << "expected the one warning of a comparison of global knowledge with a radio";
  }
  return left.join('\n');
}

QString digests_file() { return q(source_dir() / "tests/data/example-digests.txt"); }
QMap<QString, QString> read_digests() {
  QMap<QString, QString> out;
  for (const QString& line : non_empty_lines(QString::fromUtf8(read_file(digests_file())))) out[line.section(' ', 0, 0)] = line.section(' ', 1);
  return out;
}
void check_digests(const QString& example, const QString& out, const QStringList& tests) {
  QMap<QString, QString> digests = read_digests();
  const bool update = qEnvironmentVariableIntValue("SALSA_UPDATE_DIGESTS") == 1;
  for (const QString& test : tests)
    for (const char* f : data_files) {
      const QString path = out + "/" + test + "/" + f, key = example + "/" + test + "/" + f;
      if (!QFileInfo::exists(path)) continue;
      const QString digest = QString::fromLatin1(QCryptographicHash::hash(read_file(path), QCryptographicHash::Sha256).toHex());
      if (update) digests[key] = digest;
      else if (!digests.contains(key)) QFAIL(qPrintable("no digest for " + key + " in " + digests_file() + ": a new example? run test_examples with SALSA_UPDATE_DIGESTS=1 and commit the file"));
      else QVERIFY2(digests[key] == digest, qPrintable(key + " changed: its bytes differ from the committed digest (a result changed)"));
    }
  if (!update) return;
  QStringList lines;
  for (auto it = digests.begin(); it != digests.end(); ++it) lines << it.key() + " " + it.value();
  QFile file(digests_file());
  QVERIFY(file.open(QIODevice::WriteOnly | QIODevice::Truncate));
  file.write((lines.join('\n') + '\n').toUtf8());
}

bool is_map_file(const QString& file) {
  const QJsonDocument doc = QJsonDocument::fromJson(read_file(file));
  return doc.isObject() && doc.object().contains("bounds");
}

}  // namespace

class TestExamples : public QObject {
  Q_OBJECT

  static void add_rows(bool maps) {
    QTest::addColumn<QString>("file");
    const QString root = q(source_dir() / "examples");
    QDirIterator it(root, {"*.json"}, QDir::Files, QDirIterator::Subdirectories);
    QStringList files;
    while (it.hasNext()) files << it.next();
    files.sort();
    for (const QString& f : files)
      // examples/plugin/'s queue needs the example plugins built: out_of_tree_plugin.sh runs it; tune
      // files (examples/tune/) are not test files: tune_file_runs runs them.
      if (const QString rel = QDir(root).relativeFilePath(f); is_map_file(f) == maps && !rel.startsWith("plugin/") && !rel.startsWith("tune/"))
        QTest::newRow(qPrintable(rel)) << f;
  }

 private Q_SLOTS:
  void there_are_examples() {
    QDirIterator it(q(source_dir() / "examples"), {"*.json"}, QDir::Files, QDirIterator::Subdirectories);
    int tests = 0, maps = 0;
    while (it.hasNext()) (is_map_file(it.next()) ? maps : tests)++;
    QVERIFY2(tests >= 4, "examples/ should hold a test file per built-in behavior");
    QVERIFY2(maps >= 1, "examples/maps/ should hold a map file");
  }

  void test_file_validates_data() { add_rows(false); }
  void test_file_validates() {
    QFETCH(QString, file);
    const CliResult r = run_salsa({"validate", file});
    QVERIFY2(!r.crashed && r.exit_code == 0, describe(r));
    QVERIFY2(other_warnings(file, r.err).isEmpty(), describe(r));  // not even a warning
    QVERIFY2(r.out.contains(": ok ("), describe(r));
  }

  void test_file_runs_data() { add_rows(false); }
  void test_file_runs() {
    QFETCH(QString, file);
    QTemporaryDir out;
    QVERIFY(out.isValid());
    const QStringList names = test_names(file);
    QVERIFY(!names.isEmpty());
    // From another working folder: relative map files resolve against the test file's folder. Big
    // queues (the forest-health experiment: 100 tests over 50,000 trees) skip the plots, which
    // test_plots covers; their data and summary are checked all the same.
    QStringList args{"run", file, "--time", "5", "--out", out.path()};
    const bool big = names.size() > 20;
    if (big) args << "--no-plots";
    // Under the sanitizers (ten times slower) a big queue runs one shard of about 20 tests, and
    // `salsa summarize` then lists the others as missing; the Release suite runs them all.
    qsizetype shards = 1;
#ifdef __SANITIZE_ADDRESS__
    if (big) shards = (names.size() + 19) / 20;
#endif
    if (shards > 1) args << "--shard" << QString("0/%1").arg(shards);
    QStringList ran;
    for (qsizetype k = 0; k < names.size(); k += shards) ran << names[k];
    const CliResult r = run_salsa(args, out.path());
    QVERIFY2(!r.crashed && r.exit_code == 0, describe(r));
    QVERIFY2(other_warnings(file, r.err).isEmpty(), describe(r));
    for (const QString& name : ran) {
      const QString dir = out.filePath(name);
      for (const char* f : {"config.json", "map.json", "summary.csv", "drones.csv", "targets.csv"})
        QVERIFY2(QFileInfo(dir + "/" + f).size() > 0, qPrintable(dir + "/" + f + " missing or empty\n" + describe(r)));
      // 5 s simulated, whatever the file says, logged from t = 0.
      const QJsonObject config = QJsonDocument::fromJson(read_file(dir + "/config.json")).object();
      QCOMPARE(config["time"].toDouble(), 5.0);
      const double interval = config["log_interval"].toDouble();
      const QStringList summary = non_empty_lines(QString::fromUtf8(read_file(dir + "/summary.csv")));
      QCOMPARE(summary.size(), 2 + qsizetype(std::floor(5 / interval + 1e-9)));
      QVERIFY(summary.last().startsWith("5.0000,"));
      // One targets.csv row per target.
      const QStringList targets = non_empty_lines(QString::fromUtf8(read_file(dir + "/targets.csv")));
      QCOMPARE(targets.size(), 1 + config["targets"].toObject()["count"].toInt());
    }
    // Nothing else left behind (no half-written ".partial" folders), and the queue's own files: one
    // summary row per test, all ok, and its plots.
    QStringList folders = QDir(out.path()).entryList(QDir::Dirs | QDir::NoDotAndDotDot | QDir::Hidden);
    QCOMPARE(folders.removeOne("plots"), !big);
    QCOMPARE(folders.size(), ran.size());
    if (shards > 1) {
      const CliResult summarized = run_salsa({"summarize", out.path()});
      QVERIFY2(!summarized.crashed && summarized.exit_code == 0, describe(summarized));
    }
    const QStringList rows = non_empty_lines(QString::fromUtf8(read_file(out.path() + "/summary.csv")));
    QCOMPARE(rows.size(), names.size() + 1);
    for (qsizetype i = 1; i < rows.size(); ++i)
      QVERIFY2(rows[i].contains(ran.contains(rows[i].section(',', 0, 0)) ? ",ok," : ",missing,"), qPrintable(rows[i]));
    if (!big) QVERIFY(QFileInfo(out.path() + "/plots/found_boxplot.png").size() > 0);
    check_digests(QDir(q(source_dir() / "examples")).relativeFilePath(file), out.path(), ran);
  }

  void tune_file_runs_data() {
    QTest::addColumn<QString>("file");
    QDirIterator it(q(source_dir() / "examples" / "tune"), {"*.json"}, QDir::Files);
    while (it.hasNext()) {
      const QString f = it.next();
      QTest::newRow(qPrintable(QFileInfo(f).fileName())) << f;
    }
  }
  void tune_file_runs() {
    // Shrunk to seconds: 5 s tests and 8 evaluations (--time, --evaluations), 2 worlds, 1 held-out
    // world; the rest as shipped. The copy's queue path (a "world") points at the shipped queue.
    QFETCH(QString, file);
    QTemporaryDir out;
    QJsonObject tune = QJsonDocument::fromJson(read_file(file)).object();
    QVERIFY(!tune.isEmpty());
    if (tune.contains("world")) {
      QJsonObject world = tune["world"].toObject();
      world["queue"] = QFileInfo(file).dir().absoluteFilePath(world["queue"].toString());
      tune["world"] = world;
    }
    tune["worlds"] = 2;
    tune["validation"] = QJsonObject{{"worlds", 1}, {"candidates", 1}};
    tune["racing"] = false;
    const QString small = out.filePath("tune.json");
    QVERIFY(write_file(small, QJsonDocument(tune).toJson()));
    const CliResult r = run_salsa({"tune", small, "--out", out.filePath("results"), "--time", "5", "--evaluations", "8"});
    QVERIFY2(!r.crashed && r.exit_code == 0, describe(r));
    QVERIFY2(r.err.trimmed().isEmpty(), describe(r));
    for (const char* f : {"tune.csv", "candidates.csv", "best.json", "report.txt", "plots/convergence.png"})
      QVERIFY2(QFileInfo(out.filePath(QString("results/") + f)).size() > 0, f);
    const QString csv = QString::fromUtf8(read_file(out.filePath("results/tune.csv")));
    QCOMPARE(csv.count(",tuning,"), 8);  // the budget, spent in full
    QVERIFY(csv.count(",validation,") >= 1);
    const QJsonObject config = QJsonDocument::fromJson(read_file(out.filePath("results/c0000_w00/config.json"))).object();
    QCOMPARE(config["time"].toDouble(), 5.0);
  }

  void map_file_validates_data() { add_rows(true); }
  void map_file_validates() {
    QFETCH(QString, file);
    const CliResult r = run_salsa({"validate", file});
    QVERIFY2(!r.crashed && r.exit_code == 0, describe(r));
    QVERIFY2(r.err.trimmed().isEmpty(), describe(r));
    QVERIFY2(r.out.contains("ok (map)"), describe(r));
  }

  void map_file_runs_data() { add_rows(true); }
  void map_file_runs() {
    // A map file is only useful if drones can fly in it: run every behavior on it briefly.
    QFETCH(QString, file);
    QTemporaryDir out;
    QVERIFY(out.isValid());
    const QString test = out.filePath("on-map.json");
    QVERIFY(write_file(test, QString(R"([
      {"name": "flocking", "behavior": "flocking", "drones": 20, "map": "%1", "targets": {"count": 20}, "time": 3},
      {"name": "pheromone", "behavior": "pheromone_avoidance", "drones": 20, "map": "%1", "targets": {"count": 20}, "time": 3},
      {"name": "dsp", "behavior": "dynamic_space_partitioning", "drones": 20, "map": "%1", "targets": {"count": 20}, "time": 3},
      {"name": "random", "behavior": "random_walk", "drones": 20, "map": "%1", "targets": {"count": 20}, "time": 3}
    ])").arg(file).toUtf8()));
    const CliResult r = run_salsa({"run", test, "--out", out.filePath("results")});
    QVERIFY2(!r.crashed && r.exit_code == 0, describe(r));
    for (const char* name : {"flocking", "pheromone", "dsp", "random"})
      QVERIFY2(QFileInfo(out.filePath(QString("results/%1/config.json").arg(name))).exists(), describe(r));
  }
};

QTEST_GUILESS_MAIN(TestExamples)
#include "test_examples.moc"
