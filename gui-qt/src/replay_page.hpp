#pragma once
// Replay: finished tests played back without simulating (File > Open results…). One run, or two side by
// side in step on one timeline ("Compare with…"): each view shows its run's last frame at or before the
// playhead, drawn by the sandbox's view; the live plots show both runs up to the playhead and the
// inspector the clicked drone's recorded state in each.
#include <QString>
#include <QWidget>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "frame_renderer.hpp"
#include "player.hpp"
#include "salsa/core/replay/recording.hpp"

class QLabel;
class QPlainTextEdit;
class QPushButton;
class QComboBox;
class QSlider;
class QSplitter;

namespace salsa::gui {

class SwarmView;
class LiveCharts;

/// The rows the live plots draw for `recording`: from its summary.csv when it has one, else what the
/// recording itself gives (targets found and mean speed at each frame).
std::vector<StatsRow> recorded_stats(const Recording& recording);

/// How many frames of trail replay draws for `recording`: its drones' last 30 s, fewer when that
/// would be more than 100,000 points in all (at least 2).
std::size_t trail_frames(const Recording& recording);

class ReplayPage : public QWidget {
  Q_OBJECT
 public:
  explicit ReplayPage(QWidget* parent = nullptr);
  ~ReplayPage() override;

  /// Opens the finished test in `folder` as the only run, the playhead at 0. Empty on success, else the
  /// one line saying why (also shown on the page and sent as message); what was open stays open.
  std::string open(const QString& folder);
  /// Opens `folder` beside the first run (replacing a second one), in step on one timeline.
  std::string compare(const QString& folder);
  void ask_open();     ///< a folder dialog, then open
  void ask_compare();  ///< a folder dialog, then compare
  void set_view_options(const ViewOptions& options);
  void select(std::optional<std::uint32_t> id);  ///< inspect drone `id` in every run

  Player& player() { return player_; }
  std::size_t runs() const { return runs_.size(); }
  const Recording& recording(std::size_t run) const;
  SwarmView* view(std::size_t run) const;
  /// What view `run` draws now.
  std::shared_ptr<const Snapshot> shown(std::size_t run) const;
  LiveCharts* charts() const { return charts_; }
  QPlainTextEdit* inspector() const { return inspector_; }
  QSlider* timeline() const { return timeline_; }
  QLabel* note() const { return note_; }  ///< the last refusal
  QString title(std::size_t run) const;    ///< the label above view `run`

 Q_SIGNALS:
  void message(const QString& text, bool error);

 private:
  struct Run;
  std::string load(const QString& folder, std::size_t run);
  void runs_changed();
  void show_time(double t, bool force = false);
  void refresh_side_panels();

  Player player_;
  std::vector<std::unique_ptr<Run>> runs_;
  std::optional<std::uint32_t> selected_;
  ViewOptions options_;
  QSplitter* views_ = nullptr;
  QLabel* empty_ = nullptr;  ///< what to do, before a run is open
  LiveCharts* charts_ = nullptr;
  QPlainTextEdit* inspector_ = nullptr;
  QSlider* timeline_ = nullptr;
  QLabel* clock_ = nullptr;
  QLabel* note_ = nullptr;
  QPushButton* play_ = nullptr;
  QPushButton* compare_ = nullptr;
  QComboBox* speed_ = nullptr;
  qint64 charts_drawn_ = 0;  ///< ms since the epoch: playing, the plots redraw a few times a second
};

}  // namespace salsa::gui
