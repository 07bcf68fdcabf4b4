// The trajectory archive (trajectories.nc, salsa/core/replay/archive.hpp): every column and attribute
// round-trips through read_archive (lengths and speeds to the millimetre, the rest exactly), a run's
// archive holds the columns it should and agrees with its drones.csv value for value (and is
// what load_recording and salsa export read), the choice in the test file and on the command line (and
// --resume's check of it), and a damaged, newer or incomplete archive is refused with one line naming
// the file, without writing anything.
#include <netcdf.h>

#include <charconv>
#include <cmath>
#include <fstream>

#include "salsa/core/files/csv_writer.hpp"  // WriteError
#include "salsa/core/files/input_error.hpp"
#include "salsa/core/replay/archive.hpp"
#include "salsa/core/replay/recording.hpp"
#include "common.hpp"

using namespace salsa_test;
using salsa::RecordedColumn;
using salsa::Recording;
using salsa::StateColumn;

namespace {

constexpr double nan = std::numeric_limits<double>::quiet_NaN();

/// A synthetic run: `base` drones, `grown` from frame `grow_at` (a timed change adds drones), drone 1
/// removed from frame 1, a "wind" column from frame `wind_from` on (a model that starts later).
struct Synthetic {
  std::size_t frames = 4, base = 3, grown = 4, grow_at = 2, wind_from = 2;
  std::size_t hint = 0;  ///< ArchiveProvenance::drones

  std::size_t drones(std::size_t f) const { return f >= grow_at ? grown : base; }
  static double time(std::size_t f) { return 0.25 * static_cast<double>(f); }
  bool removed(std::size_t f, std::size_t i) const { return i == 1 && f >= 1; }
  /// Column `c`'s value k of drone i at frame f as written: doubles with all their digits.
  static double value(const std::string& c, std::size_t f, std::size_t i, std::size_t k) {
    const double fi = static_cast<double>(f), ii = static_cast<double>(i), kk = static_cast<double>(k);
    if (c == "group") return static_cast<double>(i % 2);
    if (c == "status") return static_cast<double>((f + i) % 3);
    if (c == "rate") return 1.0 / (3.0 + fi + ii);
    return (1 + kk) * (std::sqrt(2.0) * fi + ii / 7.0) + (c == "velocity" ? 0.1 : c == "wind" ? 100 : c == "energy" ? 1e6 : 0);
  }
  /// What read_archive gives: the value (a length or speed in whole millimetres), its status for a
  /// removed drone, NaN where there is none.
  double expected(const std::string& c, std::size_t f, std::size_t i, std::size_t k) const {
    if (i >= drones(f) || (c == "wind" && f < wind_from)) return nan;
    if (removed(f, i)) return c == "status" ? 3 : nan;
    const bool packed = c == "position" || c == "velocity" || c == "wind";
    return packed ? std::nearbyint(value(c, f, i, k) / 1e-3) * 1e-3 : value(c, f, i, k);
  }

  /// Writes the run to `file` through ArchiveWriter.
  void write(const fs::path& file) const {
    salsa::ArchiveWriter w(file, {"synthetic", "9.8.7", "{\"name\": \"synthetic\"}\n", 9007199254740992ULL, 0.125, 0.25, {"scouts", "mappers"}, hint, {}});
    for (std::size_t f = 0; f < frames; ++f) {
      const std::size_t n = drones(f);
      std::vector<salsa::Vec2> position(n), velocity(n), wind(n);
      std::vector<std::uint32_t> group(n);
      std::vector<std::uint8_t> status(n);
      std::vector<double> energy(n), rate(n);
      for (std::size_t i = 0; i < n; ++i) {
        position[i] = {value("position", f, i, 0), value("position", f, i, 1)};
        velocity[i] = {value("velocity", f, i, 0), value("velocity", f, i, 1)};
        wind[i] = {value("wind", f, i, 0), value("wind", f, i, 1)};
        group[i] = static_cast<std::uint32_t>(value("group", f, i, 0));
        status[i] = removed(f, i) ? 3 : static_cast<std::uint8_t>(value("status", f, i, 0));
        energy[i] = value("energy", f, i, 0);
        rate[i] = value("rate", f, i, 0);
      }
      std::vector<StateColumn> columns{
          StateColumn::of("position", "m", "drone", "where the drone is", position),
          StateColumn::of("velocity", "m/s", "drone", "its ground velocity", velocity),
          StateColumn::of("group", "", "drone", "its group's index", group),
          StateColumn::of("status", "", "drone", "0 flying, 1 landed, 2 failed, 3 removed", status),
          StateColumn::of("energy", "J", "fleet", "energy drawn", energy),
          StateColumn::of("rate", "1/s", "plugin", "a rate", rate),
      };
      if (f >= wind_from) columns.push_back(StateColumn::of("wind", "m/s", "wind", "the wind it flew in", wind));
      w.frame(time(f), columns);
    }
    std::vector<salsa::TargetState> targets(3);
    targets[0].position = {1.5, -2.25}, targets[1].position = {1e3 / 3, 7};
    targets[2].position = {0, 0.1}, targets[2].found_time = 0.75, targets[2].found_by = 2;
    w.close(targets, 4.5);
  }

  /// Checks every value and attribute read_archive gives for the run written by write().
  void check(const Recording& r) const {
    QCOMPARE(r.test_name, std::string("synthetic"));
    QCOMPARE(r.salsa_version, std::string("9.8.7"));
    QCOMPARE(r.seed, 9007199254740992ULL);
    QCOMPARE(r.dt, 0.125);
    QCOMPARE(r.log_interval, 0.25);
    QCOMPARE(r.target_radius, 4.5);
    QCOMPARE(r.times.size(), frames);
    for (std::size_t f = 0; f < frames; ++f) QCOMPARE(r.times[f], time(f));
    QCOMPARE(r.drones, grown);
    struct Want {
      const char *name, *unit, *model;
      StateColumn::Type type;
      std::size_t width;
    };
    const Want wanted[] = {{"position", "m", "drone", StateColumn::Type::f64, 2}, {"velocity", "m/s", "drone", StateColumn::Type::f64, 2},
                           {"group", "", "drone", StateColumn::Type::u32, 1},     {"status", "", "drone", StateColumn::Type::u8, 1},
                           {"energy", "J", "fleet", StateColumn::Type::f64, 1},   {"rate", "1/s", "plugin", StateColumn::Type::f64, 1},
                           {"wind", "m/s", "wind", StateColumn::Type::f64, 2}};
    QCOMPARE(r.columns.size(), std::size(wanted));
    for (std::size_t c = 0; c < std::size(wanted); ++c) {
      const RecordedColumn& col = r.columns[c];
      QCOMPARE(col.name, std::string(wanted[c].name));
      QCOMPARE(col.unit, std::string(wanted[c].unit));
      QCOMPARE(col.model, std::string(wanted[c].model));
      QVERIFY(col.type == wanted[c].type);
      QCOMPARE(col.width, wanted[c].width);
      QVERIFY(!col.meaning.empty());
      QCOMPARE(col.values.size(), frames * grown * col.width);
      for (std::size_t f = 0; f < frames; ++f)
        for (std::size_t i = 0; i < grown; ++i)
          for (std::size_t k = 0; k < col.width; ++k) {
            const double want = expected(col.name, f, i, k), got = col.values[(f * grown + i) * col.width + k];
            if (std::isnan(want) ? !std::isnan(got) : got != want)
              QFAIL(qPrintable(QString("%1 frame %2 drone %3: %4, not %5").arg(q(col.name)).arg(f).arg(i).arg(got, 0, 'g', 17).arg(want, 0, 'g', 17)));
          }
    }
    QCOMPARE(r.targets.size(), std::size_t{3});
    QCOMPARE(r.targets[1].x, 1e3 / 3);
    QCOMPARE(r.targets[0].y, -2.25);
    QVERIFY(std::isnan(r.found_time[0]) && std::isnan(r.found_time[1]));
    QCOMPARE(r.found_time[2], 0.75);
    QCOMPARE(r.found_by, (std::vector<std::int64_t>{-1, -1, 2}));
  }
};

/// The one line read_archive refuses `file` with ("" when it reads it).
std::string refusal(const fs::path& file) {
  try {
    Recording r;
    salsa::read_archive(file, r);
  } catch (const salsa::InputError& e) {
    return e.what();
  }
  return {};
}

/// Flips 64 bytes at each sixteenth of an archive's second half, keeping its size: some land in its
/// compressed data, which the writer puts after the definitions, wherever the variables' chunks lie.
void flip_data(const fs::path& file) {
  std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
  const auto size = static_cast<std::streamoff>(fs::file_size(file));
  for (std::streamoff at = 8; at < 16; ++at)
    for (std::streamoff byte = size * at / 16; byte < size * at / 16 + 64 && byte < size; ++byte) {
      f.seekg(byte);
      const char c = static_cast<char>(f.get() ^ 0x5a);
      f.seekp(byte);
      f.put(c);
    }
}

void copy_over(const fs::path& from, const fs::path& to) { fs::copy_file(from, to, fs::copy_options::overwrite_existing); }

/// The type variable `name` has in `file` and its scale_factor (0 when none).
std::pair<nc_type, double> stored_as(const fs::path& file, const char* name) {
  int nc = -1, id = -1;
  nc_type type = NC_NAT;
  double scale = 0;
  if (nc_open(file.c_str(), NC_NOWRITE, &nc) != NC_NOERR) return {NC_NAT, 0};
  if (nc_inq_varid(nc, name, &id) == NC_NOERR) {
    nc_inq_vartype(nc, id, &type);
    nc_get_att_double(nc, id, "scale_factor", &scale);
  }
  nc_close(nc);
  return {type, scale};
}

/// netCDF calls that change an archive for the tests of bad archives.
void edit(const fs::path& file, const std::function<int(int)>& change) {
  int nc = -1;
  QCOMPARE(nc_open(file.c_str(), NC_WRITE, &nc), NC_NOERR);
  QCOMPARE(nc_redef(nc), NC_NOERR);
  QCOMPARE(change(nc), NC_NOERR);
  QCOMPARE(nc_close(nc), NC_NOERR);
}

/// A small run with every kind of drone: a fleet (two groups, failures, a battery that runs out),
/// drones removed and added by timed changes, targets found.
const QByteArray run_test = R"({"name": "rec", "groups": [
  {"name": "scouts", "behavior": "random_walk", "drones": 5, "drone": {"base": "small", "battery_capacity": 0.05}},
  {"name": "mappers", "behavior": "flocking", "drones": 3}],
  "map": {"name": "forest", "params": {"size": 200}}, "targets": {"kind": "tree", "count": 40},
  "time": 6, "log_interval": 0.5, "failures": {"drone_mtbf": 20}, "seed": 3, "archive": true,
  "changes": [{"time": 2, "set": {"groups.scouts.drones": 2}}, {"time": 4, "set": {"groups.scouts.drones": 6}}]})";

/// drones.csv's extra columns, written with all their digits; the archive adds them to archive_columns.
const QString drone_columns = "status_since,battery_left,energy_used,failure_due,obstacle_hits,camera_works,steering";

double number(const std::string& text) {
  double v = nan;
  std::from_chars(text.data(), text.data() + text.size(), v);
  return v;
}

}  // namespace

class TestArchive : public QObject {
  Q_OBJECT

 private Q_SLOTS:
  void every_column_and_attribute_round_trips() {
    QTemporaryDir dir;
    // One chunk; many, growing between them; a few drones growing to many (written before a chunk is full).
    for (const Synthetic& s : {Synthetic{}, Synthetic{50, 3000, 3500, 30, 10, 3000}, Synthetic{5, 3, 270000, 2, 1, 270000}}) {
      const fs::path file = fs::path(dir.path().toStdString()) / fs::path(std::to_string(s.base)).replace_extension(".nc");
      s.write(file);
      QVERIFY(!fs::exists(fs::path(file) += ".part"));
      Recording r;
      salsa::read_archive(file, r);
      QCOMPARE(r.source, file);
      s.check(r);
      // Lengths and speeds as whole millimetres (CF packing, which xarray undoes); the rest as it is.
      QVERIFY((stored_as(file, "position") == std::pair<nc_type, double>{NC_INT, 1e-3}));
      QVERIFY((stored_as(file, "wind") == std::pair<nc_type, double>{NC_INT, 1e-3}));
      QVERIFY((stored_as(file, "energy") == std::pair<nc_type, double>{NC_DOUBLE, 0}));
    }
  }

  void a_length_beyond_32_bits_of_millimetres_is_refused() {
    QTemporaryDir dir;
    const fs::path file = fs::path(dir.path().toStdString()) / "far.nc";
    salsa::ArchiveWriter w(file, {"far", "1", "{}", 1, 0.1, 0.1, {"swarm"}, 1, {}});
    std::vector<salsa::Vec2> p{{2.2e6, 0}};
    w.frame(0, {StateColumn::of("position", "m", "drone", "where", p)});
    try {
      w.close({}, 1);
      QFAIL("2,200 km was archived");
    } catch (const salsa::WriteError& e) {
      const std::string line = e.what();
      QVERIFY2(line.find("far.nc.part: position 2.2e+06 is beyond") != std::string::npos && line.find("allowed: within ±2147483") != std::string::npos, e.what());
    }
    QVERIFY(!fs::exists(file));
  }

  void cut_short_leaves_no_archive() {
    QTemporaryDir dir;
    const fs::path file = fs::path(dir.path().toStdString()) / "t.nc";
    {
      salsa::ArchiveWriter w(file, {"t", "1", "{}", 1, 0.1, 0.1, {"swarm"}, 2, {}});
      std::vector<salsa::Vec2> p(2);
      w.frame(0, {StateColumn::of("position", "m", "drone", "where", p)});
    }  // never closed: a crash or a stop
    QVERIFY(!fs::exists(file));
    QVERIFY(fs::exists(fs::path(file) += ".part"));
  }

  void a_run_agrees_with_drones_csv() {
    QTemporaryDir dir;
    QVERIFY(write_file(dir.filePath("rec.json"), run_test));
    const CliResult r = run_salsa({"run", "rec.json", "--out", "out", "-q", "--no-plots", "--drone-columns", drone_columns}, dir.path());
    QVERIFY2(r.exit_code == 0, qPrintable(r.err));
    const fs::path folder = fs::path(dir.path().toStdString()) / "out" / "rec";
    QVERIFY(read_file(q(folder / "manifest.json")).contains("\"trajectories.nc\""));
    QVERIFY(!fs::exists(folder / "trajectories.nc.part"));
    Recording a;
    salsa::read_archive(folder / "trajectories.nc", a);
    QCOMPARE(a.test_name, std::string("rec"));
    QCOMPARE(a.seed, std::uint64_t{3});
    QCOMPARE(a.log_interval, 0.5);
    // archive_columns, then those asked for by name, in the simulation's order; no others (commanded,
    // failure_exposure).
    std::vector<std::string> names;
    for (const RecordedColumn& c : a.columns) names.push_back(c.name);
    QCOMPARE(names, (std::vector<std::string>{"position", "velocity", "steering", "group", "status", "status_since", "camera_works", "energy_used",
                                              "battery_left", "failure_due", "obstacle_hits"}));
    auto col = [&](const char* name) -> const RecordedColumn& {
      for (const RecordedColumn& c : a.columns)
        if (c.name == name) return c;
      qFatal("the archive has no column %s", name);
    };
    auto at = [&](const RecordedColumn& c, std::size_t f, std::size_t id, std::size_t k = 0) { return c.values[(f * a.drones + id) * c.width + k]; };

    const auto rows = rows_of(q(folder / "drones.csv"));
    const std::size_t t = column(rows, "time"), id = column(rows, "id"), group = column(rows, "group"), status = column(rows, "status");
    const char* const statuses[] = {"flying", "landed", "failed", "removed"};
    const char* const groups[] = {"scouts", "mappers"};
    std::vector<std::size_t> listed(a.frames(), 0);
    for (std::size_t k = 1; k < rows.size(); ++k) {
      const auto& row = rows[k];
      std::size_t f = 0;
      while (f < a.frames() && std::abs(a.times[f] - number(row[t])) > 0.5e-4) ++f;
      QVERIFY2(f < a.frames(), row[t].c_str());
      const std::size_t i = std::stoul(row[id]);
      QVERIFY(i < a.drones);
      ++listed[f];
      // drones.csv's 4 decimals and the archive's millimetres: within both roundings.
      const std::pair<const char*, std::pair<const char*, std::size_t>> rounded[] = {
          {"x", {"position", 0}}, {"y", {"position", 1}}, {"vx", {"velocity", 0}}, {"vy", {"velocity", 1}}};
      for (const auto& [csv, where] : rounded) {
        const double v = at(col(where.first), f, i, where.second);
        QVERIFY2(std::abs(v - number(row[column(rows, csv)])) <= (0.5e-3 + 0.5e-4) * (1 + 1e-9), csv);
      }
      QVERIFY(std::abs(at(col("energy_used"), f, i) / 3600 - number(row[column(rows, "energy_used_Wh")])) <= 0.5e-4 * (1 + 1e-9));
      QCOMPARE(row[group], std::string(groups[static_cast<std::size_t>(at(col("group"), f, i))]));
      QCOMPARE(row[status], std::string(statuses[static_cast<std::size_t>(at(col("status"), f, i))]));
      // The columns drones.csv writes with all their digits: exactly.
      for (const char* name : {"status_since", "battery_left", "energy_used", "failure_due", "obstacle_hits", "camera_works"})
        QCOMPARE(at(col(name), f, i), number(row[column(rows, name)]));
      QCOMPARE(at(col("steering"), f, i, 0), std::nearbyint(number(row[column(rows, "steering_x")]) / 1e-3) * 1e-3);
      QCOMPARE(at(col("steering"), f, i, 1), std::nearbyint(number(row[column(rows, "steering_y")]) / 1e-3) * 1e-3);
    }
    // Every drone drones.csv leaves out is removed (status 3) or not yet added (NaN) in the archive.
    bool removed = false, added = false;
    for (std::size_t f = 0; f < a.frames(); ++f) {
      std::size_t present = 0;
      for (std::size_t i = 0; i < a.drones; ++i) {
        const double s = at(col("status"), f, i);
        removed |= s == 3, added |= std::isnan(s);
        present += !std::isnan(s) && s != 3;
        if (s == 3 || std::isnan(s)) QVERIFY(std::isnan(at(col("position"), f, i)));
      }
      QCOMPARE(listed[f], present);
    }
    QVERIFY(removed && added);
    QCOMPARE(a.times.back(), 6.0);
    // targets.csv: the same targets, found at the same times by the same drones.
    const auto targets = rows_of(q(folder / "targets.csv"));
    QCOMPARE(a.targets.size(), targets.size() - 1);
    std::size_t found = 0;
    for (std::size_t k = 1; k < targets.size(); ++k) {
      const auto& row = targets[k];
      QVERIFY(std::abs(a.targets[k - 1].x - number(row[1])) <= 0.5e-4 * (1 + 1e-9));
      if (row[4].empty()) {
        QCOMPARE(a.found_by[k - 1], std::int64_t{-1});
        QVERIFY(std::isnan(a.found_time[k - 1]));
      } else {
        ++found;
        QCOMPARE(a.found_by[k - 1], std::int64_t{std::stoll(row[4])});
        QVERIFY(std::abs(a.found_time[k - 1] - number(row[3])) <= 0.5e-4 * (1 + 1e-9));
      }
    }
    QVERIFY(found > 0);

    // load_recording reads the folder's archive, as read_archive does.
    const Recording loaded = salsa::load_recording(folder);
    QCOMPARE(loaded.source, folder / "trajectories.nc");
    QCOMPARE(loaded.columns.size(), a.columns.size());
    QCOMPARE(loaded.frames(), a.frames());
    QCOMPARE(loaded.groups.size(), std::size_t{2});

    // salsa export of a folder whose archive was damaged (the same size, so its manifest passes):
    // exit 2, one line naming the archive, nothing written into the folder.
    flip_data(folder / "trajectories.nc");
    const QMap<QString, QByteArray> before = snapshot(q(folder));
    const CliResult e = run_salsa({"export", "out/rec", "--mcap", "rec.mcap"}, dir.path());
    QCOMPARE(e.exit_code, 2);
    QCOMPARE(non_empty_lines(e.err).size(), 1);
    QVERIFY2(e.err.contains("trajectories.nc: corrupt or truncated"), qPrintable(e.err));
    QCOMPARE(snapshot(q(folder)), before);
    QVERIFY(!QFile::exists(dir.filePath("rec.mcap")));
  }

  void chosen_in_the_file_or_on_the_command_line() {
    QTemporaryDir dir;
    const QByteArray plain = R"({"name": "p", "behavior": "random_walk", "drones": 3, "time": 1})";
    QVERIFY(write_file(dir.filePath("p.json"), plain));
    QVERIFY(run_salsa({"run", "p.json", "--out", "out", "-q", "--no-plots"}, dir.path()).exit_code == 0);
    QVERIFY(!QFile::exists(dir.filePath("out/p/trajectories.nc")));  // off by default
    const QByteArray config = read_file(dir.filePath("out/p/config.json"));
    // --resume: the same test, now wanted with the archive: rerun, and then kept.
    CliResult r = run_salsa({"run", "p.json", "--out", "out", "-q", "--no-plots", "--resume", "--archive"}, dir.path());
    QVERIFY2(r.exit_code == 0, qPrintable(r.err));
    QVERIFY(QFile::exists(dir.filePath("out/p/trajectories.nc")));
    QCOMPARE(read_file(dir.filePath("out/p/config.json")), config);  // an output choice: not in config.json
    const QByteArray archive = read_file(dir.filePath("out/p/trajectories.nc"));
    // Byte for byte the same from another run, on another thread count.
    r = run_salsa({"run", "p.json", "--out", "again", "-q", "--no-plots", "--archive", "--threads", "1"}, dir.path());
    QVERIFY2(r.exit_code == 0, qPrintable(r.err));
    QCOMPARE(read_file(dir.filePath("again/p/trajectories.nc")), archive);
    r = run_salsa({"run", "p.json", "--out", "out", "-q", "--no-plots", "--resume", "--archive"}, dir.path());
    QVERIFY2(r.exit_code == 0, qPrintable(r.err));
    QCOMPARE(read_file(dir.filePath("out/p/trajectories.nc")), archive);
    // In the test file, and in a queue's base; --no-drones-csv leaves the archive alone.
    QVERIFY(write_file(dir.filePath("q.json"),
                       R"({"base": {"behavior": "random_walk", "drones": 3, "time": 1, "archive": true}, "tests": [{"name": "a"}, {"name": "b", "seed": 2, "archive": false}]})"));
    r = run_salsa({"run", "q.json", "--out", "q", "-q", "--no-plots", "--no-drones-csv"}, dir.path());
    QVERIFY2(r.exit_code == 0, qPrintable(r.err));
    QVERIFY(QFile::exists(dir.filePath("q/a/trajectories.nc")) && !QFile::exists(dir.filePath("q/a/drones.csv")));
    QVERIFY(!QFile::exists(dir.filePath("q/b/trajectories.nc")));
    // --resume keeps a test whose archive was asked for the columns named now, and reruns it for others
    // (drones.csv not wanted: the archive alone decides).
    r = run_salsa({"run", "q.json", "--out", "q", "--no-plots", "--no-drones-csv", "--archive", "--resume", "--drone-columns", "battery_left"}, dir.path());
    QVERIFY2(r.exit_code == 0 && r.out.contains("a: already complete"), qPrintable(r.out + r.err));
    r = run_salsa({"run", "q.json", "--out", "q", "--no-plots", "--no-drones-csv", "--archive", "--resume", "--drone-columns", "steering"}, dir.path());
    QVERIFY2(r.exit_code == 0 && !r.out.contains("a: already complete"), qPrintable(r.out + r.err));
    Recording steered;
    salsa::read_archive(fs::path(dir.path().toStdString()) / "q" / "a" / "trajectories.nc", steered);
    QVERIFY(std::any_of(steered.columns.begin(), steered.columns.end(), [](const RecordedColumn& c) { return c.name == "steering"; }));
    r = run_salsa({"run", "q.json", "--out", "q", "--no-plots", "--no-drones-csv", "--archive", "--resume", "--drone-columns", "steering"}, dir.path());
    QVERIFY2(r.exit_code == 0 && r.out.contains("a: already complete"), qPrintable(r.out + r.err));
    QVERIFY(write_file(dir.filePath("bad.json"), R"({"behavior": "random_walk", "archive": 1})"));
    r = run_salsa({"run", "bad.json", "--out", "bad", "-q"}, dir.path());
    QCOMPARE(r.exit_code, 2);
    QCOMPARE(non_empty_lines(r.err).size(), 1);
    QVERIFY2(r.err.contains("bad.json") && r.err.contains("archive: 1 is not true or false"), qPrintable(r.err));
  }

  void bad_archives_are_refused_in_one_line() {
    QTemporaryDir dir;
    const fs::path root = dir.path().toStdString();
    const fs::path good = root / "good.nc";
    Synthetic{20, 50, 50, 0, 0}.write(good);
    const auto size = fs::file_size(good);
    auto refused = [&](const fs::path& file, const char* why) {
      const QMap<QString, QByteArray> before = snapshot(dir.path());
      const std::string line = refusal(file);
      QVERIFY2(line.starts_with(file.string() + ": ") && line.find('\n') == std::string::npos, line.c_str());
      QVERIFY2(line.find(why) != std::string::npos, line.c_str());
      QCOMPARE(snapshot(dir.path()), before);  // nothing written
    };
    QCOMPARE(refusal(good), std::string());

    const fs::path flipped = root / "flipped.nc";
    copy_over(good, flipped);
    flip_data(flipped);
    refused(flipped, "corrupt or truncated");

    const fs::path truncated = root / "truncated.nc";
    copy_over(good, truncated);
    fs::resize_file(truncated, size / 2);
    refused(truncated, "corrupt or truncated");

    const fs::path text = root / "text.nc";
    QVERIFY(write_file(q(text), "time,id,x,y\n"));
    refused(text, "not a netCDF file");
    refused(root / "absent.nc", "missing");

    const fs::path newer = root / "newer.nc";
    copy_over(good, newer);
    edit(newer, [](int nc) {
      const int version = salsa::archive_version + 1;
      return nc_put_att_int(nc, NC_GLOBAL, "salsa_archive_version", NC_INT, 1, &version);
    });
    refused(newer, "newer than this salsa reads");

    const fs::path lacking = root / "lacking.nc";
    copy_over(good, lacking);
    edit(lacking, [](int nc) {
      int id = -1;
      const int s = nc_inq_varid(nc, "velocity", &id);
      return s != NC_NOERR ? s : nc_rename_var(nc, id, "speed");
    });
    refused(lacking, "lacks the variable velocity");

    const fs::path foreign = root / "foreign.nc";
    copy_over(good, foreign);
    edit(foreign, [](int nc) { return nc_del_att(nc, NC_GLOBAL, "salsa_archive_version"); });
    refused(foreign, "not a salsa trajectory archive");
  }
};

QTEST_GUILESS_MAIN(TestArchive)
#include "test_archive.moc"
