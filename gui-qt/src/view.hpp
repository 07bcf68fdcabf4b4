#pragma once
// Drawing a snapshot. render_scene draws into any QPainter (the widget, a screenshot, a recording
// frame, the render benchmark); SwarmView is the sandbox's interactive view: zoom, pan, fit, click to
// select. Raster only: a cached static layer (obstacles, targets, heat map, spawn) redrawn only when the
// transform, size, options or the scene / found targets / heat map change; drones stamped as pre-drawn
// sprites and trails drawn by hand into a mask (view.cpp says why), both blended straight into the frame.
#include <QImage>
#include <QStringList>
#include <QTransform>
#include <QWidget>
#include <memory>
#include <optional>

#include "engine.hpp"

namespace salsa::gui {

struct ViewOptions {
  bool camera_range = false, obstacle_range = false, detection_range = false;
  bool targets = true;     ///< found and unfound targets, in two colours
  bool trails = true;
  bool heat_map = false;
  bool obstacles = true;
  bool spawn = true;
  bool links = false;      ///< messages delivered for the next step, receiver to sender (with "comm")
  bool wind = true;        ///< arrows of the wind on a grid (with "wind")
  bool operator==(const ViewOptions&) const = default;
};

/// The colour group `group` of `groups` is drawn in: today's blue for one group; with several, Okabe &
/// Ito's colour-blind-safe set in the order the plots use.
QColor group_colour(std::size_t group, std::size_t groups);

/// The legend's rows with two or more groups ("surveyors: 6 flying", ", 1 stopped" when some landed
/// or failed, then a row for the ✕), else none: one group keeps the legend-free look.
QStringList legend_rows(const Snapshot& snap);

/// World → pixels for a `size` widget showing `area` (m) whole, centred, y up.
QTransform fit_transform(const Rect& area, QSizeF size);

/// Draws everything but the static layer (drones in their groups' colours, a ✕ where one stopped,
/// trails, ranges, selection, and with two or more groups their legend) over what the painter holds. `world_to_px` maps metres to pixels.
void render_dynamic(QPainter& painter, const Snapshot& snap, const ViewOptions& options, const QTransform& world_to_px);
/// Draws the static layer (background, heat map, obstacles, spawn, targets).
void render_static(QPainter& painter, const Snapshot& snap, const ViewOptions& options, const QTransform& world_to_px);
/// A whole frame of `size` px (static layer, then dynamic): screenshots, recordings, golden images.
QImage render_frame(const Snapshot& snap, const ViewOptions& options, QSize size,
                    std::optional<QTransform> world_to_px = std::nullopt);

struct TrailLayers;

/// Caches the static layer of the last frame; redraws it only when the scene, options, transform, size
/// or (shown) heat map change. Targets found since are stamped over it. The trails' lines are kept too,
/// until a sample is taken.
class FrameRenderer {
 public:
  FrameRenderer();
  ~FrameRenderer();
  /// Draws `snap` into `target` (its whole size) with the cached static layer.
  void draw(QPainter& painter, QSize size, const Snapshot& snap, const ViewOptions& options, const QTransform& world_to_px);
  std::size_t static_redraws() const { return static_redraws_; }  ///< whole static layers drawn (tests, benchmark)
  std::size_t found_updates() const { return found_updates_; }    ///< newly found targets stamped over it

 private:
  QImage layer_;
  QImage frame_;  ///< the static layer with the drones over it (at one pixel per unit)
  const Scene* scene_ = nullptr;
  const HeatMap* heat_ = nullptr;
  std::uint64_t found_version_ = ~0ull;
  ViewOptions options_;
  QTransform transform_;
  std::size_t static_redraws_ = 0, found_updates_ = 0;
  std::uint64_t layer_version_ = 0;  ///< changes with every change of layer_
  std::vector<std::uint8_t> drawn_found_;  ///< the found flags the layer shows
  std::unique_ptr<TrailLayers> trails_;
};

class SwarmView : public QWidget {
  Q_OBJECT
 public:
  explicit SwarmView(QWidget* parent = nullptr);
  void show_snapshot(std::shared_ptr<const Snapshot> snap);  ///< repaints
  void set_options(const ViewOptions& options);
  const ViewOptions& options() const { return options_; }
  void fit();                      ///< whole map in view
  void zoom(double factor, std::optional<QPointF> around = std::nullopt);
  QTransform world_to_px() const;
  QImage screenshot();             ///< the view as shown

 Q_SIGNALS:
  void drone_clicked(std::optional<std::uint32_t> id);  ///< nullopt: clicked on empty space

 protected:
  void paintEvent(QPaintEvent*) override;
  void wheelEvent(QWheelEvent*) override;
  void mousePressEvent(QMouseEvent*) override;
  void mouseMoveEvent(QMouseEvent*) override;
  void mouseReleaseEvent(QMouseEvent*) override;
  void keyPressEvent(QKeyEvent*) override;
  void resizeEvent(QResizeEvent*) override;

 private:
  std::shared_ptr<const Snapshot> snap_;
  ViewOptions options_;
  FrameRenderer renderer_;
  double zoom_ = 1;   ///< relative to fit
  QPointF pan_;       ///< px
  std::optional<QPoint> press_;
  bool dragged_ = false;
};

}  // namespace salsa::gui
