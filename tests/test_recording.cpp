// A finished test read back for replay and export (load_recording): from drones.csv it gives what the
// run wrote, value for value (positions, groups, statuses, state columns, found times, the map); it
// refuses what is not a finished test, or a cut copy, in one line, and writes nothing.
#include <QtTest>

#include <cmath>
#include <map>

#include "common.hpp"
#include "salsa/core/files/input_error.hpp"
#include "salsa/core/replay/recording.hpp"

using namespace salsa;
using namespace salsa_test;

class TestRecording : public QObject {
  Q_OBJECT
  QTemporaryDir dir_;
  QString test_;  ///< groups-forest run for 20 s with two state columns in drones.csv

  static std::string refusal(const fs::path& folder) {
    try {
      load_recording(folder);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }

 private Q_SLOTS:
  void initTestCase() {
    const CliResult r = run_salsa({"run", q(source_dir() / "examples/groups-forest.json"), "--out", dir_.path() + "/out", "--time", "20",
                                   "--drone-columns", "battery_left,steering"});
    QVERIFY2(r.exit_code == 0, qPrintable(r.err));
    test_ = dir_.path() + "/out/groups-forest";
  }

  void drones_csv_value_for_value() {
    const Recording rec = load_recording(test_.toStdString());
    QCOMPARE(rec.source.filename().string(), std::string("drones.csv"));
    QCOMPARE(rec.test_name, std::string("groups-forest"));
    QCOMPARE(rec.seed, std::uint64_t{7});
    QCOMPARE(rec.groups.size(), std::size_t{2});
    QCOMPARE(rec.groups[0].name, std::string("surveyors"));
    QCOMPARE(rec.groups[0].radius, 2.5);
    QCOMPARE(rec.groups[0].base.x, 40.0);
    // The inspectors start around the map's own spawn (the forest's centre, 250, 250), which map.json does
    // not keep when the first group has a point of its own: their start gives it.
    QVERIFY2(salsa::distance(rec.groups[1].base, {250, 250}) < 1, qPrintable(QString("%1, %2").arg(rec.groups[1].base.x).arg(rec.groups[1].base.y)));
    QCOMPARE(rec.drones, std::size_t{18});
    QCOMPARE(rec.frames(), std::size_t{21});  // 0, 1, …, 20 s
    QCOMPARE(rec.times.front(), 0.0);
    QCOMPARE(rec.times.back(), 20.0);
    for (const char* name : {"position", "velocity", "group", "status", "camera_works", "energy_used", "battery_left", "steering"})
      QVERIFY2(rec.column(name), name);
    QCOMPARE(rec.column("position")->unit, std::string("m"));
    QCOMPARE(rec.column("steering")->width, std::size_t{2});

    const auto rows = rows_of(test_ + "/drones.csv");
    const std::size_t t = column(rows, "time"), id = column(rows, "id"), x = column(rows, "x"), vy = column(rows, "vy"), group = column(rows, "group"),
                      status = column(rows, "status"), energy = column(rows, "energy_used_Wh"), battery = column(rows, "battery_left"),
                      steer_y = column(rows, "steering_y");
    std::size_t statuses = 0;
    for (std::size_t k = 1; k < rows.size(); ++k) {
      const auto& row = rows[k];
      const std::size_t f = rec.frame_at(std::stod(row[t])), i = std::stoul(row[id]);
      QCOMPARE(rec.times[f], std::stod(row[t]));
      QCOMPARE(rec.position(f, i).x, std::stod(row[x]));
      QCOMPARE(rec.at(*rec.column("velocity"), f, i, 1), std::stod(row[vy]));
      QCOMPARE(rec.groups[static_cast<std::size_t>(rec.at(*rec.column("group"), f, i))].name, row[group]);
      const std::map<std::string, int> code{{"flying", 0}, {"camera_failed", 0}, {"landed", 1}, {"failed", 2}};
      QCOMPARE(int{rec.status(f, i)}, code.at(row[status]));
      QCOMPARE(rec.at(*rec.column("camera_works"), f, i), row[status] == "camera_failed" ? 0.0 : 1.0);
      statuses += row[status] != "flying";
      QCOMPARE(rec.at(*rec.column("energy_used"), f, i), std::stod(row[energy]) * 3600);
      QCOMPARE(rec.at(*rec.column("battery_left"), f, i), std::stod(row[battery]));  // written shortest-exact
      QCOMPARE(rec.at(*rec.column("steering"), f, i, 1), std::stod(row[steer_y]));
    }
    QCOMPARE(rows.size() - 1, rec.frames() * rec.drones);  // no drone removed: a row each, every frame

    // Targets: where they are and when each was found, as targets.csv says; the map as map.json.
    const auto targets = rows_of(test_ + "/targets.csv");
    QCOMPARE(rec.targets.size(), targets.size() - 1);
    QCOMPARE(rec.target_radius, 5.0);
    const std::size_t found_time = column(targets, "found_time");
    for (double at : {0.0, 5.0, 20.0}) {
      std::size_t found = 0;
      for (std::size_t k = 1; k < targets.size(); ++k) found += !targets[k][found_time].empty() && std::stod(targets[k][found_time]) <= at;
      QCOMPARE(rec.found_by_time(at), found);
    }
    QVERIFY(rec.found_by_time(20) > 0);
    QCOMPARE(rec.map.bounds.max.x - rec.map.bounds.min.x, 500.0);
    QVERIFY(!rec.map.obstacles.empty());
    Q_UNUSED(statuses);
  }

  void frame_at_is_the_frame_shown_at_a_time() {
    const Recording rec = load_recording(test_.toStdString());
    QCOMPARE(rec.frame_at(-1), std::size_t{0});
    QCOMPARE(rec.frame_at(0.5), std::size_t{0});
    QCOMPARE(rec.frame_at(1), std::size_t{1});
    QCOMPARE(rec.frame_at(1e9), rec.frames() - 1);
  }

  void refuses_in_one_line_and_writes_nothing() {
    const auto before = snapshot(dir_.path());
    auto one_line = [](const std::string& s) { return !s.empty() && s.find('\n') == std::string::npos; };
    const std::string missing = refusal(dir_.path().toStdString() + "/nowhere");
    QVERIFY2(one_line(missing) && missing.find("not a folder") != std::string::npos, missing.c_str());
    const std::string queue = refusal(dir_.path().toStdString() + "/out");
    QVERIFY2(one_line(queue) && queue.find("not a finished test") != std::string::npos, queue.c_str());
    QCOMPARE(snapshot(dir_.path()), before);

    // A copy whose drones.csv was cut: its size is not the manifest's.
    const QString copy = dir_.path() + "/cut";
    QDir().mkpath(copy);
    for (const QString& f : QDir(test_).entryList(QDir::Files | QDir::Hidden)) QFile::copy(test_ + "/" + f, copy + "/" + f);
    QByteArray csv = read_file(copy + "/drones.csv");
    QVERIFY(write_file(copy + "/drones.csv", csv.left(csv.size() / 2)));
    const std::string cut = refusal(copy.toStdString());
    QVERIFY2(one_line(cut) && cut.find("drones.csv") != std::string::npos && cut.find("manifest") != std::string::npos, cut.c_str());

    // A test run without drones.csv or archive has nothing to replay.
    QFile::remove(copy + "/drones.csv");
    const std::string none = refusal(copy.toStdString());
    QVERIFY2(one_line(none) && none.find("drones.csv") != std::string::npos, none.c_str());

    // A bad status in drones.csv names the line and what is allowed.
    QVERIFY(write_file(copy + "/drones.csv", "time,id,x,y,vx,vy,group,status,energy_used_Wh\n0,0,1,2,0,0,surveyors,dancing,0\n"));
    const QString manifest = copy + "/manifest.json";
    QVERIFY(write_file(manifest, "{\"files\": {}}"));
    const std::string status = refusal(copy.toStdString());
    QVERIFY2(one_line(status) && status.find("line 2") != std::string::npos && status.find("allowed") != std::string::npos, status.c_str());
  }
};

QTEST_GUILESS_MAIN(TestRecording)
#include "test_recording.moc"
