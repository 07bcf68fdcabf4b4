// Overlays: wind arrows, communication links, sensor ranges, the selected drone and the groups' legend.
#include <QPainter>
#include <algorithm>
#include <cmath>

#include "view_draw.hpp"

namespace salsa::gui {
namespace {

const QColor selected_colour(0xe0, 0x3a, 0x1e);
const QColor neighbour_colour(0xf0, 0x9a, 0x1a);

}  // namespace

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
    if (group) draw_drone(painter, symbol, colour, 5, true, std::nullopt);
    else draw_cross(painter, symbol, colour);
    painter.setPen(Qt::black);
    painter.drawText(QRectF(box.left() + 30, symbol.y() - line / 2.0, width + 4, line), Qt::AlignLeft | Qt::AlignVCenter, rows[k]);
  }
}

void draw_wind(QPainter& painter, const Snapshot& snap, const QTransform& world_to_px) {
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

void draw_links(QPainter& painter, const Snapshot& snap, const Layout& layout) {
  const std::size_t n = snap.positions.size();
  const std::vector<QPointF>& at = layout.at;
  // Each delivery once a pair: a link heard both ways is one line, drawn purple under the drones.
  std::vector<QLineF> lines;
  lines.reserve(snap.links.size());
  for (const auto& [receiver, sender] : snap.links)
    if (receiver < n && sender < n && (sender < receiver || !std::binary_search(snap.links.begin(), snap.links.end(), std::pair{sender, receiver})))
      lines.emplace_back(at[receiver], at[sender]);
  painter.setPen(QPen(QColor(0x7b, 0x3f, 0xa0, 90), 1));
  painter.drawLines(lines.data(), static_cast<int>(lines.size()));
}

void draw_ranges(QPainter& painter, const Snapshot& snap, const ViewOptions& options, const Layout& layout, double px) {
  const std::vector<QPointF>& at = layout.at;
  const std::vector<std::vector<std::uint32_t>>& members = layout.members;  // drawn a group at a time
  const auto flying = [&](std::uint32_t i) { return snap.status_of(i) == DroneStatus::flying; };
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
    for (std::size_t g = 0; g < members.size(); ++g) {
      if (members[g].empty()) continue;
      const double radius = snap.drone_of(members[g].front()).*r.metres * px;
      if (radius <= 0) continue;
      for (std::uint32_t i : members[g])
        if (flying(i) && (r.metres != &DroneConfig::camera_range || snap.camera_works(i))) painter.drawEllipse(at[i], radius, radius);
    }
  }
}

void draw_selection(QPainter& painter, const Snapshot& snap, const Layout& layout, const QTransform& world_to_px) {
  const double px = px_per_m(world_to_px);
  const std::size_t n = snap.positions.size();
  const std::vector<QPointF>& at = layout.at;
  const auto flying = [&](std::uint32_t i) { return snap.status_of(i) == DroneStatus::flying; };
  const Inspection& in = *snap.selected;
  const QPointF me = at[in.id];
  const double radius = radius_px(snap, in.id, px);
  painter.setBrush(Qt::NoBrush);
  painter.setPen(QPen(neighbour_colour, 2));
  for (std::uint32_t j : in.neighbours)
    if (j < n) painter.drawEllipse(at[j], radius_px(snap, j, px) + 3, radius_px(snap, j, px) + 3);
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

}  // namespace salsa::gui
