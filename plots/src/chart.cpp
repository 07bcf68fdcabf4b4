#include "salsa/plots/chart.hpp"

#include <QApplication>
#include <QGraphicsScene>
#include <QImage>
#include <QPainter>
#include <QtCharts/QChart>
#include <QtCharts/QLineSeries>
#include <QtCharts/QLogValueAxis>
#include <QtCharts/QValueAxis>

#include <algorithm>
#include <string>
#include <memory>
#include <stdexcept>

#include "figure.hpp"
#include "salsa/plots/results.hpp"

namespace salsa::plots {

namespace {

QAbstractAxis* make_axis(bool log, const std::string& title, double lo, double hi) {
  QAbstractAxis* axis;
  if (log) {
    auto* a = new QLogValueAxis;
    a->setBase(10);
    a->setLabelFormat("%g");
    a->setRange(lo, hi);
    axis = a;
  } else {
    // Round ticks from the range's ends: Qt's own split the raw range into equal parts (37.275).
    const std::vector<double> ticks = nice_ticks(lo, hi);
    auto* a = new QValueAxis;
    a->setRange(ticks.front(), ticks.back());
    a->setTickCount(static_cast<int>(ticks.size()));
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
  else y0 = std::min(0.0, y0);

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
  write_png(image, file);
}

}  // namespace salsa::plots
