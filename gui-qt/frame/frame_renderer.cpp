// A frame: the static layer (cached by the FrameRenderer), then trails, moving targets, wind, links, ranges, drones,
// selection, legend.
#include <QPainter>
#include <algorithm>
#include <cstring>

#include "view_draw.hpp"

namespace salsa::gui {

Layout layout_of(const Snapshot& snap, const QTransform& world_to_px) {
  const std::size_t n = snap.positions.size(), groups = std::max<std::size_t>(1, snap.groups.size());
  const Affine map(world_to_px);
  Layout out{std::vector<QPointF>(n), std::vector<std::vector<std::uint32_t>>(groups)};
  for (std::size_t i = 0; i < n; ++i) out.at[i] = map(snap.positions[i].x, snap.positions[i].y);
  for (std::uint32_t i = 0; i < n; ++i)
    if (snap.status_of(i) != DroneStatus::removed) out.members[std::min<std::size_t>(snap.group_of(i), groups - 1)].push_back(i);
  return out;
}

QTransform fit_transform(const Rect& area, QSizeF size) {
  const double w = std::max(area.width(), 1e-9), h = std::max(area.height(), 1e-9);
  const double margin = 12;
  const double scale = std::max(1e-9, std::min((size.width() - 2 * margin) / w, (size.height() - 2 * margin) / h));
  const double cx = (area.min.x + area.max.x) / 2, cy = (area.min.y + area.max.y) / 2;
  // y up: world y grows towards the top of the picture.
  return QTransform(scale, 0, 0, -scale, size.width() / 2 - scale * cx, size.height() / 2 + scale * cy);
}

namespace {

/// Everything over the static layer. `trails_drawn`: the FrameRenderer drew the trails already.
void draw_dynamic(QPainter& painter, const Snapshot& snap, const ViewOptions& options, const QTransform& world_to_px, const Layout& layout,
                  TrailLayers* cache, bool trails_drawn) {
  painter.save();
  painter.resetTransform();
  painter.setRenderHint(QPainter::Antialiasing, true);
  const double px = px_per_m(world_to_px);
  if (!trails_drawn && shows_trails(snap, options)) draw_trails(painter, snap, layout, world_to_px, cache);
  if (options.targets && !snap.targets.empty()) draw_moving_targets(painter, snap, world_to_px);
  if (options.wind && !snap.wind.empty()) draw_wind(painter, snap, world_to_px);
  if (options.links && !snap.links.empty()) draw_links(painter, snap, layout);
  draw_ranges(painter, snap, options, layout, px);
  draw_drones(painter, snap, layout, px);
  if (snap.selected && snap.selected->id < snap.positions.size()) draw_selection(painter, snap, layout, world_to_px);
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
  } else if (found_version_ != snap.found_version && options.targets && snap.scene && snap.targets.empty()) {
    // Targets found since: stamped over the layer, not a redraw of 50,000.
    QPainter p(&layer_);
    drawn_found_.resize(snap.found.size(), 0);
    draw_found_since(p, *snap.scene, snap.found, drawn_found_, world_to_px);
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

}  // namespace salsa::gui
