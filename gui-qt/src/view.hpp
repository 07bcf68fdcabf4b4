#pragma once
// SwarmView: the sandbox's view of the swarm, with zoom, pan, fit and click to select.
#include <QImage>
#include <QTransform>
#include <QWidget>
#include <memory>
#include <optional>

#include "frame_renderer.hpp"

namespace salsa::gui {

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
