#pragma once
// Drawing a snapshot: into any painter (render_frame), or the sandbox view's frames (FrameRenderer).
#include <QColor>
#include <QImage>
#include <QStringList>
#include <QTransform>
#include <memory>
#include <optional>

#include "snapshot.hpp"

class QPainter;

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
/// until a sample is taken. Raster only: drones are stamped as pre-drawn sprites and trails drawn by
/// hand into a mask (view_trails.cpp says why), both blended straight into the frame.
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

}  // namespace salsa::gui
