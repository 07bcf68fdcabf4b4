#pragma once
// What the view's drawing files share (private): pixels blended by hand, drones on screen, trails' layers.
#include <QColor>
#include <QImage>
#include <QPainter>
#include <QTransform>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "frame_renderer.hpp"
#include "marks.hpp"

namespace salsa::gui {

/// The map's area (the static layer; the view before a snapshot).
inline const QColor map_background(0xf4, 0xf1, 0xea);

inline double px_per_m(const QTransform& t) { return std::hypot(t.m11(), t.m12()); }

/// A drone's radius on screen at `px` pixels per metre: at least 3 px, so that every drone shows.
inline double radius_px(const Snapshot& snap, std::uint32_t id, double px) { return std::max(3.0, snap.drone_of(id).radius * px); }

/// World → pixels without a call per point: the view's transforms are affine (no perspective).
struct Affine {
  double m11, m12, m21, m22, dx, dy;
  explicit Affine(const QTransform& t) : m11(t.m11()), m12(t.m12()), m21(t.m21()), m22(t.m22()), dx(t.dx()), dy(t.dy()) {}
  QPointF operator()(double x, double y) const { return {m11 * x + m21 * y + dx, m12 * x + m22 * y + dy}; }
};

/// ⌊x⌋ for |x| < 2^31 without a libm call (x86-64's baseline has no rounding instruction): per pixel.
inline int floor_int(double x) {
  const int i = static_cast<int>(x);
  return i - (x < i ? 1 : 0);
}

/// `source` (premultiplied) over `dest`, as Qt's raster engine computes it.
inline QRgb over(QRgb source, QRgb dest) {
  const std::uint32_t a = 255 - qAlpha(source);
  std::uint32_t rb = (dest & 0xff00ff) * a, ag = ((dest >> 8) & 0xff00ff) * a;
  rb = ((rb + ((rb >> 8) & 0xff00ff) + 0x800080) >> 8) & 0xff00ff;
  ag = (ag + ((ag >> 8) & 0xff00ff) + 0x800080) & 0xff00ff00;
  return source + (ag | rb);
}

/// The pixels the painter paints on when they may be blended into directly: a premultiplied or opaque
/// 32-bit image at one pixel per unit, with no transform, clip or other composition. Stamping 100,000
/// sprites through QPainter::drawImage costs its per-call overhead 100,000 times; the raster engine
/// writes straight into the image, so the two may take turns.
struct Pixels {
  QRgb* bits;
  qsizetype stride;  ///< QRgb per row
  int width, height;
  QRgb* row(int y) const { return bits + y * stride; }
};
inline std::optional<Pixels> direct_pixels(QPainter& painter) {
  QPaintDevice* device = painter.device();
  if (!device || device->devType() != QInternal::Image) return std::nullopt;
  auto* image = static_cast<QImage*>(device);
  const bool format = image->format() == QImage::Format_ARGB32_Premultiplied || image->format() == QImage::Format_RGB32;
  if (!format || image->devicePixelRatio() != 1 || !image->isDetached() || painter.hasClipping() ||
      painter.compositionMode() != QPainter::CompositionMode_SourceOver || !painter.combinedTransform().isIdentity())
    return std::nullopt;
  return Pixels{reinterpret_cast<QRgb*>(image->bits()), image->bytesPerLine() / 4, image->width(), image->height()};
}

/// Where each drone is on screen (px), and the drones by group, removed ones left out.
struct Layout {
  std::vector<QPointF> at;
  std::vector<std::vector<std::uint32_t>> members;
};
Layout layout_of(const Snapshot& snap, const QTransform& world_to_px);

/// The part of a screen `viewport` (px) whose lines are drawn: a line with an end in it.
struct Visible {
  double left, right, top, bottom;
  explicit Visible(QRectF viewport) {
    const QRectF r = viewport.adjusted(-50, -50, 50, 50);
    left = r.left(), right = r.right(), top = r.top(), bottom = r.bottom();
  }
  bool operator()(QPointF q) const { return q.x() >= left && q.x() <= right && q.y() >= top && q.y() <= bottom; }
};

// ---- The static layer (view_static.cpp)

/// Moving targets (Snapshot::targets) where they are now, found ones green; the painter has no transform.
void draw_moving_targets(QPainter& painter, const Snapshot& snap, const QTransform& world_to_px);
/// Stamps over a static layer the targets whose found flag in `found` differs from `drawn` (the flags
/// the layer shows, as long as `found`). The painter has no transform (pixels).
void draw_found_since(QPainter& painter, const Scene& scene, const std::vector<std::uint8_t>& found,
                      const std::vector<std::uint8_t>& drawn, const QTransform& world_to_px);

// ---- Trails (view_trails.cpp)

/// Thin antialiased lines of one colour, drawn by hand into an alpha mask that is then blended once.
/// Qt blends each pixel of a thin line through a general span function: 10,000 drones' trails cost
/// ~60 ms a frame that way, against a few here. Lines over each other add up as source-over does for
/// one colour (a' = a + s·(1 − a)), so the picture is the one Qt would draw. Per thread, kept between
/// frames (recordings draw on the engine's).
class LineMask {
 public:
  /// Starts a picture of `size` device pixels.
  void begin(QSize size);
  /// A 1 px line from `a` to `b` (device pixels) of opacity `alpha` (0–255): wu_line.
  void line(QPointF a, QPointF b, int alpha);
  /// Blends the lines into `target` (of the mask's size) in `colour`, keeping them.
  void blend_into(const Pixels& target, const QColor& colour) const;
  /// The lines `other` holds (its size and what it drew), to draw more over.
  void assign_lines(const LineMask& other);
  /// Blends what was drawn since begin() in `colour` (its alpha ignored) over the painter's picture.
  void finish(QPainter& painter, const QColor& colour, qreal dpr);

 private:
  /// The mask is stored in 8 × 8 blocks of one cache line each: a short line of any slope touches a
  /// few lines, where rows of the whole width would cost a cache miss per pixel row.
  std::size_t block_index(int x, int y) const {
    return (static_cast<std::size_t>(y >> 3) * static_cast<std::size_t>(blocks_x_) + static_cast<std::size_t>(x >> 3)) * 64 +
           static_cast<std::size_t>((y & 7) * 8 + (x & 7));
  }
  std::uint8_t& at(int x, int y) { return mask_[block_index(x, y)]; }
  void plot(int x, int y, int alpha) {
    std::uint8_t& m = at(x, y);
    m = static_cast<std::uint8_t>(m + (alpha * (255 - m) + 127) / 255);
  }
  /// Zeroes the blocks drawn on and forgets them: the mask is all 0 again.
  void clear_drawn();

  QSize size_;
  int blocks_x_ = 0;
  std::vector<std::uint8_t> mask_;  ///< all 0 between pictures
  QImage image_;
  int x0_ = 0, y0_ = 0, x1_ = -1, y1_ = -1;  ///< what was drawn on, inclusive
};

/// The trails' lines of a picture but for each drone's last one, to the drone (the head), kept by the
/// FrameRenderer: the drones move every frame, their trail samples only every few steps. They are drawn
/// again when a sample was taken (a new Snapshot::trails), the view moved or drones changed group or
/// were removed; each frame blends a copy with the heads added, the picture a whole redraw gives (one
/// colour's lines add up in any order).
struct TrailLayers {
  std::shared_ptr<const std::vector<Vec2>> trails;  ///< what they were drawn for
  QTransform transform;
  QSize size;
  std::vector<std::vector<std::uint32_t>> members;
  std::vector<LineMask> masks;  ///< per group
  std::vector<QPointF> ends;    ///< per drone: where its lines end (NaN: none), px
  /// The FrameRenderer's static layer with the lines blended in, made again when either changes: a
  /// frame then copies it and adds the heads.
  QImage base;
  std::uint64_t base_version = ~0ull;  ///< of the static layer it was made from
};

bool shows_trails(const Snapshot& snap, const ViewOptions& options);

/// The trail samples' lines, one mask per group (LineMask), decimated on screen: a sample closer than
/// 2 px to the last one drawn adds nothing visible, so the cost follows the trails' length in pixels,
/// not in samples. Past a million samples (15,000 drones of 64) only every stride-th is looked at, so
/// that 100,000 drones' trails cost what 15,000 do; the newest sample always is. Drawn into `layers`
/// unless `kept` and they hold them already for these trails, transform, size and groups; true when
/// drawn.
bool draw_trail_lines(const Snapshot& snap, const Layout& layout, const QTransform& world_to_px, QSize size, qreal dpr,
                      const Visible& shown, TrailLayers& layers, bool kept);

/// The trails: their samples' lines, then each drone's last segment, to where it is now (the head).
/// With `cache` the samples' lines are drawn again only when they changed.
void draw_trails(QPainter& painter, const Snapshot& snap, const Layout& layout, const QTransform& world_to_px, TrailLayers* cache);

/// The heads of the trails (see draw_trails), blended straight into `pixels` (dpr 1), a band of 16
/// rows at a time (as the drones' sprites: in id order nearly every pixel is a cache miss).
void draw_trail_heads(const Pixels& pixels, const Layout& layout, const TrailLayers& layers, const Visible& shown);

// ---- Drones (view_drones.cpp)

/// A flying drone of `radius` px at `at`: a disc, or a ring when its camera failed, with its velocity
/// tick along `heading` (radians on screen; none: still).
void draw_drone(QPainter& p, QPointF at, const QColor& colour, double radius, bool camera_works, std::optional<double> heading);
/// Every drone on screen, a group at a time; `px`: pixels per metre.
void draw_drones(QPainter& painter, const Snapshot& snap, const Layout& layout, double px);

// ---- Overlays (view_overlays.cpp), in pixels: wind, links and ranges under the drones, the selection
// and the legend over them

/// Arrows of the snapshot's wind, with the scale at the bottom right.
void draw_wind(QPainter& painter, const Snapshot& snap, const QTransform& world_to_px);
/// The messages delivered for the next step: a line per pair.
void draw_links(QPainter& painter, const Snapshot& snap, const Layout& layout);
/// The ranges the options ask for, around each flying drone.
void draw_ranges(QPainter& painter, const Snapshot& snap, const ViewOptions& options, const Layout& layout, double px);
/// The selected drone (snap.selected, an id in the snapshot): its neighbours, obstacle hits and detection range.
void draw_selection(QPainter& painter, const Snapshot& snap, const Layout& layout, const QTransform& world_to_px);
/// legend_rows in a box, top left, each beside its symbol: the group's disc, or the ✕ of a stopped drone.
void draw_legend(QPainter& painter, const Snapshot& snap);

}  // namespace salsa::gui
