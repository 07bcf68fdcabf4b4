// salsa export --mcap read back by an independent reader: @mcap/core under node (tests/mcap-reader,
// installed by scripts/setup.sh) reads the file from start to end and through its summary, and what
// it decodes is the run: a message per topic and frame at the run's times, each drone's pose as in
// drones.csv, each target turning green at its found time, the map's bounds. Refusals: one line, exit 2.
#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <QtTest>

#include <cmath>
#include <map>
#include <set>

#include "common.hpp"
#include "salsa/core/replay/recording.hpp"

using namespace salsa;
using namespace salsa_test;

class TestExportMcap : public QObject {
  Q_OBJECT
  QTemporaryDir dir_;
  QString test_, mcap_;
  QJsonObject read_;  ///< what read.mjs printed

  /// read.mjs's output for `file`, or the test fails saying why (node or its package missing included).
  static QJsonObject read_back(const QString& file) {
    const QString node = QStandardPaths::findExecutable("node");
    if (node.isEmpty()) qFatal("node is not installed: scripts/setup.sh installs it (Debian package nodejs)");
    const fs::path reader = source_dir() / "tests/mcap-reader";
    if (!fs::exists(reader / "node_modules/@mcap/core/package.json"))
      qFatal("@mcap/core is not installed in %s: run scripts/setup.sh (npm ci --prefix tests/mcap-reader)", reader.c_str());
    const CliResult r = run_program(node, {q(reader / "read.mjs"), file});
    if (r.exit_code != 0) qFatal("read.mjs could not read %s: %s", qPrintable(file), describe(r).constData());
    return QJsonDocument::fromJson(r.out.toUtf8()).object();
  }

  QJsonArray messages(const QString& topic) const {
    QJsonArray out;
    for (const auto m : read_[u"messages"].toArray())
      if (m[u"topic"].toString() == topic) out.append(m);
    return out;
  }
  static qint64 ns(double t) { return std::llround(t * 1e9); }
  static std::uint32_t rgb(const QJsonValue& c) {
    auto byte = [&](const char* k) { return static_cast<std::uint32_t>(std::lround(c[k].toDouble() * 255)); };
    return byte("r") << 16 | byte("g") << 8 | byte("b");
  }

 private Q_SLOTS:
  void initTestCase() {
    CliResult r = run_salsa({"run", q(source_dir() / "examples/groups-forest.json"), "--out", dir_.path() + "/out", "--time", "20"});
    QVERIFY2(r.exit_code == 0, describe(r));
    test_ = dir_.path() + "/out/groups-forest";
    mcap_ = dir_.path() + "/run.mcap";
    r = run_salsa({"export", test_, "--mcap", mcap_});
    QVERIFY2(r.exit_code == 0, describe(r));
    read_ = read_back(mcap_);
  }

  void both_readers_read_every_message() {
    const Recording rec = load_recording(test_.toStdString());
    // /drones and /drones/poses at every frame, /map once, /targets at the first frame and each with a find.
    qint64 finds = 1;
    for (std::size_t f = 1; f < rec.frames(); ++f) finds += rec.found_by_time(rec.times[f]) != rec.found_by_time(rec.times[f - 1]);
    QCOMPARE(messages("/targets").size(), finds);
    const qint64 expected = 2 * static_cast<qint64>(rec.frames()) + 1 + finds;
    QCOMPARE(read_[u"messages"].toArray().size(), expected);
    QCOMPARE(read_[u"stream"][u"messages"].toInt(), expected);
    QVERIFY(read_[u"stream"][u"dataSectionCrcMatches"].toBool());
    // Every message is what its schema declares: no undeclared field, no value of another type.
    QVERIFY2(read_[u"schemaDepartures"].toArray().isEmpty(), QJsonDocument(read_[u"schemaDepartures"].toArray()).toJson().constData());
    QCOMPARE(read_[u"statistics"][u"messageCount"].toString().toLongLong(), expected);
    QCOMPARE(read_[u"statistics"][u"channelMessageCounts"][u"/drones"].toString().toLongLong(), static_cast<qint64>(rec.frames()));
    QCOMPARE(read_[u"statistics"][u"channelMessageCounts"][u"/map"].toString(), QString("1"));
    QVERIFY(read_[u"chunkIndexes"].toInt() >= 1);
    QCOMPARE(read_[u"statistics"][u"chunkCount"].toInt(), read_[u"chunkIndexes"].toInt());
    QCOMPARE(read_[u"stream"][u"records"][u"ChunkIndex"].toInt(), read_[u"chunkIndexes"].toInt());
    // The summary is indexed by opcode: schemas, channels, statistics, chunk indexes.
    for (int opcode : {0x03, 0x04, 0x08, 0x0B}) QVERIFY2(read_[u"summaryOffsets"].toArray().contains(opcode), qPrintable(QString::number(opcode)));
    QVERIFY(read_[u"header"][u"library"].toString().startsWith("salsa "));

    QStringList schemas, topics;
    for (const auto s : read_[u"schemas"].toArray()) {
      QCOMPARE(s[u"encoding"].toString(), QString("jsonschema"));
      QCOMPARE(s[u"schema"][u"title"].toString(), s[u"name"].toString());  // the schema is JSON and names itself
      QVERIFY2(s[u"problems"].toArray().isEmpty(), QJsonDocument(s[u"problems"].toArray()).toJson().constData());
      schemas << s[u"name"].toString();
    }
    QCOMPARE(schemas, QStringList({"foxglove.SceneUpdate", "foxglove.PosesInFrame"}));
    for (const auto c : read_[u"channels"].toArray()) {
      QCOMPARE(c[u"messageEncoding"].toString(), QString("json"));
      topics << c[u"topic"].toString();
    }
    QCOMPARE(topics, QStringList({"/map", "/targets", "/drones", "/drones/poses"}));

    // A seek through the indexes: the last second's messages, as many as the full read has there.
    const qint64 end = read_[u"statistics"][u"messageEndTime"].toString().toLongLong();
    qint64 late = 0;
    for (const auto m : read_[u"messages"].toArray()) late += m[u"logTime"].toString().toLongLong() >= end - 1'000'000'000;
    QCOMPARE(read_[u"lastSecondMessages"].toInt(), late);
    QVERIFY(late > 0 && late < expected);
  }

  void times_are_the_runs() {
    const Recording rec = load_recording(test_.toStdString());
    QCOMPARE(read_[u"statistics"][u"messageStartTime"].toString().toLongLong(), ns(rec.times.front()));
    QCOMPARE(read_[u"statistics"][u"messageEndTime"].toString().toLongLong(), ns(rec.times.back()));
    QCOMPARE(messages("/map").size(), 1);
    QCOMPARE(messages("/map")[0][u"logTime"].toString().toLongLong(), ns(rec.times.front()));
    for (const QString topic : {"/drones", "/drones/poses"}) {
      const QJsonArray ms = messages(topic);
      QCOMPARE(ms.size(), static_cast<qsizetype>(rec.frames()));
      for (qsizetype f = 0; f < ms.size(); ++f) {
        const qint64 t = ns(rec.times[static_cast<std::size_t>(f)]);
        QCOMPARE(ms[f][u"logTime"].toString().toLongLong(), t);
        QCOMPARE(ms[f][u"publishTime"].toString().toLongLong(), t);
        QCOMPARE(ms[f][u"sequence"].toInt(), f);
        const QJsonValue stamp = topic == "/drones" ? ms[f][u"data"][u"entities"][0][u"timestamp"] : ms[f][u"data"][u"timestamp"];
        QCOMPARE(stamp[u"sec"].toInteger() * 1'000'000'000 + stamp[u"nsec"].toInteger(), t);
      }
    }
  }

  void poses_are_drones_csv() {
    const Recording rec = load_recording(test_.toStdString());
    const QJsonArray poses = messages("/drones/poses"), scenes = messages("/drones");
    const auto rows = rows_of(test_ + "/drones.csv");
    const std::size_t t = column(rows, "time"), id = column(rows, "id"), x = column(rows, "x"), y = column(rows, "y"), vx = column(rows, "vx"),
                      vy = column(rows, "vy");
    for (std::size_t k = 1; k < rows.size(); ++k) {
      const auto& row = rows[k];
      const std::size_t f = rec.frame_at(std::stod(row[t]));
      const QJsonValue pose = poses[static_cast<qsizetype>(f)][u"data"][u"poses"][static_cast<qsizetype>(std::stoul(row[id]))];
      QCOMPARE(pose[u"position"][u"x"].toDouble(), std::stod(row[x]));
      QCOMPARE(pose[u"position"][u"y"].toDouble(), std::stod(row[y]));
      const double heading = std::atan2(std::stod(row[vy]), std::stod(row[vx]));
      if (std::stod(row[vx]) != 0 || std::stod(row[vy]) != 0)
        QVERIFY(std::abs(2 * std::atan2(pose[u"orientation"][u"z"].toDouble(), pose[u"orientation"][u"w"].toDouble()) - heading) < 1e-9 ||
                std::abs(std::abs(heading) - M_PI) < 1e-9);
      QCOMPARE(poses[static_cast<qsizetype>(f)][u"data"][u"frame_id"].toString(), QString("world"));
    }
    // The scene: each group an entity of spheres in its colour (a landed drone faded, a failed one
    // black), the group's drones in id order.
    const RecordedColumn& group = *rec.column("group");
    std::size_t stopped = 0;
    for (std::size_t f = 0; f < rec.frames(); ++f) {
      const QJsonArray entities = scenes[static_cast<qsizetype>(f)][u"data"][u"entities"].toArray();
      QCOMPARE(entities.size(), static_cast<qsizetype>(rec.groups.size()));
      for (std::size_t g = 0; g < rec.groups.size(); ++g) {
        const QJsonValue e = entities[static_cast<qsizetype>(g)];
        QCOMPARE(e[u"id"].toString(), QString::fromStdString("drones/" + rec.groups[g].name));
        const QJsonArray spheres = e[u"spheres"].toArray();
        qsizetype k = 0;
        for (std::size_t i = 0; i < rec.drones; ++i) {
          if (rec.at(group, f, i) != static_cast<double>(g)) continue;
          QVERIFY(k < spheres.size());
          const QJsonValue s = spheres[k++];
          QCOMPARE(s[u"pose"][u"position"][u"x"].toDouble(), rec.position(f, i).x);
          QCOMPARE(s[u"pose"][u"position"][u"z"].toDouble(), rec.groups[g].radius);  // resting on the ground
          QCOMPARE(s[u"size"][u"x"].toDouble(), 2 * rec.groups[g].radius);
          const std::uint8_t status = rec.status(f, i);
          QCOMPARE(rgb(s[u"color"]), status == 2 ? 0u : g == 0 ? 0xE69F00u : 0x0072B2u);  // the desktop's group colours
          QCOMPARE(s[u"color"][u"a"].toDouble(), status == 1 ? 0.35 : 1.0);
          stopped += status != 0;
        }
        QCOMPARE(k, spheres.size());
      }
    }
    QVERIFY(stopped > 0);  // the run has landed or failed drones to show
  }

  void targets_turn_green_when_found() {
    // At every frame, the last /targets message sent by then (what a viewer shows) colours each target
    // as targets.csv's found time says.
    const Recording rec = load_recording(test_.toStdString());
    const auto rows = rows_of(test_ + "/targets.csv");
    const std::size_t found_time = column(rows, "found_time"), tx = column(rows, "x");
    const QJsonArray sent = messages("/targets");
    std::size_t switched = 0;
    std::vector<bool> was_found(rows.size(), false);
    qsizetype last = -1;
    for (double t : rec.times) {
      while (last + 1 < sent.size() && sent[last + 1][u"logTime"].toString().toLongLong() <= ns(t)) ++last;
      QVERIFY(last >= 0);
      const QJsonValue targets = sent[last][u"data"][u"entities"][0];
      QCOMPARE(targets[u"id"].toString(), QString("targets"));
      const QJsonArray cylinders = targets[u"cylinders"].toArray();
      QCOMPARE(cylinders.size(), static_cast<qsizetype>(rows.size() - 1));
      for (std::size_t k = 1; k < rows.size(); ++k) {
        const bool found = !rows[k][found_time].empty() && std::stod(rows[k][found_time]) <= t;
        const QJsonValue c = cylinders[static_cast<qsizetype>(k - 1)];
        QCOMPARE(c[u"pose"][u"position"][u"x"].toDouble(), std::stod(rows[k][tx]));
        QCOMPARE(rgb(c[u"color"]), found ? 0x2e9e48u : 0x9a9a9au);
        switched += found && !was_found[k] && t > rec.times.front();
        was_found[k] = found;
      }
    }
    QVERIFY(switched > 0);  // some target was found during the run, not before it
  }

  void map_is_its_walls() {
    const Recording rec = load_recording(test_.toStdString());
    const QJsonValue map = messages("/map")[0][u"data"][u"entities"][0];
    QCOMPARE(map[u"frame_id"].toString(), QString("world"));
    const QJsonArray lines = map[u"lines"].toArray();
    QCOMPARE(lines.size(), 2);  // the bounds, then every obstacle's outline as segments
    QCOMPARE(lines[0][u"type"].toInt(), 1);  // LINE_LOOP
    QCOMPARE(lines[0][u"points"][2][u"x"].toDouble(), rec.map.bounds.max.x);
    QCOMPARE(lines[0][u"points"][2][u"y"].toDouble(), rec.map.bounds.max.y);
    std::size_t edges = 0;
    for (const auto& p : rec.map.obstacles) edges += p.size();
    QCOMPARE(lines[1][u"type"].toInt(), 2);  // LINE_LIST
    QCOMPARE(lines[1][u"points"].toArray().size(), static_cast<qsizetype>(2 * edges));
  }

  void removed_and_added_drones() {
    // 6 drones, 3 from 2 s, 5 from 4 s (two new ids): each frame shows the drones drones.csv has then.
    const QString file = dir_.path() + "/drop.json";
    QVERIFY(write_file(file, R"({"name": "drop", "behavior": {"name": "random_walk"}, "drones": 6,
      "map": {"name": "forest", "params": {"size": 200}}, "targets": {"kind": "tree", "count": 50}, "time": 6, "seed": 3,
      "changes": [{"time": 2, "set": {"drones": 3}}, {"time": 4, "set": {"drones": 5}}]})"));
    CliResult r = run_salsa({"run", file, "--out", dir_.path() + "/drop"});
    QVERIFY2(r.exit_code == 0, describe(r));
    r = run_salsa({"export", dir_.path() + "/drop/drop", "--mcap", dir_.path() + "/drop.mcap"});
    QVERIFY2(r.exit_code == 0, describe(r));
    const QJsonObject read = read_back(dir_.path() + "/drop.mcap");
    QVERIFY(read[u"schemaDepartures"].toArray().isEmpty());
    std::map<qint64, std::vector<std::pair<double, double>>> by_time;  // ns → positions in id order
    const auto rows = rows_of(dir_.path() + "/drop/drop/drones.csv");
    const std::size_t t = column(rows, "time"), x = column(rows, "x"), y = column(rows, "y");
    for (std::size_t k = 1; k < rows.size(); ++k) by_time[ns(std::stod(rows[k][t]))].emplace_back(std::stod(rows[k][x]), std::stod(rows[k][y]));
    std::set<std::size_t> counts;
    for (const auto m : read[u"messages"].toArray()) {
      const qint64 at = m[u"logTime"].toString().toLongLong();
      if (m[u"topic"].toString() == u"/drones")
        QCOMPARE(m[u"data"][u"entities"][0][u"spheres"].toArray().size(), static_cast<qsizetype>(by_time.at(at).size()));
      if (m[u"topic"].toString() != u"/drones/poses") continue;
      const QJsonArray poses = m[u"data"][u"poses"].toArray();
      QCOMPARE(poses.size(), static_cast<qsizetype>(by_time.at(at).size()));
      for (qsizetype i = 0; i < poses.size(); ++i) {
        QCOMPARE(poses[i][u"position"][u"x"].toDouble(), by_time.at(at)[static_cast<std::size_t>(i)].first);
        QCOMPARE(poses[i][u"position"][u"y"].toDouble(), by_time.at(at)[static_cast<std::size_t>(i)].second);
      }
      counts.insert(static_cast<std::size_t>(poses.size()));
    }
    QCOMPARE(counts, (std::set<std::size_t>{3, 5, 6}));
  }

  void writing_again_replaces_the_file_whole() {
    const QString again = dir_.path() + "/again.mcap";
    QVERIFY(write_file(again, "an older file, longer than nothing"));
    const CliResult r = run_salsa({"export", test_, "--mcap", again});
    QVERIFY2(r.exit_code == 0, describe(r));
    QCOMPARE(read_file(again), read_file(mcap_));  // the same run, the same bytes
    QVERIFY(!QFile::exists(again + ".part"));
  }

  void refuses_in_one_line() {
    const auto before = snapshot(test_);
    const QString folder = dir_.path() + "/a-folder";
    QDir().mkpath(folder);
    for (const QString& bad : {dir_.path() + "/no/such/folder/run.mcap", folder, test_ + "/run.mcap"}) {
      const CliResult r = run_salsa({"export", test_, "--mcap", bad});
      QVERIFY2(r.exit_code == 2, describe(r));
      QCOMPARE(non_empty_lines(r.err).size(), 1);
      QVERIFY2(r.err.contains("--mcap") && r.err.contains(bad), describe(r));
    }
    QVERIFY(QDir(folder).isEmpty());
    QVERIFY(!QFile::exists(dir_.path() + "/no"));
    QCOMPARE(snapshot(test_), before);
  }
};

QTEST_GUILESS_MAIN(TestExportMcap)
#include "test_export_mcap.moc"
