#pragma once
// The replay's playhead, apart from any widget (tests drive it): a time on the runs' timeline, playing
// at a speed (recorded seconds per wall second) or paused, moved by seeking or one frame at a time.
#include <QElapsedTimer>
#include <QObject>
#include <QTimer>
#include <vector>

namespace salsa::gui {

class Player : public QObject {
  Q_OBJECT
 public:
  explicit Player(QObject* parent = nullptr);

  /// The frames' times of every run open (any order, repeats allowed): stepping moves between them, and
  /// the timeline ends at the last. The playhead stays where it was, clamped to the new end.
  void set_frames(std::vector<double> times);
  double time() const { return time_; }
  double end() const { return frames_.empty() ? 0 : frames_.back(); }
  bool playing() const { return timer_.isActive(); }
  double speed() const { return speed_; }

  void play();   ///< from the start when at the end
  void pause();
  void toggle();
  void set_speed(double speed);  ///< recorded seconds per wall second, > 0
  void seek(double t);           ///< clamped to [0, end]
  void step(int frames);         ///< to the frame that many frames after (before, when negative) the playhead; pauses
  /// Playing: moves on by `wall_seconds` × speed, pausing at the end (the timer calls it every frame).
  void advance(double wall_seconds);

 Q_SIGNALS:
  void moved(double time);       ///< the playhead moved (any way)
  void playing_changed(bool playing);

 private:
  void move_to(double t);
  std::vector<double> frames_;  ///< sorted, unique
  double time_ = 0, speed_ = 1;
  QTimer timer_;
  QElapsedTimer clock_;
};

}  // namespace salsa::gui
