#include "inspector_text.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "format.hpp"

namespace salsa::gui {
namespace {

QString q(const std::string& s) { return QString::fromStdString(s); }

/// A unit shown in another for a person: energy in Wh, as the battery's capacity is given.
struct ShownUnit {
  const char* unit;
  const char* shown;
  double factor;
};
constexpr ShownUnit shown_units[] = {{"J", "Wh", 1.0 / 3600}};

/// `v` rounded for reading: 2 decimals from 1 up, 3 significant digits below (exact values stay exact).
double rounded(double v) {
  if (!std::isfinite(v) || v == 0) return v;
  if (std::fabs(v) >= 1) return std::round(v * 100) / 100;
  return std::strtod(format::significant(v, 3).c_str(), nullptr);
}

/// "position [12.35, -3.1] m", "energy used 0.52 Wh", "status 0".
QString state_line(const StateLine& line) {
  std::string_view unit = line.unit;
  double factor = 1;
  for (const ShownUnit& s : shown_units)
    if (unit == s.unit) unit = s.shown, factor = s.factor;
  auto value = [&](double v) { return line.whole ? v : rounded(v * factor); };
  QString text = q(line.name).replace('_', ' ');
  if (line.values.size() == 2) text += " " + q(format::point({value(line.values[0]), value(line.values[1])}));
  else
    for (double v : line.values) text += " " + q(format::number(value(v)));
  if (!unit.empty()) text += " " + QString::fromUtf8(unit.data(), static_cast<qsizetype>(unit.size()));
  return text;
}

QString ids(const std::vector<std::uint32_t>& list) {
  QString text;
  for (std::size_t i = 0; i < std::min<std::size_t>(list.size(), 12); ++i) text += QString(" %1").arg(list[i]);
  if (list.size() > 12) text += " …";
  return text;
}

}  // namespace

QString inspection_text(const Snapshot& snap) {
  if (!snap.selected) return {};
  const Inspection& in = *snap.selected;
  QString text = QString("drone %1").arg(in.id);
  if (snap.groups.size() > 1) text += QString(" of group %1").arg(q(in.group));
  if (in.fleet) text += QString(": %1").arg(q(in.status));
  // Grouped by model, in the order the simulation lists them.
  std::vector<std::string> models;
  for (const StateLine& l : in.state)
    if (std::find(models.begin(), models.end(), l.model) == models.end()) models.push_back(l.model);
  for (const std::string& model : models) {
    text += "\n" + q(model) + ":";
    for (const StateLine& l : in.state)
      if (l.model == model) text += "\n  " + state_line(l);
  }
  text += QString("\nneighbours (%1 within %2 m):").arg(in.neighbours.size()).arg(snap.drone_of(in.id).detection_range) + ids(in.neighbours);
  if (!in.recorded) {
    text += QString("\nobstacle hits: %1").arg(in.hits.size());
    for (const ObstacleHit& h : in.hits) text += QString(" %1 m").arg(h.distance, 0, 'f', 1);
  }
  if (in.perceived)
    text += QString("\nperceived position %1 m, %2 m off").arg(q(format::point({rounded(in.perceived->x), rounded(in.perceived->y)})))
                .arg(distance(*in.perceived, in.position), 0, 'f', 2);
  if (in.heard) text += QString("\nmessages next step: %1 from").arg(in.heard->size()) + ids(*in.heard);
  if (!in.memory.empty()) text += "\nmemory: " + q(in.memory);
  return text;
}

}  // namespace salsa::gui
