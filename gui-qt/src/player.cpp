#include "player.hpp"

#include <algorithm>

namespace salsa::gui {

Player::Player(QObject* parent) : QObject(parent) {
  timer_.setInterval(16);  // the display's 60 Hz: each tick draws the frame at the playhead
  connect(&timer_, &QTimer::timeout, this, [this] {
    const double wall = static_cast<double>(clock_.nsecsElapsed()) / 1e9;
    clock_.restart();
    advance(wall);
  });
}

void Player::set_frames(std::vector<double> times) {
  std::sort(times.begin(), times.end());
  times.erase(std::unique(times.begin(), times.end()), times.end());
  frames_ = std::move(times);
  move_to(std::clamp(time_, 0.0, end()));
}

void Player::play() {
  if (playing() || frames_.empty()) return;
  if (time_ >= end()) move_to(0);
  clock_.start();
  timer_.start();
  Q_EMIT playing_changed(true);
}

void Player::pause() {
  if (!playing()) return;
  timer_.stop();
  Q_EMIT playing_changed(false);
}

void Player::toggle() { playing() ? pause() : play(); }

void Player::set_speed(double speed) {
  if (speed > 0) speed_ = speed;
}

void Player::seek(double t) { move_to(std::clamp(t, 0.0, end())); }

void Player::step(int frames) {
  pause();
  if (frames_.empty() || frames == 0) return;
  // The frame shown is the last at or before the playhead; step from it.
  auto at = std::upper_bound(frames_.begin(), frames_.end(), time_);
  std::ptrdiff_t i = (at - frames_.begin()) - 1 + frames;
  i = std::clamp<std::ptrdiff_t>(i, 0, static_cast<std::ptrdiff_t>(frames_.size()) - 1);
  move_to(frames_[static_cast<std::size_t>(i)]);
}

void Player::advance(double wall_seconds) {
  if (!playing()) return;
  const double t = time_ + wall_seconds * speed_;
  move_to(std::min(t, end()));
  if (t >= end()) pause();
}

void Player::move_to(double t) {
  time_ = t;
  Q_EMIT moved(t);
}

}  // namespace salsa::gui
