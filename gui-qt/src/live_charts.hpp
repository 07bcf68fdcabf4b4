#pragma once
// The live plots beside the sandbox view (Qt Charts): targets found, coverage, mean speed and mean
// nearest-neighbour distance over time. Fed from the snapshots' rows with QXYSeries::replace, a few
// times a second (the caller's timer), never per step. Replay draws two runs side by side in one set
// of charts: a second line each, and a legend naming the runs.
#include <QString>
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
  /// Shows `rows` as run `run` (0, or 1 beside it); does nothing when it is the object shown last.
  /// Null for run 1: one run alone.
  void show_rows(const std::shared_ptr<const std::vector<StatsRow>>& rows, int run = 0);
  /// The runs' names in the legend (shown while run 1 has a name).
  void set_names(const QString& first, const QString& second);
  QLineSeries* series(int i, int run = 0) const { return charts_[static_cast<std::size_t>(i)].series[static_cast<std::size_t>(run)]; }
  QChartView* view(int i) const { return charts_[static_cast<std::size_t>(i)].view; }

 private:
  struct Chart {
    QChartView* view = nullptr;
    std::array<QLineSeries*, 2> series{};
    QValueAxis* x = nullptr;
    QValueAxis* y = nullptr;
  };
  std::array<Chart, 4> charts_;
  std::array<std::shared_ptr<const std::vector<StatsRow>>, 2> shown_;
  std::array<double, 2> ends_{};  ///< s, the last row's time of each run shown
};

}  // namespace salsa::gui
