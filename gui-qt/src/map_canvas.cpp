// The map creator's canvas: the map drawn with its problems flagged red, and mouse gestures made edits.
#include "map_canvas.hpp"

#include <QKeyEvent>
#include <QMouseEvent>
#include <QPainter>
#include <QWheelEvent>
#include <algorithm>
#include <cmath>

namespace salsa::gui {
namespace {

using Part = MapProblem::Part;

double distance_to_segment(Vec2 p, Vec2 a, Vec2 b) {
  const Vec2 ab = b - a;
  const double len2 = ab.length_squared();
  const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0;
  return distance(p, a + ab * t);
}

}  // namespace

std::vector<Polyline>* shapes_of(MapData& m, Part part) {
  switch (part) {
    case Part::obstacle: return &m.obstacles;
    case Part::hollow: return &m.hollow;
    case Part::line: return &m.lines;
    default: return nullptr;
  }
}
const std::vector<Polyline>* shapes_of(const MapData& m, Part part) { return shapes_of(const_cast<MapData&>(m), part); }

MapCanvas::MapCanvas(MapEditor& editor) : editor_(editor) {
  setMouseTracking(true);  // the shape being drawn follows the cursor
  setFocusPolicy(Qt::StrongFocus);
  setMinimumSize(400, 300);
  setAutoFillBackground(false);
}

void MapCanvas::fit() {
  const Rect& b = editor_.map().bounds;
  const double w = std::max(b.width(), 1.0), h = std::max(b.height(), 1.0);
  scale_ = 0.92 * std::min(width() / w, height() / h);
  const Vec2 c = b.centre();
  origin_ = QPointF(width() / 2.0 - c.x * scale_, height() / 2.0 + c.y * scale_);
  fitted_ = true;
  update();
}

void MapCanvas::cancel() {
  draft_.clear();
  drag_.reset();
  update();
}

void MapCanvas::resizeEvent(QResizeEvent*) {
  if (fitted_ || !zoomed_) fit();
}

void MapCanvas::paintEvent(QPaintEvent*) {
  QPainter p(this);
  p.setRenderHint(QPainter::Antialiasing);
  p.fillRect(rect(), QColor(200, 200, 205));
  const MapData& m = editor_.map();
  const QRectF bounds(to_px({m.bounds.min.x, m.bounds.max.y}), to_px({m.bounds.max.x, m.bounds.min.y}));
  p.fillRect(bounds, Qt::white);
  draw_grid(p, m.bounds);
  p.setPen(QPen(QColor(60, 60, 60), 2));
  p.setBrush(Qt::NoBrush);
  p.drawRect(bounds);

  auto flagged = [&](Part part, std::size_t i) {
    const auto& ps = editor_.problems();
    return std::any_of(ps.begin(), ps.end(), [&](const MapProblem& x) { return x.part == part && x.index == i; });
  };
  auto selected = [&](Part part, std::size_t i) { return editor_.selection() == MapEditor::Selection{part, i}; };
  auto polygon = [&](const Polyline& pts) {
    QPolygonF poly;
    for (Vec2 v : pts) poly << to_px(v);
    return poly;
  };
  const QColor red(215, 40, 40), blue(30, 110, 230);
  for (std::size_t i = 0; i < m.obstacles.size(); ++i) {
    const bool bad = flagged(Part::obstacle, i);
    p.setPen(QPen(selected(Part::obstacle, i) ? blue : bad ? red : QColor(50, 50, 50), selected(Part::obstacle, i) ? 3 : 1.5));
    p.setBrush(bad ? QColor(240, 120, 120) : QColor(120, 120, 125));
    p.drawPolygon(polygon(m.obstacles[i]));
  }
  p.setBrush(Qt::NoBrush);
  for (std::size_t i = 0; i < m.hollow.size(); ++i) {
    p.setPen(QPen(selected(Part::hollow, i) ? blue : flagged(Part::hollow, i) ? red : QColor(70, 70, 70), 3, Qt::SolidLine, Qt::RoundCap, Qt::RoundJoin));
    p.drawPolygon(polygon(m.hollow[i]));
  }
  for (std::size_t i = 0; i < m.lines.size(); ++i) {
    p.setPen(QPen(selected(Part::line, i) ? blue : flagged(Part::line, i) ? red : QColor(70, 70, 70), 3, Qt::SolidLine, Qt::RoundCap, Qt::RoundJoin));
    p.drawPolyline(polygon(m.lines[i]));
  }
  if (editor_.selection() && editor_.selection()->part != Part::spawn) {  // vertex handles
    p.setPen(QPen(blue, 1.5));
    p.setBrush(Qt::white);
    for (Vec2 v : (*shapes_of(m, editor_.selection()->part))[editor_.selection()->index]) p.drawRect(QRectF(to_px(v) - QPointF(3, 3), QSizeF(6, 6)));
  }
  // Spawn: a green ring with a cross.
  const QPointF s = to_px(m.spawn);
  const bool spawn_bad = flagged(Part::spawn, 0);
  p.setPen(QPen(editor_.selection() == MapEditor::Selection{Part::spawn, 0} ? blue : spawn_bad ? red : QColor(20, 150, 60), 2.5));
  p.setBrush(Qt::NoBrush);
  p.drawEllipse(s, 8, 8);
  p.drawLine(s - QPointF(12, 0), s + QPointF(12, 0));
  p.drawLine(s - QPointF(0, 12), s + QPointF(0, 12));

  draw_draft(p);
  if (hover_) {  // where the cursor is, and where a click would land
    p.setPen(QColor(60, 60, 60));
    p.drawText(rect().adjusted(8, 0, 0, -6), Qt::AlignLeft | Qt::AlignBottom,
               QString("x %1 m, y %2 m  →  [%3, %4]").arg(hover_->x, 0, 'f', 1).arg(hover_->y, 0, 'f', 1).arg(cursor_.x).arg(cursor_.y));
  }
}

void MapCanvas::mousePressEvent(QMouseEvent* e) {
  setFocus();
  if (e->button() == Qt::RightButton || e->button() == Qt::MiddleButton) {
    pan_from_ = e->position();
    return;
  }
  if (e->button() != Qt::LeftButton) return;
  const Vec2 at = editor_.to_world(e->position());
  const Vec2 p = snapped(at);
  switch (editor_.tool()) {
    case MapEditor::Tool::select: {
      const auto hit = hit_test(e->position());
      editor_.select(hit);
      if (hit) drag_ = Drag{p, editor_.map()};
      break;
    }
    case MapEditor::Tool::line:
    case MapEditor::Tool::bounds: drag_ = Drag{p, editor_.map()}; break;
    case MapEditor::Tool::polygon:
    case MapEditor::Tool::hollow: {
      // Close on the first vertex (within 10 px); otherwise a new vertex.
      if (draft_.size() >= 3 && QLineF(e->position(), to_px(draft_.front())).length() <= 10) {
        MapData after = editor_.map();
        const bool solid = editor_.tool() == MapEditor::Tool::polygon;
        (solid ? after.obstacles : after.hollow).push_back(draft_);
        draft_.clear();
        editor_.edit(solid ? "draw polygon" : "draw hollow polygon", std::move(after));
      } else if (draft_.empty() || !(draft_.back() == p)) {
        draft_.push_back(p);
      }
      break;
    }
    case MapEditor::Tool::spawn: {
      MapData after = editor_.map();
      after.spawn = p;
      editor_.edit("set spawn", std::move(after));
      break;
    }
  }
  cursor_ = p;
  update();
}

void MapCanvas::mouseMoveEvent(QMouseEvent* e) {
  if (pan_from_) {
    origin_ += e->position() - *pan_from_;
    pan_from_ = e->position();
    zoomed_ = true;
    fitted_ = false;
    update();
    return;
  }
  const Vec2 at = editor_.to_world(e->position());
  cursor_ = snapped(at);
  hover_ = at;
  if (drag_ && editor_.tool() == MapEditor::Tool::select && editor_.selection()) {
    // A live preview of the move; the edit is made on release.
    editor_.map_ = moved(drag_->before, cursor_ - drag_->from);
    editor_.refresh();
  }
  update();
}

void MapCanvas::mouseReleaseEvent(QMouseEvent* e) {
  if (e->button() == Qt::RightButton || e->button() == Qt::MiddleButton) {
    pan_from_.reset();
    return;
  }
  if (e->button() != Qt::LeftButton || !drag_) return;
  const Drag d = *drag_;
  drag_.reset();
  const Vec2 to = snapped(editor_.to_world(e->position()));
  switch (editor_.tool()) {
    case MapEditor::Tool::select:
      if (editor_.selection() && !(to == d.from)) {
        editor_.map_ = d.before;  // the preview goes; the edit makes it for good
        editor_.edit(editor_.selection()->part == Part::spawn ? "move spawn" : "move shape", moved(d.before, to - d.from));
      }
      break;
    case MapEditor::Tool::line:
      if (!(to == d.from)) {
        MapData after = editor_.map();
        after.lines.push_back({d.from, to});
        editor_.edit("draw line", std::move(after));
      }
      break;
    case MapEditor::Tool::bounds:
      if (to.x != d.from.x && to.y != d.from.y) {
        MapData after = editor_.map();
        after.bounds = {{std::min(to.x, d.from.x), std::min(to.y, d.from.y)}, {std::max(to.x, d.from.x), std::max(to.y, d.from.y)}};
        editor_.edit("set bounds", std::move(after));
      }
      break;
    default: break;
  }
  update();
}

void MapCanvas::wheelEvent(QWheelEvent* e) {
  // Zoom about the cursor: the point under it stays put.
  const Vec2 under = editor_.to_world(e->position());
  scale_ *= std::pow(1.0015, e->angleDelta().y());
  scale_ = std::clamp(scale_, 1e-4, 1e4);
  const QPointF now = to_px(under);
  origin_ += e->position() - now;
  zoomed_ = true;
  fitted_ = false;
  update();
}

void MapCanvas::keyPressEvent(QKeyEvent* e) {
  if (e->key() == Qt::Key_Escape) cancel();
  else if (e->key() == Qt::Key_Delete || e->key() == Qt::Key_Backspace) editor_.delete_selected();
  else QWidget::keyPressEvent(e);
}

Vec2 MapCanvas::snapped(Vec2 p) const {
  const double g = editor_.snap();
  return g > 0 ? Vec2{std::round(p.x / g) * g, std::round(p.y / g) * g} : p;
}

MapData MapCanvas::moved(MapData m, Vec2 by) const {
  const auto& sel = editor_.selection();
  if (!sel) return m;
  if (sel->part == Part::spawn) {
    m.spawn += by;
  } else if (auto* list = shapes_of(m, sel->part); list && sel->index < list->size()) {
    for (Vec2& v : (*list)[sel->index]) v += by;
  }
  return m;
}

std::optional<MapEditor::Selection> MapCanvas::hit_test(QPointF px) const {
  const MapData& m = editor_.map();
  if (QLineF(px, to_px(m.spawn)).length() <= 10) return MapEditor::Selection{Part::spawn, 0};
  const Vec2 w = editor_.to_world(px);
  const double tolerance = 6 / scale_;
  auto near = [&](const Polyline& pts, bool closed) {
    for (std::size_t i = 0; i + 1 < pts.size() + (closed ? 1 : 0); ++i)
      if (distance_to_segment(w, pts[i], pts[(i + 1) % pts.size()]) <= tolerance) return true;
    return pts.size() == 1 && distance(w, pts[0]) <= tolerance;
  };
  for (std::size_t i = m.lines.size(); i-- > 0;)
    if (near(m.lines[i], false)) return MapEditor::Selection{Part::line, i};
  for (std::size_t i = m.hollow.size(); i-- > 0;)
    if (near(m.hollow[i], true)) return MapEditor::Selection{Part::hollow, i};
  for (std::size_t i = m.obstacles.size(); i-- > 0;)
    if (near(m.obstacles[i], true) || (m.obstacles[i].size() >= 3 && inside_polygon(w, m.obstacles[i])))
      return MapEditor::Selection{Part::obstacle, i};
  return std::nullopt;
}

void MapCanvas::draw_grid(QPainter& p, const Rect& b) const {
  double step = editor_.snap() > 0 ? editor_.snap() : 10;
  while (step * scale_ < 8) step *= 5;  // never denser than 8 px
  p.setPen(QPen(QColor(232, 232, 238), 1));
  for (double x = std::ceil(b.min.x / step) * step; x <= b.max.x; x += step) p.drawLine(to_px({x, b.min.y}), to_px({x, b.max.y}));
  for (double y = std::ceil(b.min.y / step) * step; y <= b.max.y; y += step) p.drawLine(to_px({b.min.x, y}), to_px({b.max.x, y}));
}

void MapCanvas::draw_draft(QPainter& p) const {
  const QColor ink(30, 110, 230), red(215, 40, 40);
  p.setBrush(Qt::NoBrush);
  if (drag_ && editor_.tool() == MapEditor::Tool::line) {
    p.setPen(QPen(ink, 3, Qt::DashLine));
    p.drawLine(to_px(drag_->from), to_px(cursor_));
  }
  if (drag_ && editor_.tool() == MapEditor::Tool::bounds) {
    p.setPen(QPen(ink, 2, Qt::DashLine));
    p.drawRect(QRectF(to_px(drag_->from), to_px(cursor_)).normalized());
  }
  if (draft_.empty()) return;
  // Flagged as it is drawn: red once the polygon it would close to crosses itself.
  Polyline closing = draft_;
  closing.push_back(cursor_);
  const auto [e1, e2] = crossing_edges(closing);
  const bool bad = e1 != e2;
  QPolygonF line;
  for (Vec2 v : draft_) line << to_px(v);
  p.setPen(QPen(bad ? red : ink, 2.5));
  p.drawPolyline(line);
  p.setPen(QPen(bad ? red : ink, 1.5, Qt::DashLine));
  p.drawLine(line.back(), to_px(cursor_));
  p.setPen(QPen(ink, 1.5));
  p.setBrush(Qt::white);
  for (const QPointF& v : line) p.drawEllipse(v, 3, 3);
  p.setBrush(ink);
  p.drawEllipse(line.front(), 6, 6);  // click here to close
}

}  // namespace salsa::gui
