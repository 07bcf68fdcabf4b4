#include "view.hpp"

#include <QKeyEvent>
#include <QMouseEvent>
#include <QPainter>
#include <QPainterPath>
#include <QWheelEvent>
#include <algorithm>
#include <cmath>
#include <limits>

namespace salsa::gui {
namespace {

const QColor background(0xf4, 0xf1, 0xea);
const QColor outside(0xd8, 0xd4, 0xcc);
const QColor obstacle_fill(0x6b, 0x6b, 0x6b);
const QColor obstacle_line(0x3c, 0x3c, 0x3c);
const QColor found_colour(0x2e, 0x9e, 0x48);
const QColor unfound_colour(0x9a, 0x9a, 0x9a);
const QColor drone_colour(0x1f, 0x3f, 0x8c);  // one group
const QColor spawn_colour(0x8c, 0x1f, 0x6b);
const QColor selected_colour(0xe0, 0x3a, 0x1e);
const QColor neighbour_colour(0xf0, 0x9a, 0x1a);

QPolygonF polygon(const Polyline& points) {
  QPolygonF out;
  out.reserve(static_cast<qsizetype>(points.size()));
  for (Vec2 p : points) out << QPointF(p.x, p.y);
  return out;
}

/// The heat map as an image, one pixel per cell (row 0 at the bottom: flipped by the transform).
QImage heat_image(const HeatMap& heat) {
  QImage image(heat.cols, heat.rows, QImage::Format_ARGB32_Premultiplied);
  for (int r = 0; r < heat.rows; ++r) {
    auto* line = reinterpret_cast<QRgb*>(image.scanLine(r));
    for (int c = 0; c < heat.cols; ++c) {
      const float v = heat.values[static_cast<std::size_t>(r) * heat.cols + c] / 100.f;  // 0..1
      if (v <= 0) {
        line[c] = 0;
        continue;
      }
      // Transparent yellow to opaque red, on a square-root scale so rare visits still show.
      const float s = std::sqrt(v);
      const int alpha = static_cast<int>(40 + 190 * s);
      const int red = 255, green = static_cast<int>(210 - 170 * s), blue = static_cast<int>(40 * (1 - s));
      line[c] = qPremultiply(qRgba(red, green, blue, alpha));
    }
  }
  return image;
}

double px_per_m(const QTransform& t) { return std::hypot(t.m11(), t.m12()); }

/// A ✕ with a white rim where a drone stopped (landed or failed), as the plots draw it.
void draw_cross(QPainter& p, QPointF at, const QColor& colour) {
  const QPointF a(5, 5), b(5, -5);
  for (const QPen& pen : {QPen(Qt::white, 5, Qt::SolidLine, Qt::RoundCap), QPen(colour, 2.5, Qt::SolidLine, Qt::RoundCap)}) {
    p.setPen(pen);
    p.drawLine(at - a, at + a);
    p.drawLine(at - b, at + b);
  }
}

/// An antialiased disc of `diameter` px, stamped for each target: ~10× faster than drawPoints with a
/// round pen (50,000 targets: 3–8 ms against 50–110 ms at 1920×1080).
QImage disc(double diameter, const QColor& colour) {
  const int side = static_cast<int>(std::ceil(diameter)) + 2;
  QImage image(side, side, QImage::Format_ARGB32_Premultiplied);
  image.fill(Qt::transparent);
  QPainter p(&image);
  p.setRenderHint(QPainter::Antialiasing, true);
  p.setPen(Qt::NoPen);
  p.setBrush(colour);
  p.drawEllipse(QPointF(side / 2.0, side / 2.0), diameter / 2, diameter / 2);
  return image;
}

/// Targets `which(i)` of `scene`, found ones green and the others grey, those on screen only. The
/// painter has no transform (pixels).
template <class Which>
void draw_targets(QPainter& painter, const Scene& scene, const std::vector<std::uint8_t>& found, const QTransform& world_to_px,
                  Which which) {
  const double diameter = std::max(2.0, 2 * scene.target_radius * px_per_m(world_to_px));
  const QRectF visible = QRectF(painter.viewport()).adjusted(-diameter, -diameter, diameter, diameter);
  const QImage sprites[2] = {disc(diameter, unfound_colour), disc(diameter, found_colour)};
  const double half = sprites[0].width() / 2.0;
  for (std::size_t i = 0; i < scene.targets.size(); ++i) {
    if (!which(i)) continue;
    const QPointF p = world_to_px.map(QPointF(scene.targets[i].x, scene.targets[i].y));
    if (!visible.contains(p)) continue;
    painter.drawImage(QPointF(p.x() - half, p.y() - half), sprites[i < found.size() && found[i] ? 1 : 0]);
  }
}

}  // namespace

QColor group_colour(std::size_t group, std::size_t groups) {
  // Okabe & Ito's colour-blind-safe set in the plots' order (plots/src/figure.cpp), so a group has one
  // colour on screen and in the figures.
  static const QColor colours[] = {0xE69F00, 0x0072B2, 0x009E73, 0xD55E00, 0x56B4E9, 0xCC79A7, 0xF0E442};
  return groups < 2 ? drone_colour : colours[group % std::size(colours)];
}

QStringList legend_rows(const Snapshot& snap) {
  if (snap.groups.size() < 2) return {};
  std::vector<std::size_t> flying(snap.groups.size()), stopped(snap.groups.size());
  for (std::uint32_t i = 0; i < snap.positions.size(); ++i) {
    const std::size_t g = std::min<std::size_t>(snap.group_of(i), snap.groups.size() - 1);
    const DroneStatus status = snap.status_of(i);
    if (status == DroneStatus::flying) ++flying[g];
    else if (status != DroneStatus::removed) ++stopped[g];
  }
  QStringList rows;
  for (std::size_t g = 0; g < snap.groups.size(); ++g)
    rows << QString("%1: %2 flying").arg(QString::fromStdString(snap.groups[g].name)).arg(flying[g]) +
                (stopped[g] ? QString(", %1 stopped").arg(stopped[g]) : QString());
  if (std::any_of(stopped.begin(), stopped.end(), [](std::size_t n) { return n > 0; })) rows << "landed or failed";
  return rows;
}

namespace {

/// legend_rows in a box, top left, each beside its symbol: the group's disc, or the ✕ of a stopped drone.
void draw_legend(QPainter& painter, const Snapshot& snap) {
  const QStringList rows = legend_rows(snap);
  QFont font = painter.font();
  font.setPixelSize(12);
  painter.setFont(font);
  const QFontMetrics metrics(font);
  const int line = metrics.height() + 4;
  int width = 0;
  for (const QString& r : rows) width = std::max(width, metrics.horizontalAdvance(r));
  const QRectF box(8, 8, width + 38, line * static_cast<int>(rows.size()) + 8);
  painter.setPen(QPen(QColor(0, 0, 0, 60), 1));
  painter.setBrush(QColor(255, 255, 255, 215));
  painter.drawRoundedRect(box, 4, 4);
  for (int k = 0; k < static_cast<int>(rows.size()); ++k) {
    const QPointF symbol(box.left() + 16, box.top() + 4 + line * (k + 0.5));
    const bool group = static_cast<std::size_t>(k) < snap.groups.size();
    const QColor colour = group ? group_colour(static_cast<std::size_t>(k), snap.groups.size()) : QColor(0x55, 0x55, 0x55);
    if (group) {
      painter.setPen(Qt::NoPen);
      painter.setBrush(colour);
      painter.drawEllipse(symbol, 5, 5);
    } else {
      draw_cross(painter, symbol, colour);
    }
    painter.setPen(Qt::black);
    painter.drawText(QRectF(box.left() + 30, symbol.y() - line / 2.0, width + 4, line), Qt::AlignLeft | Qt::AlignVCenter, rows[k]);
  }
}

}  // namespace

QTransform fit_transform(const Rect& area, QSizeF size) {
  const double w = std::max(area.width(), 1e-9), h = std::max(area.height(), 1e-9);
  const double margin = 12;
  const double scale = std::max(1e-9, std::min((size.width() - 2 * margin) / w, (size.height() - 2 * margin) / h));
  const double cx = (area.min.x + area.max.x) / 2, cy = (area.min.y + area.max.y) / 2;
  // y up: world y grows towards the top of the picture.
  return QTransform(scale, 0, 0, -scale, size.width() / 2 - scale * cx, size.height() / 2 + scale * cy);
}

void render_static(QPainter& painter, const Snapshot& snap, const ViewOptions& options, const QTransform& world_to_px) {
  painter.save();
  painter.fillRect(painter.viewport(), outside);
  if (!snap.scene) {
    painter.restore();
    return;
  }
  const Scene& scene = *snap.scene;
  const Rect& b = scene.map.bounds;
  painter.setTransform(world_to_px);
  const QRectF bounds(QPointF(b.min.x, b.min.y), QPointF(b.max.x, b.max.y));
  painter.fillRect(bounds, background);
  if (options.heat_map && snap.heat && !snap.heat->values.empty()) {
    const HeatMap& h = *snap.heat;
    painter.setRenderHint(QPainter::SmoothPixmapTransform, true);
    painter.drawImage(QRectF(h.origin.x, h.origin.y, h.cell * h.cols, h.cell * h.rows), heat_image(h));
  }
  painter.setRenderHint(QPainter::Antialiasing, true);
  const double px = px_per_m(world_to_px);
  if (options.obstacles) {
    QPen line(obstacle_line, 1.5 / px);
    painter.setPen(line);
    painter.setBrush(obstacle_fill);
    for (const auto& o : scene.map.obstacles) painter.drawPolygon(polygon(o));
    painter.setBrush(Qt::NoBrush);
    QPen wall(obstacle_line, std::max(2.0 / px, 0.5));
    painter.setPen(wall);
    for (const auto& o : scene.map.hollow) painter.drawPolygon(polygon(o));
    for (const auto& l : scene.map.lines) painter.drawPolyline(polygon(l));
  }
  painter.setPen(QPen(obstacle_line, 2 / px));
  painter.drawRect(bounds);
  if (options.targets && !scene.targets.empty()) {
    painter.resetTransform();
    draw_targets(painter, scene, snap.found, world_to_px, [](std::size_t) { return true; });
    painter.setTransform(world_to_px);
  }
  if (options.spawn) {  // each group's base, in its colour when there are several
    painter.resetTransform();
    painter.setRenderHint(QPainter::Antialiasing, true);
    painter.setBrush(Qt::NoBrush);
    for (std::size_t g = 0; g < scene.bases.size(); ++g) {
      const QPointF s = world_to_px.map(QPointF(scene.bases[g].x, scene.bases[g].y));
      painter.setPen(QPen(scene.bases.size() < 2 ? spawn_colour : group_colour(g, scene.bases.size()).darker(130), 2));
      painter.drawEllipse(s, 7, 7);
      painter.drawLine(s - QPointF(10, 0), s + QPointF(10, 0));
      painter.drawLine(s - QPointF(0, 10), s + QPointF(0, 10));
    }
  }
  painter.restore();
}

void render_dynamic(QPainter& painter, const Snapshot& snap, const ViewOptions& options, const QTransform& world_to_px) {
  painter.save();
  painter.resetTransform();
  painter.setRenderHint(QPainter::Antialiasing, true);
  const double px = px_per_m(world_to_px);
  const std::size_t n = snap.positions.size();
  const std::size_t groups = std::max<std::size_t>(1, snap.groups.size());
  std::vector<QPointF> at(n);
  for (std::size_t i = 0; i < n; ++i) at[i] = world_to_px.map(QPointF(snap.positions[i].x, snap.positions[i].y));
  // Ids by group, drawn a group at a time (one brush each); removed drones are not drawn.
  std::vector<std::vector<std::uint32_t>> members(groups);
  for (std::uint32_t i = 0; i < n; ++i)
    if (snap.status_of(i) != DroneStatus::removed) members[std::min<std::size_t>(snap.group_of(i), groups - 1)].push_back(i);
  const auto flying = [&](std::uint32_t i) { return snap.status_of(i) == DroneStatus::flying; };
  const auto radius_of = [&](std::uint32_t i) { return std::max(3.0, snap.drone_of(i).radius * px); };

  if (options.trails && snap.trail_length > 1 && snap.trails.size() >= n * snap.trail_length) {
    // One batch of lines per group, decimated on screen: a sample closer than 2 px to the last one
    // drawn adds nothing visible, so the cost follows the trails' length in pixels, not in samples.
    std::vector<QLineF> lines;
    lines.reserve(n * 8);
    const QRectF visible = QRectF(painter.viewport()).adjusted(-50, -50, 50, 50);
    for (std::size_t g = 0; g < groups; ++g) {
      lines.clear();
      for (std::uint32_t d : members[g]) {
        std::optional<QPointF> last;
        for (std::size_t k = 0; k <= snap.trail_length; ++k) {
          const Vec2 p = k < snap.trail_length ? snap.trails[d * snap.trail_length + k] : snap.positions[d];
          if (!std::isfinite(p.x)) {
            last.reset();
            continue;
          }
          const QPointF q = world_to_px.map(QPointF(p.x, p.y));
          if (last && std::abs(q.x() - last->x()) + std::abs(q.y() - last->y()) < 2 && k < snap.trail_length) continue;
          if (last && (visible.contains(q) || visible.contains(*last))) lines.emplace_back(*last, q);
          last = q;
        }
      }
      QColor trail = group_colour(g, groups);
      trail.setAlpha(70);
      painter.setPen(QPen(trail, 1.2));
      painter.drawLines(lines.data(), static_cast<int>(lines.size()));
    }
  }

  if (options.wind && !snap.wind.empty()) {
    // Arrows on the snapshot's grid, the strongest as long as 80 % of a grid cell; the scale is written
    // at the bottom right so that lengths compare across frames.
    double strongest = 0;
    for (const auto& [p, w] : snap.wind) strongest = std::max(strongest, w.length());
    if (strongest > 0) {
      const QPointF a0 = world_to_px.map(QPointF(snap.wind[0].first.x, snap.wind[0].first.y));
      const QPointF a1 = world_to_px.map(QPointF(snap.wind[1 % snap.wind.size()].first.x, snap.wind[1 % snap.wind.size()].first.y));
      const double cell = std::max(8.0, std::hypot(a1.x() - a0.x(), a1.y() - a0.y()));
      const double scale = 0.8 * cell / strongest;  // px per m/s
      const QColor colour(0x3a, 0x5f, 0x7d, 150);
      painter.setPen(QPen(colour, 1.4));
      for (const auto& [p, w] : snap.wind) {
        const QPointF from = world_to_px.map(QPointF(p.x, p.y));
        const QPointF screen = world_to_px.map(QPointF(p.x + w.x, p.y + w.y)) - from;  // y flips with the map
        const double length = std::hypot(screen.x(), screen.y());
        if (length <= 0) continue;
        const QPointF d = screen / length * (w.length() * scale);
        const QPointF tip = from + d / 2, tail = from - d / 2;
        painter.drawLine(tail, tip);
        const QPointF back = -d / std::max(1.0, std::hypot(d.x(), d.y())) * std::min(8.0, 0.35 * std::hypot(d.x(), d.y()));
        const QPointF side(-back.y() * 0.5, back.x() * 0.5);
        painter.drawLine(tip, tip + back + side);
        painter.drawLine(tip, tip + back - side);
      }
      const QString label = QString("wind up to %1 m/s").arg(strongest, 0, 'f', 1);
      const QRectF box = QRectF(painter.viewport()).adjusted(0, 0, -10, -8);
      painter.drawText(box, Qt::AlignRight | Qt::AlignBottom, label);
    }
  }

  if (options.links && !snap.links.empty()) {
    // Each delivery once a pair: a link heard both ways is one line, drawn purple under the drones.
    std::vector<QLineF> lines;
    lines.reserve(snap.links.size());
    for (const auto& [receiver, sender] : snap.links)
      if (receiver < n && sender < n && (sender < receiver || !std::binary_search(snap.links.begin(), snap.links.end(), std::pair{sender, receiver})))
        lines.emplace_back(at[receiver], at[sender]);
    painter.setPen(QPen(QColor(0x7b, 0x3f, 0xa0, 90), 1));
    painter.drawLines(lines.data(), static_cast<int>(lines.size()));
  }

  struct Range {
    bool on;
    double DroneConfig::*metres;
    QColor colour;
  };
  for (const Range& r : {Range{options.detection_range, &DroneConfig::detection_range, QColor(0x1f, 0x3f, 0x8c, 60)},
                         Range{options.obstacle_range, &DroneConfig::obstacle_range, QColor(0x8c, 0x4f, 0x1f, 80)},
                         Range{options.camera_range, &DroneConfig::camera_range, QColor(0x2e, 0x9e, 0x48, 110)}}) {
    if (!r.on) continue;
    painter.setPen(QPen(r.colour, 1));
    painter.setBrush(QColor(r.colour.red(), r.colour.green(), r.colour.blue(), r.colour.alpha() / 4));
    for (std::size_t g = 0; g < groups; ++g) {
      if (members[g].empty()) continue;
      const double radius = snap.drone_of(members[g].front()).*r.metres * px;
      if (radius <= 0) continue;
      for (std::uint32_t i : members[g])
        if (flying(i) && (r.metres != &DroneConfig::camera_range || snap.camera_works(i))) painter.drawEllipse(at[i], radius, radius);
    }
  }

  // Drones: discs with one brush per group (a QPainterPath of all of them is 10× slower to fill), a ring
  // for a drone whose camera failed, then one batch of velocity ticks; a ✕ where a drone stopped.
  std::vector<QLineF> ticks;
  ticks.reserve(n);
  for (std::size_t g = 0; g < groups; ++g) {
    if (members[g].empty()) continue;
    const QColor colour = group_colour(g, groups);
    const double radius = radius_of(members[g].front());
    painter.setPen(Qt::NoPen);
    painter.setBrush(colour);
    for (std::uint32_t i : members[g])
      if (flying(i) && snap.camera_works(i)) painter.drawEllipse(at[i], radius, radius);
    painter.setPen(QPen(colour, 2));
    painter.setBrush(Qt::NoBrush);
    for (std::uint32_t i : members[g])
      if (flying(i) && !snap.camera_works(i)) painter.drawEllipse(at[i], radius - 1, radius - 1);
    ticks.clear();
    for (std::uint32_t i : members[g]) {
      const Vec2 v = snap.velocities[i];
      const double speed = v.length();
      if (speed <= 0 || !flying(i)) continue;
      const QPointF dir(v.x / speed, -v.y / speed);  // screen y points down
      ticks.emplace_back(at[i], at[i] + dir * (radius + 5));
    }
    painter.setPen(QPen(colour, 1.5));
    painter.drawLines(ticks.data(), static_cast<int>(ticks.size()));
    for (std::uint32_t i : members[g])
      if (!flying(i)) draw_cross(painter, at[i], colour);
  }

  if (snap.selected && snap.selected->id < n) {
    const Inspection& in = *snap.selected;
    const QPointF me = at[in.id];
    const double radius = radius_of(in.id);
    painter.setBrush(Qt::NoBrush);
    painter.setPen(QPen(neighbour_colour, 2));
    for (std::uint32_t j : in.neighbours)
      if (j < n) painter.drawEllipse(at[j], radius_of(j) + 3, radius_of(j) + 3);
    painter.setPen(QPen(selected_colour, 1.5, Qt::DashLine));
    for (const ObstacleHit& h : in.hits) {
      const QPointF hit = world_to_px.map(QPointF(h.point.x, h.point.y));
      painter.drawLine(me, hit);
      painter.drawEllipse(hit, 3, 3);
    }
    painter.setPen(QPen(selected_colour, 2.5));
    painter.drawEllipse(me, radius + 5, radius + 5);
    if (const double range = snap.drone_of(in.id).detection_range; range > 0 && flying(in.id)) {  // a stopped one detects no one
      painter.setPen(QPen(selected_colour, 1, Qt::DotLine));
      painter.drawEllipse(me, range * px, range * px);
    }
  }
  if (snap.groups.size() >= 2) draw_legend(painter, snap);
  painter.restore();
}

QImage render_frame(const Snapshot& snap, const ViewOptions& options, QSize size, std::optional<QTransform> world_to_px) {
  QImage image(size, QImage::Format_ARGB32_Premultiplied);
  const QTransform t = world_to_px ? *world_to_px
                                   : fit_transform(snap.scene ? snap.scene->map.bounds : Rect{{0, 0}, {1, 1}}, QSizeF(size));
  QPainter painter(&image);
  render_static(painter, snap, options, t);
  render_dynamic(painter, snap, options, t);
  return image;
}

void FrameRenderer::draw(QPainter& painter, QSize size, const Snapshot& snap, const ViewOptions& options, const QTransform& world_to_px) {
  const qreal dpr = painter.device() ? painter.device()->devicePixelRatioF() : 1;
  const QSize pixels = (QSizeF(size) * dpr).toSize();
  const bool stale = layer_.size() != pixels || scene_ != snap.scene.get() || !(options_ == options) ||
                     transform_ != world_to_px || (options.heat_map && heat_ != snap.heat.get());
  if (stale) {
    layer_ = QImage(pixels, QImage::Format_ARGB32_Premultiplied);
    layer_.setDevicePixelRatio(dpr);
    QPainter p(&layer_);
    render_static(p, snap, options, world_to_px);
    scene_ = snap.scene.get();
    heat_ = snap.heat.get();
    options_ = options;
    transform_ = world_to_px;
    drawn_found_ = snap.found;
    ++static_redraws_;
  } else if (found_version_ != snap.found_version && options.targets && snap.scene) {
    // Targets found since: stamped over the layer, not a redraw of 50,000.
    QPainter p(&layer_);
    drawn_found_.resize(snap.found.size(), 0);
    draw_targets(p, *snap.scene, snap.found, world_to_px, [&](std::size_t i) { return i < snap.found.size() && snap.found[i] != drawn_found_[i]; });
    drawn_found_ = snap.found;
    ++found_updates_;
  }
  found_version_ = snap.found_version;
  painter.drawImage(QPointF(0, 0), layer_);
  render_dynamic(painter, snap, options, world_to_px);
}

// ---------------------------------------------------------------- SwarmView

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
    painter.fillRect(rect(), background);
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
