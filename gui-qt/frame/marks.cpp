#include "marks.hpp"

#include <QPen>

namespace salsa::gui {

void draw_cross(QPainter& p, QPointF at, const QColor& colour) {
  const QPointF a(5, 5), b(5, -5);
  for (const QPen& pen : {QPen(Qt::white, 5, Qt::SolidLine, Qt::RoundCap), QPen(colour, 2.5, Qt::SolidLine, Qt::RoundCap)}) {
    p.setPen(pen);
    p.drawLine(at - a, at + a);
    p.drawLine(at - b, at + b);
  }
}

}  // namespace salsa::gui
