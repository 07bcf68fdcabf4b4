// SwarmView: the sandbox's view of the swarm, with zoom, pan, fit and click to select.
#include "view.hpp"

#include <QKeyEvent>
#include <QMouseEvent>
#include <QPainter>
#include <QWheelEvent>
#include <algorithm>
#include <cmath>
#include <limits>

#include "view_draw.hpp"

namespace salsa::gui {

SwarmView::SwarmView(QWidget* parent) : QWidget(parent) {
  setAttribute(Qt::WA_OpaquePaintEvent);  // the static layer covers every pixel
  setFocusPolicy(Qt::StrongFocus);
  setMinimumSize(400, 300);
  setMouseTracking(false);
}

void SwarmView::show_snapshot(std::shared_ptr<const Snapshot> snap) {
  const bool first = !snap_ || (snap && snap_->scene != snap->scene && snap_->scene && snap->scene &&
                                snap_->scene->map.bounds != snap->scene->map.bounds);
  snap_ = std::move(snap);
  if (first) fit();
  update();
}

void SwarmView::set_options(const ViewOptions& options) {
  options_ = options;
  update();
}

void SwarmView::fit() {
  zoom_ = 1;
  pan_ = {};
  update();
}

QTransform SwarmView::world_to_px() const {
  const Rect area = snap_ && snap_->scene ? snap_->scene->map.bounds : Rect{{0, 0}, {1, 1}};
  QTransform t = fit_transform(area, QSizeF(size()));
  // Zoom about the widget's centre, then pan (in pixels).
  const QPointF c(width() / 2.0, height() / 2.0);
  QTransform z;
  z.translate(c.x() + pan_.x(), c.y() + pan_.y());
  z.scale(zoom_, zoom_);
  z.translate(-c.x(), -c.y());
  return t * z;
}

void SwarmView::zoom(double factor, std::optional<QPointF> around) {
  const double next = std::clamp(zoom_ * factor, 0.2, 2000.0);
  factor = next / zoom_;
  // Keep the point under `around` (default: the centre) where it is on screen.
  const QPointF c(width() / 2.0, height() / 2.0);
  const QPointF a = around.value_or(c);
  pan_ = (pan_ + c - a) * factor + a - c;
  zoom_ = next;
  update();
}

QImage SwarmView::screenshot() { return grab().toImage(); }

void SwarmView::paintEvent(QPaintEvent*) {
  QPainter painter(this);
  if (!snap_) {
    painter.fillRect(rect(), map_background);
    return;
  }
  renderer_.draw(painter, size(), *snap_, options_, world_to_px());
}

void SwarmView::wheelEvent(QWheelEvent* event) {
  const double steps = event->angleDelta().y() / 120.0;
  zoom(std::pow(1.25, steps), event->position());
  event->accept();
}

void SwarmView::mousePressEvent(QMouseEvent* event) {
  if (event->button() != Qt::LeftButton) return;
  press_ = event->position().toPoint();
  dragged_ = false;
}

void SwarmView::mouseMoveEvent(QMouseEvent* event) {
  if (!press_) return;
  const QPoint delta = event->position().toPoint() - *press_;
  if (!dragged_ && delta.manhattanLength() < 4) return;  // a click may wobble a little
  dragged_ = true;
  pan_ += QPointF(delta);
  press_ = event->position().toPoint();
  update();
}

void SwarmView::mouseReleaseEvent(QMouseEvent* event) {
  if (event->button() != Qt::LeftButton || !press_) return;
  press_.reset();
  if (dragged_ || !snap_) return;
  // The nearest drone whose circle (at least 6 px) holds the click.
  const QTransform t = world_to_px();
  std::optional<std::uint32_t> best;
  double best_d = std::numeric_limits<double>::infinity();
  for (std::uint32_t i = 0; i < snap_->positions.size(); ++i) {
    if (snap_->status_of(i) == DroneStatus::removed) continue;
    const QPointF p = t.map(QPointF(snap_->positions[i].x, snap_->positions[i].y));
    const double d = std::hypot(p.x() - event->position().x(), p.y() - event->position().y());
    if (d <= std::max(6.0, snap_->drone_of(i).radius * px_per_m(t)) && d < best_d) best_d = d, best = i;
  }
  Q_EMIT drone_clicked(best);
}

void SwarmView::keyPressEvent(QKeyEvent* event) {
  switch (event->key()) {
    case Qt::Key_Plus:
    case Qt::Key_Equal: zoom(1.25); break;
    case Qt::Key_Minus: zoom(0.8); break;
    case Qt::Key_0:
    case Qt::Key_F: fit(); break;
    default: QWidget::keyPressEvent(event); return;
  }
  event->accept();
}

void SwarmView::resizeEvent(QResizeEvent* event) {
  QWidget::resizeEvent(event);
  update();
}

}  // namespace salsa::gui
