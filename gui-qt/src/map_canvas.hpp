#pragma once
// The map creator's canvas (private to it): draws the map being edited and turns mouse gestures into edits.
#include <QWidget>
#include <optional>
#include <vector>

#include "map_editor.hpp"

namespace salsa::gui {

/// The list the shapes of `part` are kept in (nullptr for the spawn point).
std::vector<Polyline>* shapes_of(MapData& m, MapProblem::Part part);
const std::vector<Polyline>* shapes_of(const MapData& m, MapProblem::Part part);

// Draws the map and turns mouse gestures into edits. Metres to pixels: `scale_` px per m, y up,
// world (0, 0) at `origin_` px.
class MapCanvas final : public QWidget {
 public:
  explicit MapCanvas(MapEditor& editor);

  QPointF to_px(Vec2 p) const { return {origin_.x() + p.x * scale_, origin_.y() - p.y * scale_}; }
  Vec2 to_world(QPointF px) const { return {(px.x() - origin_.x()) / scale_, (origin_.y() - px.y()) / scale_}; }

  void fit();
  void cancel();
  const std::vector<Vec2>& draft() const { return draft_; }

 protected:
  void resizeEvent(QResizeEvent*) override;
  void paintEvent(QPaintEvent*) override;
  void mousePressEvent(QMouseEvent* e) override;
  void mouseMoveEvent(QMouseEvent* e) override;
  void mouseReleaseEvent(QMouseEvent* e) override;
  void wheelEvent(QWheelEvent* e) override;
  void keyPressEvent(QKeyEvent* e) override;

 private:
  struct Drag {
    Vec2 from;
    MapData before;
  };

  Vec2 snapped(Vec2 p) const;
  MapData moved(MapData m, Vec2 by) const;
  // The spawn point, then the topmost shape under `px`: an edge within 6 px, or inside a polygon.
  std::optional<MapEditor::Selection> hit_test(QPointF px) const;
  void draw_grid(QPainter& p, const Rect& b) const;
  void draw_draft(QPainter& p) const;

  MapEditor& editor_;
  double scale_ = 1;
  QPointF origin_;
  bool fitted_ = false, zoomed_ = false;
  std::vector<Vec2> draft_;  ///< the polygon being clicked in
  std::optional<Drag> drag_;
  std::optional<QPointF> pan_from_;
  Vec2 cursor_;                ///< the snapped point under the mouse (m)
  std::optional<Vec2> hover_;  ///< the point under the mouse, not snapped (m)
};

}  // namespace salsa::gui
