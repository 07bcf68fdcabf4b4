#include "live_charts.hpp"

#include <QChart>
#include <QChartView>
#include <QLineSeries>
#include <QScrollArea>
#include <QValueAxis>
#include <QVBoxLayout>
#include <cmath>

namespace salsa::gui {
namespace {
struct Spec {
  const char* title;
  double StatsRow::*field;
  double fixed_max;  // 0: grows with the data
};
constexpr std::array<Spec, 4> specs{{{"Targets found (%)", &StatsRow::found_percent, 100},
                                     {"Coverage (%)", &StatsRow::coverage_percent, 100},
                                     {"Mean speed (m/s)", &StatsRow::mean_speed, 0},
                                     {"Mean nearest-neighbour distance (m)", &StatsRow::mean_nn_distance, 0}}};
constexpr int min_chart_height = 170;  // title, tick numbers and axis title all drawn in full
}  // namespace

LiveCharts::LiveCharts(QWidget* parent) : QWidget(parent) {
  // The charts scroll rather than shrink: below about 150 px Qt Charts elides every tick label to
  // "...", and four readable charts do not fit beside the view on a 768 px screen.
  auto* scroll = new QScrollArea;
  scroll->setObjectName("live_charts_scroll");
  scroll->setWidgetResizable(true);
  scroll->setHorizontalScrollBarPolicy(Qt::ScrollBarAlwaysOff);
  scroll->setFrameShape(QFrame::NoFrame);
  auto* outer = new QVBoxLayout(this);
  outer->setContentsMargins(0, 0, 0, 0);
  outer->addWidget(scroll);
  auto* inner = new QWidget;
  scroll->setWidget(inner);
  auto* layout = new QVBoxLayout(inner);
  layout->setContentsMargins(0, 0, 0, 0);
  layout->setSpacing(2);
  for (std::size_t i = 0; i < specs.size(); ++i) {
    Chart& c = charts_[i];
    auto* chart = new QChart;
    chart->setTitle(specs[i].title);
    chart->legend()->hide();
    chart->setMargins(QMargins(2, 2, 2, 2));
    chart->setBackgroundRoundness(0);
    QFont title = chart->titleFont();
    title.setPointSizeF(title.pointSizeF() * 0.9);
    chart->setTitleFont(title);
    c.series = new QLineSeries;
    c.series->setPen(QPen(QColor(0x1f, 0x4e, 0x9c), 1.6));
    chart->addSeries(c.series);
    c.x = new QValueAxis;
    c.y = new QValueAxis;
    c.x->setTitleText("time (s)");
    c.x->setLabelFormat("%.0f");
    c.y->setLabelFormat(specs[i].fixed_max > 0 ? "%.0f" : "%.1f");
    for (QValueAxis* a : {c.x, c.y}) {
      QFont f = a->labelsFont();
      f.setPointSizeF(f.pointSizeF() * 0.8);
      a->setLabelsFont(f);
      a->setTitleFont(f);
    }
    c.x->setRange(0, 10);
    c.x->setTickCount(6);
    c.y->setRange(0, specs[i].fixed_max > 0 ? specs[i].fixed_max : 1);
    chart->addAxis(c.x, Qt::AlignBottom);
    chart->addAxis(c.y, Qt::AlignLeft);
    c.series->attachAxis(c.x);
    c.series->attachAxis(c.y);
    c.view = new QChartView(chart);
    c.view->setRenderHint(QPainter::Antialiasing);
    c.view->setMinimumHeight(min_chart_height);
    layout->addWidget(c.view);
  }
}

void LiveCharts::show_rows(const std::shared_ptr<const std::vector<StatsRow>>& rows) {
  if (!rows || rows == shown_) return;
  shown_ = rows;
  const double end = rows->empty() ? 0 : rows->back().time;
  for (std::size_t i = 0; i < specs.size(); ++i) {
    QList<QPointF> points;
    points.reserve(static_cast<qsizetype>(rows->size()));
    double top = 0;
    for (const StatsRow& r : *rows) {
      const double v = r.*specs[i].field;
      if (!std::isfinite(v)) continue;
      points.append({r.time, v});
      top = std::max(top, v);
    }
    charts_[i].series->replace(points);  // one update of the whole series
    charts_[i].x->setRange(0, std::max(10.0, end));
    charts_[i].x->applyNiceNumbers();  // ticks at round times
    if (specs[i].fixed_max == 0) {
      charts_[i].y->setRange(0, top > 0 ? top * 1.1 : 1);
      charts_[i].y->applyNiceNumbers();
    }
  }
}

}  // namespace salsa::gui
