// Drones: a disc or ring with its velocity tick, or a ✕ where one stopped, stamped as sprites (DroneSprites says why).
#include <QPainter>
#include <algorithm>
#include <cmath>
#include <numeric>

#include "view_draw.hpp"

namespace salsa::gui {
namespace {

const QColor drone_colour(0x1f, 0x3f, 0x8c);  // one group

}  // namespace

QColor group_colour(std::size_t group, std::size_t groups) {
  // Okabe & Ito's colour-blind-safe set in the plots' order (plots/src/figure.cpp), so a group has one
  // colour on screen and in the figures.
  static const QColor colours[] = {0xE69F00, 0x0072B2, 0x009E73, 0xD55E00, 0x56B4E9, 0xCC79A7, 0xF0E442};
  return groups < 2 ? drone_colour : colours[group % std::size(colours)];
}

void draw_drone(QPainter& p, QPointF at, const QColor& colour, double radius, bool camera_works, std::optional<double> heading) {
  if (camera_works) {
    p.setPen(Qt::NoPen);
    p.setBrush(colour);
    p.drawEllipse(at, radius, radius);
  } else {
    p.setPen(QPen(colour, 2));
    p.setBrush(Qt::NoBrush);
    p.drawEllipse(at, radius - 1, radius - 1);
  }
  if (!heading) return;
  p.setPen(QPen(colour, 1.5));
  p.drawLine(at, at + QPointF(std::cos(*heading), std::sin(*heading)) * (radius + 5));
}

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
      draw_drone(p, c, colour_, radius_, kind == disc, h == headings ? std::nullopt : std::optional<double>(2 * pi * h / headings));
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

void draw_drones(QPainter& painter, const Snapshot& snap, const Layout& layout, double px) {
  const std::size_t groups = layout.members.size();
  const std::vector<QPointF>& at = layout.at;
  const std::vector<std::vector<std::uint32_t>>& members = layout.members;
  const auto flying = [&](std::uint32_t i) { return snap.status_of(i) == DroneStatus::flying; };
    // Drones: each a disc (a ring when its camera failed) with its velocity tick, a ✕ where one stopped,
  // a group at a time. Up to DroneSprites::largest_radius they are stamped sprites; bigger (zoomed in,
  // so few on screen) they are drawn.
  const qreal dpr = painter.device() ? painter.device()->devicePixelRatioF() : 1;
  const QRectF screen = QRectF(painter.viewport());
  const std::optional<Pixels> pixels = direct_pixels(painter);
  for (std::size_t g = 0; g < groups; ++g) {
    if (members[g].empty()) continue;
    const QColor colour = group_colour(g, groups);
    const double radius = radius_px(snap, members[g].front(), px);
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
      draw_drone(painter, at[i], colour, radius, snap.camera_works(i), heading(i));
    }
  }
}

}  // namespace salsa::gui
