// salsa export --html: the page it writes opened in headless Chromium (Debian's chromium) from file://,
// offline. It loads and says which frame it shows; seeking to a time puts each drone where drones.csv
// has it, in its group's colour (pixels read from a screenshot, through the map → page transform the
// page keeps in <body>'s data-ox, data-oy, data-scale); the drones move between two times; a found
// target turns from grey to green at its found time. Bad destinations are refused in one line, and
// nothing is written.
#include <QImage>
#include <QRegularExpression>
#include <QStandardPaths>
#include <QtTest>

#include <cmath>
#include <map>

#include "common.hpp"

using namespace salsa_test;

namespace {

constexpr int page_width = 1000, page_height = 800;

QColor okabe_ito(int group) { return QColor(group == 0 ? 0xE69F00 : 0x0072B2); }  // groups-forest has two groups
bool near(QColor a, QColor b, int tolerance = 12) {
  return std::abs(a.red() - b.red()) <= tolerance && std::abs(a.green() - b.green()) <= tolerance && std::abs(a.blue() - b.blue()) <= tolerance;
}
QString rgb(QColor c) { return QString("(%1, %2, %3)").arg(c.red()).arg(c.green()).arg(c.blue()); }

struct Drone {
  double x, y;
  int group;
  QString status;
};

}  // namespace

class TestExportHtml : public QObject {
  Q_OBJECT
  QTemporaryDir dir_;
  QString test_, page_, chromium_;
  /// What headless Chromium's window takes from --window-size's height for itself when it loads a page
  /// (a screenshot is of the whole height): added, the page's state dumped is the screenshot's.
  int chrome_ = 0;
  std::map<double, std::map<int, Drone>> drones_;  ///< by time, by id (drones.csv)
  std::vector<std::pair<double, double>> targets_;
  std::vector<double> found_;  ///< NaN: never

  /// Chromium showing the page at URL fragment `fragment` with its own profile folder; `what` is
  /// --dump-dom or --screenshot=FILE.
  CliResult chromium(const QString& what, const QString& fragment) {
    static int profile = 0;
    const int height = page_height + (what == "--dump-dom" ? chrome_ : 0);
    return run_program(chromium_, {"--headless=new", "--disable-gpu", "--no-sandbox", "--hide-scrollbars", "--force-device-scale-factor=1",
                                   QString("--window-size=%1,%2").arg(page_width).arg(height),
                                   "--user-data-dir=" + dir_.path() + "/profile" + QString::number(profile++), what,
                                   QUrl::fromLocalFile(page_ + "/index.html").toString() + "#" + fragment});
  }
  /// <body>'s data-* attributes after the page ran at `fragment`.
  std::map<QString, QString> state(const QString& fragment) {
    const CliResult r = chromium("--dump-dom", fragment);
    std::map<QString, QString> out;
    if (r.exit_code != 0) qWarning("chromium: %s", qPrintable(r.err));
    const QRegularExpression body("<body([^>]*)>"), attribute("data-([a-z]+)=\"([^\"]*)\"");
    const auto m = body.match(r.out);
    for (auto it = attribute.globalMatch(m.captured(1)); it.hasNext();) {
      const auto a = it.next();
      out[a.captured(1)] = a.captured(2);
    }
    return out;
  }
  QImage screenshot(const QString& fragment, const QString& name) {
    const QString file = dir_.path() + "/" + name + ".png";
    const CliResult r = chromium("--screenshot=" + file, fragment);
    if (r.exit_code != 0) qWarning("chromium: %s", qPrintable(r.err));
    return QImage(file).convertToFormat(QImage::Format_RGB32);
  }

 private Q_SLOTS:
  void initTestCase() {
    chromium_ = QStandardPaths::findExecutable("chromium");
    if (chromium_.isEmpty()) QFAIL("chromium is not installed (Debian: apt-get install chromium): the web page cannot be tested");
    CliResult r = run_salsa({"run", q(source_dir() / "examples/groups-forest.json"), "--out", dir_.path() + "/out", "--time", "30"});
    QVERIFY2(r.exit_code == 0, qPrintable(r.err));
    test_ = dir_.path() + "/out/groups-forest";
    page_ = dir_.path() + "/page";
    r = run_salsa({"export", test_, "--html", page_});
    QVERIFY2(r.exit_code == 0, qPrintable(r.err));
    for (const char* file : {"index.html", "replay.js", "data.js"}) QVERIFY2(QFile::exists(page_ + "/" + file), file);
    const QStringList viewport = state("t=0")["viewport"].split('x');
    QVERIFY2(viewport.size() == 2, "the page did not say its window's size (data-viewport)");
    chrome_ = page_height - viewport[1].toInt();
    QCOMPARE(state("t=0")["viewport"], QString("%1x%2").arg(page_width).arg(page_height));

    const auto rows = rows_of(test_ + "/drones.csv");
    const std::size_t t = column(rows, "time"), id = column(rows, "id"), x = column(rows, "x"), y = column(rows, "y"),
                      group = column(rows, "group"), status = column(rows, "status");
    for (std::size_t k = 1; k < rows.size(); ++k)
      drones_[std::stod(rows[k][t])][std::stoi(rows[k][id])] = {std::stod(rows[k][x]), std::stod(rows[k][y]),
                                                                rows[k][group] == "surveyors" ? 0 : 1, q(rows[k][status])};
    const auto targets = rows_of(test_ + "/targets.csv");
    const std::size_t tx = column(targets, "x"), ty = column(targets, "y"), tf = column(targets, "found_time");
    for (std::size_t k = 1; k < targets.size(); ++k) {
      targets_.emplace_back(std::stod(targets[k][tx]), std::stod(targets[k][ty]));
      found_.push_back(targets[k].size() > tf && !targets[k][tf].empty() ? std::stod(targets[k][tf]) : std::nan(""));
    }
  }

  void page_loads_at_the_time_asked() {
    const auto s = state("t=12");
    QCOMPARE(s.count("ready") ? s.at("ready") : QString(), QString("1"));
    QCOMPARE(s.at("frame"), QString("12"));  // logged each second from 0
    QCOMPARE(s.at("time"), QString("12"));
    const auto found = std::count_if(found_.begin(), found_.end(), [](double f) { return f <= 12; });
    QVERIFY(found > 0);
    QCOMPARE(s.at("found").toLong(), static_cast<long>(found));
  }

  /// At two times, the isolated flying drones' pixels hold their group's colour where drones.csv puts
  /// them; between the two they moved off where they were.
  void scrub_moves_the_drones() {
    const auto s = state("t=5");
    const double ox = s.at("ox").toDouble(), oy = s.at("oy").toDouble(), scale = s.at("scale").toDouble();
    QVERIFY(scale > 0.5);
    const auto at = [&](double x, double y) { return QPoint(static_cast<int>(std::floor(ox + scale * x)), static_cast<int>(std::floor(oy - scale * y))); };
    const auto isolated = [&](const std::map<int, Drone>& drones, int id, QPoint p) {
      for (const auto& [other, d] : drones)
        if (other != id && (at(d.x, d.y) - p).manhattanLength() < 30) return false;
      return true;
    };
    std::map<int, QPoint> before;
    for (const double t : {5.0, 25.0}) {
      const QImage shot = screenshot(QString("t=%1").arg(t), QString("t%1").arg(t));
      QCOMPARE(shot.size(), QSize(page_width, page_height));
      std::size_t checked[2] = {0, 0}, moved = 0;
      const auto& drones = drones_.at(t);
      for (const auto& [id, d] : drones) {
        const QPoint p = at(d.x, d.y);
        if (d.status != "flying" || !isolated(drones, id, p)) continue;
        const QColor c = shot.pixelColor(p);
        QVERIFY2(near(c, okabe_ito(d.group)), qPrintable(QString("t = %1 s, drone %2 at page pixel (%3, %4): %5, not its group's %6")
                                                                 .arg(t).arg(id).arg(p.x()).arg(p.y()).arg(rgb(c), rgb(okabe_ito(d.group)))));
        ++checked[d.group];
        // Where it was at 5 s, now empty: no drone (nor its tick) there.
        if (const auto was = before.find(id); was != before.end() && (was->second - p).manhattanLength() > 30 && isolated(drones, -1, was->second)) {
          QVERIFY2(!near(shot.pixelColor(was->second), okabe_ito(d.group)), qPrintable(QString("drone %1 still drawn where it was").arg(id)));
          ++moved;
        }
        before[id] = p;
      }
      QVERIFY2(checked[0] >= 2 && checked[1] >= 3, qPrintable(QString("t = %1 s: %2 and %3 drones checked").arg(t).arg(checked[0]).arg(checked[1])));
      if (t == 25.0) QVERIFY2(moved >= 3, qPrintable(QString("%1 drones seen moving").arg(moved)));
    }
  }

  /// A target is grey before its found time and green from it: at 15 s those found in the 3 s before
  /// are green and those found in the 3 s after grey (trails hidden, so that none covers them).
  void found_target_turns_green() {
    const auto s = state("t=0");
    const double ox = s.at("ox").toDouble(), oy = s.at("oy").toDouble(), scale = s.at("scale").toDouble();
    const auto at = [&](double x, double y) { return QPoint(static_cast<int>(std::floor(ox + scale * x)), static_cast<int>(std::floor(oy - scale * y))); };
    const double t = 15;
    const QImage shot = screenshot(QString("t=%1&trails=0").arg(t), "found");
    const auto is_green = [](QColor c) { return c.green() - c.red() > 50 && c.green() - c.blue() > 40; };
    const auto is_grey = [](QColor c) { return std::abs(c.red() - c.green()) < 15 && std::abs(c.green() - c.blue()) < 15 && c.red() < 215; };
    std::size_t checked[2] = {0, 0};
    for (std::size_t i = 0; i < targets_.size(); ++i) {
      if (!(std::abs(found_[i] - t) <= 3)) continue;
      const QPoint p = at(targets_[i].first, targets_[i].second);
      bool clear = true;  // no drone near it now, nor a second before (the picture lies between two frames)
      for (const double when : {t - 1, t})
        for (const auto& [id, d] : drones_.at(when)) clear = clear && (at(d.x, d.y) - p).manhattanLength() >= 30;
      if (!clear) continue;
      const bool found = found_[i] <= t;
      const QColor c = shot.pixelColor(p);
      QVERIFY2(found ? is_green(c) : is_grey(c), qPrintable(QString("target %1 (found at %2 s) at %3 s: %4, not %5")
                                                               .arg(i).arg(found_[i]).arg(t).arg(rgb(c), found ? "green" : "grey")));
      ++checked[found];
    }
    QVERIFY2(checked[0] >= 3 && checked[1] >= 3, qPrintable(QString("%1 targets grey and %2 green looked at").arg(checked[0]).arg(checked[1])));
  }

  void refuses_bad_destinations() {
    const QString file = dir_.path() + "/a-file";
    QVERIFY(write_file(file, "kept"));
    CliResult r = run_salsa({"export", test_, "--html", file});
    QCOMPARE(r.exit_code, 2);
    QVERIFY2(r.err.contains("--html: " + file + " is a file"), qPrintable(r.err));
    QCOMPARE(read_file(file), QByteArray("kept"));
    r = run_salsa({"export", test_, "--html", ""});
    QCOMPARE(r.exit_code, 2);
    QVERIFY2(r.err.contains("--html: an empty path"), qPrintable(r.err));
    r = run_salsa({"export", test_, "--html", test_ + "/page"});
    QCOMPARE(r.exit_code, 2);
    QVERIFY2(r.err.contains("is inside"), qPrintable(r.err));
    QVERIFY(!QFile::exists(test_ + "/page"));
  }
};

QTEST_GUILESS_MAIN(TestExportHtml)
#include "test_export_html.moc"
