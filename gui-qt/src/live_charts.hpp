#pragma once
// The live plots beside the sandbox view (Qt Charts): targets found, coverage, mean speed and mean
// nearest-neighbour distance over time. Fed from the snapshots' rows with QXYSeries::replace, a few
// times a second (the caller's timer), never per step.
#include <QWidget>
#include <array>
#include <memory>
#include <vector>

#include "engine.hpp"

class QLineSeries;
class QValueAxis;
class QChartView;

namespace salsa::gui {

class LiveCharts : public QWidget {
  Q_OBJECT
 public:
  explicit LiveCharts(QWidget* parent = nullptr);
  /// Shows `rows` (does nothing when it is the object shown last).
  void show_rows(const std::shared_ptr<const std::vector<StatsRow>>& rows);
  QLineSeries* series(int i) const { return charts_[static_cast<std::size_t>(i)].series; }
  QChartView* view(int i) const { return charts_[static_cast<std::size_t>(i)].view; }

 private:
  struct Chart {
    QChartView* view = nullptr;
    QLineSeries* series = nullptr;
    QValueAxis* x = nullptr;
    QValueAxis* y = nullptr;
  };
  std::array<Chart, 4> charts_;
  std::shared_ptr<const std::vector<StatsRow>> shown_;
};

}  // namespace salsa::gui
