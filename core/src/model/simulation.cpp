#include "salsa/core/model/simulation.hpp"

#include "model/light_world.hpp"
#include "model/physics_world.hpp"
#include "salsa/core/model/map_check.hpp"

#include <oneapi/tbb/enumerable_thread_specific.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_group.h>
#include <oneapi/tbb/task_arena.h>

#include <cxxabi.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <mutex>
#include <stdexcept>

namespace salsa {

namespace {

// Rng streams: a few fixed ones for set-up, then one per drone.
constexpr std::uint64_t targets_stream = 1, spawn_stream = 2, first_drone_stream = 16;
constexpr double inf = std::numeric_limits<double>::infinity();

/// A number in a message: whole numbers in full, others with 6 significant digits ("nan", "inf" too).
std::string num(double v) {
  char buf[40];
  if (std::isfinite(v) && v == std::floor(v) && std::abs(v) < 1e15) std::snprintf(buf, sizeof buf, "%.0f", v);
  else std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}
std::string short_num(double v) {  // 3 significant digits for a derived figure ("16.7 m per step"), no exponent from 1000 up
  char buf[40];
  std::snprintf(buf, sizeof buf, std::abs(v) >= 1000 && std::abs(v) < 1e15 ? "%.0f" : "%.3g", v);
  return buf;
}
std::string point(Vec2 p) {  // appended, not "(" + ...: GCC 12 -O3 warns (-Wrestrict) on that
  std::string s = "(";
  s += num(p.x);
  s += ", ";
  s += num(p.y);
  return s += ')';
}
std::string rect(const Rect& r) { return point(r.min) + " to " + point(r.max); }
bool finite(Vec2 p) { return std::isfinite(p.x) && std::isfinite(p.y); }
/// x rounded down to 4 significant digits: a limit quoted to the user is one they may type in.
double quoted_limit(double x) {
  const double scale = std::pow(10.0, std::floor(std::log10(x)) - 3);
  return std::floor(x * (1 + 1e-9) / scale) * scale;
}

/// A world that is not (yet) the simulation's: the map alone when targets are placed at the start (no
/// drones), or the state a live change builds aside, shown to the contact handlers before it is
/// swapped in.
class StateView final : public WorldView {
 public:
  StateView(const MapData& map, const StaticGeometry& geometry, const DroneProperties& drone, double time, double dt,
            std::span<const Vec2> positions = {}, std::span<const Vec2> velocities = {},
            std::span<const std::uint32_t> groups = {}, std::span<const DroneStatus> status = {})
      : map_(map), geometry_(geometry), drone_(drone), time_(time), dt_(dt), positions_(positions), velocities_(velocities),
        groups_(groups.begin(), groups.end()), status_(status.begin(), status.end()) {
    groups_.resize(positions.size(), 0);
    status_.resize(positions.size(), DroneStatus::flying);
  }
  Rect bounds() const override { return map_.bounds; }
  double time() const override { return time_; }
  double dt() const override { return dt_; }
  std::span<const Vec2> drone_positions() const override { return positions_; }
  std::span<const Vec2> drone_velocities() const override { return velocities_; }
  bool is_free(Vec2 p, double clearance) const override { return geometry_.is_free(p, clearance); }
  std::optional<ObstacleHit> ray_cast(Vec2 from, Vec2 to) const override { return geometry_.ray_cast(from, to); }
  const DroneProperties& drone(std::uint32_t) const override { return drone_; }
  std::span<const std::uint32_t> drone_groups() const override { return groups_; }
  std::span<const DroneStatus> drone_status() const override { return status_; }
  std::size_t group_count() const override { return 1; }
  Vec2 base(std::uint32_t) const override { return map_.spawn; }
  const MapData& map() const override { return map_; }

 private:
  const MapData& map_;
  const StaticGeometry& geometry_;
  DroneProperties drone_;
  double time_, dt_;
  std::span<const Vec2> positions_, velocities_;
  std::vector<std::uint32_t> groups_;
  std::vector<DroneStatus> status_;
};

/// The simulation as a contact handler sees it during an event: as it is, at the event's time (a
/// sighting's time is the end of the step it was seen in, one dt after the snapshot it was seen on).
class EventView final : public WorldView {
 public:
  EventView(const WorldView& world, double time) : world_(world), time_(time) {}
  Rect bounds() const override { return world_.bounds(); }
  double time() const override { return time_; }
  double dt() const override { return world_.dt(); }
  std::span<const Vec2> drone_positions() const override { return world_.drone_positions(); }
  std::span<const Vec2> drone_velocities() const override { return world_.drone_velocities(); }
  bool is_free(Vec2 p, double clearance) const override { return world_.is_free(p, clearance); }
  std::optional<ObstacleHit> ray_cast(Vec2 from, Vec2 to) const override { return world_.ray_cast(from, to); }
  const DroneProperties& drone(std::uint32_t group) const override { return world_.drone(group); }
  std::span<const std::uint32_t> drone_groups() const override { return world_.drone_groups(); }
  std::span<const DroneStatus> drone_status() const override { return world_.drone_status(); }
  std::size_t group_count() const override { return world_.group_count(); }
  Vec2 base(std::uint32_t group) const override { return world_.base(group); }
  const MapData& map() const override { return world_.map(); }

 private:
  const WorldView& world_;
  double time_;
};

constexpr const char* behavior_kind = "behavior";
constexpr const char* target_kind = "target kind";
constexpr const char* handler_kind = "contact handler";
constexpr const char* wind_kind = "wind";

/// Calls plugin code: whatever it throws comes back as a PluginFailure naming the plugin (a failure
/// already named, from a nested call, passes through; so does a thread's cancellation).
template <class Fn>
decltype(auto) plugin_call(const char* kind, std::size_t index, Fn&& fn) {
  try {
    return fn();
  } catch (const PluginFailure&) {
    throw;
  } catch (const abi::__forced_unwind&) {
    throw;
  } catch (const std::exception& e) {
    throw PluginFailure(kind, index, e.what());
  } catch (...) {
    throw PluginFailure(kind, index, "an exception that is not a std::exception");
  }
}

/// Ids are 32-bit (and Box2D's user data holds id + 1).
void check_drone_count(std::size_t n) {
  if (n >= std::numeric_limits<std::uint32_t>::max())
    throw std::invalid_argument("drones: " + std::to_string(n) + " is too many (allowed: fewer than 4294967295)");
}

}  // namespace

// ---------------------------------------------------------------- limits

PluginFailure::PluginFailure(std::string kind_, std::size_t index_, const std::string& message)
    : std::runtime_error([&] {
        std::string line = message;  // one line, whatever the plugin wrote
        for (char& c : line)
          if (c == '\n' || c == '\r') c = ' ';
        return line;
      }()),
      kind(std::move(kind_)),
      index(index_) {}

static_assert(box2d_max_step == b2_maxTranslation, "the step limit quoted to users is Box2D's own");

Problem check_drone(const DroneConfig& d, double dt) {
  for (const DroneProperty& p : drone_schema())
    if (const double v = p.get(d); !p.spec.check(v).empty())
      return {"drone." + p.spec.name, num(v) + (p.spec.unit.empty() ? "" : " " + p.spec.unit) + " " + p.spec.check(v)};
  if (!(std::isfinite(dt) && dt > 0)) return {"dt", num(dt) + " s is out of range (allowed: a finite time step > 0 s)"};

  // Contacts are found once per step (continuous collision is off): a drone that starts a step clear of
  // a wall (farther than radius + Box2D's 0.01 m skin) and moves at most its radius ends it on the same
  // side, touching, and the contact then stops it. Box2D itself caps a step at b2_maxTranslation.
  const double step = d.max_speed * dt;
  const double limit = std::min(d.radius, box2d_max_step);
  if (step <= limit * (1 + 1e-9)) return {};
  const std::string why = d.radius <= box2d_max_step
                              ? "more than the drone's radius " + num(d.radius) + " m, so it could pass through a wall between two contact checks"
                              : "more than the " + num(box2d_max_step) + " m Box2D moves a body per step";
  return {"drone.max_speed", num(d.max_speed) + " m/s × dt " + num(dt) + " s = " + short_num(step) + " m per step, " + why +
                                 " (allowed: max_speed ≤ " + num(quoted_limit(limit / dt)) + " m/s at this dt, or dt ≤ " +
                                 num(quoted_limit(limit / d.max_speed)) + " s at this max_speed)"};
}

Problem check_wind(const Wind& w, const DroneConfig& d, double dt) {
  for (const WindProperty& p : wind_schema())
    if (const double v = p.get(w); !p.spec.check(v).empty()) return {"wind." + p.spec.name, num(v) + " " + p.spec.unit + " " + p.spec.check(v)};
  // The gusts are clamped to gust_clamp standard deviations, so this is the most the drones meet
  // without a field (a field's own speed is checked as the run asks it).
  const double strongest = w.velocity.length() + gust_clamp * w.gust_strength;
  const double limit = wind_limit(d, dt);
  if (strongest == 0 || strongest <= limit * (1 + 1e-9)) return {};
  return {w.gust_strength > 0 ? "wind.gusts.strength" : "wind.velocity",
          "|velocity| " + num(w.velocity.length()) + " m/s + " + num(gust_clamp) + " × gusts.strength " + num(w.gust_strength) +
              " m/s = " + short_num(strongest) + " m/s of wind; a drone at max_speed " + num(d.max_speed) + " m/s carried by it moves " +
              short_num((d.max_speed + strongest) * dt) + " m per step (dt " + num(dt) + " s), more than " +
              (d.radius <= box2d_max_step ? "its radius " + num(d.radius) + " m, so it could pass through a wall"
                                          : "the " + num(box2d_max_step) + " m Box2D moves a body per step") +
              " (allowed: |velocity| + " + num(gust_clamp) + " × gusts.strength ≤ " + (limit > 0 ? num(quoted_limit(limit)) : "0") +
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
  return {"bounds", rect(bounds) + (box2d ? ": Box2D keeps positions as 32-bit floats, " : ": the light physics keeps positions as 64-bit doubles, ") +
                        short_num(spacing) + " m apart at " +
                        num(largest) + " m, more than 2 % of a drone's step (max_speed " + num(drone.max_speed) +
                        " m/s × dt " + num(dt) + " s = " + short_num(step) +
                        " m), so drones would move in jumps or not at all (allowed: coordinates within ±" + num(allowed) +
                        " m at this max_speed and dt)"};
}

Problem check_targets(std::span<const Vec2> positions, std::size_t count, double radius, const Rect& bounds) {
  if (!(std::isfinite(radius) && radius >= 0)) return {"radius", num(radius) + " m (allowed: a finite radius ≥ 0 m)"};
  if (positions.size() != count)
    return {"positions", std::to_string(positions.size()) + " placed for " + std::to_string(count) + " targets asked for"};
  for (std::size_t i = 0; i < positions.size(); ++i)
    if (!finite(positions[i]) || !bounds.contains(positions[i]))
      return {"positions[" + std::to_string(i) + "]",
              point(positions[i]) + (finite(positions[i]) ? " is outside" : " is not finite (allowed: a point inside") +
                  " the bounds " + rect(bounds) + (finite(positions[i]) ? "" : ")")};
  return {};
}

Problem check_view_range(const TargetKind& kind, const DroneConfig& drone) {
  const double range = plugin_call(target_kind, 0, [&] { return kind.view_range(drone.camera_range); });
  if (std::isfinite(range) && range >= 0) return {};
  return {"view_range", num(range) + " m for a camera range of " + num(drone.camera_range) +
                            " m (allowed: a finite distance ≥ 0 m)"};
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
  const StateView view(map, geometry, drone_properties(drone), 0, dt);
  Rng rng(seed, targets_stream);
  std::vector<Vec2> positions = plugin_call(target_kind, 0, [&] { return kind.place(count, view, rng); });
  if (auto p = check_targets(positions, count, radius, map.bounds)) throw std::invalid_argument(p.text());
  return positions;
}

// ---------------------------------------------------------------- set-up and live changes

struct Simulation::Scratch {
  std::vector<PointGrid::Hit> hits, senders;
  std::vector<Message> messages;
  Outbox outbox;  ///< without "comm": broadcast writes here (its size still checked), nobody reads it
  std::array<double, max_message_size> room;
  std::vector<Neighbour> neighbours;
  std::vector<TargetSeen> targets;
  std::vector<ObstacleHit> obstacles;  ///< the noisy copy of a drone's hits (obstacle or position noise)
  std::vector<std::uint32_t> segment_ids;
};

struct Simulation::Parallel {
  static constexpr std::size_t grain = 64;  // drones per task
  tbb::task_arena arena;
  tbb::enumerable_thread_specific<Scratch> scratch;
  explicit Parallel(int threads) : arena(threads > 0 ? threads : tbb::task_arena::automatic) {}

  /// Runs `side` (one long serial job) while this thread goes on with `main`; both done on return.
  /// With few drones both are shorter than waking a thread, so they simply run one after the other.
  template <class Side, class Main>
  void overlap(std::size_t drones, Side&& side, Main&& main) {
    if (drones <= grain) {
      side();
      main();
      return;
    }
    arena.execute([&] {
      tbb::task_group group;
      group.run(side);  // the oldest task: the first a free worker steals
      main();
      group.wait();
    });
  }

  /// What fn threw for the lowest drone id: the failure reported whatever the thread count and the
  /// order the drones ran in. Drones above the lowest failing id so far are skipped (none of theirs
  /// can be reported).
  struct FirstFailure {
    std::atomic<std::uint32_t> id{std::numeric_limits<std::uint32_t>::max()};
    std::mutex mutex;
    std::exception_ptr error;
    bool skip(std::uint32_t i) const { return i > id.load(std::memory_order_relaxed); }
    void note(std::uint32_t i) {
      const std::lock_guard lock(mutex);
      if (i < id.load(std::memory_order_relaxed) || !error) {
        id.store(i, std::memory_order_relaxed);
        error = std::current_exception();
      }
    }
  };

  /// fn(order[k], scratch) for every k, spread over the arena's threads. Drones go in grid-cell order,
  /// so that neighbouring drones, which read the same cells, run one after the other. A throw is
  /// caught where it happens (not left to TBB, which would pass on whichever came first) and the
  /// lowest drone id's is rethrown once all are done.
  /// With `ahead`, ahead(order[k + 8], 0) and ahead(order[k + 4], 1) run before fn(order[k]): a
  /// place to prefetch what those drones will read, in two stages (a record, then what it points to).
  template <class Fn, class Ahead = void (*)(std::uint32_t, int)>
  void for_each(std::span<const std::uint32_t> order, Fn&& fn, Ahead&& ahead = [](std::uint32_t, int) {}) {
    FirstFailure failure;
    auto one = [&](std::uint32_t i, Scratch& s) {
      if (failure.skip(i)) return;
      try {
        fn(i, s);
      } catch (const abi::__forced_unwind&) {
        throw;
      } catch (...) {
        failure.note(i);
      }
    };
    auto run = [&](std::size_t begin, std::size_t end) {
      Scratch& s = scratch.local();
      for (std::size_t k = begin; k != end; ++k) {
        if (k + 8 < end) ahead(order[k + 8], 0);
        if (k + 4 < end) ahead(order[k + 4], 1);
        one(order[k], s);
      }
    };
    if (order.size() <= grain) {  // one chunk: not worth a task
      run(0, order.size());
    } else {
      arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, order.size(), grain),
                          [&](const tbb::blocked_range<std::size_t>& r) { run(r.begin(), r.end()); });
      });
    }
    if (failure.error) std::rethrow_exception(failure.error);
  }
};

struct Simulation::World {
  StaticGeometry geometry;
  std::vector<Group> groups;
  std::unique_ptr<Physics> physics;
  Rng spawn_rng;
  Drones drones;
  Targets targets;
};

Simulation::Simulation(SimulationSetup setup)
    : setup_(std::move(setup)), parallel_(std::make_unique<Parallel>(setup_.threads)), comm_(std::make_unique<CommState>()) {
  if (setup_.groups.empty()) throw std::invalid_argument("groups: none given");
  for (const GroupSetup& g : setup_.groups)
    if (!g.behavior) throw std::invalid_argument("behavior: none given");
  if (setup_.log_every == 0) setup_.log_every = 1;
  if (const std::string why = comm_problem(setup_.comm); !why.empty()) throw std::invalid_argument(why);
  World world = build_world(setup_, *parallel_);
  for (std::uint32_t g = 0; g < setup_.groups.size(); ++g) {
    Behavior& b = *setup_.groups[g].behavior;
    b.group_ = g;
    message_sizes_.push_back(message_size(b, g));
    plugin_call(behavior_kind, g, [&] { b.reset(world.drones.positions.size()); });
  }
  install(std::move(world));
  gusts_ = Gusts(setup_.seed, setup_.wind.gust_strength);
  if (setup_.wind != Wind{} || setup_.wind_field) {
    wind_active_ = true;
    track_air();
  }
  reset_handlers(*this);
}

Simulation::~Simulation() = default;

namespace {

/// Where a new drone starts: in spawn mode disc a random point of the spawn disc (or, outside the walls,
/// the nearest point inside them, as the paper does), else a random free point of the map; every try
/// bounded, the spawn point itself (checked free) as the last resort.
Vec2 spawn_position(const GroupSetup& g, const Rect& bounds, const StaticGeometry& geometry, Vec2 spawn, std::size_t total,
                    Rng& rng, bool& scarce) {
  const double r = g.drone.radius;
  if (g.spawn_mode == SpawnMode::disc) {
    // The paper's default radius, drones × radius, at most the distance to the map's farthest corner:
    // a wider disc covers no more of the map, it only clamps more drones onto the walls (100,000 drones
    // on a 6 km map would pile up in the corners).
    const double farthest = std::hypot(std::max(spawn.x - bounds.min.x, bounds.max.x - spawn.x),
                                       std::max(spawn.y - bounds.min.y, bounds.max.y - spawn.y));
    const double disc = g.spawn_radius > 0 ? g.spawn_radius : std::min(static_cast<double>(total) * r, farthest);
    Vec2 p;
    for (int tries = 0; tries < 100; ++tries) {
      p = rng.in_disc(spawn, disc);
      if (geometry.is_free(p, r)) return p;
    }
    p = {std::clamp(p.x, bounds.min.x + r, bounds.max.x - r), std::clamp(p.y, bounds.min.y + r, bounds.max.y - r)};
    if (geometry.is_free(p, r)) return p;
  }
  // Free space under 1/10,000 of the map: once a drone found none, the others try briefly.
  for (int tries = 0, most = scarce ? 100 : 10'000; tries < most; ++tries)
    if (Vec2 p = rng.in_rect(bounds); geometry.is_free(p, r)) return p;
  scarce = true;
  return spawn;
}

std::vector<Vec2> ray_directions(int rays) {
  std::vector<Vec2> out;
  for (int k = 0; k < rays; ++k) out.push_back(Vec2::polar(1, 2 * pi * k / rays));
  return out;
}

/// A drone's failure draws: Exp(1) for the whole drone, then for its camera, from its own stream.
constexpr std::uint64_t first_failure_stream = std::uint64_t{1} << 40;

/// Sensor noise draws from counter-based streams, one per (purpose, step, drone), never the behavior's:
/// any thread count, any order of the drones and every behavior of a repeat draw the same noise, and
/// one purpose's draws never shift another's. Bit 63 sets the family apart from the streams above;
/// bits 61-62 hold the purpose, 32-60 the step (the same draws come back after 2^29 steps, 103 days of
/// simulated time at 60 steps a second), 0-31 the drone id.
enum class NoiseStream : std::uint64_t { position_and_rays = 0, neighbours = 1, misses = 2, phantoms = 3 };
Rng noise_rng(std::uint64_t seed, NoiseStream purpose, std::uint64_t step, std::uint32_t id) {
  constexpr std::uint64_t first_noise_stream = std::uint64_t{1} << 63, step_mask = (std::uint64_t{1} << 29) - 1;
  return Rng(seed, first_noise_stream | static_cast<std::uint64_t>(purpose) << 61 | (step & step_mask) << 32 | id);
}
/// Two independent N(0, sd²) draws: both halves of one Box–Muller pair.
Vec2 gaussian(Rng& rng, double sd) {
  const double u1 = 1.0 - rng.uniform();  // (0, 1]: the log is finite
  const double u2 = rng.uniform();
  const double r = sd * std::sqrt(-2.0 * std::log(u1)), a = 2 * pi * u2;
  return {r * std::cos(a), r * std::sin(a)};
}
/// A Poisson(mean) count: Knuth's product of uniforms, in parts of mean ≤ 8 so that exp(−part) stays
/// far from underflow (a sum of Poisson counts is Poisson).
std::size_t poisson(Rng& rng, double mean) {
  std::size_t count = 0;
  while (mean > 0) {
    const double part = std::min(mean, 8.0), limit = std::exp(-part);
    mean -= part;
    for (double product = rng.uniform(); product >= limit; product *= rng.uniform()) ++count;
  }
  return count;
}
std::pair<double, double> failure_draws(std::uint64_t seed, std::uint32_t id) {
  Rng rng(seed, first_failure_stream + id);
  const double drone = -std::log1p(-rng.uniform());
  return {drone, -std::log1p(-rng.uniform())};
}

}  // namespace

Simulation::Group Simulation::make_group(const GroupSetup& g, Vec2 base, const TargetKind* kind, bool with_targets) {
  Group out;
  out.properties = drone_properties(g.drone);
  out.base = base;
  out.rays = ray_directions(g.drone.obstacle_rays);
  out.noise = {g.drone.position_noise, g.drone.neighbour_noise, g.drone.obstacle_noise, g.drone.miss_probability,
               g.drone.false_detection_rate};
  if (kind && with_targets) {
    if (auto p = check_view_range(*kind, g.drone)) throw std::invalid_argument(p.text());
    out.reach = plugin_call(target_kind, 0, [&] { return kind->view_range(g.drone.camera_range); });
  }
  return out;
}

std::size_t Simulation::message_size(const Behavior& behavior, std::uint32_t g) {
  const std::size_t size = plugin_call(behavior_kind, g, [&] { return behavior.message_size(); });
  if (size > max_message_size)
    throw PluginFailure(behavior_kind, g, "message_size() is " + std::to_string(size) + " doubles (allowed: at most " +
                                              std::to_string(max_message_size) + ")");
  return size;
}

std::size_t Simulation::ray_slots(const std::vector<Group>& groups) {
  std::size_t most = 0;
  for (const Group& g : groups) most = std::max(most, g.rays.size());
  return most;
}

Simulation::World Simulation::build_world(const SimulationSetup& s, Parallel& parallel) {
  if (auto p = check_map(s.map)) throw std::invalid_argument("map: " + p.text());
  double obstacle_range = 0;
  for (const GroupSetup& g : s.groups) {
    const std::string in = s.groups.size() > 1 ? "groups." + g.name + "." : "";
    if (auto p = check_drone(g.drone, s.dt)) throw std::invalid_argument(in + p.text());
    if (auto p = check_resolution(s.map.bounds, g.drone, s.dt, s.physics)) throw std::invalid_argument(in + "map: " + p.text());
    if (auto p = check_wind(s.wind, g.drone, s.dt)) throw std::invalid_argument(in + p.text());
    check_drone_count(g.drones);
    obstacle_range = std::max(obstacle_range, g.drone.obstacle_range);
  }
  World w;
  w.geometry = StaticGeometry(s.map, std::max(obstacle_range, 1.0));
  // Targets go on the map before any drone exists, so make_setup can check them without spawning; they
  // see the first group's drone properties.
  std::vector<Vec2> targets;
  if (s.target_kind) targets = initial_targets(*s.target_kind, s.targets, s.map, w.geometry, s.groups[0].drone, s.dt, s.seed);
  for (const GroupSetup& g : s.groups) {
    const Vec2 base = g.spawn.value_or(s.map.spawn);
    if (!finite(base) || !w.geometry.is_free(base, g.drone.radius))
      throw std::invalid_argument((s.groups.size() > 1 ? "groups." + g.name + ": " : "") + "spawn point " + point(base) +
                                  " is inside an obstacle or outside the map bounds (it needs a free disc of the drone radius)");
    w.groups.push_back(make_group(g, base, s.target_kind.get(), !targets.empty()));
  }
  w.targets = make_targets(std::move(targets), w.groups);
  if (s.physics == PhysicsMode::light) w.physics = std::make_unique<LightWorld>(parallel.arena);
  else w.physics = std::make_unique<PhysicsWorld>(w.geometry);
  w.spawn_rng = Rng(s.seed, spawn_stream);
  for (std::uint32_t g = 0; g < s.groups.size(); ++g)
    w.drones = grown(std::move(w.drones), g, s.groups[g].drones, s, w.geometry, w.groups[g].base, w.spawn_rng, 0);
  w.drones.hits.assign(w.drones.positions.size() * ray_slots(w.groups), {});
  return w;
}

// `from` and `count` new drones of group `group` after it, spawned at `base` at time `time`, each with
// a fresh Rng stream of its own id and its failure draws.
Simulation::Drones Simulation::grown(Drones d, std::uint32_t group, std::size_t count, const SimulationSetup& s,
                                     const StaticGeometry& geometry, Vec2 base, Rng& spawn_rng, double time) {
  const GroupSetup& g = s.groups[group];
  const std::size_t first = d.positions.size(), n = first + count;
  check_drone_count(n);
  std::size_t total = count;  // the group's drones once these are added: the spawn disc's size
  for (std::size_t i = 0; i < first; ++i) total += d.groups[i] == group && d.status[i] != DroneStatus::removed;
  bool scarce = false;
  for (std::size_t i = first; i < n; ++i) {
    d.positions.push_back(spawn_position(g, s.map.bounds, geometry, base, total, spawn_rng, scarce));
    const double heading = spawn_rng.angle();  // drawn first, as g++ evaluated the call: the order is fixed, not the compiler's
    d.velocities.push_back(Vec2::polar(spawn_rng.uniform(0.1 * g.drone.max_speed, g.drone.max_speed), heading));
    d.rngs.emplace_back(s.seed, first_drone_stream + i);
    const auto [drone, camera] = failure_draws(s.seed, static_cast<std::uint32_t>(i));
    d.due.push_back(drone);
    d.camera_due.push_back(camera);
  }
  d.steering.resize(n);
  d.commanded.resize(n);
  d.groups.resize(n, group);
  d.status.resize(n, DroneStatus::flying);
  d.camera.resize(n, 1);
  d.used.resize(n, 0.0);
  d.charge.resize(n, g.drone.battery_capacity > 0 ? g.drone.battery_capacity * 3600 : inf);
  d.since.resize(n, time);
  d.exposure.resize(n, 0.0);
  d.camera_exposure.resize(n, 0.0);
  d.hit_counts.resize(n, 0);
  return d;
}

Simulation::Targets Simulation::make_targets(std::vector<Vec2> positions, const std::vector<Group>& groups) {
  Targets t;
  double reach = 0;
  for (const Group& g : groups) reach = std::max(reach, g.reach);
  t.states.reserve(positions.size());
  for (Vec2 p : positions) t.states.push_back({p});
  // Cells of the query radius: a query touches 3 × 3 cells whatever the kind's view range.
  t.grid.build(positions, std::max(reach, 1.0));
  return t;
}

void Simulation::reset_handlers(const WorldView& world) const {
  for (std::size_t k = 0; k < setup_.contact_handlers.size(); ++k)
    plugin_call(handler_kind, k, [&] { setup_.contact_handlers[k]->reset(world); });
}

void Simulation::install(World&& w) noexcept {
  geometry_ = std::move(w.geometry);
  groups_ = std::move(w.groups);
  ray_slots_ = ray_slots(groups_);
  grid_range_ = 0;
  for (const GroupSetup& g : setup_.groups) grid_range_ = std::max(grid_range_, g.drone.detection_range);
  physics_ = std::move(w.physics);
  spawn_rng_ = w.spawn_rng;
  drones_ = std::move(w.drones);
  targets_ = std::move(w.targets);
  flying_ = static_cast<std::size_t>(std::count(drones_.status.begin(), drones_.status.end(), DroneStatus::flying));
  physics_->remove_drones_from(0);
  add_bodies();
  sensed_.clear();             // new drones and targets: whatever is in view next comes into view
  if (comm_) comm_->clear();  // new drones: nothing in flight reaches them
  comm_changed();
  if (wind_active_) track_air();  // the new drones' air velocities: their velocities as spawned
}

void Simulation::track_air() {
  for (std::size_t i = drones_.air.size(); i < drones_.velocities.size(); ++i) {
    drones_.air.push_back(drones_.velocities[i]);
    drones_.wind.push_back({});
  }
}

void Simulation::add_bodies() {
  for (std::uint32_t i = 0; i < drones_.positions.size(); ++i)
    physics_->add_drone(i, drones_.positions[i], drones_.velocities[i], setup_.groups[drones_.groups[i]].drone,
                        drones_.status[i] == DroneStatus::flying);
}

void Simulation::ground(std::uint32_t id, DroneStatus status) {
  drones_.status[id] = status;
  drones_.since[id] = time();
  drones_.velocities[id] = drones_.commanded[id] = drones_.steering[id] = {};
  if (wind_active_) drones_.air[id] = drones_.wind[id] = {};
  physics_->disable(id);
  --flying_;
}

void Simulation::set_drone_count(std::size_t n, std::uint32_t group) {
  check_drone_count(n);
  if (group >= setup_.groups.size()) throw std::invalid_argument("group " + std::to_string(group) + " does not exist");
  std::vector<std::uint32_t> present;  // the group's drones not removed, by id
  for (std::uint32_t i = 0; i < drones_.positions.size(); ++i)
    if (drones_.groups[i] == group && drones_.status[i] != DroneStatus::removed) present.push_back(i);
  Rng rng = spawn_rng_;
  Drones next = n > present.size() ? grown(drones_, group, n - present.size(), setup_, geometry_, groups_[group].base, rng, time())
                                   : drones_;
  for (std::size_t k = n; k < present.size(); ++k) {  // the highest ids go
    const std::uint32_t i = present[k];
    next.status[i] = DroneStatus::removed;
    next.since[i] = time();
    next.velocities[i] = next.commanded[i] = next.steering[i] = {};
  }
  next.hits.resize(next.positions.size() * ray_slots_);
  for (std::uint32_t g = 0; g < setup_.groups.size(); ++g)
    plugin_call(behavior_kind, g, [&] { setup_.groups[g].behavior->resize(next.positions.size()); });
  // Handlers see the drones as they will be (removed ones stay in the spans, with their status).
  std::swap(drones_, next);
  try {
    reset_handlers(*this);
  } catch (...) {
    std::swap(drones_, next);
    throw;
  }
  // Nothing below throws.
  const std::size_t before = next.positions.size();  // the drones before the change (swapped out)
  for (std::uint32_t i = 0; i < drones_.positions.size(); ++i) {
    if (i >= before) physics_->add_drone(i, drones_.positions[i], drones_.velocities[i], setup_.groups[group].drone, true);
    else if (drones_.status[i] == DroneStatus::removed) physics_->disable(i);
  }
  flying_ = static_cast<std::size_t>(std::count(drones_.status.begin(), drones_.status.end(), DroneStatus::flying));
  if (wind_active_) track_air();
  sensed_.clear();  // ids may name other drones: whatever is in view next comes into view
  spawn_rng_ = rng;
  setup_.groups[group].drones = n;
  comm_changed();
}

void Simulation::set_drone_config(const DroneConfig& config, std::uint32_t group) {
  if (group >= setup_.groups.size()) throw std::invalid_argument("group " + std::to_string(group) + " does not exist");
  if (auto p = check_drone(config, setup_.dt)) throw std::invalid_argument(p.text());
  if (auto p = check_resolution(setup_.map.bounds, config, setup_.dt, setup_.physics)) throw std::invalid_argument("map: " + p.text());
  if (auto p = check_wind(setup_.wind, config, setup_.dt)) throw std::invalid_argument(p.text());
  SimulationSetup next_setup = setup_;
  next_setup.groups[group].drone = config;
  std::vector<Group> next_groups = groups_;
  const TargetKind* kind = setup_.target_kind.get();
  next_groups[group] = make_group(next_setup.groups[group], groups_[group].base, kind, !targets_.states.empty());
  std::vector<Vec2> points;  // the cameras size the target grid
  points.reserve(targets_.states.size());
  for (const auto& t : targets_.states) points.push_back(t.position);
  Targets regridded = make_targets(std::move(points), next_groups);
  // Nothing below throws. A battery keeps its charge as a fraction of the new capacity.
  const double old_capacity = setup_.groups[group].drone.battery_capacity * 3600, capacity = config.battery_capacity * 3600;
  for (std::uint32_t i = 0; i < drones_.positions.size(); ++i) {
    if (drones_.groups[i] != group) continue;
    // Max speed bounds the air velocity: with wind the ground velocity may exceed it.
    if (wind_active_) drones_.air[i] = drones_.air[i].clamped(config.max_speed);
    else drones_.velocities[i] = drones_.velocities[i].clamped(config.max_speed);
    if (capacity != old_capacity)
      drones_.charge[i] = capacity <= 0 ? inf : old_capacity <= 0 ? capacity : drones_.charge[i] / old_capacity * capacity;
  }
  setup_ = std::move(next_setup);
  groups_ = std::move(next_groups);
  ray_slots_ = ray_slots(groups_);
  drones_.hits.assign(drones_.positions.size() * ray_slots_, {});
  grid_range_ = 0;
  for (const GroupSetup& g : setup_.groups) grid_range_ = std::max(grid_range_, g.drone.detection_range);
  targets_.grid = std::move(regridded.grid);
  for (Sensed& d : sensed_) d.reach = -1;  // their lists are in the old grid's order
  physics_->remove_drones_from(0);
  add_bodies();
}

void Simulation::set_dt(double dt) {
  for (const GroupSetup& g : setup_.groups) {
    if (auto p = check_drone(g.drone, dt)) throw std::invalid_argument(p.text());
    if (auto p = check_resolution(setup_.map.bounds, g.drone, dt, setup_.physics)) throw std::invalid_argument("map: " + p.text());
    if (auto p = check_wind(setup_.wind, g.drone, dt)) throw std::invalid_argument(p.text());
  }
  dt_base_time_ = time();
  dt_base_steps_ = steps_;
  setup_.dt = dt;
}

void Simulation::set_wind(const Wind& wind, std::shared_ptr<WindField> field) {
  for (const GroupSetup& g : setup_.groups)
    if (auto p = check_wind(wind, g.drone, setup_.dt))
      throw std::invalid_argument((setup_.groups.size() > 1 ? "groups." + g.name + ": " : "") + p.text());
  setup_.wind = wind;
  setup_.wind_field = std::move(field);
  if (!wind_active_ && (wind != Wind{} || setup_.wind_field)) {
    wind_active_ = true;  // for good: air velocities are kept from now on, even if the wind drops to zero
    track_air();          // the velocities now are relative to still air
  }
}

void Simulation::set_behavior(std::shared_ptr<Behavior> behavior, std::uint32_t group) {
  if (!behavior) throw std::invalid_argument("behavior: none given");
  if (group >= setup_.groups.size()) throw std::invalid_argument("group " + std::to_string(group) + " does not exist");
  behavior->group_ = group;
  const std::size_t size = message_size(*behavior, group);
  plugin_call(behavior_kind, group, [&] { behavior->reset(drones_.positions.size()); });
  setup_.groups[group].behavior = std::move(behavior);
  message_sizes_[group] = size;
  comm_changed();
}

void Simulation::comm_changed() {
  comm_stale_ = true;
  inbox_grid_step_ = std::numeric_limits<std::uint64_t>::max();
}

void Simulation::set_comm(const CommSetup& comm) {
  if (const std::string why = comm_problem(comm); !why.empty()) throw std::invalid_argument(why);
  setup_.comm = comm;
  comm_changed();
}

std::vector<Message> Simulation::inbox(std::uint32_t id) const {
  std::vector<Message> out;
  if (!setup_.comm.on || comm_stale_) return out;
  if (id >= drones_.positions.size()) return out;
  // The grid the next step's sense will build (drones do not move between steps), kept for the step.
  if (inbox_grid_step_ != steps_) {
    inbox_grid_.build(drones_.positions, grid_range_ / 2);
    inbox_grid_step_ = steps_;
  }
  std::vector<PointGrid::Hit> candidates, hits;
  inbox_grid_.gather(drones_.positions[id], comm_->reach(steps_, drones_.positions, setup_.comm.range), candidates);
  CommState::Counts counts;
  comm_->receive(steps_, id, setup_.comm, setup_.seed, drones_.groups, geometry_, candidates, hits, out, counts);
  return out;
}

void Simulation::set_map(const MapData& map, std::optional<Vec2> spawn) {
  SimulationSetup next = setup_;
  next.map = map;
  next.groups[0].spawn = spawn;
  for (std::uint32_t g = 0; g < next.groups.size(); ++g) {  // each group as many as it has now
    next.groups[g].drones = 0;
    for (std::uint32_t i = 0; i < drones_.positions.size(); ++i)
      next.groups[g].drones += drones_.groups[i] == g && drones_.status[i] != DroneStatus::removed;
  }
  World world = build_world(next, *parallel_);
  for (std::uint32_t g = 0; g < next.groups.size(); ++g)
    plugin_call(behavior_kind, g, [&] { next.groups[g].behavior->reset(world.drones.positions.size()); });
  StateView view(next.map, world.geometry, world.groups[0].properties, time(), next.dt, world.drones.positions,
                 world.drones.velocities, world.drones.groups, world.drones.status);
  reset_handlers(view);
  // Nothing below throws.
  setup_ = std::move(next);
  install(std::move(world));
}

void Simulation::set_targets(std::shared_ptr<TargetKind> kind, std::size_t count) {
  std::vector<Vec2> positions;
  if (kind) positions = initial_targets(*kind, count, setup_.map, geometry_, setup_.groups[0].drone, setup_.dt, setup_.seed);
  std::vector<Group> next_groups;
  for (std::uint32_t g = 0; g < setup_.groups.size(); ++g)
    next_groups.push_back(make_group(setup_.groups[g], groups_[g].base, kind.get(), !positions.empty()));
  Targets next = make_targets(std::move(positions), next_groups);
  reset_handlers(*this);  // what a handler sees of the world (no targets) is as it will be
  // Nothing below throws.
  targets_ = std::move(next);
  sensed_.clear();  // new targets: whatever is in view next comes into view
  groups_ = std::move(next_groups);
  setup_.target_kind = std::move(kind);
  setup_.targets = count;
}

void Simulation::set_failures(const FailureSetup& f) {
  for (const auto& [name, mtbf] : {std::pair{"failures.drone_mtbf", f.drone_mtbf}, std::pair{"failures.camera_mtbf", f.camera_mtbf}})
    if (!(std::isfinite(mtbf) && mtbf >= 0))
      throw std::invalid_argument(std::string(name) + ": " + num(mtbf) + " s is out of range (allowed: a finite time ≥ 0 s; 0: never)");
  setup_.failures = f;
}

void Simulation::fail(std::uint32_t id, bool camera_only) {
  if (id >= drones_.positions.size())
    throw std::invalid_argument("drone " + std::to_string(id) + " does not exist (allowed: ids 0 to " +
                                std::to_string(drones_.positions.size() - 1) + ")");
  if (drones_.status[id] != DroneStatus::flying) return;  // down already
  if (!camera_only) ground(id, DroneStatus::failed);
  else if (drones_.camera[id]) drones_.camera[id] = 0;
}

void Simulation::fail_fraction(double fraction, bool camera_only) {
  if (!(fraction >= 0 && fraction <= 1))
    throw std::invalid_argument(num(fraction) + " is out of range (allowed: a fraction in [0, 1])");
  std::vector<std::uint32_t> candidates;
  for (std::uint32_t i = 0; i < drones_.positions.size(); ++i)
    if (drones_.status[i] == DroneStatus::flying && (!camera_only || drones_.camera[i])) candidates.push_back(i);
  // A shuffle from the seed's own stream for this event: the same drones whatever the behavior.
  Rng rng(setup_.seed, first_failure_stream - 1 - fraction_failures_++);
  for (std::size_t k = candidates.size(); k > 1; --k) std::swap(candidates[k - 1], candidates[rng.index(k)]);
  const auto count = static_cast<std::size_t>(std::llround(fraction * static_cast<double>(candidates.size())));
  for (std::size_t k = 0; k < count; ++k) fail(candidates[k], camera_only);
}

// ---------------------------------------------------------------- one step

void Simulation::timed(Phase phase, const auto& fn) {
  if (!setup_.profile) return fn();
  const auto start = std::chrono::steady_clock::now();
  fn();
  profile_[static_cast<std::size_t>(phase)] += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void Simulation::step() {
  // The drones' side of a step: sense, decide and report what they saw, all on the snapshot of
  // positions the step started from.
  auto think = [this] {
    timed(Phase::sense, [this] { sense(); });
    timed(Phase::decide, [this] { decide(); });
    if (setup_.comm.on) timed(Phase::communicate, [this] { communicate(); });
  };
  auto report = [this] { timed(Phase::detect, [this] { dispatch_sightings(); }); };
  auto step_physics = [this] { timed(Phase::physics, [this] { physics(); }); };
  // While the physics steps, the other side runs: nothing one writes is read by the other (the physics
  // owns its bodies until read_back).
  if (setup_.decision_lag == 0) {
    think();
    timed(Phase::act, [this] { act(); });
    parallel_->overlap(drones_.positions.size(), step_physics, report);
  } else {
    timed(Phase::act, [this] { act(); });  // last step's decisions
    parallel_->overlap(drones_.positions.size(), step_physics, [&] { think(), report(); });
  }
  ++steps_;
  read_back();
  timed(Phase::fleet, [this] { fleet(); });
  timed(Phase::detect, [this] { dispatch_contacts(); });
  timed(Phase::observe, [this] { observe(); });
}

// A drone's targets come from a short list kept across steps rather than from the grid's cells, which
// lie in three rows rarely in cache. The list holds the targets within reach + margin of where it was
// made, in the grid's order; while the drone stays within the margin of that spot every target within
// reach is on it (the triangle inequality, with 1 % to spare for rounding), so filtering it gives the
// grid's answer: the same distances in the same order. At full speed a drone remakes its list about
// every 30 steps. `Record` is a Simulation::Sensed.
template <class Record, class Fn>
void targets_in_reach(const PointGrid& grid, Record& d, Vec2 p, double reach, Fn&& fn) {
  if (!(reach > 0)) return;  // the grid finds nothing closer than 0
  const double margin = reach / 4;
  if (d.reach != reach || !(distance_squared(p, d.anchor) <= 0.98 * margin * margin)) {
    d.anchor = p;
    d.reach = reach;
    d.near.clear();
    grid.query(p, reach + margin, [&](std::uint32_t t, Vec2 at, double) { d.near.push_back({at, t}); });
  }
  const double r2 = reach * reach;
  for (const auto& c : d.near)
    if (const double d2 = distance_squared(c.at, p); d2 < r2) fn(c.id, c.at, d2);
}

// Sense: index the drones for neighbour queries, cast each flying drone's obstacle rays against static
// geometry and find the targets in its camera view. Neighbours are gathered per drone in `decide`,
// where they stay in cache. With detection noise a target in view may be missed (then neither the
// behavior nor the contact handlers hear of it this step) and false detections appear (the behavior
// alone sees them); the other noise is added where the perception is built (add_noise).
void Simulation::sense() {
  drone_grid_.build(drones_.positions, grid_range_ / 2);  // 5×5 cells of R/2 cover less than 3×3 of R
  sensed_.resize(drones_.positions.size());
  const TargetKind* kind = targets_.states.empty() ? nullptr : setup_.target_kind.get();
  bool false_detections = false;
  for (const Group& g : groups_) false_detections = false_detections || g.noise.false_rate > 0;
  if (false_detections) phantoms_.resize(drones_.positions.size());
  // A few drones ahead in grid order, their records, then what those point to: drone ids are scattered
  // in grid order, and with 100,000 drones each record would otherwise be a miss waited on.
  auto ahead = [&](std::uint32_t j, int stage) {
    const Sensed& d = sensed_[j];
    if (stage == 0) {
      for (const char* at = reinterpret_cast<const char*>(&d); at < reinterpret_cast<const char*>(&d + 1); at += 64) __builtin_prefetch(at);
      __builtin_prefetch(reinterpret_cast<const char*>(&d + 1) - 1);
    } else {
      __builtin_prefetch(d.near.data());
      __builtin_prefetch(d.seen.data());  // `before` once swapped
    }
  };
  parallel_->for_each(drone_grid_.cell_order(), [&](std::uint32_t i, Scratch& s) {
    Sensed& sensed = sensed_[i];
    std::swap(sensed.seen, sensed.before);
    std::vector<TargetSeen>& seen = sensed.seen;
    seen.clear();
    sensed.entered.clear();
    if (false_detections) phantoms_[i].clear();
    if (drones_.status[i] != DroneStatus::flying) return void(drones_.hit_counts[i] = 0);  // a stopped drone sees nothing
    const Group& group = groups_[drones_.groups[i]];
    const DroneProperties& cfg = group.properties;
    const Vec2 p = drones_.positions[i];
    std::uint8_t count = 0;
    geometry_.candidates(p, cfg.obstacle_range, s.segment_ids);
    if (!s.segment_ids.empty())
      for (Vec2 direction : group.rays)
        if (auto hit = geometry_.ray_cast(p, direction, cfg.obstacle_range, s.segment_ids))
          drones_.hits[i * ray_slots_ + count++] = *hit;
    drones_.hit_counts[i] = count;
    const Group::Noise& noise = group.noise;
    // Whether each target came into view: `before` is in the same grid order, so a target still in
    // view lies past the last one met there.
    const std::vector<TargetSeen>& before = sensed.before;
    std::size_t from = 0;
    auto sighted = [&](std::uint32_t t, Vec2 at, double d) {
      seen.push_back({at, d, t, false});  // found: filled in where a behavior asks (perceive)
      std::size_t k = from;
      while (k < before.size() && before[k].id != t) ++k;
      if (k < before.size()) from = k + 1;
      else sensed.entered.push_back(static_cast<std::uint32_t>(seen.size() - 1));
    };
    if (kind && drones_.camera[i] && noise.miss > 0) {
      Rng rng = noise_rng(setup_.seed, NoiseStream::misses, steps_, i);  // one draw per target in view, in grid order
      targets_in_reach(targets_.grid, sensed, p, group.reach, [&](std::uint32_t t, Vec2 at, double d2) {
        const double d = std::sqrt(d2);
        if (plugin_call(target_kind, 0, [&] { return kind->in_view(d, cfg.camera_range); }) && !rng.chance(noise.miss))
          sighted(t, at, d);
      });
    } else if (kind && drones_.camera[i])
      targets_in_reach(targets_.grid, sensed, p, group.reach, [&](std::uint32_t t, Vec2 at, double d2) {
        const double d = std::sqrt(d2);
        if (plugin_call(target_kind, 0, [&] { return kind->in_view(d, cfg.camera_range); })) sighted(t, at, d);
      });
    if (noise.false_rate > 0 && drones_.camera[i]) {  // anywhere in the camera's disc, with or without targets
      Rng rng = noise_rng(setup_.seed, NoiseStream::phantoms, steps_, i);
      for (std::size_t k = poisson(rng, noise.false_rate * setup_.dt); k > 0; --k) {
        const double angle = rng.angle();  // drawn first, in its own statement: the order is not the compiler's
        phantoms_[i].push_back(Vec2::polar(cfg.camera_range * std::sqrt(rng.uniform()), angle));
      }
    }
  }, ahead);
  if (false_detections)
    for (const auto& phantoms : phantoms_) false_detections_ += phantoms.size();
}

Vec2 Simulation::perceived_position(std::uint32_t id) const {
  const Vec2 p = drones_.positions[id];
  const double sd = groups_[drones_.groups[id]].noise.position;
  if (!(sd > 0)) return p;
  Rng rng = noise_rng(setup_.seed, NoiseStream::position_and_rays, steps_, id);
  return p + gaussian(rng, sd);
}

// What noisy sensors make of the truth. Everything is measured from where the drone is and placed
// around where it believes it is: its own position error moves the whole picture (neighbours, hits,
// targets) with it, so every distance stays |point − position| as without noise, and neighbour and
// ray noise are the errors of those relative measurements.
void Simulation::add_noise(Perception& me, Senses senses, Scratch& s) const {
  const Group::Noise& noise = groups_[me.group].noise;
  if (!noise.perceived() && !(noise.false_rate > 0)) return;  // another group's noise
  const Vec2 p = me.position;
  // The position error first (drawn whatever its sd), then one draw per ray hit, in ray order.
  Rng rng = noise_rng(setup_.seed, NoiseStream::position_and_rays, steps_, me.id);
  const Vec2 error = gaussian(rng, noise.position);
  me.position = p + error;
  if (noise.position > 0 || noise.obstacles > 0) {
    s.obstacles.assign(me.obstacles.begin(), me.obstacles.end());
    for (ObstacleHit& h : s.obstacles) {
      Vec2 offset = h.point - p;
      double d = h.distance;
      if (noise.obstacles > 0) {  // along the ray, within what a ray can report
        d = std::clamp(d + rng.normal(0, noise.obstacles), 0.0, me.obstacle_range);
        if (h.distance > 0) offset = offset * (d / h.distance);
      }
      h = {me.position + offset, d};
    }
    me.obstacles = s.obstacles;
  }
  if (noise.neighbours > 0) {
    Rng neighbours = noise_rng(setup_.seed, NoiseStream::neighbours, steps_, me.id);  // in neighbour order
    for (Neighbour& n : s.neighbours) {
      const Vec2 offset = n.position - p + gaussian(neighbours, noise.neighbours);
      n.position = me.position + offset;
      n.distance = offset.length();
    }
  } else if (noise.position > 0)
    for (Neighbour& n : s.neighbours) n.position += error;
  if (senses.targets) {
    if (noise.position > 0)
      for (TargetSeen& t : s.targets) t.position += error;
    if (noise.false_rate > 0)
      for (Vec2 offset : phantoms_[me.id]) s.targets.push_back({me.position + offset, offset.length(), TargetSeen::phantom, false});
    me.targets = s.targets;
  }
}

Perception Simulation::perceive(std::uint32_t id, Senses senses, Scratch& s) const {
  const std::uint32_t g = drones_.groups[id];
  const DroneProperties& cfg = groups_[g].properties;
  const Vec2 p = drones_.positions[id];
  s.neighbours.clear();
  // One search of the drone grid serves the neighbours and the messages' candidate senders (comm's
  // reach may pass the detection range: then neighbours are those within it, in the same order).
  const double detection = senses.neighbours ? cfg.detection_range : 0, reach = setup_.comm.on ? comm_reach_ : 0;
  s.hits.clear();
  if (detection > 0 || reach > 0) drone_grid_.gather(p, std::max(detection, reach), s.hits);
  if (senses.neighbours) {
    const double within = reach > detection ? detection * detection : std::numeric_limits<double>::infinity();
    // The common case, every drone flying in one group, reads neither status nor group per neighbour.
    if (flying_ == drones_.positions.size() && groups_.size() == 1) {
      for (const auto& [j, d2] : s.hits)
        if (j != id && d2 < within) s.neighbours.push_back({drones_.positions[j], drones_.velocities[j], std::sqrt(d2), j, 0});
    } else {
      for (const auto& [j, d2] : s.hits)
        if (j != id && d2 < within && drones_.status[j] == DroneStatus::flying)
          s.neighbours.push_back({drones_.positions[j], drones_.velocities[j], std::sqrt(d2), j, drones_.groups[j]});
    }
  }
  const GroupSetup& group = setup_.groups[g];
  Perception me;
  me.id = id;
  me.position = p;
  me.velocity = drones_.velocities[id];
  me.air_velocity = wind_active_ ? drones_.air[id] : drones_.velocities[id];
  me.max_speed = cfg.max_speed;
  me.max_force = cfg.max_force;
  me.radius = cfg.radius;
  me.mass = cfg.mass;
  me.camera_range = cfg.camera_range;
  me.obstacle_range = cfg.obstacle_range;
  me.detection_range = cfg.detection_range;
  me.dt = setup_.dt;
  me.time = time();
  me.group = g;
  me.base = groups_[g].base;
  me.battery_capacity = group.drone.battery_capacity;
  me.battery = me.battery_capacity > 0 ? std::clamp(drones_.charge[id] / (me.battery_capacity * 3600), 0.0, 1.0) : 1.0;
  me.neighbours = s.neighbours;
  me.obstacles = {drones_.hits.data() + id * ray_slots_, drones_.hit_counts[id]};
  s.targets.clear();
  if (senses.targets) {
    s.targets.assign(sensed_[id].seen.begin(), sensed_[id].seen.end());
    for (TargetSeen& t : s.targets) t.found = targets_.states[t.id].found();
  }
  me.targets = s.targets;
  me.world = this;
  if (setup_.comm.on) {
    comm_->receive(steps_, id, setup_.comm, setup_.seed, drones_.groups, geometry_, s.hits, s.senders, s.messages, comm_counts_[id]);
    me.messages = s.messages;
    me.outbox = &comm_->outbox(id);
  } else {
    s.outbox = {{s.room.data(), message_sizes_[g]}, 0, false};
    me.outbox = &s.outbox;
  }
  return me;
}

// Decide: each group's behavior's shared state first (serial, in group order), then every flying drone
// in parallel, each perceiving only what its behavior senses. Each drone writes only its own steering
// slot and uses its own Rng stream, so any thread count gives the same result.
void Simulation::decide() {
  std::array<Senses, 1> one{};
  std::vector<Senses> many;
  std::span<Senses> senses = one;
  if (setup_.groups.size() > 1) many.resize(setup_.groups.size()), senses = many;
  for (std::uint32_t g = 0; g < setup_.groups.size(); ++g) {
    Behavior& behavior = *setup_.groups[g].behavior;
    plugin_call(behavior_kind, g, [&] { behavior.prepare(*this); });
    senses[g] = plugin_call(behavior_kind, g, [&] { return behavior.senses(); });
  }
  // Asked once per step, so that without noise a drone's perception costs one test of a local more.
  bool noise = false;
  for (const Group& g : groups_) noise = noise || g.noise.perceived() || g.noise.false_rate > 0;
  if (setup_.comm.on && (comm_stale_ || comm_counts_.size() != drones_.positions.size())) {
    comm_->resize(drones_.positions.size(), message_sizes_, drones_.groups, setup_.comm.latency);
    comm_stale_ = false;
  }
  if (setup_.comm.on) {
    comm_counts_.assign(drones_.positions.size(), {});
    comm_reach_ = comm_->reach(steps_, drones_.positions, setup_.comm.range);
  }
  parallel_->for_each(drone_grid_.cell_order(), [&](std::uint32_t i, Scratch& s) {
    if (drones_.status[i] != DroneStatus::flying) return;
    const std::uint32_t g = drones_.groups[i];
    Behavior& behavior = *setup_.groups[g].behavior;
    Perception me = perceive(i, senses[g], s);
    if (noise) add_noise(me, senses[g], s);
    drones_.steering[i] = plugin_call(behavior_kind, g, [&] { return behavior.decide(me, drones_.rngs[i]); });
  });
}

// Communicate: the counts of the messages each drone received in this decide (its inbox was gathered
// right before its decide, as its neighbours are) summed, then the messages broadcast in this decide
// packed with the positions they were decided on, for the receivers'
// decide latency + 1 steps on. Serial, O(drones). Runs only with "comm".
void Simulation::communicate() {
  CommState::Counts total;
  for (const CommState::Counts& c : comm_counts_) {
    total.offered += c.offered, total.in_range += c.in_range, total.obstacle += c.obstacle, total.loss += c.loss;
    total.cap += c.cap, total.delivered += c.delivered;
  }
  // Each message is offered to every other drone flying when it arrives; those the grid did not find
  // in range are dropped by range, counted without looking at them.
  CommCounters& k = comm_counters_;
  k.dropped_range += total.offered - total.in_range;
  k.dropped_obstacle += total.obstacle;
  k.dropped_loss += total.loss;
  k.dropped_cap += total.cap;
  k.delivered += total.delivered;
  k.sent += comm_->collect(steps_, time(), drones_.positions, drones_.status);
}

// Act: add the steering to the velocity as it is, clamp the speed to max speed, hand the velocity to
// Box2D. Max force bounds each steering term (the SDK's helpers clamp to it), not a behavior's weighted
// sum of terms: table1's flocking applies 1.6 + 3 + 1 + 4 = 9.6 × max force at most.
void Simulation::act() {
  if (wind_active_) return act_in_wind();
  for (std::size_t i = 0; i < drones_.positions.size(); ++i) {
    if (drones_.status[i] != DroneStatus::flying) continue;
    const std::uint32_t g = drones_.groups[i];
    const Vec2 a = drones_.steering[i];
    if (!std::isfinite(a.x) || !std::isfinite(a.y))
      throw PluginFailure(behavior_kind, g, "decide returned a non-finite steering " + point(a) + " for drone " + std::to_string(i));
    const Vec2 v = (drones_.velocities[i] + a).clamped(groups_[g].properties.max_speed);
    drones_.commanded[i] = v;
  }
  physics_->set_velocities(drones_.commanded, drones_.status);
}

Vec2 Simulation::wind_at(Vec2 p, double t) const {
  Vec2 w = setup_.wind.velocity + gusts_.value();
  if (const WindField* field = setup_.wind_field.get()) w += plugin_call(wind_kind, 0, [&] { return field->velocity(p, t); });
  return w;
}

// Act in wind: the steering changes the air velocity, clamped to max speed; Box2D gets the ground
// velocity, air + the wind at the drone's position now. A field that would carry a drone through a
// wall in one step (or returns no number) stops the run, naming the plugin.
void Simulation::act_in_wind() {
  const double t = time(), dt = setup_.dt;
  const bool field = setup_.wind_field != nullptr;
  for (std::size_t i = 0; i < drones_.positions.size(); ++i) {
    if (drones_.status[i] != DroneStatus::flying) continue;
    const std::uint32_t g = drones_.groups[i];
    const Vec2 a = drones_.steering[i];
    if (!std::isfinite(a.x) || !std::isfinite(a.y))
      throw PluginFailure(behavior_kind, g, "decide returned a non-finite steering " + point(a) + " for drone " + std::to_string(i));
    const Vec2 p = drones_.positions[i];
    const Vec2 w = wind_at(p, t);
    if (field) {
      const DroneConfig& d = setup_.groups[g].drone;
      const double limit = wind_limit(d, dt), speed = w.length();
      if (!finite(w))
        throw PluginFailure(wind_kind, 0, "velocity at " + point(p) + ", t = " + num(t) + " s gave a wind of " + point(w) +
                                              " m/s (allowed: finite numbers)");
      if (speed > limit * (1 + 1e-9))
        throw PluginFailure(wind_kind, 0, "velocity at " + point(p) + ", t = " + num(t) + " s gave a wind of " + short_num(speed) +
                                              " m/s with the test's constant wind and gusts; a drone at max_speed " + num(d.max_speed) +
                                              " m/s carried by it moves more than min(radius " + num(d.radius) + " m, " +
                                              num(box2d_max_step) + " m) per step (dt " + num(dt) +
                                              " s) and could pass through a wall (allowed: at most " +
                                              (limit > 0 ? num(quoted_limit(limit)) : "0") + " m/s here)");
    }
    const Vec2 air = (drones_.air[i] + a).clamped(groups_[g].properties.max_speed);
    drones_.air[i] = air;
    drones_.wind[i] = w;
    drones_.commanded[i] = air + w;
  }
  physics_->set_velocities(drones_.commanded, drones_.status);
}

void Simulation::physics() {
  physics_->advance(geometry_, setup_.dt, setup_.velocity_iterations, setup_.position_iterations);
}

void Simulation::read_back() {
  physics_->read_back(drones_.positions, drones_.velocities);
  if (!wind_active_) return;
  // What the physics left of the ground velocity (a collision changes it) less the wind flown in.
  for (std::size_t i = 0; i < drones_.positions.size(); ++i)
    if (drones_.status[i] == DroneStatus::flying) drones_.air[i] = drones_.velocities[i] - drones_.wind[i];
  gusts_.advance(setup_.wind.gust_strength, setup_.wind.gust_time_scale, setup_.dt);
}

// Fleet: each flying drone's battery drains by the power its speed over the step takes (or charges on
// its base), and its failure clocks advance. An empty battery lands the drone, a due failure grounds
// it, at the end of this step. Nothing to do (and no cost) without batteries or failure rates.
void Simulation::fleet() {
  const double dt = setup_.dt;
  const FailureSetup& f = setup_.failures;
  bool batteries = false;
  for (const GroupSetup& g : setup_.groups) batteries = batteries || g.drone.battery_capacity > 0;
  if (!batteries && f.drone_mtbf <= 0 && f.camera_mtbf <= 0) return;
  for (std::uint32_t i = 0; i < drones_.positions.size(); ++i) {
    if (drones_.status[i] != DroneStatus::flying) continue;
    const GroupSetup& g = setup_.groups[drones_.groups[i]];
    if (g.drone.battery_capacity > 0) {
      const double speed = drones_.velocities[i].length();
      const bool on_base = g.drone.charge_power > 0 && speed < 1 &&
                           distance(drones_.positions[i], groups_[drones_.groups[i]].base) <= g.drone.charge_radius;
      if (on_base) {
        drones_.charge[i] = std::min(drones_.charge[i] + g.drone.charge_power * dt, g.drone.battery_capacity * 3600);
      } else {
        // Power is drawn for the speed through the air (the ground speed without wind).
        const double energy = flight_power(g.drone, wind_active_ ? drones_.air[i].length() : speed) * dt;
        drones_.used[i] += energy;
        drones_.charge[i] -= energy;
        if (drones_.charge[i] <= 0) {
          drones_.charge[i] = 0;
          ground(i, DroneStatus::landed);
          continue;
        }
      }
    }
    if (f.drone_mtbf > 0 && (drones_.exposure[i] += dt / f.drone_mtbf) >= drones_.due[i]) {
      ground(i, DroneStatus::failed);
      continue;
    }
    if (f.camera_mtbf > 0 && drones_.camera[i] && (drones_.camera_exposure[i] += dt / f.camera_mtbf) >= drones_.camera_due[i])
      drones_.camera[i] = 0;
  }
}

namespace {
class Actions final : public ContactActions {
 public:
  Actions(std::vector<TargetState>& targets, std::size_t& found, std::size_t drones, const WorldView& world, double time)
      : targets_(targets), found_(found), drones_(drones), world_(world, time), time_(time) {}
  /// The handler about to be called: ids it gives are checked here, where the fault can be named.
  std::size_t handler = 0;
  void mark_found(std::uint32_t target, std::uint32_t drone) override {
    if (target >= targets_.size()) refuse("target", target, targets_.size());
    if (drone >= drones_) refuse("drone", drone, drones_);
    if (targets_[target].found()) return;
    targets_[target].found_by = drone;
    targets_[target].found_time = time_;
    ++found_;
  }
  bool is_found(std::uint32_t target) const override { return target < targets_.size() && targets_[target].found(); }
  const WorldView& world() const override { return world_; }

 private:
  [[noreturn]] void refuse(const char* what, std::uint32_t id, std::size_t count) const {
    const std::string field = "contact_handlers[" + std::to_string(handler) + "]";
    throw PluginFailure("contact handler", handler,
                        field + ": mark_found was given " + what + " " + std::to_string(id) + ", which does not exist (allowed: " +
                            (count == 0 ? std::string("none, there are no ") + what + "s"
                                        : std::string(what) + " ids 0 to " + std::to_string(count - 1)) + ")");
  }
  std::vector<TargetState>& targets_;
  std::size_t& found_;
  std::size_t drones_;
  EventView world_;
  double time_;
};
}  // namespace

// Detect: events to the contact handlers, serially and in a fixed order: first the targets each drone
// had in view when it sensed (by drone; only those that came into view for a handler that asks for
// Sightings::on_entry), then the contacts the physics began in its step (in its order). Every event of
// a step carries the time the step ends, the time of the first row that can count it: what was in view
// on the snapshot at t is found at t + dt, so a row never misses a found target.
void Simulation::dispatch_sightings() {
  for (const Sensed& d : sensed_) {
    // Targets lie scattered in memory: ask for a drone's all at once rather than miss on each in turn.
    for (const TargetSeen& t : d.seen) __builtin_prefetch(&targets_.states[t.id], 1);
    for (const TargetSeen& t : d.seen) ++targets_.states[t.id].observations;
  }
  const auto& handlers = setup_.contact_handlers;
  if (handlers.empty()) return;
  std::vector<char> every(handlers.size());
  bool any_every = false;
  for (std::size_t k = 0; k < handlers.size(); ++k) {
    every[k] = plugin_call(handler_kind, k, [&] { return handlers[k]->sightings(); }) != Sightings::on_entry;
    any_every = any_every || every[k];
  }
  const double step_end = time_at(steps_ + 1);  // time() once this step is counted
  Actions actions(targets_.states, targets_.found, drones_.positions.size(), *this, step_end);
  auto hand_out = [&](std::uint32_t i, const TargetSeen& t, bool entered) {
    const ContactEvent e{ContactKind::target_in_view, i, t.id, t.position, step_end};
    for (std::size_t k = 0; k < handlers.size(); ++k)
      if (entered || every[k]) plugin_call(handler_kind, k, [&] { actions.handler = k, handlers[k]->on_contact(e, actions); });
  };
  for (std::uint32_t i = 0; i < sensed_.size(); ++i) {
    const auto& [seen, entered] = std::tie(sensed_[i].seen, sensed_[i].entered);
    if (!any_every) {
      for (std::uint32_t k : entered) hand_out(i, seen[k], true);
      continue;
    }
    auto next = entered.begin();
    for (std::uint32_t k = 0; k < seen.size(); ++k) {
      const bool in = next != entered.end() && *next == k;
      next += in;
      hand_out(i, seen[k], in);
    }
  }
}

void Simulation::dispatch_contacts() {
  Actions actions(targets_.states, targets_.found, drones_.positions.size(), *this, time());
  for (ContactEvent e : physics_->begun()) {
    e.time = time();
    ++collisions_;
    for (std::size_t k = 0; k < setup_.contact_handlers.size(); ++k)
      plugin_call(handler_kind, k, [&] { actions.handler = k, setup_.contact_handlers[k]->on_contact(e, actions); });
  }
}

void Simulation::observe() {
  if (steps_ % setup_.log_every != 0) return;
  for (Observer* o : observers_) o->observe(*this);
}

std::vector<double> Simulation::nearest_neighbour_distances() const {
  const std::size_t n = drones_.positions.size();
  std::vector<double> out(n, std::numeric_limits<double>::infinity());
  if (flying_ < 2) return out;
  const bool everyone = flying_ == n;
  // Cells sized by the grid to the drones' spread (not the detection range, which may be 0 or span the
  // map); the search widens from one cell until it finds someone, and ends once it covers the map.
  PointGrid grid;
  grid.build(drones_.positions, 0);
  const Rect& b = setup_.map.bounds;
  const double far = std::hypot(b.width(), b.height());
  for (std::uint32_t i = 0; i < n; ++i)
    for (double r = grid.cell_size(); everyone || drones_.status[i] == DroneStatus::flying; r *= 4) {  // r > 0, so r >= far within a few dozen rounds
      grid.query(drones_.positions[i], r, [&](std::uint32_t j, Vec2, double d2) {
        if (j != i && (everyone || drones_.status[j] == DroneStatus::flying)) out[i] = std::min(out[i], std::sqrt(d2));
      });
      if (!std::isinf(out[i]) || r >= far) break;
    }
  return out;
}

}  // namespace salsa
