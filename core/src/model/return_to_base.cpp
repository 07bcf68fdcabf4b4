// Return to base, around any behavior: when a drone's battery holds what the way home needs plus the
// group's reserve, the core takes it from its behavior (whose decide is no longer called for it; its
// memory stays), flies it home, lets it charge and flies it back to where it left off, then hands it
// back. Its errand is a column of its own; its status stays flying (it is in the air, seen, and counted
// by its behavior's shared state, as any flying drone).
#include "salsa/core/model/simulation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>

#include "salsa/behavior.hpp"  // ground_speed_along and the steering helpers every behavior uses

namespace salsa {

namespace {

constexpr double inf = std::numeric_limits<double>::infinity();

/// The deceleration (m/s²) the way home is planned and flown with: half of what the steering can do,
/// leaving the other half to obstacle avoidance.
double braking(const DroneConfig& d, double dt) { return d.max_force / (2 * dt); }

/// Weight of obstacle avoidance against the way (that of examples/plugin/return_to_base.cpp).
constexpr double avoidance = 4;

}  // namespace

double energy_home(const DroneConfig& d, double distance, Vec2 u, Vec2 velocity, Vec2 wind, double dt) {
  const double full = flight_power(d, d.max_speed);
  const double most = std::max(flight_power(d, 0), full);  // P over air speeds in [0, max_speed]: at an end
  const double accel = d.max_force / dt, a = braking(d, dt);
  if (distance == 0) return velocity.length() / accel * most;  // only stopping
  Perception me;
  me.max_speed = d.max_speed;
  me.wind = wind;
  const double g = ground_speed_along(me, u);
  if (g <= 0) return inf;
  // Turn onto the way (at most full acceleration), cruise at full air speed, brake to rest at `a`; the
  // turn and the braking are charged at the highest power they can draw, the cruise at P(max_speed).
  const double top = std::min(g, std::sqrt(2 * a * distance));
  const double turn = (u * top - velocity).length() / accel;
  const double cruise = std::max(0.0, distance - top * top / (2 * a)) / g;
  return (turn + top / a) * most + cruise * full;
}

// The way home on the map: a grid over the bounds (cells of the drone's radius, at most 1000 a side),
// a cell free when a drone and half its radius more fits at its centre, and for each free cell the length of the shortest
// 8-connected path of free cells to the base's cell (Dijkstra). A drone that sees its base (no wall or
// obstacle on the straight line) flies straight; otherwise towards the cell nearby with the shortest
// way left, so that a pocket of trees or a room's walls do not hold it, and the way's length counts
// the detour. The grid's paths are up to 8 % longer than the shortest free line: on the safe side.
struct Simulation::Drones::Errands::HomeMap {
  Vec2 base, origin;
  double radius = 0, cell = 1;
  std::size_t nx = 0, ny = 0;
  std::vector<float> way;  ///< m to the base along free cells; +inf: not free or not reachable

  /// The way left from `p`, and where to fly next: the best of the cells within two of p's, by their
  /// way plus the straight line to their centre. Nothing found: +inf.
  std::pair<double, Vec2> from(Vec2 p) const {
    const auto cx = static_cast<std::ptrdiff_t>(std::floor((p.x - origin.x) / cell));
    const auto cy = static_cast<std::ptrdiff_t>(std::floor((p.y - origin.y) / cell));
    double best = inf;
    Vec2 next = base;
    for (std::ptrdiff_t y = cy - 2; y <= cy + 2; ++y)
      for (std::ptrdiff_t x = cx - 2; x <= cx + 2; ++x) {
        if (x < 0 || y < 0 || x >= static_cast<std::ptrdiff_t>(nx) || y >= static_cast<std::ptrdiff_t>(ny)) continue;
        const float w = way[static_cast<std::size_t>(y) * nx + static_cast<std::size_t>(x)];
        if (!std::isfinite(w)) continue;
        const Vec2 c = centre(static_cast<std::size_t>(x), static_cast<std::size_t>(y));
        if (const double total = w + distance(p, c); total < best) best = total, next = c;
      }
    return {best, next};
  }
  Vec2 centre(std::size_t x, std::size_t y) const {
    return {origin.x + (static_cast<double>(x) + 0.5) * cell, origin.y + (static_cast<double>(y) + 0.5) * cell};
  }
};

const Simulation::Drones::Errands::HomeMap& Simulation::home_map(std::uint32_t group) {
  auto& maps = drones_.errands.home;
  if (maps.size() < setup_.groups.size()) maps.resize(setup_.groups.size());
  const double radius = setup_.groups[group].drone.radius;
  const Vec2 base = groups_[group].base;
  if (maps[group] && maps[group]->base == base && maps[group]->radius == radius) return *maps[group];
  auto m = std::make_shared<Drones::Errands::HomeMap>();
  const Rect b = setup_.map.bounds;
  m->base = base, m->radius = radius, m->origin = b.min;
  m->cell = std::max(radius, std::max(b.width(), b.height()) / 1000);
  m->nx = std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil(b.width() / m->cell)));
  m->ny = std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil(b.height() / m->cell)));
  const std::size_t n = m->nx * m->ny;
  std::vector<std::uint8_t> free(n);
  for (std::size_t y = 0; y < m->ny; ++y)
    for (std::size_t x = 0; x < m->nx; ++x) free[y * m->nx + x] = geometry_.is_free(m->centre(x, y), 1.5 * radius);  // room to pass
  m->way.assign(n, static_cast<float>(inf));
  const auto bx = std::min(m->nx - 1, static_cast<std::size_t>(std::max(0.0, (base.x - b.min.x) / m->cell)));
  const auto by = std::min(m->ny - 1, static_cast<std::size_t>(std::max(0.0, (base.y - b.min.y) / m->cell)));
  const std::size_t start = by * m->nx + bx;
  free[start] = 1;  // the base is free space (check_map); its cell's centre may graze an obstacle
  using Item = std::pair<float, std::size_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> queue;
  m->way[start] = static_cast<float>(distance(base, m->centre(bx, by)));
  queue.push({m->way[start], start});
  const double diagonal = m->cell * std::sqrt(2.0);
  while (!queue.empty()) {
    const auto [w, k] = queue.top();
    queue.pop();
    if (w > m->way[k]) continue;
    const std::size_t x = k % m->nx, y = k / m->nx;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        if ((dx == 0 && dy == 0) || (dx < 0 && x == 0) || (dy < 0 && y == 0) || (dx > 0 && x + 1 == m->nx) || (dy > 0 && y + 1 == m->ny)) continue;
        const std::size_t nxk = x + static_cast<std::size_t>(dx), nyk = y + static_cast<std::size_t>(dy), j = nyk * m->nx + nxk;
        if (!free[j]) continue;
        if (dx != 0 && dy != 0 && !(free[y * m->nx + nxk] && free[nyk * m->nx + x])) continue;  // no corner cutting
        const auto next = static_cast<float>(w + (dx != 0 && dy != 0 ? diagonal : m->cell));
        if (next < m->way[j]) m->way[j] = next, queue.push({next, j});
      }
  }
  maps[group] = std::move(m);
  return *maps[group];
}

// Home (or back out): full speed along the way, slowed so as to stop where it goes. Home, the way is
// the straight line while the base is in sight and the home map's otherwise; out, the straight line to
// where it left off, with the SDK's obstacle avoidance faded out on the last 20 m. Charging: hold
// still over the base.
Vec2 Simulation::errand_steering(const Perception& me) const {
  const Errand e = errand(me.id);
  if (e == Errand::charging) return steer_towards(me, {});
  const bool home = e == Errand::returning;
  const DroneConfig& config = setup_.groups[me.group].drone;
  const double d = home ? drones_.errands.need_way[me.id] : distance(me.position, drones_.errands.resume[me.id]);
  const Vec2 towards = home ? drones_.errands.next[me.id] : drones_.errands.resume[me.id];
  const Vec2 way = towards - me.position;
  if (d == 0 || way.is_zero()) return steer_towards(me, {});
  const Vec2 u = way.normalized();
  const double a = braking(config, me.dt);
  // Home, it stops halfway into the charging circle: drones coming from all sides rest around the base
  // rather than on one another at its centre.
  const double stop = home ? d - config.charge_radius / 2 : d;
  // Out, the SDK's obstacle avoidance; home, the way is free already (avoidance would push it off).
  const Vec2 avoid = home ? Vec2{} : avoidance * std::min(1.0, d / 20) * avoid_near_obstacles(me);
  return steer_towards(me, u * std::min(ground_speed_along(me, u), std::sqrt(2 * a * std::max(0.0, stop)))) + avoid;
}

// The way home from drone i now: its length and the point to fly at next.
void Simulation::way_home(std::uint32_t i) {
  Drones::Errands& e = drones_.errands;
  const std::uint32_t g = drones_.groups[i];
  const Vec2 p = drones_.positions[i], base = groups_[g].base;
  // In sight: the lines from either side of the drone's body to either side of the base are clear.
  const Vec2 side = (base - p).is_zero() ? Vec2{} : Vec2{p.y - base.y, base.x - p.x}.with_length(setup_.groups[g].drone.radius);
  if (!geometry_.blocked(p, base) && !geometry_.blocked(p + side, base + side) && !geometry_.blocked(p - side, base - side)) {
    e.need_way[i] = distance(p, base), e.next[i] = base;
    return;
  }
  const auto [length, next] = home_map(g).from(p);
  if (std::isfinite(length)) e.need_way[i] = length, e.next[i] = next;
  else e.need_way[i] = distance(p, base), e.next[i] = base;  // off the grid's free cells: straight
}

// After the battery's step (fleet.cpp): the errand's next state. `on_base`: the drone charged this step.
void Simulation::errand_step(std::uint32_t i, bool on_base) {
  Drones::Errands& e = drones_.errands;
  const std::uint32_t g = drones_.groups[i];
  const DroneConfig& d = setup_.groups[g].drone;
  const double charge = drones_.fleet.charge[i];
  auto state = static_cast<Errand>(e.state[i]);
  if (state != Errand::charging) way_home(i);
  if (state == Errand::none || state == Errand::outbound) {
    const Vec2 wind = wind_active_ ? drones_.air.wind[i] : Vec2{};
    const Vec2 way = e.next[i] - drones_.positions[i];
    e.need[i] = energy_home(d, e.need_way[i], way.is_zero() ? Vec2{} : way.normalized(), drones_.velocities[i], wind, setup_.dt);
    if (charge <= e.need[i] + d.return_reserve * 3600) {
      if (state == Errand::none) e.resume[i] = drones_.positions[i];
      state = Errand::returning;
    } else if (state == Errand::outbound && distance(drones_.positions[i], e.resume[i]) <= d.radius + 1) {
      state = Errand::none;
    }
  }
  if (state == Errand::returning && on_base) state = Errand::charging;
  if (state == Errand::charging) {
    if (!on_base) {
      state = Errand::returning;  // pushed off the base
      way_home(i);
    } else {
      e.charging[i] += setup_.dt;
      if (charge >= d.resume_charge * d.battery_capacity * 3600) state = Errand::outbound;
    }
  }
  e.state[i] = static_cast<std::uint8_t>(state);
}

void Simulation::Drones::Errands::grow(std::size_t drones) {
  state.resize(drones, 0);
  charging.resize(drones, 0.0);
  need.resize(drones, 0.0);
  need_way.resize(drones, 0.0);
  resume.resize(drones);
  next.resize(drones);
}

void Simulation::Drones::Errands::columns(std::vector<StateColumn>& out) const {
  out.push_back(StateColumn::of("errand", "", "errands", "0 its behavior flies it, 1 returning to its base, 2 charging there, 3 outbound to where it left off", state));
  out.push_back(StateColumn::of("charging_time", "s", "errands", "time it has spent charging at its base", charging));
  out.push_back(StateColumn::of("energy_home", "J", "errands", "energy the way home needs from where it is (energy_home), as last computed", need));
  out.push_back(StateColumn::of("way_home", "m", "errands", "length of its way home: the straight line in sight of the base, else along the home map", need_way));
  out.push_back(StateColumn::of("resume_point", "m", "errands", "where it left its behavior last: where it flies back out to", resume));
}

}  // namespace salsa
