// Trails: each drone's recent path as thin lines, drawn by hand into a mask per group (LineMask says why).
#include <QPainter>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>

#include "view_draw.hpp"

namespace salsa::gui {
namespace {

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

constexpr int trail_alpha = 85;  // as bold as Qt's 1.2 px lines at alpha 70 were

}  // namespace

void LineMask::begin(QSize size) {
  if (size != size_) {
    size_ = size;
    blocks_x_ = (std::max(0, size.width()) + 7) / 8;
    mask_.assign(static_cast<std::size_t>(blocks_x_) * static_cast<std::size_t>((std::max(0, size.height()) + 7) / 8) * 64, 0);
    x1_ = y1_ = -1;  // a new mask: nothing drawn on
  }
  clear_drawn();  // lines drawn and not blended
}

void LineMask::clear_drawn() {
  for (int by = y0_ & ~7; by <= y1_; by += 8)
    for (int bx = x0_ & ~7; bx <= x1_; bx += 8) std::fill_n(&at(bx, by), 64, 0);
  x0_ = size_.width(), y0_ = size_.height(), x1_ = -1, y1_ = -1;
}

void LineMask::line(QPointF a, QPointF b, int alpha) {
  const QRect r = wu_line(a, b, alpha, size_, [this](int x, int y, int v) { plot(x, y, v); });
  if (r.isEmpty()) return;
  x0_ = std::min(x0_, r.left()), x1_ = std::max(x1_, r.right());
  y0_ = std::min(y0_, r.top()), y1_ = std::max(y1_, r.bottom());
}

void LineMask::blend_into(const Pixels& target, const QColor& colour) const {
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

void LineMask::assign_lines(const LineMask& other) {
  size_ = other.size_, blocks_x_ = other.blocks_x_, mask_ = other.mask_;
  x0_ = other.x0_, y0_ = other.y0_, x1_ = other.x1_, y1_ = other.y1_;
}

void LineMask::finish(QPainter& painter, const QColor& colour, qreal dpr) {
  if (x1_ < x0_ || y1_ < y0_) return;
  if (const auto target = direct_pixels(painter); target && QSize(target->width, target->height) == size_) {
    blend_into(*target, colour);
    clear_drawn();
    return;
  }
  const std::array<QRgb, 256> shade = shades(colour);
  x0_ &= ~7, y0_ &= ~7;  // whole blocks
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

bool shows_trails(const Snapshot& snap, const ViewOptions& options) {
  return options.trails && snap.trail_length > 1 && snap.trails && snap.trails->size() >= snap.positions.size() * snap.trail_length;
}

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

}  // namespace salsa::gui
