// salsa tune through the CLI, on the test_bowl behavior (tests/plugins/tune_bowl.cpp): its mean speed
// is a known smooth function of a, b and c plus seed noise, with its optimum 8 at a = 6, b = 1, c = 8.
#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <QtTest>

#include <signal.h>

#include <cmath>
#include <map>
#include <set>

#include "common.hpp"

using namespace salsa_test;

namespace {

QString bowl_dir() { return q(test_plugins_dir() / "tune-bowl"); }

/// A tune of test_bowl's a and b (c at its optimum, 8), or of a, b and c (from c's default, 15): 5
/// drones spread over an empty map (they never meet) flying 1 s, mean_speed maximised.
QJsonObject bowl_tune(const QString& algorithm, int evaluations, int worlds = 2, bool with_c = false) {
  QJsonObject behavior{{"name", "test_bowl"}};
  if (!with_c) behavior["params"] = QJsonObject{{"c", 8}};
  QJsonObject test{{"name", "bowl"},
                   {"behavior", behavior},
                   {"drones", 5},
                   {"spawn", QJsonObject{{"mode", "uniform"}}},
                   {"map", QJsonObject{{"name", "empty"}, {"params", QJsonObject{{"size", 1000}}}}},
                   {"time", 1},
                   {"dt", 0.1},
                   {"log_interval", 0.5},
                   {"metrics", QJsonArray{}}};
  QJsonObject params{{"behavior.params.a", QJsonObject{}}, {"behavior.params.b", QJsonObject{}}};
  if (with_c) params["behavior.params.c"] = QJsonObject{};
  return QJsonObject{{"test", test},
                     {"parameters", params},
                     {"objective", QJsonObject{{"column", "mean_speed"}, {"goal", "max"}}},
                     {"algorithm", algorithm},
                     {"seed", 3},
                     {"budget", QJsonObject{{"evaluations", evaluations}}},
                     {"worlds", worlds},
                     {"validation", QJsonObject{{"worlds", 3}, {"candidates", 2}}},
                     {"racing", false}};
}

QString write_tune(const QTemporaryDir& dir, const QJsonObject& tune, const QString& name = "bowl-tune.json") {
  const QString file = dir.filePath(name);
  write_file(file, QJsonDocument(tune).toJson());
  return file;
}

CliResult tune(const QString& file, const QString& out, QStringList more = {}) {
  return run_salsa(QStringList{"tune", file, "--out", out, "--plugin-dir", bowl_dir(), "--no-plots"} + more);
}

/// A queue of two tests (test_bowl with c = 8, and random_walk), 3 repeats, under two conditions:
/// "calm" (the base) and "crowd" (8 drones, 6 from 0.5 s on, a wind, shorter steps).
QJsonObject bowl_queue() {
  QJsonObject base{{"drones", 5},
                   {"spawn", QJsonObject{{"mode", "uniform"}}},
                   {"map", QJsonObject{{"name", "empty"}, {"params", QJsonObject{{"size", 1000}}}}},
                   {"time", 1},
                   {"dt", 0.1},
                   {"log_interval", 0.5},
                   {"metrics", QJsonArray{}}};
  QJsonObject crowd{{"name", "crowd"},
                    {"drones", 8},
                    {"dt", 0.05},  // with the wind, a step must stay shorter than a drone's radius
                    {"changes", QJsonArray{QJsonObject{{"time", 0.5}, {"set", QJsonObject{{"drones", 6}}}}}},
                    {"set", QJsonObject{{"wind.velocity.x", 1}}}};
  QJsonArray tests{QJsonObject{{"name", "bowl"}, {"behavior", QJsonObject{{"name", "test_bowl"}, {"params", QJsonObject{{"c", 8}}}}}},
                   QJsonObject{{"name", "walk"}, {"behavior", "random_walk"}}};
  return QJsonObject{{"seed", 5}, {"repeats", 3}, {"base", base}, {"conditions", QJsonArray{QJsonObject{{"name", "calm"}}, crowd}}, {"tests", tests}};
}

/// A test folder's config.json as an object, without the keys named.
QJsonObject config_without(const QString& folder, const QStringList& keys) {
  QJsonObject o = QJsonDocument::fromJson(read_file(folder + "/config.json")).object();
  for (const QString& k : keys) o.remove(k);
  return o;
}

/// A CSV file as rows of column → text.
QList<QMap<QString, QString>> csv_rows(const QString& file) {
  const QStringList lines = non_empty_lines(QString::fromUtf8(read_file(file)));
  QList<QMap<QString, QString>> rows;
  if (lines.isEmpty()) return rows;
  const QStringList header = lines[0].split(',');
  for (qsizetype i = 1; i < lines.size(); ++i) {
    const QStringList cells = lines[i].split(',');
    QMap<QString, QString> row;
    for (qsizetype k = 0; k < header.size(); ++k) row[header[k]] = cells.value(k);
    rows << row;
  }
  return rows;
}

/// The winner's row of candidates.csv: the complete candidate with the best mean_speed.
QMap<QString, QString> winner(const QString& out) {
  QMap<QString, QString> best;
  for (const auto& row : csv_rows(out + "/candidates.csv"))
    if (row["status"] == "complete" && (best.isEmpty() || row["mean_speed"].toDouble() > best["mean_speed"].toDouble())) best = row;
  return best;
}

}  // namespace

class TestTune : public QObject {
  Q_OBJECT

 private Q_SLOTS:
  void algorithm_finds_the_optimum_data() {
    QTest::addColumn<QString>("algorithm");
    QTest::addColumn<int>("evaluations");
    for (const char* a : {"cmaes", "xnes", "pso", "de", "bobyqa", "neldermead", "random", "lhs", "grid"})
      QTest::newRow(a) << a << 100;
  }
  void algorithm_finds_the_optimum() {
    QFETCH(QString, algorithm);
    QFETCH(int, evaluations);
    QTemporaryDir dir;
    const QString out = dir.filePath("out");
    const CliResult r = tune(write_tune(dir, bowl_tune(algorithm, evaluations)), out, {"--jobs", "2"});
    QVERIFY2(r.exit_code == 0, describe(r));
    const auto best = winner(out);
    // The optimum is 8 (a = 6, b = 1); within 0.5 of it means |a − 6| < 1.6 and |log10 b| < 0.58.
    QVERIFY2(best["mean_speed"].toDouble() > 7.5, describe(r) + "\nbest: " + best["behavior.params.a"].toUtf8() + " " +
                                                        best["behavior.params.b"].toUtf8() + " " + best["mean_speed"].toUtf8());
    int evaluations_run = 0;
    for (const auto& row : csv_rows(out + "/tune.csv")) evaluations_run += row["phase"] == "tuning";
    QVERIFY2(evaluations_run <= evaluations, describe(r));
    QVERIFY2(r.out.contains("validation on 3 held-out worlds"), describe(r));
  }

  void whole_numbers_and_log_scale() {
    // c is a whole number; b's declared range [0.01, 100] spans four decades, so it is searched on a
    // log scale: random points fall below 1 as often as above.
    QTemporaryDir dir;
    const QString out = dir.filePath("out");
    const CliResult r = tune(write_tune(dir, bowl_tune("random", 120, 2, true)), out);
    QVERIFY2(r.exit_code == 0, describe(r));
    int below = 0, above = 0;
    for (const auto& row : csv_rows(out + "/candidates.csv")) {
      const double c = row["behavior.params.c"].toDouble();
      QCOMPARE(c, std::round(c));
      (row["behavior.params.b"].toDouble() < 1 ? below : above)++;
    }
    QVERIFY2(below >= 15 && above >= 15, qPrintable(QString("%1 below 1, %2 above").arg(below).arg(above)));
  }

  void cmaes_three_parameters() {
    QTemporaryDir dir;
    const QString out = dir.filePath("out");
    const CliResult r = tune(write_tune(dir, bowl_tune("cmaes", 300, 2, true)), out);
    QVERIFY2(r.exit_code == 0, describe(r));
    const auto best = winner(out);
    QVERIFY2(std::fabs(best["behavior.params.c"].toDouble() - 8) <= 3, describe(r));
    QVERIFY2(best["mean_speed"].toDouble() > 7.5, describe(r));
  }

  void racing_drops_a_clearly_worse_candidate() {
    QTemporaryDir dir;
    const QString out = dir.filePath("out");
    QJsonObject t = bowl_tune("random", 200, 8);
    t["racing"] = QJsonObject{{"level", 0.05}, {"first_test", 3}};
    const CliResult r = tune(write_tune(dir, t), out);
    QVERIFY2(r.exit_code == 0, describe(r));
    const auto rows = csv_rows(out + "/candidates.csv");
    const double best = winner(out)["mean_speed"].toDouble();
    int dropped = 0;
    for (const auto& row : rows) {
      if (row["status"] != "dropped") continue;
      ++dropped;
      // Dropped after fewer worlds than a complete candidate runs, and worse than the best.
      QVERIFY2(row["worlds"].toInt() < 8, qPrintable(row["candidate"]));
      QVERIFY2(row["mean_speed"].toDouble() < best, qPrintable(row["candidate"]));
    }
    QVERIFY2(dropped >= 5, describe(r));
    // The defaults (mean speed about 0.5, the optimum 8) are clearly worse than the best: a candidate
    // as bad as them never runs all eight worlds once a good one is known.
    for (const auto& row : rows)
      if (row["candidate"] != "0" && row["status"] == "complete") QVERIFY2(row["mean_speed"].toDouble() > 1, qPrintable(row["candidate"]));
    QVERIFY2(r.out.contains("dropped by racing (paired t-test, one-sided level 0.05"), describe(r));
  }

  void validation_worlds_are_disjoint_from_tuning_worlds() {
    QTemporaryDir dir;
    const QString out = dir.filePath("out");
    const CliResult r = tune(write_tune(dir, bowl_tune("lhs", 40, 4)), out);
    QVERIFY2(r.exit_code == 0, describe(r));
    std::set<QString> tuning_seeds, validation_seeds;
    std::set<int> tuning_worlds, validation_worlds;
    std::map<QString, std::set<QString>> seeds_per_world;
    int validation_rows = 0;
    for (const auto& row : csv_rows(out + "/tune.csv")) {
      const bool v = row["phase"] == "validation";
      (v ? validation_seeds : tuning_seeds).insert(row["seed"]);
      (v ? validation_worlds : tuning_worlds).insert(row["world"].toInt());
      seeds_per_world[row["world"]].insert(row["seed"]);
      validation_rows += v;
    }
    QCOMPARE(tuning_worlds, (std::set<int>{0, 1, 2, 3}));
    QCOMPARE(validation_worlds, (std::set<int>{4, 5, 6}));
    for (const QString& s : validation_seeds) QVERIFY2(!tuning_seeds.count(s), qPrintable(s));
    // Fair: every candidate faces the same seed on the same world.
    for (const auto& [world, seeds] : seeds_per_world) QVERIFY2(seeds.size() == 1, qPrintable(world));
    QCOMPARE(validation_rows, 3 * 3);  // the best two and the defaults, three worlds each
  }

  void jobs_1_and_2_and_mpi_ranks_give_the_same_tune() {
    QTemporaryDir dir;
    const QString file = write_tune(dir, bowl_tune("cmaes", 60));
    const CliResult one = tune(file, dir.filePath("one"), {"--jobs", "1"});
    const CliResult two = tune(file, dir.filePath("two"), {"--jobs", "2"});
    QVERIFY2(one.exit_code == 0 && two.exit_code == 0, describe(one) + describe(two));
    for (const char* f : {"tune.csv", "candidates.csv", "best.json"})
      QVERIFY2(read_file(dir.filePath(QString("one/") + f)) == read_file(dir.filePath(QString("two/") + f)), f);
    QVERIFY(!read_file(dir.filePath("one/tune.csv")).isEmpty());
    // Over MPI ranks (rank 0 hands out each batch's tests): the same tune again.
    const auto mpi = run_mpi(2, {"tune", file, "--out", dir.filePath("mpi"), "--plugin-dir", bowl_dir(), "--no-plots"});
    if (!mpi) QSKIP("mpirun is not installed (Debian: openmpi-bin)");
    if (mpi->err.contains("built without MPI")) QSKIP("this salsa was built without MPI");
    QVERIFY2(mpi->exit_code == 0, describe(*mpi));
    for (const char* f : {"tune.csv", "candidates.csv", "best.json"})
      QVERIFY2(read_file(dir.filePath(QString("one/") + f)) == read_file(dir.filePath(QString("mpi/") + f)), f);
  }

  void resume_after_sigkill_gives_the_same_tune() {
    QTemporaryDir dir;
    QJsonObject t = bowl_tune("cmaes", 120);
    t["racing"] = QJsonObject{{"first_test", 2}};
    t["worlds"] = 4;
    const QString file = write_tune(dir, t);
    const CliResult whole = tune(file, dir.filePath("whole"), {"--jobs", "2"});
    QVERIFY2(whole.exit_code == 0, describe(whole));

    // The same tune killed (SIGKILL: no chance to clean up) once some of its tests are done.
    const QString out = dir.filePath("killed");
    QProcess p;
    QProcessEnvironment env = QProcessEnvironment::systemEnvironment();
    env.remove("SALSA_PLUGIN_PATH");
    p.setProcessEnvironment(env);
    p.start(salsa_executable(), {"tune", file, "--out", out, "--plugin-dir", bowl_dir(), "--no-plots", "--jobs", "2"});
    QVERIFY(p.waitForStarted());
    QElapsedTimer timer;
    timer.start();
    while (QDir(out).entryList({"c*_w*"}, QDir::Dirs).size() < 30 && timer.elapsed() < 60000 && p.state() == QProcess::Running)
      QTest::qWait(5);
    QVERIFY2(p.state() == QProcess::Running, "the tune ended before it could be killed");
    ::kill(static_cast<pid_t>(p.processId()), SIGKILL);
    p.waitForFinished();
    // What it wrote so far (tune.csv after each generation) is not the finished tune's.
    QVERIFY(read_file(out + "/tune.csv") != read_file(dir.filePath("whole/tune.csv")));
    // ...but it is there to watch: the defaults (generation 0) finished before 30 tests were.
    const auto so_far = csv_rows(out + "/candidates.csv");
    QVERIFY(!so_far.empty());
    QCOMPARE(so_far.front().value("status"), QString("complete"));

    const CliResult resumed = tune(file, out, {"--jobs", "2", "--resume"});
    QVERIFY2(resumed.exit_code == 0, describe(resumed));
    for (const char* f : {"tune.csv", "candidates.csv", "best.json"})
      QVERIFY2(read_file(dir.filePath(QString("whole/") + f)) == read_file(out + "/" + f), f);
    // Without --resume the folder is refused, naming it.
    const CliResult again = tune(file, out);
    QCOMPARE(again.exit_code, 2);
    QVERIFY2(again.err.contains("--resume"), describe(again));
  }

  // --force over an earlier, longer tune leaves the new tune alone in OUT: none of the earlier
  // evaluations' folders, and a folder salsa did not write stays.
  void force_replaces_an_earlier_tune_whole() {
    QTemporaryDir dir;
    const QString out = dir.filePath("out");
    QVERIFY2(tune(write_tune(dir, bowl_tune("random", 30, 2)), out).exit_code == 0, "first tune");
    QVERIFY(QDir(out).mkpath("notes"));
    auto evaluations = [&] { return QDir(out).entryList({"c*_w*"}, QDir::Dirs).size(); };
    const qsizetype before = evaluations();
    const CliResult r = tune(write_tune(dir, bowl_tune("random", 6, 2)), out, {"--force"});
    QVERIFY2(r.exit_code == 0, describe(r));
    QVERIFY(QDir(out + "/notes").exists());
    qsizetype listed = 0;
    for (const auto& row : csv_rows(out + "/tune.csv")) {
      listed += 1;
      QVERIFY2(!row["test"].isEmpty() && QDir(out + "/" + row["test"]).exists(), qPrintable(row["test"]));
    }
    QVERIFY2(evaluations() == listed && listed < before, qPrintable(QString("%1 folders, %2 in tune.csv, %3 before").arg(evaluations()).arg(listed).arg(before)));
  }

  void best_json_replays_to_its_score() {
    QTemporaryDir dir;
    const QString out = dir.filePath("out");
    const CliResult r = tune(write_tune(dir, bowl_tune("cmaes", 40, 3)), out);
    QVERIFY2(r.exit_code == 0, describe(r));
    const CliResult replay = run_salsa({"run", out + "/best.json", "--out", dir.filePath("replay"), "--plugin-dir", bowl_dir(), "--no-plots"});
    QVERIFY2(replay.exit_code == 0, describe(replay));
    double sum = 0;
    for (int w = 0; w < 3; ++w) {
      const auto rows = csv_rows(dir.filePath(QString("replay/best_r%1/summary.csv").arg(w)));
      QVERIFY(!rows.isEmpty());
      sum += rows.last()["mean_speed"].toDouble();
    }
    const double recorded = winner(out)["mean_speed"].toDouble();
    QVERIFY2(std::fabs(sum / 3 - recorded) <= 1e-5 * std::max(1.0, std::fabs(recorded)),
             qPrintable(QString("replayed %1, recorded %2").arg(sum / 3).arg(recorded)));
  }

  void a_failing_candidate_is_scored_worst_and_tuning_goes_on() {
    QTemporaryDir dir;
    const QString out = dir.filePath("out");
    QJsonObject t = bowl_tune("random", 80);
    QJsonObject test = t["test"].toObject();
    test["behavior"] = QJsonObject{{"name", "test_bowl"}, {"params", QJsonObject{{"c", 8}, {"fail_above", 7}}}};
    t["test"] = test;
    const CliResult r = tune(write_tune(dir, t), out);
    QVERIFY2(r.exit_code == 0, describe(r));
    int failed_rows = 0, failed_candidates = 0;
    for (const auto& row : csv_rows(out + "/tune.csv")) failed_rows += row["status"] == "failed";
    for (const auto& row : csv_rows(out + "/candidates.csv")) {
      if (row["status"] != "failed") continue;
      ++failed_candidates;
      QVERIFY(row["behavior.params.a"].toDouble() > 7);
    }
    QVERIFY2(failed_rows > 0 && failed_candidates > 0, describe(r));
    QVERIFY(winner(out)["behavior.params.a"].toDouble() <= 7);
  }

  // `salsa plot OUT` on a tune folder redraws the tune's plots from candidates.csv and
  // tune_plots.json alone: deleted PNGs come back byte for byte (the tune draws them the same way),
  // with rings for candidates dropped by racing and a log-scale parameter (b); a folder without the record
  // is refused in one line naming it.
  void plot_redraws_a_tune_folder() {
    QTemporaryDir dir;
    const QString out = dir.filePath("out");
    QJsonObject t = bowl_tune("random", 80, 6, true);
    t["racing"] = QJsonObject{{"level", 0.05}, {"first_test", 3}};
    const CliResult r = run_salsa({"tune", write_tune(dir, t), "--out", out, "--plugin-dir", bowl_dir()});
    QVERIFY2(r.exit_code == 0, describe(r));
    QVERIFY2(read_file(out + "/candidates.csv").contains(",dropped,"), "no candidate dropped: the rings go untested");
    const QStringList pngs = QDir(out + "/plots").entryList({"*.png"});
    QCOMPARE(pngs, (QStringList{"convergence.png", "parameter_behavior.params.a.png", "parameter_behavior.params.b.png",
                                "parameter_behavior.params.c.png"}));
    std::map<QString, QByteArray> drawn;
    for (const QString& png : pngs) {
      drawn[png] = read_file(out + "/plots/" + png);
      QVERIFY(QFile::remove(out + "/plots/" + png));
    }
    const CliResult again = run_salsa({"plot", out});
    QVERIFY2(again.exit_code == 0 && again.out.contains("tune plots in " + out + "/plots"), describe(again));
    QCOMPARE(QDir(out + "/plots").entryList({"*.png"}), pngs);
    for (const auto& [png, bytes] : drawn) QVERIFY2(read_file(out + "/plots/" + png) == bytes, qPrintable(png));
    QVERIFY(QFile::remove(out + "/tune_plots.json"));
    const CliResult refused = run_salsa({"plot", out});
    QVERIFY2(refused.exit_code == 2 && non_empty_lines(refused.err).size() == 1 && refused.err.contains(out + "/tune_plots.json: cannot open file"),
             describe(refused));
  }

  void two_objectives_give_a_pareto_front() {
    QTemporaryDir dir;
    const QString out = dir.filePath("out");
    QJsonObject t = bowl_tune("nsga2", 96);
    t.remove("objective");
    t["objectives"] = QJsonArray{QJsonObject{{"column", "mean_speed"}, {"goal", "max"}},
                                 QJsonObject{{"column", "max_speed"}, {"goal", "min"}}};
    t["population"] = 8;
    const CliResult r = run_salsa({"tune", write_tune(dir, t), "--out", out, "--plugin-dir", bowl_dir()});
    QVERIFY2(r.exit_code == 0, describe(r));
    QVERIFY2(r.out.contains("Pareto front: c"), describe(r));
    for (const char* png : {"pareto.png", "convergence.png", "parameter_behavior.params.a.png"})
      QVERIFY2(QFileInfo(out + "/plots/" + png).size() > 1000, png);
    // salsa plot OUT draws the front again, the same bytes.
    const QByteArray pareto = read_file(out + "/plots/pareto.png");
    QVERIFY(QFile::remove(out + "/plots/pareto.png"));
    const CliResult again = run_salsa({"plot", out});
    QVERIFY2(again.exit_code == 0, describe(again));
    QVERIFY(read_file(out + "/plots/pareto.png") == pareto);
    // front/<rank>.json: every member of the front, in the report's order; 1 is best.json's candidate.
    const QString listed = r.out.section("Pareto front:", 1).section('\n', 0, 0);
    const QStringList members = listed.split(' ', Qt::SkipEmptyParts);
    QVERIFY2(members.size() >= 2, qPrintable(listed));
    QCOMPARE(QDir(out + "/front").entryList(QDir::Files), [&] {
      QStringList files;
      for (qsizetype i = 1; i <= members.size(); ++i) files << QString("%1.json").arg(i);
      std::sort(files.begin(), files.end());
      return files;
    }());
    auto test_of = [](const QString& file) {
      QJsonObject queue = QJsonDocument::fromJson(read_file(file)).object();
      QJsonObject test = queue["tests"].toArray().at(0).toObject();
      test.remove("name");
      queue["tests"] = QJsonArray{test};
      return queue;
    };
    QCOMPARE(test_of(out + "/front/1.json"), test_of(out + "/best.json"));
    // The last member replays on the tuning worlds to the data of its own evaluations.
    const QString last = QString::number(members.size());
    const CliResult replay = run_salsa({"run", out + "/front/" + last + ".json", "--out", dir.filePath("replay"), "--plugin-dir", bowl_dir(), "--no-plots"});
    QVERIFY2(replay.exit_code == 0, describe(replay));
    for (int w = 0; w < 2; ++w) {
      const QString evaluation = QString("%1/c%2_w%3/summary.csv").arg(out).arg(members.last().mid(1).toInt(), 4, 10, QChar('0')).arg(w, 2, 10, QChar('0'));
      QVERIFY2(read_file(dir.filePath(QString("replay/front_%1_r%2/summary.csv").arg(last).arg(w))) == read_file(evaluation), qPrintable(evaluation));
    }
  }

  // "world": a queue's test under one of its conditions is the tune's test, exactly: the defaults'
  // evaluation on world w is the queue's repeat w (config.json but for the name, and the data), and
  // another candidate's differs only in the tuned parameters.
  void a_world_from_a_queue_is_the_queues_test_under_its_condition() {
    QTemporaryDir dir;
    QVERIFY(QDir(dir.path()).mkpath("queues"));
    const QString queue = dir.filePath("queues/q.json");
    QVERIFY(write_file(queue, QJsonDocument(bowl_queue()).toJson()));
    QJsonObject t = bowl_tune("random", 8, 2);
    t.remove("test");
    t.remove("seed");  // the queue's seed: world w is its repeat w
    t["world"] = QJsonObject{{"queue", "queues/q.json"}, {"condition", "crowd"}, {"test", "bowl"}};
    t["validation"] = QJsonObject{{"worlds", 1}, {"candidates", 1}};
    const QString out = dir.filePath("out");
    const CliResult r = tune(write_tune(dir, t), out);
    QVERIFY2(r.exit_code == 0, describe(r));
    QVERIFY2(read_file(out + "/report.txt").contains("world: " + queue.toUtf8() + ": test bowl, condition crowd"), describe(r));
    const CliResult q = run_salsa({"run", queue, "--out", dir.filePath("queue-out"), "--plugin-dir", bowl_dir(), "--no-plots"});
    QVERIFY2(q.exit_code == 0, describe(q));
    const CliResult expand = run_salsa({"queue", "expand", queue, "--plugin-dir", bowl_dir()});
    QVERIFY2(expand.exit_code == 0, describe(expand));
    const auto rows = csv_rows(out + "/tune.csv");
    for (int w = 0; w < 2; ++w) {
      const QString queued = dir.filePath(QString("queue-out/bowl_crowd_r%1").arg(w));
      const QString tuned = QString("%1/c0000_w%2").arg(out).arg(w, 2, 10, QChar('0'));
      const QJsonObject config = config_without(tuned, {"name"});
      QCOMPARE(config, config_without(queued, {"name"}));
      QCOMPARE(config["drones"].toInt(), 8);  // the condition's, with its change and its wind
      QVERIFY(config.contains("changes") && config.contains("wind"));
      for (const char* f : {"summary.csv", "outcome.csv", "drones.csv"})
        if (QFileInfo::exists(tuned + "/" + f)) QVERIFY2(read_file(tuned + "/" + f) == read_file(queued + "/" + f), f);
      // The seed salsa queue expand lists for the queue's test of repeat w.
      const QString seed = QString::number(static_cast<qint64>(config["seed"].toDouble()));
      bool listed = false;
      for (const QString& line : non_empty_lines(expand.out))
        listed |= line.startsWith(QString("bowl_crowd_r%1 ").arg(w)) && line.contains("seed=" + seed);
      QVERIFY2(listed, qPrintable(expand.out));
      for (const auto& row : rows)
        if (row["world"].toInt() == w) QCOMPARE(row["seed"], seed);
    }
    for (const auto& row : rows) QCOMPARE(row["status"], QString("ok"));
    // Another candidate: the same world, its own parameters.
    QJsonObject other = config_without(out + "/c0001_w00", {"name", "behavior"});
    QCOMPARE(other, config_without(dir.filePath("queue-out/bowl_crowd_r0"), {"name", "behavior"}));
    QVERIFY(config_without(out + "/c0001_w00", {})["behavior"] != config_without(out + "/c0000_w00", {})["behavior"]);
  }

  // --time shortens every evaluation (timed changes past it dropped, as salsa run --time does),
  // --evaluations caps their count; both are recorded, and --resume with other values is refused.
  void time_and_evaluations_from_the_command_line() {
    QTemporaryDir dir;
    QJsonObject t = bowl_tune("random", 40, 2);
    QJsonObject test = t["test"].toObject();
    test["changes"] = QJsonArray{QJsonObject{{"time", 0.2}, {"set", QJsonObject{{"drones", 4}}}},
                                 QJsonObject{{"time", 0.8}, {"set", QJsonObject{{"drones", 3}}}}};
    t["test"] = test;
    const QString file = write_tune(dir, t);
    const QString out = dir.filePath("out");
    const QStringList quick{"--time", "0.5", "--evaluations", "6"};
    const CliResult r = tune(file, out, quick);
    QVERIFY2(r.exit_code == 0, describe(r));
    int tuning = 0, all = 0;
    for (const auto& row : csv_rows(out + "/tune.csv")) {
      tuning += row["phase"] == "tuning";
      ++all;
      const QJsonObject config = config_without(out + "/" + row["test"], {});
      QCOMPARE(config["time"].toDouble(), 0.5);
      QCOMPARE(config["changes"].toArray().size(), 1);  // the change at 0.8 s is past the end
    }
    QCOMPARE(tuning, 6);
    QVERIFY(all > tuning);  // and the validation
    const QJsonObject record = QJsonDocument::fromJson(read_file(out + "/tune.json")).object();
    QCOMPARE(record["command_line"].toObject(), (QJsonObject{{"time", 0.5}, {"evaluations", 6}}));
    QCOMPARE(record["budget"].toObject()["evaluations"].toInt(), 6);
    QCOMPARE(record["test"].toObject()["time"].toDouble(), 0.5);
    QVERIFY2(read_file(out + "/report.txt").contains("--time 0.5 --evaluations 6"), describe(r));

    const QByteArray csv = read_file(out + "/tune.csv");
    for (const QStringList& other : {QStringList{"--time", "1", "--evaluations", "6"}, QStringList{}}) {
      const CliResult again = tune(file, out, QStringList{"--resume"} + other);
      QCOMPARE(again.exit_code, 2);
      const QStringList lines = non_empty_lines(again.err);
      QCOMPARE(lines.size(), 1);
      QVERIFY2(lines[0].contains(out + ": holds a tune run with --time 0.5 --evaluations 6, and this one has " +
                                 (other.isEmpty() ? QString("neither --time nor --evaluations") : QString("--time 1 --evaluations 6"))),
               describe(again));
    }
    const CliResult same = tune(file, out, QStringList{"--resume"} + quick);
    QVERIFY2(same.exit_code == 0, describe(same));
    QVERIFY(read_file(out + "/tune.csv") == csv);
  }

  void bad_input_is_refused_before_anything_runs_data() {
    QTest::addColumn<QString>("path");   // the key to change, "a.b" for nested
    QTest::addColumn<QString>("value");  // JSON
    QTest::addColumn<QString>("expected");
    QTest::newRow("unknown parameter") << "parameters" << R"({"behavior.params.zzz": {}})" << "parameters.behavior.params.zzz: unknown parameter of behavior 'test_bowl'";
    QTest::newRow("not a number") << "parameters" << R"({"behavior.name": {}})" << "parameters.behavior.name: not a number of the test";
    QTest::newRow("outside the declared range") << "parameters" << R"({"behavior.params.a": {"min": -1}})" << "parameters.behavior.params.a.min: -1 is outside the declared range (allowed: [0, 10])";
    QTest::newRow("empty range") << "parameters" << R"({"behavior.params.a": {"min": 5, "max": 5}})" << "parameters.behavior.params.a: [5, 5] is an empty range";
    QTest::newRow("zero budget") << "budget" << R"({"evaluations": 0})" << "budget.evaluations: 0 is out of range (allowed: whole number in [1, 1000000000])";
    QTest::newRow("no such column") << "objective" << R"({"column": "trees"})" << "objective.column: \"trees\" is not a column of outcome.csv or summary.csv";
    QTest::newRow("unknown algorithm") << "algorithm" << R"("simplex")" << "algorithm: \"simplex\" is not an algorithm (allowed: random, lhs, grid, cmaes";
  }
  void bad_input_is_refused_before_anything_runs() {
    QFETCH(QString, path);
    QFETCH(QString, value);
    QFETCH(QString, expected);
    QTemporaryDir dir;
    QJsonObject t = bowl_tune("cmaes", 40);
    t[path] = QJsonDocument::fromJson("[" + value.toUtf8() + "]").array().at(0);
    const QString file = write_tune(dir, t);
    const CliResult r = tune(file, dir.filePath("out"));
    QCOMPARE(r.exit_code, 2);
    const QStringList lines = non_empty_lines(r.err);
    QCOMPARE(lines.size(), 1);
    QVERIFY2(lines[0].contains(file + ": " + expected), describe(r));
    QVERIFY(!QDir(dir.filePath("out")).exists());
  }
};

QTEST_GUILESS_MAIN(TestTune)
#include "test_tune.moc"
