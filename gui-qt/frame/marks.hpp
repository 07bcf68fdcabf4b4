#pragma once
// Marks drawn alike on the desktop's view, in videos and in the plots of a run.
#include <QColor>
#include <QPainter>
#include <QPointF>

namespace salsa::gui {

/// A ✕ in `colour` with a white rim, centred on `at`: where a drone stopped (landed or failed).
void draw_cross(QPainter& p, QPointF at, const QColor& colour);

}  // namespace salsa::gui
