#include "live_charts.hpp"

#include <QChart>
#include <QChartView>
#include <QLegend>
#include <QLegendMarker>
#include <QLineSeries>
#include <QScrollArea>
#include <QValueAxis>
#include <QVBoxLayout>
#include <algorithm>
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
    const QColor colours[] = {QColor(0x1f, 0x4e, 0x9c), QColor(0xd5, 0x5e, 0x00)};
    for (std::size_t run = 0; run < 2; ++run) {
      c.series[run] = new QLineSeries;
      c.series[run]->setPen(QPen(colours[run], 1.6));
      chart->addSeries(c.series[run]);
    }
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
    for (QLineSeries* s : c.series) s->attachAxis(c.x), s->attachAxis(c.y);
    c.view = new QChartView(chart);
    c.view->setRenderHint(QPainter::Antialiasing);
    c.view->setMinimumHeight(min_chart_height);
    layout->addWidget(c.view);
  }
}

void LiveCharts::show_rows(const std::shared_ptr<const std::vector<StatsRow>>& rows, int run) {
  const auto r = static_cast<std::size_t>(run);
  if ((!rows && r == 0) || rows == shown_[r]) return;
  shown_[r] = rows;
  ends_[r] = !rows || rows->empty() ? 0 : rows->back().time;
  const double end = std::max(ends_[0], ends_[1]);
  for (std::size_t i = 0; i < specs.size(); ++i) {
    QList<QPointF> points;
    if (rows) {
      points.reserve(static_cast<qsizetype>(rows->size()));
      for (const StatsRow& row : *rows)
        if (const double v = row.*specs[i].field; std::isfinite(v)) points.append({row.time, v});
    }
    charts_[i].series[r]->replace(points);  // one update of the whole series
    charts_[i].x->setRange(0, std::max(10.0, end));
    charts_[i].x->applyNiceNumbers();  // ticks at round times
    if (specs[i].fixed_max == 0) {
      double top = 0;
      for (QLineSeries* s : charts_[i].series)
        for (const QPointF& p : s->points()) top = std::max(top, p.y());
      charts_[i].y->setRange(0, top > 0 ? top * 1.1 : 1);
      charts_[i].y->applyNiceNumbers();
    }
  }
}

void LiveCharts::set_names(const QString& first, const QString& second) {
  for (Chart& c : charts_) {
    c.series[0]->setName(first);
    c.series[1]->setName(second);
    QLegend* legend = c.view->chart()->legend();
    legend->markers(c.series[1]).first()->setVisible(!second.isEmpty());
    legend->setVisible(!second.isEmpty());
  }
}

}  // namespace salsa::gui
