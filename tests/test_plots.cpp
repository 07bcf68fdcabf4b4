// Plots and the paired comparison: `salsa plot` on real runs and on a hand-written queue draws every
// PNG (valid, the expected size, not blank), the data behind them matches the CSV files, and
// comparison.csv matches a hand-computed t-interval.
#include <QImage>

#include <cmath>
#include <set>

#include "common.hpp"
#include "salsa/core/results/comparison.hpp"
#include "salsa/core/experiments/test_spec.hpp"
#include "salsa/plots/results.hpp"
#include "figure.hpp"  // plots/src: the layout each figure reports
#include "ranking_plots.hpp"  // plots/src: which number the conditions differ in

using namespace salsa_test;

namespace {

/// What a user looking at a PNG relies on: it loads, has the size asked for, and shows something
/// (several colours, a fair share of non-white pixels).
void check_png(const QString& file, int width, int height) {
  QVERIFY2(QFileInfo::exists(file), qPrintable(file + " missing"));
  QCOMPARE(read_file(file).left(8), QByteArray("\x89PNG\r\n\x1a\n", 8));
  const QImage image(file);
  QVERIFY2(!image.isNull(), qPrintable(file + " does not load"));
  QCOMPARE(image.width(), width);
  QCOMPARE(image.height(), height);
  std::set<QRgb> colours;
  long ink = 0;
  for (int y = 0; y < image.height(); y += 2)
    for (int x = 0; x < image.width(); x += 2) {
      const QRgb c = image.pixel(x, y);
      colours.insert(c);
      ink += c != qRgb(255, 255, 255);
    }
  QVERIFY2(colours.size() >= 8, qPrintable(file + ": " + QString::number(colours.size()) + " colours"));
  QVERIFY2(ink > image.width() * image.height() / 4 / 100, qPrintable(file + ": almost blank"));
}

/// The PNG files in a folder, by name.
QStringList pngs(const QString& dir) { return QDir(dir).entryList({"*.png"}, QDir::Files, QDir::Name); }

/// Colours within a small distance: antialiased edges and translucent paths are not exact.
bool near(QColor a, QColor b) { return std::abs(a.red() - b.red()) + std::abs(a.green() - b.green()) + std::abs(a.blue() - b.blue()) < 90; }

/// Pixels near `colour` in a rectangle of the image.
int count_near(const QImage& image, QRect r, QColor colour) {
  int n = 0;
  r &= image.rect();
  for (int y = r.top(); y <= r.bottom(); ++y)
    for (int x = r.left(); x <= r.right(); ++x) n += near(image.pixelColor(x, y), colour);
  return n;
}

// A test folder written by hand in the fleet model's format (docs/output-format.md): `none`, the files
// of a run without groups, batteries or failures; `single`, the one group "swarm" (a battery or failures
// on); `groups`, groups `a` and `b`. A 100 m square, 5 s: drone 0 flies along y = 81 to x = 51, drone 1
// along y = 31 and lands at (31, 31) at 2 s, drone 2 along x = 61, drone 3 along y = 71 and fails at
// (71, 71) at 3 s; with groups, 0 and 1 are `a`, 2 and 3 `b`. (Positions off the heat map's cell edges.)
enum class Fleet { none, single, groups };
void write_fleet_folder(const QString& folder, Fleet fleet, const QString& a = "alpha", const QString& b = "beta") {
  write_file(folder + "/config.json", R"({"name": "f"})");
  write_file(folder + "/map.json", R"({"bounds": {"min": [0, 0], "max": [100, 100]}})");
  write_file(folder + "/targets.csv", "id,x,y,found_time,found_by,observations\n0,50,50,1,0,3\n1,90,10,,,0\n");
  QString summary = "time,targets_found,fraction_found,mean_speed,max_speed,mean_nn_distance,collisions";
  if (fleet != Fleet::none) summary += ",alive,energy_used_Wh";
  if (fleet == Fleet::groups) summary += QString(",%1.found,%1.alive,%1.energy_used_Wh,%2.found,%2.alive,%2.energy_used_Wh").arg(a, b);
  QString drones = QString("time,id,x,y,vx,vy") + (fleet != Fleet::none ? ",group,status,energy_used_Wh" : "") + "\n";
  for (int t = 0; t <= 4; ++t) {
    const int found = t >= 1 ? 1 : 0, alive_a = t >= 2 ? 1 : 2, alive_b = t >= 3 ? 1 : 2;
    summary += QString("\n%1,%2,%3,10,10,20,0").arg(t).arg(found).arg(found * 0.5);
    if (fleet != Fleet::none) summary += QString(",%1,%2").arg(alive_a + alive_b).arg(5 * t);
    if (fleet == Fleet::groups) summary += QString(",%1,%2,%3,0,%4,%5").arg(found).arg(alive_a).arg(2 * t).arg(alive_b).arg(3 * t);
    struct Row { int id; double x, y; QString group, status; };
    const QString single = "swarm";
    const Row rows[] = {{0, 11.0 + 10 * t, 81, fleet == Fleet::groups ? a : single, "flying"},
                        {1, 11.0 + 10 * std::min(t, 2), 31, fleet == Fleet::groups ? a : single, t >= 2 ? "landed" : "flying"},
                        {2, 61, 11.0 + 10 * t, fleet == Fleet::groups ? b : single, t >= 1 ? "camera_failed" : "flying"},
                        {3, 41.0 + 10 * std::min(t, 3), 71, fleet == Fleet::groups ? b : single, t >= 3 ? "failed" : "flying"}};
    for (const Row& r : rows) {
      const bool stopped = r.status == "landed" || r.status == "failed";
      drones += QString("%1,%2,%3,%4,%5,0").arg(t).arg(r.id).arg(r.x).arg(r.y).arg(stopped ? 0 : 10);
      if (fleet != Fleet::none) drones += "," + r.group + "," + r.status + "," + QString::number(t);
      drones += "\n";
    }
  }
  write_file(folder + "/summary.csv", (summary + "\n").toUtf8());
  write_file(folder + "/drones.csv", drones.toUtf8());
}

/// Where map point (x, y) is in a map plot: the map's walls (3 px, black) are found along the middle
/// row and column; the map here is 0 … 100 m both ways. (-1, -1) when they are not there.
QPointF map_pixel(const QImage& image, double x, double y) {
  auto walls = [&](bool across) {
    std::vector<double> centres;
    const int n = across ? image.width() : image.height();
    for (int i = across ? 100 : 60, run = 0; i < n; ++i) {  // past the tick labels, below the title
      const QColor c = across ? image.pixelColor(i, image.height() / 2) : image.pixelColor(image.width() / 2, i);
      if (std::max({c.red(), c.green(), c.blue()}) < 50) ++run;
      else {
        if (run >= 2) centres.push_back(i - (run + 1) / 2.0);
        run = 0;
      }
    }
    return centres;
  };
  const auto columns = walls(true), rows = walls(false);
  if (columns.size() < 2 || rows.size() < 2) return {-1, -1};
  return {columns[0] + x / 100 * (columns[1] - columns[0]), rows[1] - y / 100 * (rows[1] - rows[0])};
}

/// A cross (✕, ±5 px) in `colour` centred on `at`: the colour on its four diagonal arms, 4 px out.
bool cross_at(const QImage& image, QPointF at, QColor colour) {
  for (QPointF arm : {QPointF(4, 4), QPointF(-4, 4), QPointF(4, -4), QPointF(-4, -4)})
    if (count_near(image, QRect((at + arm).toPoint() - QPoint(1, 1), QSize(3, 3)), colour) == 0) return false;
  return true;
}

/// A CSV file's rows as fields (salsa's test files hold no quoted fields).
QList<QStringList> csv_rows(const QString& file) {
  QList<QStringList> rows;
  for (const QString& line : non_empty_lines(QString::fromUtf8(read_file(file)))) rows << line.split(',');
  return rows;
}

}  // namespace

class TestPlots : public QObject {
  Q_OBJECT
  QTemporaryDir dir_;

  QString path(const QString& name) const { return dir_.filePath(name); }

  // Runs one test into OUT and draws its plots; returns the test folder.
  QString run_and_plot(const QByteArray& test, const QStringList& extra = {}) {
    write_file(path("test.json"), test);
    const CliResult run = run_salsa(QStringList{"run", path("test.json"), "--out", path("out")} + extra);
    if (run.exit_code != 0) qWarning("%s", describe(run).constData());
    const CliResult plot = run_salsa({"plot", path("out/t")});
    if (plot.exit_code != 0) qWarning("%s", describe(plot).constData());
    return path("out/t");
  }

 private Q_SLOTS:
  void init() { QDir(path("out")).removeRecursively(); }

  void test_plots_data() {
    QTest::addColumn<QByteArray>("test");
    QTest::addColumn<bool>("map_file");
    QTest::newRow("generated forest") << QByteArray(R"({"name": "t", "behavior": "random_walk", "drones": 12,
        "map": {"name": "forest", "params": {"size": 200}}, "targets": {"kind": "tree", "count": 40},
        "time": 20, "seed": 5})") << false;
    QTest::newRow("map file") << ("{\"name\": \"t\", \"behavior\": \"flocking\", \"drones\": 8, \"map\": \"" +
                                  q(source_dir() / "examples/maps/warehouse.json").toUtf8() +
                                  "\", \"targets\": {\"kind\": \"tree\", \"count\": 30}, \"time\": 20, \"seed\": 2}")
                              << true;
  }

  // Every per-test PNG, and the data drawn matches the CSV files.
  void test_plots() {
    QFETCH(QByteArray, test);
    QFETCH(bool, map_file);
    const QString t = run_and_plot(test);
    for (const char* png : {"found.png", "trajectories.png", "speeds.png", "nn_distance.png", "heatmap.png"})
      check_png(t + "/plots/" + png, salsa::plots::plot_width, salsa::plots::plot_height);
    QCOMPARE(QFileInfo::exists(t + "/plots/coverage.png"), read_file(t + "/summary.csv").split('\n')[0].contains("coverage"));

    // found.png ends at summary.csv's last fraction_found: the line's pixels next to the right border are
    // at that height (plot area 95 … 1170 × 70 … 715 px, y from 0 to 100 %, no legend).
    const auto summary = csv_rows(t + "/summary.csv");
    const double last = summary.last()[2].toDouble() * 100;
    const QImage found(t + "/plots/found.png");
    double sum = 0;
    int hits = 0;
    for (int y = 70; y <= 715; ++y)
      if (const QColor c = found.pixelColor(1166, y); c.blue() > c.red() + 40) sum += y, ++hits;
    QVERIFY2(hits > 0, "no line at the right end of found.png");
    QVERIFY2(std::abs(sum / hits - (715 - last * 6.45)) < 4, qPrintable(QString::number(sum / hits) + " vs " + QString::number(last)));

    // The area: the map's bounds, from the map.json the run wrote (a generated map too).
    QVERIFY2(QFileInfo(t + "/map.json").size() > 0, "the run writes map.json");
    const salsa::plots::Rect area = salsa::plots::test_area(t.toStdString());
    QCOMPARE(area.x0, 0.0);
    QCOMPARE(area.y0, 0.0);
    QCOMPARE(area.x1, map_file ? 300.0 : 200.0);
    QCOMPARE(area.y1, 200.0);

    // trajectories.png: the obstacles are drawn (opaque grey, far more of it than the legend's
    // square), and the frame is the map's bounds: going down the middle column, the map's top wall
    // comes a few pixels after the plot's frame (a small margin, not the next round number).
    const QImage trajectories(t + "/plots/trajectories.png");
    long grey = 0;
    for (int y = 0; y < trajectories.height(); ++y)
      for (int x = 0; x < trajectories.width(); ++x) grey += trajectories.pixel(x, y) == qRgb(150, 150, 150);
    QVERIFY2(grey > 1500, qPrintable(QString::number(grey) + " obstacle pixels"));
    auto level = [&](int y) { return qGray(trajectories.pixel(600, y)); };  // the frame is a thin grey line, the wall black
    int frame = 60;
    while (frame < 400 && level(frame) > 200) ++frame;
    int wall = frame;
    while (wall < 400 && level(wall) <= 200) ++wall;
    while (wall < 400 && level(wall) > 60) ++wall;
    QVERIFY2(frame < 300 && wall - frame >= 3 && wall - frame < 25, qPrintable(QString("frame at %1, wall at %2").arg(frame).arg(wall)));

    // The heat map's hottest cell is the cell holding the most rows of drones.csv.
    std::vector<std::pair<double, double>> positions;
    const auto drones = csv_rows(t + "/drones.csv");
    for (qsizetype i = 1; i < drones.size(); ++i) positions.emplace_back(drones[i][2].toDouble(), drones[i][3].toDouble());
    const auto grid = salsa::plots::bin_positions(positions, area, 60);
    std::map<int, int> count;
    for (auto [x, y] : positions) {
      QVERIFY2(x >= area.x0 && x < area.x1 && y >= area.y0 && y < area.y1, "a drone outside the plotted area");
      ++count[int(std::floor((y - area.y0) / grid.cell)) * grid.columns + int(std::floor((x - area.x0) / grid.cell))];
    }
    const auto busiest = std::max_element(count.begin(), count.end(), [](auto a, auto b) { return a.second < b.second; });
    QCOMPARE(grid.values[std::size_t(busiest->first)], 100.0);
    QCOMPARE(int(std::count(grid.values.begin(), grid.values.end(), 100.0)),
             int(std::count_if(count.begin(), count.end(), [&](auto c) { return c.second == busiest->second; })));
  }

  // Without drones.csv the plots that need it are skipped, the others drawn.
  void no_drones_csv() {
    const QString t = run_and_plot(R"({"name": "t", "behavior": "random_walk", "drones": 5, "map": {"name": "empty"},
        "targets": {"kind": "tree", "count": 10}, "time": 5, "seed": 1})", {"--no-drones-csv"});
    check_png(t + "/plots/found.png", salsa::plots::plot_width, salsa::plots::plot_height);
    check_png(t + "/plots/nn_distance.png", salsa::plots::plot_width, salsa::plots::plot_height);
    for (const char* png : {"trajectories.png", "speeds.png", "heatmap.png"}) QVERIFY(!QFileInfo::exists(t + "/plots/" + png));
  }

  // The coverage plot is drawn when summary.csv has the column, skipped without an error otherwise.
  void coverage_column() {
    write_file(path("out/c/config.json"), R"({"name": "c"})");
    write_file(path("out/c/summary.csv"), "time,targets_found,fraction_found,mean_nn_distance,coverage\n0,0,0,,0.1\n1,1,0.5,,0.4\n");
    // map.json (the map as a map file) gives the area and the obstacles.
    write_file(path("out/c/map.json"), R"({"bounds": {"min": [-10, 0], "max": [40, 30]}, "obstacles": [[[0, 0], [5, 0], [5, 5]]]})");
    const salsa::plots::Rect area = salsa::plots::test_area(path("out/c").toStdString());
    QCOMPARE(area.x0, -10.0);
    QCOMPARE(area.y1, 30.0);
    const CliResult r = run_salsa({"plot", path("out/c")});
    QVERIFY2(r.exit_code == 0, describe(r));
    check_png(path("out/c/plots/coverage.png"), salsa::plots::plot_width, salsa::plots::plot_height);
    QVERIFY(!QFileInfo::exists(path("out/c/plots/nn_distance.png")));  // one drone: no distances
  }

  // The fleet model's columns add alive.png and energy.png, a line per group, trajectories and the heat
  // map coloured by group (Okabe–Ito: orange, then blue) and a cross where a drone landed or failed;
  // without them a folder gives the same files as before.
  void fleet_columns() {
    const QString none = path("out/none"), single = path("out/single"), groups = path("out/groups"), renamed = path("out/renamed");
    write_fleet_folder(none, Fleet::none);
    write_fleet_folder(single, Fleet::single);
    write_fleet_folder(groups, Fleet::groups);
    write_fleet_folder(renamed, Fleet::groups, "alpha_renamed_longer");
    for (const QString& folder : {none, single, groups, renamed}) {
      const CliResult r = run_salsa({"plot", folder});
      QVERIFY2(r.exit_code == 0, describe(r));
    }
    const QStringList before{"found.png", "heatmap.png", "nn_distance.png", "speeds.png", "trajectories.png"};
    const QStringList fleet{"alive.png", "energy.png", "found.png", "heatmap.png", "nn_distance.png", "speeds.png", "trajectories.png"};
    QCOMPARE(pngs(none + "/plots"), before);
    QCOMPARE(pngs(single + "/plots"), fleet);
    QCOMPARE(pngs(groups + "/plots"), fleet);
    for (const QString& png : fleet) check_png(groups + "/plots/" + png, salsa::plots::plot_width, salsa::plots::plot_height);
    const QColor alpha(0xE6, 0x9F, 0x00), beta(0x00, 0x72, 0xB2);

    // Lines over time: the legend's rows (28 px apart from y = 74, on the right) are the total, then
    // each group in its colour with its name; one group has no legend.
    auto legend_row = [](int i) { return QRect(1040, 74 + 28 * i, 160, 24); };
    for (const char* png : {"found.png", "alive.png", "energy.png"}) {
      const QImage image(groups + "/plots/" + png), one(single + "/plots/" + png);
      QVERIFY2(count_near(image, legend_row(1), alpha) > 20 && count_near(image, legend_row(1), beta) == 0, png);
      QVERIFY2(count_near(image, legend_row(2), beta) > 20 && count_near(image, legend_row(2), alpha) == 0, png);
      QVERIFY2(count_near(one, QRect(1040, 70, 160, 100), Qt::black) == 0, png);  // no legend text
    }
    // The name is the legend's text: a longer name, more text in its row.
    auto text = [&](const QString& folder) { return count_near(QImage(folder + "/plots/found.png"), QRect(600, 74 + 28, 600, 24), Qt::black); };
    QVERIFY2(text(renamed) > text(groups) + 50, qPrintable(QString("%1 vs %2 dark pixels").arg(text(renamed)).arg(text(groups))));

    // Trajectories: each drone in its group's colour, a cross in it where drone 1 landed and drone 3
    // failed, none where drone 0 kept flying nor without the status column.
    const QImage trajectories(groups + "/plots/trajectories.png"), before_trajectories(none + "/plots/trajectories.png");
    QVERIFY(map_pixel(trajectories, 0, 0).x() > 0);
    QVERIFY(cross_at(trajectories, map_pixel(trajectories, 31, 31), alpha));
    QVERIFY(cross_at(trajectories, map_pixel(trajectories, 71, 71), beta));
    QVERIFY(!cross_at(trajectories, map_pixel(trajectories, 51, 81), alpha));
    // One group: a colour per drone as before, and the cross in the drone's colour; no status: a dot.
    const QImage one_group(single + "/plots/trajectories.png");
    for (const QImage& image : {before_trajectories, one_group})
      QVERIFY(count_near(image, image.rect(), alpha) == 0 && count_near(image, image.rect(), beta) == 0);
    const QPointF landed = map_pixel(one_group, 31, 31), dot = map_pixel(before_trajectories, 31, 31);
    QVERIFY(landed.x() > 0 && dot.x() > 0);
    QVERIFY(!near(one_group.pixelColor(landed.toPoint()), Qt::white) && cross_at(one_group, landed, one_group.pixelColor(landed.toPoint())));
    QVERIFY(!near(before_trajectories.pixelColor(dot.toPoint()), Qt::white) && !cross_at(before_trajectories, dot, before_trajectories.pixelColor(dot.toPoint())));

    // The heat map: a cell takes its group's hue (only group a was at (11, 81), only b at (61, 11)).
    const QImage heat(groups + "/plots/heatmap.png");
    auto hue_at = [&](double x, double y) { return heat.pixelColor(map_pixel(heat, x, y).toPoint()).hue(); };
    QVERIFY2(std::abs(hue_at(11, 81) - alpha.hue()) < 8, qPrintable(QString::number(hue_at(11, 81))));
    QVERIFY2(std::abs(hue_at(61, 11) - beta.hue()) < 8, qPrintable(QString::number(hue_at(61, 11))));
    const QImage before_heat(none + "/plots/heatmap.png");
    QCOMPARE(count_near(before_heat, before_heat.rect(), beta), 0);

    // Speeds leave stopped drones out: from 3 s the drones still flying all fly at 10 m/s, so the
    // min–max band is gone at 3.5 s, 5 m/s (the plot spans 0 … 4 s, 0 … 10 m/s from x = 95 to the
    // legend at ~1010 px, y = 715 … 70); without the status, the stopped drones' 0 m/s keep it.
    auto band_at_5 = [](const QString& folder) { return !near(QImage(folder + "/plots/speeds.png").pixelColor(880, 392), Qt::white); };
    QVERIFY(band_at_5(none));
    QVERIFY(!band_at_5(groups));
  }

  void binning() {
    // 10 m × 5 m in cells of 5 m: two cells side by side; a position outside is left out.
    const auto g = salsa::plots::bin_positions({{1, 1}, {2, 2}, {7, 1}, {11, 1}}, {0, 0, 10, 5}, 2);
    QCOMPARE(g.columns, 2);
    QCOMPARE(g.rows, 1);
    QCOMPARE(g.cell, 5.0);
    QCOMPARE(g.values, (std::vector<double>{100, 50}));
    // A taller area gets more rows: 4 m × 6 m in cells of 2 m is 2 × 3; row 0 at the bottom.
    const auto tall = salsa::plots::bin_positions({{3, 5}, {3, 5.5}, {0.5, 0.5}}, {0, 0, 4, 6}, 2);
    QCOMPARE(tall.rows, 3);
    QCOMPARE(tall.values, (std::vector<double>{50, 0, 0, 0, 0, 100}));
    QCOMPARE(salsa::plots::bin_positions({}, {0, 0, 1, 1}, 4).values, std::vector<double>(16, 0.0));
  }

  void ticks_data() {
    QTest::addColumn<double>("lo");
    QTest::addColumn<double>("hi");
    QTest::addColumn<std::vector<double>>("ticks");
    QTest::newRow("37.275") << 0.0 << 37.275 << std::vector<double>{0, 10, 20, 30, 40};
    QTest::newRow("percent") << 0.0 << 100.0 << std::vector<double>{0, 20, 40, 60, 80, 100};
    QTest::newRow("negative") << -3.0 << 7.0 << std::vector<double>{-4, -2, 0, 2, 4, 6, 8};
    QTest::newRow("small") << 0.013 << 0.087 << std::vector<double>{0, 0.02, 0.04, 0.06, 0.08, 0.1};
    QTest::newRow("one value") << 3.0 << 3.0 << std::vector<double>{2.4, 2.6, 2.8, 3, 3.2, 3.4, 3.6};
  }

  void ticks() {
    QFETCH(double, lo);
    QFETCH(double, hi);
    QFETCH(std::vector<double>, ticks);
    const auto got = salsa::plots::nice_ticks(lo, hi);
    QCOMPARE(got.size(), ticks.size());
    for (std::size_t i = 0; i < got.size(); ++i) QVERIFY2(std::abs(got[i] - ticks[i]) < 1e-12, qPrintable(QString::number(got[i])));
  }

  void box() {
    // 1 … 9 and 100: quartiles by linear interpolation 3.25, 5.5, 7.75; IQR 4.5, so 100 is beyond
    // 7.75 + 6.75 and the upper whisker ends at 9.
    const auto b = salsa::plots::box_stats({100, 9, 8, 7, 6, 5, 4, 3, 2, 1});
    QCOMPARE(b.q1, 3.25);
      QCOMPARE(b.median, 5.5);
      QCOMPARE(b.q3, 7.75);
    QCOMPARE(b.low, 1.0);
      QCOMPARE(b.high, 9.0);
    QCOMPARE(b.outliers, std::vector<double>{100});
  }

  // Two variants on five paired seeds, worked out by hand:
  //   A = 0.5 0.6 0.7 0.4 0.8, B = 0.4 0.6 0.5 0.5 0.6, A − B = 0.1 0 0.2 −0.1 0.2
  //   mean 0.08; sample sd √(0.068 / 4) = 0.130384; t_{0.975,4} = 2.776 → 0.08 ± 2.776 · 0.130384 / √5
  //   = [−0.081868, 0.241868]; A better in 3 pairs, tied in 1: win rate 3.5 / 5 = 0.7.
  // Left out: a failed test, a seed only A has; variant C pairs with A once (no interval).
  void comparison() {
    const QString out = path("cmp");
    write_file(out + "/summary.csv",
               "name,status,error,cell,variant,behavior,repeat,seed,drones,targets,target,map,time,fraction_found\n"
               "a1,ok,,c1,A,a,0,11,10,50,tree,forest,60,0.5\n"
               "b1,ok,,c1,B,b,0,11,10,50,tree,forest,60,0.4\n"
               "a2,ok,,c1,A,a,1,12,10,50,tree,forest,60,0.6\n"
               "b2,ok,,c1,B,b,1,12,10,50,tree,forest,60,0.6\n"
               "a3,ok,,c1,A,a,2,13,10,50,tree,forest,60,0.7\n"
               "b3,ok,,c1,B,b,2,13,10,50,tree,forest,60,0.5\n"
               "a4,ok,,c1,A,a,3,14,10,50,tree,forest,60,0.4\n"
               "b4,ok,,c1,B,b,3,14,10,50,tree,forest,60,0.5\n"
               "a5,ok,,c1,A,a,4,15,10,50,tree,forest,60,0.8\n"
               "b5,ok,,c1,B,b,4,15,10,50,tree,forest,60,0.6\n"
               "b6,failed,\"boom, at 3 s\",c1,B,b,5,16,10,50,tree,forest,60,\n"
               "a6,ok,,c1,A,a,5,16,10,50,tree,forest,60,0.9\n"
               "a7,ok,,c1,A,a,6,17,10,50,tree,forest,60,0.3\n"
               "c1,ok,,c1,\"C(x=1, y=2)\",c,0,11,10,50,tree,forest,60,0.25\n"
               "d1,ok,,c2,A,a,0,21,20,50,tree,forest,60,0.5\n");
    salsa::write_comparison(out.toStdString());
    const QStringList lines = non_empty_lines(QString::fromUtf8(read_file(out + "/comparison.csv")));
    QCOMPARE(lines.value(0), QString("cell,condition,drones,targets,target,map,time,metric,variant_a,variant_b,n,mean_a,mean_b,"
                                     "mean_diff,ci_low,ci_high,win_rate_a"));
    QCOMPARE(lines.size(), 4);  // c1: A–B, A–C, B–C; c2 has one variant
    auto field = [&](int line, int column) { return lines[line].split(',')[column]; };
    QCOMPARE(lines[1].split(',').mid(0, 11).join(','), QString("c1,,10,50,tree,forest,60,fraction_found,A,B,5"));
    QCOMPARE(field(1, 11).toDouble(), 0.6);
    QCOMPARE(field(1, 12).toDouble(), 0.52);
    QVERIFY(std::abs(field(1, 13).toDouble() - 0.08) < 1e-9);
    QVERIFY2(std::abs(field(1, 14).toDouble() - -0.081868) < 2e-4, qPrintable(lines[1]));
    QVERIFY2(std::abs(field(1, 15).toDouble() - 0.241868) < 2e-4, qPrintable(lines[1]));
    QCOMPARE(field(1, 16).toDouble(), 0.7);
    // One pair: the mean is the difference, the interval empty.
    QCOMPARE(lines[2], QString("c1,,10,50,tree,forest,60,fraction_found,A,\"C(x=1, y=2)\",1,0.5,0.25,0.25,,,1"));
    QCOMPARE(lines[3], QString("c1,,10,50,tree,forest,60,fraction_found,B,\"C(x=1, y=2)\",1,0.4,0.25,0.15,,,1"));
    QVERIFY(!QFileInfo::exists(out + "/did.csv"));  // one condition: nothing to difference
    QVERIFY(!QFileInfo::exists(out + "/condition_effects.csv"));
    // Rewritten from the same file, byte for byte.
    const QByteArray first = read_file(out + "/comparison.csv");
    salsa::write_comparison(out.toStdString());
    QCOMPARE(read_file(out + "/comparison.csv"), first);
    // Another metric by name; one that is not a column is refused in one line naming the file.
    QVERIFY_THROWS_EXCEPTION(salsa::InputError, salsa::write_comparison(out.toStdString(), "coverage"));
  }

  // Conditions, by hand. Cell c1 under "base" and "drop" (the same worlds: seeds 11-14) and "big" (its own
  // worlds: seeds 31-34, paired with the others by repeat):
  //   base: A = .5 .6 .7 .4, B = .4 .6 .5 .5 → A − B = .1 0 .2 −.1 (mean .05)
  //   drop: A = .3 .5 .4 .2, B = .4 .5 .5 .4 → A − B = −.1 0 −.1 −.2 (mean −.1)
  //   big:  A = .6 each,     B = .5 each     → A − B = .1 each
  // drop − base, per repeat: −.2 0 −.3 −.1: mean −.15, sd √(.05 / 3) = .129099, t_{0.975,3} = 3.182446
  // → −.15 ± .205426 = [−.355426, .055426]. big − base: 0 .1 −.1 .2: mean .05.
  // Each variant against itself (condition_effects.csv): A under drop − A under base = −.2 −.1 −.3 −.2:
  // mean −.2, sd √(.02 / 3) = .0816497 → −.2 ± .129924; A under base .55 ± .205426 (the sd above);
  // B: 0 −.1 0 −.1, mean −.05. A under big − base (by repeat): .1 0 −.1 .2, mean .05, higher in 2.5 of 4.
  void difference_in_differences() {
    const QString out = path("did");
    QByteArray summary = "name,status,error,cell,variant,condition,condition_label,behavior,repeat,seed,drones,targets,target,map,time,fraction_found\n";
    const std::map<std::string, std::pair<std::vector<double>, std::vector<double>>> values{
        {"base", {{.5, .6, .7, .4}, {.4, .6, .5, .5}}}, {"drop", {{.3, .5, .4, .2}, {.4, .5, .5, .4}}}, {"big", {{.6, .6, .6, .6}, {.5, .5, .5, .5}}}};
    for (const char* condition : {"base", "drop", "big"})
      for (int r = 0; r < 4; ++r)
        for (const char* v : {"A", "B"}) {
          const auto& [a, b] = values.at(condition);
          const int seed = (condition[1] == 'i' ? 31 : 11) + r;
          summary += QByteArray(v) + condition + QByteArray::number(r) + ",ok,,c1," + v + "," + condition + ",x," + v + "," + QByteArray::number(r) + "," +
                     QByteArray::number(seed) + ",10,50,tree,forest,60," + QByteArray::number(v[0] == 'A' ? a[r] : b[r]) + "\n";
        }
    write_file(out + "/summary.csv", summary);
    salsa::write_comparison(out.toStdString());
    // Within each condition: A − B on its own worlds.
    const QStringList cmp = non_empty_lines(QString::fromUtf8(read_file(out + "/comparison.csv")));
    QCOMPARE(cmp.size(), 4);
    QVERIFY2(cmp[1].startsWith("c1,base,10,50,tree,forest,60,fraction_found,A,B,4,0.55,0.5,0.05,"), qPrintable(cmp[1]));
    QVERIFY2(cmp[2].startsWith("c1,drop,10,50,tree,forest,60,fraction_found,A,B,4,0.35,0.45,-0.1,"), qPrintable(cmp[2]));
    const QStringList did = non_empty_lines(QString::fromUtf8(read_file(out + "/did.csv")));
    QCOMPARE(did.value(0), QString("cell,drones,targets,target,map,time,metric,variant_a,variant_b,baseline,condition,n,diff_baseline,diff_condition,"
                                   "did,ci_low,ci_high"));
    QCOMPARE(did.size(), 3);
    const QStringList drop = did[1].split(',');
    QCOMPARE(drop.mid(0, 12).join(','), QString("c1,10,50,tree,forest,60,fraction_found,A,B,base,drop,4"));
    QVERIFY2(std::abs(drop[12].toDouble() - 0.05) < 1e-9 && std::abs(drop[13].toDouble() - -0.1) < 1e-9, qPrintable(did[1]));
    QVERIFY2(std::abs(drop[14].toDouble() - -0.15) < 1e-9, qPrintable(did[1]));
    QVERIFY2(std::abs(drop[15].toDouble() - -0.355426) < 2e-5 && std::abs(drop[16].toDouble() - 0.055426) < 2e-5, qPrintable(did[1]));
    const QStringList big = did[2].split(',');
    QCOMPARE(big.mid(9, 3).join(','), QString("base,big,4"));  // paired by repeat: its seeds are its own
    QVERIFY2(std::abs(big[14].toDouble() - 0.05) < 1e-9, qPrintable(did[2]));
    // Each variant under each condition against itself under the first: the same pairing.
    const QStringList effects = non_empty_lines(QString::fromUtf8(read_file(out + "/condition_effects.csv")));
    QCOMPARE(effects.value(0), QString("cell,drones,targets,target,map,time,metric,variant,baseline,condition,n,mean_baseline,baseline_ci_low,"
                                       "baseline_ci_high,mean_condition,mean_diff,ci_low,ci_high,win_rate"));
    QCOMPARE(effects.size(), 5);  // A and B under drop, then under big
    const QStringList a_drop = effects[1].split(',');
    QCOMPARE(a_drop.mid(0, 11).join(','), QString("c1,10,50,tree,forest,60,fraction_found,A,base,drop,4"));
    auto about = [](const QString& field, double v, double tolerance = 1e-9) { return std::abs(field.toDouble() - v) < tolerance; };
    QVERIFY2(about(a_drop[11], 0.55) && about(a_drop[12], 0.344574, 2e-5) && about(a_drop[13], 0.755426, 2e-5), qPrintable(effects[1]));
    QVERIFY2(about(a_drop[14], 0.35) && about(a_drop[15], -0.2), qPrintable(effects[1]));
    QVERIFY2(about(a_drop[16], -0.329924, 2e-5) && about(a_drop[17], -0.070076, 2e-5) && a_drop[18] == "0", qPrintable(effects[1]));
    const QStringList b_drop = effects[2].split(',');
    QVERIFY2(b_drop[7] == "B" && about(b_drop[15], -0.05), qPrintable(effects[2]));
    const QStringList a_big = effects[3].split(',');
    QCOMPARE(a_big.mid(7, 4).join(','), QString("A,base,big,4"));  // paired by repeat: its seeds are its own
    QVERIFY2(about(a_big[15], 0.05) && a_big[18] == "0.625", qPrintable(effects[3]));
    // A queue without conditions written into the same folder: neither file is left over.
    write_file(out + "/summary.csv", "name,status,error,cell,variant,behavior,repeat,seed,drones,targets,target,map,time,fraction_found\n"
                                     "a,ok,,c1,A,a,0,11,10,50,tree,forest,60,0.5\nb,ok,,c1,B,b,0,11,10,50,tree,forest,60,0.4\n");
    salsa::write_comparison(out.toStdString());
    QVERIFY(!QFileInfo::exists(out + "/did.csv"));
    QVERIFY(!QFileInfo::exists(out + "/condition_effects.csv"));
  }

  // ranking.csv by hand. Cell c1, three variants over repeats 0-3 (C lacks repeat 3):
  //   A = .5 .6 .7 .4: mean .55, sd √(.05 / 3) = .129099, t_{0.975,3} = 3.182446 → [.344574, .755426]
  //   B = .2 .4 .3 .1: mean .25, the same sd → [.044574, .455426]
  //   C = .5 .7 .6:    mean .6,  sd .1, t_{0.975,2} = 4.302653 → .6 ± .248414
  // Ranks by mean: C 1, A 2, B 3. The repeats all three have: 0-2; best in repeat 0: A and C tie (½
  // each), 1: C, 2: A → shares A .5, C .5, B 0. Against the best (C), paired on repeats 0-2 (as
  // comparison.csv would): A − C = 0 −.1 .1: mean 0 ± .248414 (not apart); B − C = −.3 each: [−.3, −.3]
  // (below). Cell c2: D = .5 .5 and E = .4 .6 have equal means: both rank 1, D (first seen) is the best;
  // each best in one repeat.
  void ranking() {
    const QString out = path("ranking");
    QByteArray summary = "name,status,error,cell,variant,behavior,repeat,seed,drones,targets,target,map,time,fraction_found\n";
    const std::vector<std::pair<const char*, std::vector<double>>> c1{{"A", {.5, .6, .7, .4}}, {"B", {.2, .4, .3, .1}}, {"C", {.5, .7, .6}}};
    for (int r = 0; r < 4; ++r)
      for (const auto& [v, x] : c1)
        if (r < static_cast<int>(x.size()))
          summary += QByteArray(v) + QByteArray::number(r) + ",ok,,c1," + v + ",b," + QByteArray::number(r) + "," + QByteArray::number(11 + r) +
                     ",10,50,tree,forest,60," + QByteArray::number(x[r]) + "\n";
    summary += "d0,ok,,c2,D,b,0,21,20,50,tree,forest,60,0.5\ne0,ok,,c2,E,b,0,21,20,50,tree,forest,60,0.4\n"
               "d1,ok,,c2,D,b,1,22,20,50,tree,forest,60,0.5\ne1,ok,,c2,E,b,1,22,20,50,tree,forest,60,0.6\n";
    write_file(out + "/summary.csv", summary);
    salsa::write_comparison(out.toStdString());
    const QStringList lines = non_empty_lines(QString::fromUtf8(read_file(out + "/ranking.csv")));
    QCOMPARE(lines.value(0), QString("cell,condition,drones,targets,target,map,time,metric,rank,variant,n,mean,ci_low,ci_high,repeats,best_share,"
                                     "n_vs_best,diff_vs_best,ci_low_vs_best,ci_high_vs_best,differs_from_best"));
    QCOMPARE(lines.size(), 1 + 3 + 2);
    auto about = [](const QString& field, double v) { return std::abs(field.toDouble() - v) < 2e-6; };
    const QStringList c = lines[1].split(','), a = lines[2].split(','), b = lines[3].split(',');
    QCOMPARE(c.mid(0, 11).join(','), QString("c1,,10,50,tree,forest,60,fraction_found,1,C,3"));
    QVERIFY2(about(c[11], .6) && about(c[12], .6 - .248414) && about(c[13], .6 + .248414), qPrintable(lines[1]));
    QVERIFY2(c[14] == "3" && about(c[15], .5) && c.mid(16).join(',') == ",,,,", qPrintable(lines[1]));  // the best: nothing against itself
    QCOMPARE(a.mid(8, 3).join(','), QString("2,A,4"));
    QVERIFY2(about(a[11], .55) && about(a[12], .344574) && about(a[13], .755426) && about(a[15], .5), qPrintable(lines[2]));
    QVERIFY2(a[16] == "3" && about(a[17], 0) && about(a[18], -.248414) && about(a[19], .248414) && a[20] == "no", qPrintable(lines[2]));
    QCOMPARE(b.mid(8, 3).join(','), QString("3,B,4"));
    QVERIFY2(about(b[11], .25) && about(b[12], .044574) && about(b[13], .455426) && b[15] == "0", qPrintable(lines[3]));
    QVERIFY2(b[16] == "3" && about(b[17], -.3) && about(b[18], -.3) && about(b[19], -.3) && b[20] == "yes", qPrintable(lines[3]));
    QVERIFY2(lines[4].startsWith("c2,,20,50,tree,forest,60,fraction_found,1,D,2,0.5,0.5,0.5,2,0.5,,,,,"), qPrintable(lines[4]));
    const QStringList e = lines[5].split(',');
    QVERIFY2(e.mid(8, 3).join(',') == "1,E,2" && about(e[11], .5) && about(e[15], .5) && about(e[17], 0) && e[20] == "no", qPrintable(lines[5]));
    // ranking.png: a row per variant under a heading per cell.
    salsa::plots::ensure_application();
    std::filesystem::create_directories((out + "/plots").toStdString());
    salsa::plots::ranking_plots(out.toStdString(), {"A", "B", "C", "D", "E"}, {});
    check_png(out + "/plots/ranking.png", 1200, salsa::plots::comparison_plot_height(2 + 5));
    QCOMPARE(pngs(out + "/plots"), QStringList{"ranking.png"});  // no conditions: no plot against a number
  }

  // The number the conditions differ in: exactly one input column the same within each condition and
  // different between them, a number in each.
  void condition_number() {
    const QString out = path("number");
    const QByteArray header = "name,status,error,cell,variant,condition,condition_label,behavior,repeat,seed,drones,targets,target,map,time,behavior.speed,comm.range,comm.loss,outcome.targets,fraction_found\n";
    auto rows = [&](const char* r50, const char* r100, const char* loss100) {
      QByteArray s = header;
      for (const char* v : {"a", "b"})
        for (int r = 0; r < 2; ++r) {
          s += QByteArray(v) + "50_" + QByteArray::number(r) + ",ok,,c,\"" + v + "\",r50,x," + v + "," + QByteArray::number(r) + ",1,10,5,tree,empty,60," +
               (v[0] == 'a' ? "1" : "2") + "," + r50 + ",0,5,0.5\n";
          s += QByteArray(v) + "100_" + QByteArray::number(r) + ",ok,,c,\"" + v + "\",r100,x," + v + "," + QByteArray::number(r) + ",1,10,5,tree,empty,60," +
               (v[0] == 'a' ? "1" : "2") + "," + r100 + "," + loss100 + ",5,0.6\n";
        }
      write_file(out + "/summary.csv", s);
      return salsa::plots::condition_number(out.toStdString());
    };
    const auto range = rows("50.0", "100.0", "0");  // the behavior's parameter differs too: between variants, not conditions
    QVERIFY(range && range->key == "comm.range");
    QCOMPARE(range->values, (std::map<std::string, double>{{"r100", 100}, {"r50", 50}}));
    QVERIFY(!rows("50.0", "100.0", "0.5"));  // two settings differ
    QVERIFY(!rows("", "100.0", "0"));        // not a number under r50
    QVERIFY(!rows("50.0", "50.0", "0"));     // none differs
  }

  // Many variants: each against the reference, or the first beyond max_all_pairs; few: every pair.
  void pairs_that_matter() {
    using P = std::vector<std::pair<std::size_t, std::size_t>>;
    QCOMPARE(salsa::compared_pairs({"a", "b", "c"}, ""), (P{{0, 1}, {0, 2}, {1, 2}}));
    QCOMPARE(salsa::compared_pairs({"a", "b", "c"}, "c"), (P{{0, 2}, {1, 2}}));
    QCOMPARE(salsa::compared_pairs({"a", "b", "c", "d", "e"}, ""), (P{{1, 0}, {2, 0}, {3, 0}, {4, 0}}));
    QCOMPARE(salsa::compared_pairs({"a", "b", "c", "d", "e"}, "d"), (P{{0, 3}, {1, 3}, {2, 3}, {4, 3}}));
    QCOMPARE(salsa::compared_pairs({"a", "b", "c", "d", "e"}, "z"), (P{{1, 0}, {2, 0}, {3, 0}, {4, 0}}));  // not in this cell
    // 9 variants with a reference recorded in queue.json: 8 rows, not 36.
    const QString out = path("many");
    QByteArray summary = "name,status,error,cell,variant,behavior,repeat,seed,drones,targets,target,map,time,fraction_found\n";
    for (int v = 0; v < 9; ++v)
      for (int r = 0; r < 3; ++r)
        summary += "t" + QByteArray::number(v) + "_" + QByteArray::number(r) + ",ok,,c1,\"f: a = " + QByteArray::number(v) + "\",f," +
                   QByteArray::number(r) + "," + QByteArray::number(r + 1) + ",10,50,tree,forest,60,0." + QByteArray::number(v) + "\n";
    write_file(out + "/summary.csv", summary);
    write_file(out + "/queue.json", R"({"tests": [], "configs_hash": "0123456789abcdef", "command": [], "reference": "f: a = 4"})");
    salsa::write_comparison(out.toStdString());
    const QStringList lines = non_empty_lines(QString::fromUtf8(read_file(out + "/comparison.csv")));
    QCOMPARE(lines.size(), 1 + 8);
    for (qsizetype i = 1; i < lines.size(); ++i) QVERIFY2(lines[i].contains(",f: a = 4,3,"), qPrintable(lines[i]));
  }

  void variants_in_numeric_order() {
    using salsa::plots::natural_less;
    const std::vector<std::string> sorted{"flocking: alpha = 1", "flocking: alpha = 1.4", "flocking: alpha = 1.8", "flocking: alpha = 10",
                                          "flocking: alpha = 10, beta = -2", "flocking: alpha = 10, beta = 0.5"};
    for (std::size_t i = 0; i < sorted.size(); ++i)
      for (std::size_t j = 0; j < sorted.size(); ++j)
        QVERIFY2(natural_less(sorted[i], sorted[j]) == (i < j), qPrintable(QString::fromStdString(sorted[i] + " vs " + sorted[j])));
    QVERIFY(natural_less("d5", "d20"));
    QVERIFY(natural_less("x = -2", "x = 1"));
    QVERIFY(natural_less("x-2", "x-10"));  // a dash inside a word is no minus sign
    QVERIFY(!natural_less("a", "a"));
  }

  // Queue plots from a hand-written summary.csv and test folders holding only summary.csv.
  void queue_plots() {
    const QString out = path("queue");
    QByteArray summary = "name,status,error,cell,variant,behavior,repeat,seed,drones,targets,target,map,time,fraction_found\n";
    int k = 0;
    for (const char* variant : {"flocking", "random_walk(step=2)"})
      for (int drones : {5, 20})
        for (int repeat = 0; repeat < 6; ++repeat, ++k) {
          const double end = (drones == 5 ? 0.3 : 0.6) + (variant[0] == 'f' ? 0.1 : 0.0) + 0.02 * repeat + (repeat == 5 ? 0.3 : 0);
          const QByteArray name = "t" + QByteArray::number(k);
          summary += name + ",ok,,c" + QByteArray::number(drones) + ",\"" + variant + "\",x," + QByteArray::number(repeat) + "," +
                     QByteArray::number(repeat + 1) + "," + QByteArray::number(drones) + ",50,tree,forest,10," + QByteArray::number(end) + "\n";
          // The 5-drone tests have the fleet model's `alive` (a drone lost from 5 s in odd repeats).
          QByteArray rows = drones == 5 ? "time,targets_found,fraction_found,alive\n" : "time,targets_found,fraction_found\n";
          for (int s = 0; s <= 10; ++s)
            rows += QByteArray::number(s) + ",0," + QByteArray::number(end * s / 10) +
                    (drones == 5 ? "," + QByteArray::number(s >= 5 && repeat % 2 ? 4 : 5) : QByteArray()) + "\n";
          write_file(out + "/" + name + "/summary.csv", rows);
        }
    summary += "t99,failed,boom,c5,flocking,x,6,7,5,50,tree,forest,10,\n";
    write_file(out + "/summary.csv", summary);
    // A queue folder's record: a summary.csv without one is the user's own, left alone.
    write_file(out + "/queue.json", R"({"tests": ["t0"], "configs_hash": "0123456789abcdef", "command": ["salsa", "run"]})");
    const CliResult r = run_salsa({"plot", out});
    QVERIFY2(r.exit_code == 0, describe(r));
    QCOMPARE(non_empty_lines(QString::fromUtf8(read_file(out + "/comparison.csv"))).size(), 3);
    for (const char* png : {"found_boxplot.png", "found_over_time_5_drones.png", "found_over_time_20_drones.png", "alive_over_time_5_drones.png"})
      check_png(out + "/plots/" + png, salsa::plots::plot_width, salsa::plots::plot_height);
    // Drones alive over time only for the swarm size whose tests have the column.
    QCOMPARE(pngs(out + "/plots"), (QStringList{"alive_over_time_5_drones.png", "comparison.png", "found_boxplot.png",
                                                "found_over_time_20_drones.png", "found_over_time_5_drones.png", "ranking.png"}));
    check_png(out + "/plots/comparison.png", salsa::plots::plot_width, salsa::plots::comparison_plot_height(2 + 2));  // a heading per swarm size
    check_png(out + "/plots/ranking.png", salsa::plots::plot_width, salsa::plots::comparison_plot_height(2 + 2 * 2));  // and a row per variant
  }

  // A queue with conditions and a swept parameter: every plot, grouped by condition; the change's time
  // is marked on found-over-time.
  void queue_plots_with_conditions() {
    const QString out = path("conditions");
    QByteArray summary = "name,status,error,cell,variant,condition,condition_label,behavior,repeat,seed,drones,targets,target,map,time,"
                         "behavior.alpha,fraction_found\n";
    int k = 0;
    for (const char* condition : {"baseline", "dropout"})
      for (const char* alpha : {"1", "1.4", "10", "1.8"})
        for (int repeat = 0; repeat < 4; ++repeat, ++k) {
          const double a = QByteArray(alpha).toDouble();
          const double end = 0.3 + 0.02 * a + 0.03 * repeat - (condition[0] == 'd' ? 0.1 : 0.0);
          const QByteArray name = "t" + QByteArray::number(k), variant = QByteArray("f: alpha = ") + alpha;
          summary += name + ",ok,,c1,\"" + variant + "\"," + condition + "," + (condition[0] == 'd' ? "drones → 4 at 5 s" : "no change") + ",f," +
                     QByteArray::number(repeat) + "," + QByteArray::number(repeat + 1) + ",5,50,tree,forest,10," + alpha + "," +
                     QByteArray::number(end) + "\n";
          QByteArray rows = "time,targets_found,fraction_found\n";
          for (int s = 0; s <= 10; ++s) rows += QByteArray::number(s) + ",0," + QByteArray::number(end * s / 10) + "\n";
          write_file(out + "/" + name + "/summary.csv", rows);
          write_file(out + "/" + name + "/config.json", condition[0] == 'd' ? R"({"changes": [{"time": 5, "set": {"drones": 4}}]})" : "{}");
        }
    write_file(out + "/summary.csv", summary);
    write_file(out + "/queue.json", R"({"tests": ["t0"], "configs_hash": "0123456789abcdef", "command": ["salsa", "run"], "reference": "f: alpha = 1"})");
    CliResult r = run_salsa({"plot", out});
    QVERIFY2(r.exit_code == 0, describe(r));
    // The conditions differ in a timed change, not a number: no plot against one.
    QCOMPARE(pngs(out + "/plots"), (QStringList{"comparison.png", "did.png", "found_boxplot.png", "found_over_time_5_drones.png", "found_vs_f_alpha.png",
                                                "ranking.png"}));
    check_png(out + "/plots/ranking.png", salsa::plots::plot_width, salsa::plots::comparison_plot_height(2 * (1 + 4)));
    for (const char* png : {"found_boxplot.png", "found_over_time_5_drones.png", "found_vs_f_alpha.png"})
      check_png(out + "/plots/" + png, salsa::plots::plot_width, salsa::plots::plot_height);
    // 3 against the reference under each of 2 conditions, each condition's rows under a heading.
    check_png(out + "/plots/comparison.png", salsa::plots::plot_width, salsa::plots::comparison_plot_height(2 * (1 + 3)));
    check_png(out + "/plots/did.png", salsa::plots::plot_width, salsa::plots::comparison_plot_height(1 + 3));
    // The change at 5 s is a line of its own: without it the plot differs.
    const QImage with_change(out + "/plots/found_over_time_5_drones.png");
    for (int i = 0; i < k; ++i) write_file(out + "/t" + QByteArray::number(i) + "/config.json", "{}");
    r = run_salsa({"plot", out});
    QVERIFY2(r.exit_code == 0, describe(r));
    QVERIFY(QImage(out + "/plots/found_over_time_5_drones.png") != with_change);
  }

  // Real labels are long: a tuned variant's parameters, a condition that changes wind, radio and the
  // swarm. Every queue plot keeps its plot area on its canvas and of a readable size, however long the
  // labels (the layout each figure reports before it draws).
  void long_labels_keep_the_plot_on_its_canvas() {
    const QString out = path("long");
    const QByteArray tuned = "flocking: separation_distance = 37.51234, alignment_weight = 9.876543, cohesion_weight = 0.812345, separation_weight = 1.234567";
    const QByteArray combined = "wind.velocity = [3,1], wind.gusts.strength = 1.5, wind.gusts.time_scale = 8, comm.range = 50, comm.loss = 0.2, "
                                "comm.latency = 2, comm.max_received = 5, drones → 4 at 3 s, " + QByteArray("and_a_key_without_spaces_").repeated(12);
    QByteArray summary = "name,status,error,cell,variant,condition,condition_label,behavior,repeat,seed,drones,targets,target,map,time,fraction_found\n";
    int k = 0;
    for (const char* condition : {"baseline", "combined_wind_gusts_and_radio_with_a_long_name"})
      for (const QByteArray& variant : {QByteArray("random_walk (defaults)"), tuned})
        for (int drones : {6, 12})
          for (int repeat = 0; repeat < 3; ++repeat, ++k) {
            const double end = 0.2 + 0.05 * repeat + (variant[0] == 'f' ? 0.1 : 0) + (condition[0] == 'c' ? 0.05 : 0);
            const QByteArray name = "t" + QByteArray::number(k);
            summary += name + ",ok,,c" + QByteArray::number(drones) + ",\"" + variant + "\"," + condition + ",\"" +
                       (condition[0] == 'c' ? combined : QByteArray("no change")) + "\",x," + QByteArray::number(repeat) + "," +
                       QByteArray::number(repeat + 1) + "," + QByteArray::number(drones) + ",50,tree,forest,10," + QByteArray::number(end) + "\n";
            QByteArray rows = "time,targets_found,fraction_found,alive\n";
            for (int s = 0; s <= 10; ++s) rows += QByteArray::number(s) + ",0," + QByteArray::number(end * s / 10) + "," + QByteArray::number(drones) + "\n";
            write_file(out + "/" + name + "/summary.csv", rows);
          }
    write_file(out + "/summary.csv", summary);
    write_file(out + "/queue.json", R"({"tests": ["t0"], "configs_hash": "0123456789abcdef", "command": ["salsa", "run"]})");
    const CliResult r = run_salsa({"plot", out});  // comparison.csv, did.csv
    QVERIFY2(r.exit_code == 0, describe(r));
    struct Drawn { QString title; QSize canvas; QRectF plot; };
    std::vector<Drawn> drawn;
    salsa::plots::observe_layouts([&](const QString& title, QSize canvas, QRectF plot) { drawn.push_back({title, canvas, plot}); });
    salsa::plots::draw_queue_plots(out.toStdString());
    salsa::plots::observe_layouts({});
    QCOMPARE(drawn.size(), std::size_t{8});  // box plot, found and alive over time for 2 sizes, comparison, did, ranking
    for (const Drawn& d : drawn) {
      const QString what = d.title + ": plot area " + QString("%1,%2 %3 × %4 on %5 × %6").arg(d.plot.left()).arg(d.plot.top()).arg(d.plot.width())
                                                        .arg(d.plot.height()).arg(d.canvas.width()).arg(d.canvas.height());
      QVERIFY2(QRectF(QPointF(0, 0), QSizeF(d.canvas)).contains(d.plot), qPrintable(what));
      QVERIFY2(d.plot.width() >= 0.3 * d.canvas.width() && d.plot.height() >= 200, qPrintable(what));  // 360 px across at least
      QCOMPARE(d.canvas.width(), salsa::plots::plot_width);
    }
  }

  // A queue's own labels name its conditions and variants everywhere: config.json, summary.csv,
  // comparison.csv (a label is a valid reference) and the plots.
  void labels_name_conditions_and_variants() {
    write_file(path("labelled.json"), R"({"repeats": 2, "base": {"map": {"name": "empty", "params": {"size": 200}}, "drones": 4, "time": 2,
        "targets": {"kind": "tree", "count": 50, "params": {"radius": 5}}},
      "conditions": [{"name": "baseline"}, {"name": "windy", "label": "gusty air", "wind": {"velocity": [3, 1], "gusts": {"strength": 1.5}}}],
      "sweep": {"behaviors": ["random_walk", {"name": "flocking", "params": {"cohesion_weight": 0.812345, "alignment_weight": 9.876543}, "label": "tuned"}]},
      "reference": "tuned"})");
    const CliResult r = run_salsa({"run", path("labelled.json"), "--out", path("labelled")});
    QVERIFY2(r.exit_code == 0, describe(r));
    const QString summary = QString::fromUtf8(read_file(path("labelled/summary.csv")));
    QVERIFY2(summary.contains(",tuned,windy,gusty air,flocking,"), qPrintable(summary.left(2000)));
    QVERIFY2(summary.contains(",tuned,baseline,no change,flocking,"), qPrintable(summary.left(2000)));  // the label the file left out: what changes
    QVERIFY(!summary.contains("cohesion_weight = 0.812345"));
    const QString comparison = QString::fromUtf8(read_file(path("labelled/comparison.csv")));
    QVERIFY2(comparison.contains(",random_walk (defaults),tuned,"), qPrintable(comparison));
    const QString config = QString::fromUtf8(read_file(path("labelled/flocking_aw9.876543_cw0.812345_windy_r0/config.json")));
    QVERIFY2(config.contains("\"label\": \"tuned\"") && config.contains("\"label\": \"gusty air\""), qPrintable(config));
    QVERIFY(QFileInfo::exists(path("labelled/plots/comparison.png")));
  }

  // A sweep.set key (here the failure clock, with the camera's written 0 exactly where it is set) is
  // plotted apart, under each queue condition; a setting every test shares is no split.
  void swept_settings_are_plotted_apart() {
    const QString out = path("swept");
    QByteArray summary = "name,status,error,cell,variant,condition,condition_label,behavior,repeat,seed,drones,map,time,"
                         "failures.drone_mtbf,failures.camera_mtbf,outcome.targets,fraction_found\n";
    std::vector<std::string> expected;
    int k = 0;
    for (const char* condition : {"baseline", "dropout"})
      for (const char* mtbf : {"", "3000.0"})
        for (const char* variant : {"a", "b"})
          for (int repeat = 0; repeat < 3; ++repeat, ++k) {
            summary += "t" + QByteArray::number(k) + ",ok,,c1," + variant + "," + condition + ",x," + variant + "," + QByteArray::number(repeat) +
                       "," + QByteArray::number(10 + repeat) + ",5,forest,10," + mtbf + "," + (*mtbf ? "0.0" : "") + ",50,0.5\n";
            expected.push_back(std::string(condition) + ", failures.drone_mtbf = " + (*mtbf ? "3000" : "none"));
          }
    summary += "t99,failed,boom,c1,a,baseline,x,a,0,1,5,forest,10,100,,50,\n";  // a failed test is no row
    write_file(out + "/summary.csv", summary);
    QCOMPARE(salsa::plots::plotted_conditions(out.toStdString()), expected);
    // Without the sweep (one failure clock for all), the queue's conditions alone.
    summary.replace("3000.0,0.0", ",");
    write_file(out + "/summary.csv", summary);
    for (auto& e : expected) e = e.substr(0, e.find(','));
    QCOMPARE(salsa::plots::plotted_conditions(out.toStdString()), expected);
  }

  // The single-file mode stays: a summary.csv column over time into --out.
  void column_chart() {
    write_file(path("s/summary.csv"), "time,targets_found\n0,0\n1,3\n2,7\n");
    const CliResult r = run_salsa({"plot", path("s/summary.csv"), "--out", path("s/found.png")});
    QVERIFY2(r.exit_code == 0, describe(r));
    check_png(path("s/found.png"), 960, 600);
  }

  // What `salsa plot FILE.csv` says of a bad CSV is one short line of text: it says what a CSV needs
  // when empty, escapes bytes that are not UTF-8, cuts a huge header, and lists only columns that are
  // there (a column in the list is never the one reported missing).
  void csv_refusals_are_one_printable_line_data() {
    QTest::addColumn<QByteArray>("csv");
    QTest::addColumn<QString>("column");
    QTest::addColumn<QString>("expect");
    QTest::newRow("empty") << QByteArray() << "targets_found" << "empty (allowed: a CSV written by salsa with a header row)";
    QTest::newRow("blank line") << QByteArray("\n") << "targets_found" << "empty (allowed: a CSV written by salsa with a header row)";
    QTest::newRow("not UTF-8") << QByteArray("time,a\xff\xfe,b\xc3\n0,1,2\n") << "nope"
                               << "--column: 'nope' is not a column (allowed: time, a\\xff\\xfe, b\\xc3)";
    QTest::newRow("UTF-8 kept") << QByteArray("time,caf\xc3\xa9\n0,1\n") << "nope" << "(allowed: time, caf\u00e9)";
    QTest::newRow("1.4 MB header") << "time" + QByteArray(",column_with_a_long_name").repeated(60000) + "\n" << "nope"
                                   << ", ... (60001 columns in all))";
    QTest::newRow("1.4 MB column name") << "time," + QByteArray(1400000, 'x') + "\n" << "nope" << "(allowed: time, xxxxx";
    QTest::newRow("time not first") << QByteArray("targets_found,time\n0,0\n") << "targets_found"
                                    << "the first column is 'targets_found', not 'time'";
    QTest::newRow("CRLF header") << QByteArray("time,targets_found\r\n") << "nope" << "(allowed: time, targets_found)";
  }
  void csv_refusals_are_one_printable_line() {
    QFETCH(QByteArray, csv);
    QFETCH(QString, column);
    QFETCH(QString, expect);
    write_file(path("bad/summary.csv"), csv);
    const CliResult r = run_salsa({"plot", path("bad/summary.csv"), "--out", path("bad/out.png"), "--column", column});
    QVERIFY2(r.exit_code == 2 && !r.crashed, describe(r));
    const QStringList lines = non_empty_lines(r.err);
    QVERIFY2(lines.size() == 1 && r.err.size() < 2000, qPrintable(r.err.left(300)));
    QVERIFY2(lines[0].contains(path("bad/summary.csv") + ": ") && lines[0].contains(expect), qPrintable(r.err.left(300)));
    QVERIFY2(!r.err.contains(QChar::ReplacementCharacter), qPrintable(r.err.left(300)));  // valid UTF-8 throughout
    QVERIFY(!QFileInfo::exists(path("bad/out.png")));
  }
};

QTEST_MAIN(TestPlots)  // a QGuiApplication: the layout test draws text in this process
#include "test_plots.moc"
