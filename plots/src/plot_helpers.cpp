// What the plots of a run share: Qt set up, the run's files read, and values drawn as lines and bands.
#include "salsa/plots/results.hpp"

#include <QPainterPath>
#include <QPolygonF>

#include <algorithm>
#include <cmath>

#include "salsa/core/experiments/test_spec.hpp"
#include "strict_json.hpp"
#include "plot_helpers.hpp"

namespace salsa::plots {

namespace fs = std::filesystem;
using nlohmann::json;

void start_plotting() { ensure_application(); }

std::string name_of(const fs::path& p) { return strict_json::printable(p.string(), 200); }

json read_json(const fs::path& file, const char* what) {
  try {
    return strict_json::read_file<json>(file, what);
  } catch (const strict_json::Error& e) {
    throw InputError(e.what());
  }
}

bool is_file(const fs::path& p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec);
}

void draw_line(Figure& f, const std::vector<double>& x, const std::vector<double>& y, const QColor& colour, double width,
               Qt::PenStyle style) {
  QPainterPath path;
  bool pen_down = false;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (std::isnan(y[i])) {
      pen_down = false;
      continue;
    }
    pen_down ? path.lineTo(f.at(x[i], y[i])) : path.moveTo(f.at(x[i], y[i]));
    pen_down = true;
  }
  f.painter().setBrush(Qt::NoBrush);
  f.painter().setPen(QPen(colour, width, style, Qt::RoundCap, Qt::RoundJoin));
  f.painter().drawPath(path);
}

void draw_band(Figure& f, const std::vector<double>& x, const std::vector<double>& lo, const std::vector<double>& hi, QColor colour) {
  QPolygonF band;
  for (std::size_t i = 0; i < x.size(); ++i) band << f.at(x[i], lo[i]);
  for (std::size_t i = x.size(); i-- > 0;) band << f.at(x[i], hi[i]);
  f.painter().setPen(Qt::NoPen);
  f.painter().setBrush(colour);
  f.painter().drawPolygon(band);
}

std::pair<double, double> range_of(const std::vector<double>& v) {
  double lo = 1e300, hi = -1e300;
  for (double x : v)
    if (!std::isnan(x)) lo = std::min(lo, x), hi = std::max(hi, x);
  return lo > hi ? std::pair{0.0, 1.0} : std::pair{lo, hi};
}

}  // namespace salsa::plots
