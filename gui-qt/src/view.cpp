#include "view.hpp"

#include <QKeyEvent>
#include <QMouseEvent>
#include <QPainter>
#include <QPainterPath>
#include <QWheelEvent>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>

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
std::optional<Pixels> direct_pixels(QPainter& painter) {
  QPaintDevice* device = painter.device();
  if (!device || device->devType() != QInternal::Image) return std::nullopt;
  auto* image = static_cast<QImage*>(device);
  const bool format = image->format() == QImage::Format_ARGB32_Premultiplied || image->format() == QImage::Format_RGB32;
  if (!format || image->devicePixelRatio() != 1 || !image->isDetached() || painter.hasClipping() ||
      painter.compositionMode() != QPainter::CompositionMode_SourceOver || !painter.combinedTransform().isIdentity())
    return std::nullopt;
  return Pixels{reinterpret_cast<QRgb*>(image->bits()), image->bytesPerLine() / 4, image->width(), image->height()};
}

}  // namespace

/// A 1 px antialiased line from `a` to `b` (device pixels; a pixel's centre at +0.5) of opacity
/// `alpha` (0–255) on a `size` picture, as plot(x, y, opacity) calls. Wu's algorithm: along the long
/// axis, one step per pixel, shared by the two nearest pixels across. Returns the rows and columns it
/// may have touched (empty when none).
template <class Plot>
QRect wu_line(QPointF a, QPointF b, int alpha, QSize size, Plot&& plot) {
  double ax = a.x() - 0.5, ay = a.y() - 0.5, bx = b.x() - 0.5, by = b.y() - 0.5;
  const bool steep = std::abs(by - ay) > std::abs(bx - ax);
  if (steep) std::swap(ax, ay), std::swap(bx, by);
  if (ax > bx) std::swap(ax, bx), std::swap(ay, by);
  const int long_size = steep ? size.height() : size.width(), cross_size = steep ? size.width() : size.height();
  const double gradient = bx - ax > 1e-9 ? (by - ay) / (bx - ax) : 0;
  // Clamped first: a line may reach far off screen when zoomed in.
  const int from = std::max(0, floor_int(std::max(ax, -1.0) + 0.5)), to = std::min(long_size - 1, floor_int(std::min(bx, long_size + 1.0) + 0.5));
  if (from > to) return {};
  for (int i = from; i <= to; ++i) {
    const double across = ay + (i - ax) * gradient;
    const int j = floor_int(across);
    const int far = static_cast<int>(alpha * (across - j) + 0.5);
    if (j >= 0 && j < cross_size) plot(steep ? j : i, steep ? i : j, alpha - far);
    if (j + 1 >= 0 && j + 1 < cross_size) plot(steep ? j + 1 : i, steep ? i : j + 1, far);
  }
  const int j0 = std::max(0, floor_int(std::clamp(std::min(ay, by), -1.0, cross_size + 1.0)));
  const int j1 = std::min(cross_size - 1, floor_int(std::clamp(std::max(ay, by), -1.0, cross_size + 1.0)) + 1);
  return steep ? QRect(QPoint(j0, from), QPoint(j1, to)) : QRect(QPoint(from, j0), QPoint(to, j1));
}

/// The premultiplied colours of `colour` at each opacity 0–255.
std::array<QRgb, 256> shades(const QColor& colour) {
  std::array<QRgb, 256> shade;
  for (int m = 0; m < 256; ++m) shade[static_cast<std::size_t>(m)] = qPremultiply(qRgba(colour.red(), colour.green(), colour.blue(), m));
  return shade;
}

/// Thin antialiased lines of one colour, drawn by hand into an alpha mask that is then blended once.
/// Qt blends each pixel of a thin line through a general span function: 10,000 drones' trails cost
/// ~60 ms a frame that way, against a few here. Lines over each other add up as source-over does for
/// one colour (a' = a + s·(1 − a)), so the picture is the one Qt would draw. Per thread, kept between
/// frames (recordings draw on the engine's).
class LineMask {
 public:
  /// Starts a picture of `size` device pixels.
  void begin(QSize size) {
    if (size != size_) {
      size_ = size;
      blocks_x_ = (std::max(0, size.width()) + 7) / 8;
      mask_.assign(static_cast<std::size_t>(blocks_x_) * static_cast<std::size_t>((std::max(0, size.height()) + 7) / 8) * 64, 0);
    } else {  // lines drawn and not blended
      for (int by = y0_ & ~7; by <= y1_; by += 8)
        for (int bx = x0_ & ~7; bx <= x1_; bx += 8) std::fill_n(&at(bx, by), 64, 0);
    }
    x0_ = size.width(), y0_ = size.height(), x1_ = -1, y1_ = -1;
  }

  /// A 1 px line from `a` to `b` (device pixels) of opacity `alpha` (0–255): wu_line.
  void line(QPointF a, QPointF b, int alpha) {
    const QRect r = wu_line(a, b, alpha, size_, [this](int x, int y, int v) { plot(x, y, v); });
    if (r.isEmpty()) return;
    x0_ = std::min(x0_, r.left()), x1_ = std::max(x1_, r.right());
    y0_ = std::min(y0_, r.top()), y1_ = std::max(y1_, r.bottom());
  }

  /// Blends the lines into `target` (of the mask's size) in `colour`, keeping them.
  void blend_into(const Pixels& target, const QColor& colour) const {
    if (x1_ < x0_ || y1_ < y0_ || QSize(target.width, target.height) != size_) return;
    const std::array<QRgb, 256> shade = shades(colour);
    for (int by = y0_ & ~7; by <= y1_; by += 8)
      for (int bx = x0_ & ~7; bx <= x1_; bx += 8) {
        const std::uint8_t* block = &mask_[block_index(bx, by)];
        for (int y = 0; y < 8 && by + y <= y1_; ++y) {
          std::uint64_t row;
          std::memcpy(&row, block + y * 8, 8);
          if (!row) continue;  // most of a trail's neighbourhood
          QRgb* out = target.row(by + y) + bx;
          for (int x = 0; x < 8 && bx + x <= x1_; ++x)
            if (const std::uint8_t m = block[y * 8 + x]) out[x] = over(shade[m], out[x]);
        }
      }
  }

  /// The lines `other` holds (its size and what it drew), to draw more over.
  void assign_lines(const LineMask& other) {
    size_ = other.size_, blocks_x_ = other.blocks_x_, mask_ = other.mask_;
    x0_ = other.x0_, y0_ = other.y0_, x1_ = other.x1_, y1_ = other.y1_;
  }

  /// Blends what was drawn since begin() in `colour` (its alpha ignored) over the painter's picture.
  void finish(QPainter& painter, const QColor& colour, qreal dpr) {
    if (x1_ < x0_ || y1_ < y0_) return;
    const std::array<QRgb, 256> shade = shades(colour);
    x0_ &= ~7, y0_ &= ~7;  // whole blocks
    if (const auto target = direct_pixels(painter); target && QSize(target->width, target->height) == size_) {
      for (int by = y0_; by <= y1_; by += 8)
        for (int bx = x0_; bx <= x1_; bx += 8) {
          std::uint8_t* block = &at(bx, by);
          for (int y = 0; y < 8 && by + y <= y1_; ++y) {
            std::uint64_t row;
            std::memcpy(&row, block + y * 8, 8);
            if (!row) continue;  // most of a trail's neighbourhood
            QRgb* out = target->row(by + y) + bx;
            for (int x = 0; x < 8 && bx + x <= x1_; ++x)
              if (const std::uint8_t m = block[y * 8 + x]) out[x] = over(shade[m], out[x]);
          }
          std::fill(block, block + 64, 0);
        }
      x0_ = size_.width(), y0_ = size_.height(), x1_ = -1, y1_ = -1;
      return;
    }
    const int w = x1_ - x0_ + 1, h = y1_ - y0_ + 1;
    if (image_.width() < w || image_.height() < h) image_ = QImage(std::max(w, image_.width()), std::max(h, image_.height()), QImage::Format_ARGB32_Premultiplied);
    for (int by = y0_; by <= y1_; by += 8)
      for (int bx = x0_; bx <= x1_; bx += 8) {
        std::uint8_t* block = &at(bx, by);
        for (int y = 0; y < 8 && by + y <= y1_; ++y) {
          auto* out = reinterpret_cast<QRgb*>(image_.scanLine(by + y - y0_)) + (bx - x0_);
          for (int x = 0; x < 8 && bx + x <= x1_; ++x) out[x] = shade[block[y * 8 + x]];
        }
        std::fill(block, block + 64, 0);  // cleared for the next picture
      }
    QImage part(image_.constBits(), w, h, image_.bytesPerLine(), QImage::Format_ARGB32_Premultiplied);
    part.setDevicePixelRatio(dpr);
    painter.drawImage(QPointF(x0_ / dpr, y0_ / dpr), part);
    x0_ = size_.width(), y0_ = size_.height(), x1_ = -1, y1_ = -1;
  }

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

namespace {

/// Pre-drawn drones of one colour and size: the disc (or the ring of a drone whose camera failed) with
/// its velocity tick at 128 headings, and the ✕ of a stopped drone, each at half-pixel offsets, drawn
/// as first needed. Stamping one costs about a tenth of an antialiased ellipse and a wide line, which
/// at 10,000 drones is most of a frame. Headings are rounded to 2.8°: under half a pixel at the tick's
/// tip up to the largest sprite.
class DroneSprites {
 public:
  static constexpr double largest_radius = 24;  ///< px; bigger drones (zoomed in, few on screen) are drawn directly
  static constexpr int headings = 128;
  enum Kind { disc, ring };

  DroneSprites(QColor colour, double radius, qreal dpr) : colour_(colour), radius_(radius), dpr_(dpr) {
    side_ = 2 * static_cast<int>(std::ceil(radius + 5 + 2));  // the tick reaches radius + 5, its pen 0.75 beyond
    sprites_.resize(static_cast<std::size_t>(2 * (headings + 1) * 4 + 4));
  }
  bool fits(QColor colour, double radius, qreal dpr) const { return colour == colour_ && radius == radius_ && dpr == dpr_; }

  /// A flying drone at `at` (px) moving along heading `h` (heading_index; −1: still, no tick), into
  /// `pixels` when given, else through the painter.
  void draw(QPainter& painter, const Pixels* pixels, QPointF at, Kind kind, int h) {
    if (h < 0) h = headings;  // the last: no tick
    stamp(painter, pixels, at, static_cast<std::size_t>((kind * (headings + 1) + h) * 4), [&](QPainter& p, QPointF c) {
      if (kind == disc) {
        p.setPen(Qt::NoPen);
        p.setBrush(colour_);
        p.drawEllipse(c, radius_, radius_);
      } else {
        p.setPen(QPen(colour_, 2));
        p.setBrush(Qt::NoBrush);
        p.drawEllipse(c, radius_ - 1, radius_ - 1);
      }
      if (h == headings) return;
      const double a = 2 * pi * h / headings;
      p.setPen(QPen(colour_, 1.5));
      p.drawLine(c, c + QPointF(std::cos(a), std::sin(a)) * (radius_ + 5));
    });
  }
  /// A stopped drone's ✕.
  void draw_stopped(QPainter& painter, const Pixels* pixels, QPointF at) {
    stamp(painter, pixels, at, sprites_.size() - 4, [&](QPainter& p, QPointF c) { draw_cross(p, c, colour_); });
  }

  /// The heading of screen direction (x, y) (y down) in 128ths of a turn, −1 for none. atan2 costs
  /// more than the stamp; an approximation within 0.3° is plenty for bins of 2.8°.
  static int heading_index(double x, double y) {
    const double ax = std::abs(x), ay = std::abs(y);
    if (!(ax + ay > 0)) return -1;
    const double z = std::min(ax, ay) / std::max(ax, ay);
    double a = z * (pi / 4 + 0.273 * (1 - z));  // atan(z), |error| < 0.0038 rad
    if (ay > ax) a = pi / 2 - a;
    if (x < 0) a = pi - a;
    if (y < 0) a = 2 * pi - a;
    return floor_int(a / (2 * pi) * headings + 0.5) & (headings - 1);
  }

 private:
  /// The sprite `first` + phase (the half-pixel offsets in x and y), centred on `at` rounded to half a pixel.
  template <class Draw>
  void stamp(QPainter& painter, const Pixels* pixels, QPointF at, std::size_t first, Draw&& draw) {
    // Off-screen drones were left out, so the coordinates fit an int.
    const int hx = floor_int(at.x() * 2 + 0.5), hy = floor_int(at.y() * 2 + 0.5);  // half pixels
    const int ix = hx >> 1, iy = hy >> 1;  // floors, negative ones too
    const int phase = (hx & 1) + 2 * (hy & 1);
    Sprite& sprite = sprites_[first + static_cast<std::size_t>(phase)];
    if (sprite.image.isNull()) {
      QImage image(QSize(side_, side_) * dpr_, QImage::Format_ARGB32_Premultiplied);
      image.fill(Qt::transparent);
      {
        QPainter p(&image);
        p.scale(dpr_, dpr_);
        p.setRenderHint(QPainter::Antialiasing, true);
        draw(p, QPointF(side_ / 2 + (phase & 1 ? 0.5 : 0), side_ / 2 + (phase & 2 ? 0.5 : 0)));
      }
      // Trimmed to what it covers: a small disc with its tick fills a fifth of the square, and every
      // pixel stamped costs a blend.
      int x0 = image.width(), y0 = image.height(), x1 = -1, y1 = -1;
      for (int y = 0; y < image.height(); ++y) {
        const auto* line = reinterpret_cast<const QRgb*>(image.constScanLine(y));
        for (int x = 0; x < image.width(); ++x)
          if (qAlpha(line[x])) x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
      }
      if (x1 < 0) x0 = y0 = x1 = y1 = 0;
      sprite.image = image.copy(x0, y0, x1 - x0 + 1, y1 - y0 + 1);
      sprite.image.setDevicePixelRatio(dpr_);
      sprite.offset = QPointF(x0, y0) / dpr_;
    }
    const QPointF corner = QPointF(ix - side_ / 2, iy - side_ / 2) + sprite.offset;
    if (pixels) {  // dpr 1: the offset is whole pixels
      const int x0 = static_cast<int>(corner.x()), y0 = static_cast<int>(corner.y());
      const int w = sprite.image.width(), h = sprite.image.height();
      const auto* in = reinterpret_cast<const QRgb*>(sprite.image.constBits());
      const qsizetype in_stride = sprite.image.bytesPerLine() / 4;
      const int from_x = std::max(0, -x0), to_x = std::min(w, pixels->width - x0);
      for (int y = std::max(0, -y0); y < std::min(h, pixels->height - y0); ++y) {
        const QRgb* from = in + y * in_stride;
        QRgb* out = pixels->row(y0 + y) + x0;
        for (int x = from_x; x < to_x; ++x)
          if (const QRgb p = from[x]; p) out[x] = qAlpha(p) == 255 ? p : over(p, out[x]);
      }
      return;
    }
    painter.drawImage(corner, sprite.image);
  }

  struct Sprite {
    QImage image;
    QPointF offset;  ///< of the image in the untrimmed square, px
  };

  static constexpr double pi = 3.14159265358979323846;
  QColor colour_;
  double radius_;
  qreal dpr_;
  int side_;
  std::vector<Sprite> sprites_;  ///< [kind][heading, or none][phase], then the ✕'s 4 phases
};

/// The sprites for `colour` and `radius`, kept between frames (per thread: recordings draw on the
/// engine's). A zoom makes new ones; a handful of sizes and colours are kept.
DroneSprites& drone_sprites(QColor colour, double radius, qreal dpr) {
  thread_local std::vector<std::unique_ptr<DroneSprites>> cache;
  for (auto& s : cache)
    if (s->fits(colour, radius, dpr)) return *s;
  if (cache.size() >= 16) cache.erase(cache.begin());
  cache.push_back(std::make_unique<DroneSprites>(colour, radius, dpr));
  return *cache.back();
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

namespace {

/// Where each drone is on screen (px), and the drones by group, removed ones left out.
struct Layout {
  std::vector<QPointF> at;
  std::vector<std::vector<std::uint32_t>> members;
};
Layout layout_of(const Snapshot& snap, const QTransform& world_to_px) {
  const std::size_t n = snap.positions.size(), groups = std::max<std::size_t>(1, snap.groups.size());
  const Affine map(world_to_px);
  Layout out{std::vector<QPointF>(n), std::vector<std::vector<std::uint32_t>>(groups)};
  for (std::size_t i = 0; i < n; ++i) out.at[i] = map(snap.positions[i].x, snap.positions[i].y);
  for (std::uint32_t i = 0; i < n; ++i)
    if (snap.status_of(i) != DroneStatus::removed) out.members[std::min<std::size_t>(snap.group_of(i), groups - 1)].push_back(i);
  return out;
}

bool shows_trails(const Snapshot& snap, const ViewOptions& options) {
  return options.trails && snap.trail_length > 1 && snap.trails && snap.trails->size() >= snap.positions.size() * snap.trail_length;
}

constexpr int trail_alpha = 85;  // as bold as Qt's 1.2 px lines at alpha 70 were

/// The part of a screen `viewport` (px) whose lines are drawn: a line with an end in it.
struct Visible {
  double left, right, top, bottom;
  explicit Visible(QRectF viewport) {
    const QRectF r = viewport.adjusted(-50, -50, 50, 50);
    left = r.left(), right = r.right(), top = r.top(), bottom = r.bottom();
  }
  bool operator()(QPointF q) const { return q.x() >= left && q.x() <= right && q.y() >= top && q.y() <= bottom; }
};

/// The trail samples' lines, one mask per group (LineMask), decimated on screen: a sample closer than
/// 2 px to the last one drawn adds nothing visible, so the cost follows the trails' length in pixels,
/// not in samples. Past a million samples (15,000 drones of 64) only every stride-th is looked at, so
/// that 100,000 drones' trails cost what 15,000 do; the newest sample always is. Drawn into `layers`
/// unless `kept` and they hold them already for these trails, transform, size and groups; true when
/// drawn.
bool draw_trail_lines(const Snapshot& snap, const Layout& layout, const QTransform& world_to_px, QSize size, qreal dpr,
                      const Visible& shown, TrailLayers& layers, bool kept) {
  if (kept && layers.trails == snap.trails && layers.transform == world_to_px && layers.size == size && layers.members == layout.members)
    return false;
  const std::size_t n = snap.positions.size(), length = snap.trail_length, groups = layout.members.size();
  constexpr std::size_t sample_budget = 1'000'000;
  const std::size_t stride = std::max<std::size_t>(1, (n * length + sample_budget - 1) / sample_budget);
  const Affine map(world_to_px);
  const std::vector<Vec2>& trails = *snap.trails;
  layers.masks.resize(groups);
  layers.ends.assign(n, QPointF(std::numeric_limits<double>::quiet_NaN(), 0));
  for (std::size_t g = 0; g < groups; ++g) {
    LineMask& mask = layers.masks[g];
    mask.begin(size);
    for (std::uint32_t d : layout.members[g]) {
      const Vec2* trail = trails.data() + d * length;
      bool have_last = false;
      QPointF last;
      for (std::size_t k = (length - 1) % stride; k < length; k += stride) {
        const Vec2 p = trail[k];
        if (!std::isfinite(p.x)) {
          have_last = false;
          continue;
        }
        const QPointF q = map(p.x, p.y);
        if (have_last && std::abs(q.x() - last.x()) + std::abs(q.y() - last.y()) < 2) continue;
        if (have_last && (shown(q) || shown(last))) mask.line(last * dpr, q * dpr, trail_alpha);
        last = q;
        have_last = true;
      }
      if (have_last) layers.ends[d] = last;
    }
  }
  if (kept) {
    layers.trails = snap.trails;
    layers.transform = world_to_px;
    layers.size = size;
    layers.members = layout.members;
  }
  return true;
}

/// The trails: their samples' lines, then each drone's last segment, to where it is now (the head).
/// With `cache` the samples' lines are drawn again only when they changed.
void draw_trails(QPainter& painter, const Snapshot& snap, const Layout& layout, const QTransform& world_to_px, TrailLayers* cache) {
  const qreal dpr = painter.device() ? painter.device()->devicePixelRatioF() : 1;
  const QSize size = (QSizeF(painter.viewport().size()) * dpr).toSize();
  const Visible shown(QRectF(painter.viewport()));
  thread_local TrailLayers scratch;  // without a cache (render_frame): drawn, headed and blended at once
  TrailLayers& layers = cache ? *cache : scratch;
  draw_trail_lines(snap, layout, world_to_px, size, dpr, shown, layers, cache != nullptr);
  thread_local LineMask work;
  for (std::size_t g = 0; g < layout.members.size(); ++g) {
    LineMask* mask = &layers.masks[g];
    if (cache) {
      work.assign_lines(*mask);
      mask = &work;
    }
    for (std::uint32_t d : layout.members[g])
      if (const QPointF end = layers.ends[d]; std::isfinite(end.x()) && (shown(end) || shown(layout.at[d])))
        mask->line(end * dpr, layout.at[d] * dpr, trail_alpha);
    mask->finish(painter, group_colour(g, layout.members.size()), dpr);
  }
}

/// The heads of the trails (see draw_trails), blended straight into `pixels` (dpr 1), a band of 16
/// rows at a time (as the drones' sprites: in id order nearly every pixel is a cache miss).
void draw_trail_heads(const Pixels& pixels, const Layout& layout, const TrailLayers& layers, const Visible& shown) {
  const QSize size(pixels.width, pixels.height);
  constexpr int band = 16;
  const int bands = std::max(1, pixels.height / band + 1);
  std::vector<std::uint32_t> starts, order;
  for (std::size_t g = 0; g < layout.members.size(); ++g) {
    const auto band_of = [&](std::uint32_t d) { return static_cast<std::size_t>(std::clamp(layout.at[d].y() / band, 0.0, bands - 1.0)); };
    const auto drawn = [&](std::uint32_t d) {
      const QPointF end = layers.ends[d];
      return std::isfinite(end.x()) && (shown(end) || shown(layout.at[d]));
    };
    starts.assign(static_cast<std::size_t>(bands) + 1, 0);
    for (std::uint32_t d : layout.members[g])
      if (drawn(d)) ++starts[band_of(d) + 1];
    std::partial_sum(starts.begin(), starts.end(), starts.begin());
    order.resize(starts.back());
    for (std::uint32_t d : layout.members[g])
      if (drawn(d)) order[starts[band_of(d)]++] = d;
    const std::array<QRgb, 256> shade = shades(group_colour(g, layout.members.size()));
    for (std::uint32_t d : order)
      wu_line(layers.ends[d], layout.at[d], trail_alpha, size, [&](int x, int y, int v) {
        if (v > 0) pixels.row(y)[x] = over(shade[static_cast<std::size_t>(v)], pixels.row(y)[x]);
      });
  }
}

/// Everything over the static layer. `trails_drawn`: the FrameRenderer drew the trails already.
void draw_dynamic(QPainter& painter, const Snapshot& snap, const ViewOptions& options, const QTransform& world_to_px, const Layout& layout,
                  TrailLayers* cache, bool trails_drawn) {
  painter.save();
  painter.resetTransform();
  painter.setRenderHint(QPainter::Antialiasing, true);
  const double px = px_per_m(world_to_px);
  const std::size_t n = snap.positions.size();
  const std::size_t groups = layout.members.size();
  const std::vector<QPointF>& at = layout.at;
  const std::vector<std::vector<std::uint32_t>>& members = layout.members;  // drawn a group at a time
  const auto flying = [&](std::uint32_t i) { return snap.status_of(i) == DroneStatus::flying; };
  const auto radius_of = [&](std::uint32_t i) { return std::max(3.0, snap.drone_of(i).radius * px); };

  if (!trails_drawn && shows_trails(snap, options)) draw_trails(painter, snap, layout, world_to_px, cache);

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

  // Drones: each a disc (a ring when its camera failed) with its velocity tick, a ✕ where one stopped,
  // a group at a time. Up to DroneSprites::largest_radius they are stamped sprites; bigger (zoomed in,
  // so few on screen) they are drawn.
  const qreal dpr = painter.device() ? painter.device()->devicePixelRatioF() : 1;
  const QRectF screen = QRectF(painter.viewport());
  const std::optional<Pixels> pixels = direct_pixels(painter);
  for (std::size_t g = 0; g < groups; ++g) {
    if (members[g].empty()) continue;
    const QColor colour = group_colour(g, groups);
    const double radius = radius_of(members[g].front());
    const QRectF near = screen.adjusted(-radius - 8, -radius - 8, radius + 8, radius + 8);  // the tick and the ✕ too
    if (radius <= DroneSprites::largest_radius) {
      // What each drone on screen shows, read in id order, then stamped a band of 16 rows at a time,
      // top to bottom (a counting sort): the band's rows stay in the cache, where in id order nearly
      // every row of every sprite is a miss.
      struct Stamp {
        QPointF at;
        int kind;     ///< DroneSprites::Kind, or −1: stopped
        int heading;  ///< DroneSprites::heading_index
      };
      constexpr double band = 16;
      const int bands = static_cast<int>(near.height() / band) + 1;
      std::vector<Stamp> stamps;
      std::vector<std::uint16_t> band_of;
      std::vector<std::uint32_t> starts(static_cast<std::size_t>(bands) + 1, 0);
      for (std::uint32_t i : members[g]) {
        if (!near.contains(at[i])) continue;
        const Vec2 v = snap.velocities[i];
        stamps.push_back({at[i], !flying(i) ? -1 : snap.camera_works(i) ? DroneSprites::disc : DroneSprites::ring,
                          DroneSprites::heading_index(v.x, -v.y)});  // screen y points down
        band_of.push_back(static_cast<std::uint16_t>(std::min(bands - 1, static_cast<int>((at[i].y() - near.top()) / band))));
        ++starts[band_of.back() + 1u];
      }
      std::partial_sum(starts.begin(), starts.end(), starts.begin());
      std::vector<Stamp> sorted(stamps.size());
      for (std::size_t k = 0; k < stamps.size(); ++k) sorted[starts[band_of[k]]++] = stamps[k];
      DroneSprites& sprites = drone_sprites(colour, radius, dpr);
      const Pixels* direct = pixels ? &*pixels : nullptr;
      for (const Stamp& d : sorted) {
        if (d.kind < 0) sprites.draw_stopped(painter, direct, d.at);
        else sprites.draw(painter, direct, d.at, static_cast<DroneSprites::Kind>(d.kind), d.heading);
      }
      continue;
    }
    const auto heading = [&](std::uint32_t i) -> std::optional<double> {
      const Vec2 v = snap.velocities[i];
      if (!(v.length() > 0)) return std::nullopt;
      return std::atan2(-v.y, v.x);  // screen y points down
    };
    for (std::uint32_t i : members[g]) {
      if (!near.contains(at[i])) continue;
      if (!flying(i)) {
        draw_cross(painter, at[i], colour);
        continue;
      }
      if (snap.camera_works(i)) {
        painter.setPen(Qt::NoPen);
        painter.setBrush(colour);
        painter.drawEllipse(at[i], radius, radius);
      } else {
        painter.setPen(QPen(colour, 2));
        painter.setBrush(Qt::NoBrush);
        painter.drawEllipse(at[i], radius - 1, radius - 1);
      }
      if (const auto h = heading(i)) {
        painter.setPen(QPen(colour, 1.5));
        painter.drawLine(at[i], at[i] + QPointF(std::cos(*h), std::sin(*h)) * (radius + 5));
      }
    }
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

}  // namespace

void render_dynamic(QPainter& painter, const Snapshot& snap, const ViewOptions& options, const QTransform& world_to_px) {
  draw_dynamic(painter, snap, options, world_to_px, layout_of(snap, world_to_px), nullptr, false);
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

FrameRenderer::FrameRenderer() = default;
FrameRenderer::~FrameRenderer() = default;

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
    ++layer_version_;
  } else if (found_version_ != snap.found_version && options.targets && snap.scene) {
    // Targets found since: stamped over the layer, not a redraw of 50,000.
    QPainter p(&layer_);
    drawn_found_.resize(snap.found.size(), 0);
    draw_targets(p, *snap.scene, snap.found, world_to_px, [&](std::size_t i) { return i < snap.found.size() && snap.found[i] != drawn_found_[i]; });
    drawn_found_ = snap.found;
    ++found_updates_;
    ++layer_version_;
  }
  found_version_ = snap.found_version;
  if (!trails_) trails_ = std::make_unique<TrailLayers>();
  const Layout layout = layout_of(snap, world_to_px);
  if (dpr != 1) {
    painter.drawImage(QPointF(0, 0), layer_);
    draw_dynamic(painter, snap, options, world_to_px, layout, trails_.get(), false);
    return;
  }
  // The frame is put together in an image of our own, where trails and drones are blended straight
  // into the pixels (direct_pixels), then shown with one copy, as the static layer was before. It
  // starts as the static layer with the trail samples' lines blended in, kept until either changes.
  const bool trails = shows_trails(snap, options);
  const QImage* base = &layer_;
  const Visible shown{QRectF(QPointF(0, 0), QSizeF(layer_.size()))};
  if (trails) {
    const bool drawn = draw_trail_lines(snap, layout, world_to_px, layer_.size(), 1, shown, *trails_, true);
    if (drawn || trails_->base_version != layer_version_ || trails_->base.size() != layer_.size()) {
      if (trails_->base.size() != layer_.size()) trails_->base = QImage(layer_.size(), QImage::Format_ARGB32_Premultiplied);
      std::memcpy(trails_->base.bits(), layer_.constBits(), static_cast<std::size_t>(layer_.sizeInBytes()));
      const Pixels into{reinterpret_cast<QRgb*>(trails_->base.bits()), trails_->base.bytesPerLine() / 4, trails_->base.width(), trails_->base.height()};
      for (std::size_t g = 0; g < layout.members.size(); ++g) trails_->masks[g].blend_into(into, group_colour(g, layout.members.size()));
      trails_->base_version = layer_version_;
    }
    base = &trails_->base;
  }
  if (frame_.size() != layer_.size()) frame_ = QImage(layer_.size(), QImage::Format_ARGB32_Premultiplied);
  std::memcpy(frame_.bits(), base->constBits(), static_cast<std::size_t>(layer_.sizeInBytes()));
  if (trails) {
    const Pixels into{reinterpret_cast<QRgb*>(frame_.bits()), frame_.bytesPerLine() / 4, frame_.width(), frame_.height()};
    draw_trail_heads(into, layout, *trails_, shown);
  }
  {
    QPainter p(&frame_);
    draw_dynamic(p, snap, options, world_to_px, layout, trails_.get(), trails);
  }
  painter.drawImage(QPointF(0, 0), frame_);
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
