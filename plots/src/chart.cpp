#include "salsa/plots/chart.hpp"

#include <QApplication>
#include <QGraphicsScene>
#include <QImage>
#include <QPainter>
#include <QtCharts/QChart>
#include <QtCharts/QLineSeries>
#include <QtCharts/QLogValueAxis>
#include <QtCharts/QValueAxis>

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <string>
#include <cstdlib>
#include <memory>
#include <stdexcept>

namespace salsa::plots {

namespace {

// Charts are QGraphicsWidgets and need a QApplication; a headless program gets an offscreen one.
void ensure_application() {
  if (QCoreApplication::instance()) return;
  if (!std::getenv("QT_QPA_PLATFORM")) qputenv("QT_QPA_PLATFORM", "offscreen");
  if (!std::getenv("XDG_RUNTIME_DIR")) {  // Qt warns on stderr without one
    const std::string dir = "/tmp/salsa-runtime-" + std::to_string(::getuid());
    ::mkdir(dir.c_str(), 0700);
    qputenv("XDG_RUNTIME_DIR", dir.c_str());
  }
  static int argc = 1;
  static char name[] = "salsa";
  static char* argv[] = {name, nullptr};
  static QApplication app(argc, argv);
}

QAbstractAxis* make_axis(bool log, const std::string& title, double lo, double hi) {
  QAbstractAxis* axis;
  if (log) {
    auto* a = new QLogValueAxis;
    a->setBase(10);
    a->setLabelFormat("%g");
    a->setRange(lo, hi);
    axis = a;
  } else {
    auto* a = new QValueAxis;
    a->setRange(lo, hi);
    a->setLabelFormat("%g");
    axis = a;
  }
  axis->setTitleText(QString::fromStdString(title));
  return axis;
}

}  // namespace

void save_png(const Chart& chart, const std::filesystem::path& file, int width, int height) {
  ensure_application();
  double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
  for (const auto& s : chart.series)
    for (auto [x, y] : s.points) {
      if ((chart.log_x && x <= 0) || (chart.log_y && y <= 0)) continue;
      x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
    }
  if (x0 > x1) x0 = 0, x1 = 1, y0 = 0, y1 = 1;
  if (x0 == x1) x0 -= 0.5, x1 += 0.5;
  if (y0 == y1) y0 -= 0.5, y1 += 0.5;
  if (chart.log_y) y0 /= 2, y1 *= 2;
  else y0 = std::min(0.0, y0), y1 += (y1 - y0) * 0.05;

  QGraphicsScene scene;
  auto* c = new QChart;  // owned by the scene
  c->setTitle(QString::fromStdString(chart.title));
  c->setAnimationOptions(QChart::NoAnimation);
  c->legend()->setAlignment(Qt::AlignBottom);
  QAbstractAxis* ax = make_axis(chart.log_x, chart.x_label, x0, x1);
  QAbstractAxis* ay = make_axis(chart.log_y, chart.y_label, y0, y1);
  c->addAxis(ax, Qt::AlignBottom);
  c->addAxis(ay, Qt::AlignLeft);
  for (const auto& s : chart.series) {
    auto* line = new QLineSeries;
    line->setName(QString::fromStdString(s.name));
    line->setPointsVisible(s.points.size() < 50);
    for (auto [x, y] : s.points)
      if (!(chart.log_x && x <= 0) && !(chart.log_y && y <= 0)) line->append(x, y);
    c->addSeries(line);
    line->attachAxis(ax);
    line->attachAxis(ay);
  }
  scene.addItem(c);
  c->resize(width, height);
  QCoreApplication::processEvents();  // lets the chart lay out its axes and legend before it is drawn

  QImage image(width, height, QImage::Format_ARGB32);
  image.fill(Qt::white);
  {
    QPainter painter(&image);
    painter.setRenderHint(QPainter::Antialiasing);
    scene.render(&painter, QRectF(0, 0, width, height), QRectF(0, 0, width, height));
  }
  if (!image.save(QString::fromStdString(file.string()), "PNG"))
    throw std::runtime_error(file.string() + ": cannot write PNG");
}

}  // namespace salsa::plots
