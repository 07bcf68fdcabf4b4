// Limits: what the core can simulate faithfully, checked when a test is set up and at every live change.
#include "salsa/core/model/simulation.hpp"

#include <algorithm>
#include <map>
#include <cmath>
#include <limits>

#include "model/physics_world.hpp"  // b2_maxTranslation
#include "model/plugin_call.hpp"
#include "model/world_views.hpp"
#include "model/streams.hpp"
#include "salsa/core/model/map_check.hpp"
#include "format.hpp"

namespace salsa {

using namespace detail;

static_assert(box2d_max_step == b2_maxTranslation, "the step limit quoted to users is Box2D's own");

Problem check_drone(const DroneConfig& d, double dt) {
  for (const DroneProperty& p : drone_schema())
    if (const double v = p.get(d); !p.spec.check(v).empty())
      return {"drone." + p.spec.name, format::number(v) + (p.spec.unit.empty() ? "" : " " + p.spec.unit) + " " + p.spec.check(v)};
  if (d.return_to_base > 0 && !(d.battery_capacity > 0 && d.charge_power > 0))
    return {"drone.return_to_base", "1 needs a battery and a base that charges, here battery_capacity " + format::number(d.battery_capacity) +
                                         " Wh and charge_power " + format::number(d.charge_power) +
                                         " W (allowed: 1 with battery_capacity > 0 and charge_power > 0, or 0)"};
  if (!(std::isfinite(dt) && dt > 0)) return {"dt", format::figure(dt) + " s is out of range (allowed: a finite time step > 0 s)"};

  // Contacts are found once per step (continuous collision is off): a drone that starts a step clear of
  // a wall (farther than radius + Box2D's 0.01 m skin) and moves at most its radius ends it on the same
  // side, touching, and the contact then stops it. Box2D itself caps a step at b2_maxTranslation.
  const double step = d.max_speed * dt;
  const double limit = std::min(d.radius, box2d_max_step);
  if (step <= limit * (1 + 1e-9)) return {};
  const std::string why = d.radius <= box2d_max_step
                              ? "more than the drone's radius " + format::number(d.radius) + " m, so it could pass through a wall between two contact checks"
                              : "more than the " + format::figure(box2d_max_step) + " m Box2D moves a body per step";
  return {"drone.max_speed", format::number(d.max_speed) + " m/s × dt " + format::figure(dt) + " s = " + format::beyond(step, limit) + " m per step, " + why +
                                 " (allowed: max_speed ≤ " + format::limit((limit / dt)) + " m/s at this dt, or dt ≤ " +
                                 format::limit((limit / d.max_speed)) + " s at this max_speed)"};
}

Problem check_wind(const Wind& w, const DroneConfig& d, double dt) {
  for (const WindProperty& p : wind_schema())
    if (const double v = p.get(w); !p.spec.check(v).empty()) return {"wind." + p.spec.name, format::number(v) + " " + p.spec.unit + " " + p.spec.check(v)};
  // The gusts are clamped to gust_clamp standard deviations, so this is the most the drones meet
  // without a field (a field's own speed is checked as the run asks it).
  const double strongest = w.velocity.length() + gust_clamp * w.gust_strength;
  const double limit = wind_limit(d, dt);
  if (strongest == 0 || strongest <= limit * (1 + 1e-9)) return {};
  return {w.gust_strength > 0 ? "wind.gusts.strength" : "wind.velocity",
          "|velocity| " + format::beyond(w.velocity.length(), limit) + " m/s + " + format::figure(gust_clamp) + " × gusts.strength " + format::number(w.gust_strength) +
              " m/s = " + format::beyond(strongest, limit) + " m/s of wind; a drone at max_speed " + format::number(d.max_speed) + " m/s carried by it moves " +
              format::beyond((d.max_speed + strongest) * dt, std::min(d.radius, box2d_max_step)) + " m per step (dt " + format::figure(dt) + " s), more than " +
              (d.radius <= box2d_max_step ? "its radius " + format::number(d.radius) + " m, so it could pass through a wall"
                                          : "the " + format::figure(box2d_max_step) + " m Box2D moves a body per step") +
              " (allowed: |velocity| + " + format::figure(gust_clamp) + " × gusts.strength ≤ " + (limit > 0 ? format::limit((limit)) : "0") +
              " m/s with this drone and dt; or a smaller dt)"};
}

Problem check_map(const MapData& map) {
  const auto problems = map_problems(map, 0, MapRules::structure, 1);
  return problems.empty() ? Problem{} : Problem{problems[0].field, problems[0].message};
}

Problem check_resolution(const Rect& bounds, const DroneConfig& drone, double dt, PhysicsMode physics) {
  const double largest = std::max({std::abs(bounds.min.x), std::abs(bounds.min.y), std::abs(bounds.max.x), std::abs(bounds.max.y)});
  const bool box2d = physics == PhysicsMode::box2d;  // the light physics keeps doubles
  const auto f = static_cast<float>(largest);
  const double spacing = box2d ? static_cast<double>(std::nextafter(f, std::numeric_limits<float>::infinity())) - f
                               : std::nextafter(largest, std::numeric_limits<double>::infinity()) - largest;
  const double step = drone.max_speed * dt;
  if (spacing <= 0.02 * step) return {};
  // Floats in [2^e, 2^(e+1)) are 2^(e-23) apart (doubles 2^(e-52)): the last binade where that is ≤ 2 % of a step.
  const double allowed = std::ldexp(1.0, (box2d ? 24 : 53) + std::ilogb(0.02 * step));
  return {"bounds", format::rect(bounds) + (box2d ? ": Box2D keeps positions as 32-bit floats, " : ": the light physics keeps positions as 64-bit doubles, ") +
                        format::beyond(spacing, 0.02 * step) + " m apart at " +
                        format::figure(largest) + " m, more than 2 % of a drone's step (max_speed " + format::figure(drone.max_speed) +
                        " m/s × dt " + format::figure(dt) + " s = " + format::short_figure(step) +
                        " m), so drones would move in jumps or not at all (allowed: coordinates within ±" + format::figure(allowed) +
                        " m at this max_speed and dt)"};
}

Problem check_room(const Rect& bounds, Vec2 map_spawn, std::span<const GroupSetup> groups) {
  double bodies = 0, largest = 0;
  std::size_t drones = 0;
  for (const GroupSetup& g : groups) {
    bodies += static_cast<double>(g.drones) * pi * g.drone.radius * g.drone.radius;
    drones += g.drones, largest = std::max(largest, g.drone.radius);
  }
  const double area = bounds.width() * bounds.height();
  auto most = [](double room, double radius) { return format::grouped(std::floor(room * disc_packing / (pi * radius * radius))); };
  if (drones > 1 && bodies > area * disc_packing)
    return {"drones", format::grouped(static_cast<double>(drones)) + " drones (bodies of " + format::short_figure(bodies) + " m²) do not fit on the map (" +
                          format::rect(bounds) + ": " + format::short_figure(area * disc_packing) +
                          " m² at the densest packing of discs); they would start piled, each touching the others (allowed: at most " +
                          most(area, largest) + " drones of radius " + format::number(largest) + " m here; or a larger map)"};
  // The groups that spawn in discs around one point share that room (one pass, grouped by point). One
  // drone alone always fits: the packing density bounds many discs, not one.
  struct Here {
    double bodies = 0, disc = 0, radius = 0;
    std::size_t count = 0, sharing = 0;
  };
  std::map<std::pair<double, double>, Here> points;
  std::vector<std::pair<double, double>> order;  // first seen first: the message names the first pile
  for (const GroupSetup& g : groups) {
    if (g.spawn_mode != SpawnMode::disc) continue;
    const Vec2 point = g.spawn.value_or(map_spawn);
    const auto [it, fresh] = points.try_emplace({point.x, point.y});
    if (fresh) order.push_back(it->first);
    Here& h = it->second;
    ++h.sharing, h.count += g.drones, h.radius = std::max(h.radius, g.drone.radius);
    h.bodies += static_cast<double>(g.drones) * pi * g.drone.radius * g.drone.radius;
    h.disc = std::max(h.disc, g.spawn_radius > 0 ? g.spawn_radius : static_cast<double>(g.drones) * g.drone.radius);
  }
  for (const auto& key : order) {
    const Here& h = points.at(key);
    const double room = std::min(pi * (h.disc + h.radius) * (h.disc + h.radius), area);
    if (h.count < 2 || h.bodies <= room * disc_packing) continue;
    const double needed = std::sqrt(h.bodies / (disc_packing * pi)) - h.radius;  // the disc that holds them
    return {"spawn.radius", (h.sharing > 1 ? format::grouped(static_cast<double>(h.sharing)) + " groups spawn " : "") +
                                format::grouped(static_cast<double>(h.count)) + " drones (bodies of " + format::short_figure(h.bodies) + " m²) at " +
                                format::point({key.first, key.second}) + " in discs of at most " + format::number(h.disc) + " m, which hold " +
                                format::short_figure(room * disc_packing) +
                                " m² at the densest packing; they would start piled, each touching the others (allowed: spawn.radius ≥ " +
                                format::figure(std::ceil(needed)) + " m" + (h.sharing > 1 ? " for these groups, or spawn points of their own)" : ")")};
  }
  return {};
}

Problem check_targets(std::span<const Vec2> positions, std::size_t count, double radius, const Rect& bounds) {
  if (!(std::isfinite(radius) && radius >= 0)) return {"radius", format::figure(radius) + " m (allowed: a finite radius ≥ 0 m)"};
  if (positions.size() != count)
    return {"positions", std::to_string(positions.size()) + " placed for " + std::to_string(count) + " targets asked for"};
  for (std::size_t i = 0; i < positions.size(); ++i)
    if (!positions[i].finite() || !bounds.contains(positions[i]))
      return {"positions[" + std::to_string(i) + "]",
              format::point(positions[i]) + (positions[i].finite() ? " is outside" : " is not finite (allowed: a point inside") +
                  " the bounds (" + format::rect(bounds) + ")" + (positions[i].finite() ? "" : ")")};
  return {};
}

Problem check_view_range(const TargetKind& kind, const DroneConfig& drone) {
  const double range = plugin_call(target_kind, 0, [&] { return kind.view_range(drone.camera_range); });
  if (std::isfinite(range) && range >= 0) return {};
  return {"view_range", format::figure(range) + " m for a camera range of " + format::figure(drone.camera_range) +
                            " m (allowed: a finite distance ≥ 0 m)"};
}

Problem check_target_motion(const TargetKind& kind, double dt) {
  if (!plugin_call(target_kind, 0, [&] { return kind.moves(); })) return {};
  const double speed = plugin_call(target_kind, 0, [&] { return kind.max_speed(); });
  const double radius = plugin_call(target_kind, 0, [&] { return kind.radius(); });
  if (!(std::isfinite(speed) && speed >= 0)) return {"max_speed", format::figure(speed) + " m/s (allowed: a finite speed ≥ 0 m/s)"};
  if (speed * dt <= radius) return {};
  const double most = radius / speed, digits = std::pow(10.0, 3 - std::floor(std::log10(most)));  // 4 figures, rounded down: itself allowed
  return {"dt", format::figure(dt) + " s lets a target moving at up to " + format::figure(speed) + " m/s go " + format::figure(speed * dt) +
                    " m in a step, more than its radius " + format::figure(radius) + " m: it could step through a wall (allowed: a time step of at most " +
                    format::figure(std::floor(most * digits) / digits) + " s, a slower speed or a larger radius)"};
}

DroneProperties drone_properties(const DroneConfig& d) {
  DroneProperties p;
  p.camera_range = d.camera_range;
  p.obstacle_range = d.obstacle_range;
  p.detection_range = d.detection_range;
  p.max_speed = d.max_speed;
  p.max_force = d.max_force;
  p.radius = d.radius;
  p.mass = d.mass;
  return p;
}

std::vector<Vec2> initial_targets(const TargetKind& kind, std::size_t count, const MapData& map,
                                  const StaticGeometry& geometry, const DroneConfig& drone, double dt,
                                  std::uint64_t seed) {
  if (count == 0) return {};
  // The radius first: placement keeps targets `radius` clear of obstacles.
  const double radius = plugin_call(target_kind, 0, [&] { return kind.radius(); });
  if (auto p = check_targets({}, 0, radius, map.bounds)) throw std::invalid_argument(p.text());
  if (auto p = check_view_range(kind, drone)) throw std::invalid_argument(p.text());
  if (auto p = check_target_motion(kind, dt)) throw std::invalid_argument(p.text());
  const StateView view(map, geometry, drone_properties(drone), 0, dt);
  Rng rng(seed, targets_stream);
  std::vector<Vec2> positions = plugin_call(target_kind, 0, [&] { return kind.place(count, view, rng); });
  if (auto p = check_targets(positions, count, radius, map.bounds)) throw std::invalid_argument(p.text());
  return positions;
}

}  // namespace salsa
