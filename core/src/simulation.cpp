#include "salsa/core/simulation.hpp"

#include "physics_world.hpp"

#include <oneapi/tbb/enumerable_thread_specific.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_group.h>
#include <oneapi/tbb/task_arena.h>

#include <chrono>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace salsa {

namespace {

// Rng streams: a few fixed ones for set-up, then one per drone.
constexpr std::uint64_t targets_stream = 1, spawn_stream = 2, first_drone_stream = 16;

std::string format_point(Vec2 p) {
  std::ostringstream s;
  s << "(" << p.x << ", " << p.y << ")";
  return s.str();
}

}  // namespace

struct Simulation::Scratch {
  std::vector<PointGrid::Hit> hits;
  std::vector<Neighbour> neighbours;
  std::vector<TargetSeen> targets;
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

  /// fn(order[k], scratch) for every k, spread over the arena's threads. Drones go in grid-cell order,
  /// so that neighbouring drones, which read the same cells, run one after the other.
  template <class Fn>
  void for_each(std::span<const std::uint32_t> order, Fn&& fn) {
    if (order.size() <= grain) {  // one chunk: not worth a task
      Scratch& s = scratch.local();
      for (std::uint32_t i : order) fn(i, s);
      return;
    }
    arena.execute([&] {
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, order.size(), grain), [&](const tbb::blocked_range<std::size_t>& r) {
        Scratch& s = scratch.local();
        for (std::size_t k = r.begin(); k != r.end(); ++k) fn(order[k], s);
      });
    });
  }
};

Simulation::Simulation(SimulationSetup setup)
    : setup_(std::move(setup)), parallel_(std::make_unique<Parallel>(setup_.threads)) {
  if (!setup_.behavior) throw std::invalid_argument("no behavior given");
  if (!(setup_.dt > 0)) throw std::invalid_argument("time step must be > 0 s");
  if (setup_.log_every == 0) setup_.log_every = 1;
  build_world();
}

Simulation::~Simulation() = default;

// ---------------------------------------------------------------- set-up and live changes

void Simulation::build_world() {
  const Rect& b = setup_.map.bounds;
  if (!(b.width() > 0 && b.height() > 0))
    throw std::invalid_argument("map bounds must have a positive width and height");
  geometry_ = StaticGeometry(setup_.map, std::max(setup_.drone.obstacle_range, 1.0));
  spawn_ = setup_.spawn.value_or(setup_.map.spawn);
  if (!geometry_.is_free(spawn_, setup_.drone.radius))
    throw std::invalid_argument("spawn point " + format_point(spawn_) +
                                " is inside an obstacle or outside the map bounds (it needs a free disc of the drone radius)");
  physics_ = std::make_unique<PhysicsWorld>(geometry_);
  const std::size_t n = setup_.drones;
  positions_.clear();
  velocities_.clear();
  spawn_rng_ = Rng(setup_.seed, spawn_stream);
  spawn_drones(0, n);
  place_targets();
}

Vec2 Simulation::spawn_position(std::size_t total) {
  const double r = setup_.drone.radius;
  if (setup_.spawn_mode == SpawnMode::disc) {
    const double disc = setup_.spawn_radius > 0 ? setup_.spawn_radius : static_cast<double>(total) * r;
    Vec2 p;
    for (int tries = 0; tries < 100; ++tries) {
      p = spawn_rng_.in_disc(spawn_, disc);
      if (geometry_.is_free(p, r)) return p;
    }
    // Outside the walls: the paper places such drones inside instead.
    const Rect& b = setup_.map.bounds;
    p = {std::clamp(p.x, b.min.x + r, b.max.x - r), std::clamp(p.y, b.min.y + r, b.max.y - r)};
    if (geometry_.is_free(p, r)) return p;
  }
  for (int tries = 0; tries < 1'000'000; ++tries)
    if (Vec2 p = spawn_rng_.in_rect(setup_.map.bounds); geometry_.is_free(p, r)) return p;
  return spawn_;
}

void Simulation::spawn_drones(std::size_t from, std::size_t to) {
  const DroneConfig& cfg = setup_.drone;
  for (std::size_t i = from; i < to; ++i) {
    const Vec2 p = spawn_position(to);
    const Vec2 v = Vec2::polar(spawn_rng_.uniform(0.1 * cfg.max_speed, cfg.max_speed), spawn_rng_.angle());
    positions_.push_back(p);
    velocities_.push_back(v);
    physics_->add_drone(static_cast<std::uint32_t>(i), p, v, cfg);
  }
  positions_.resize(to);
  velocities_.resize(to);
  physics_->remove_drones_from(to);
  steering_.assign(to, {});
  commanded_.resize(to);
  rngs_.clear();
  for (std::size_t i = 0; i < to; ++i) rngs_.emplace_back(setup_.seed, first_drone_stream + i);
  size_rays();
  hits_.assign(to * ray_directions_.size(), {});
  hit_counts_.assign(to, 0);
  setup_.drones = to;
  setup_.behavior->reset(to);
}

void Simulation::size_rays() {
  const int rays = std::max(setup_.drone.obstacle_rays, 0);
  ray_directions_.clear();
  for (int k = 0; k < rays; ++k) ray_directions_.push_back(Vec2::polar(1, 2 * pi * k / rays));
}

void Simulation::place_targets() {
  targets_.clear();
  found_count_ = 0;
  if (setup_.target_kind && setup_.targets > 0) {
    Rng rng(setup_.seed, targets_stream);
    for (Vec2 p : setup_.target_kind->place(setup_.targets, *this, rng)) targets_.push_back({p});
  }
  std::vector<Vec2> points;
  points.reserve(targets_.size());
  for (const auto& t : targets_) points.push_back(t.position);
  const double reach = setup_.drone.camera_range + (setup_.target_kind ? setup_.target_kind->radius() : 0);
  target_grid_.build(points, std::max(reach, 1.0));
}

void Simulation::set_drone_count(std::size_t n) {
  if (n < positions_.size()) {
    physics_->remove_drones_from(n);
    spawn_drones(n, n);
  } else {
    spawn_drones(positions_.size(), n);
  }
}

void Simulation::set_drone_config(const DroneConfig& config) {
  setup_.drone = config;
  physics_->remove_drones_from(0);
  for (std::size_t i = 0; i < positions_.size(); ++i)
    physics_->add_drone(static_cast<std::uint32_t>(i), positions_[i], velocities_[i].clamped(config.max_speed), config);
  size_rays();
  hits_.assign(positions_.size() * ray_directions_.size(), {});
  place_targets();  // the camera range sizes the target grid
}

void Simulation::set_behavior(std::shared_ptr<Behavior> behavior) {
  if (!behavior) throw std::invalid_argument("no behavior given");
  setup_.behavior = std::move(behavior);
  setup_.behavior->reset(positions_.size());
}

void Simulation::set_map(const MapData& map, std::optional<Vec2> spawn) {
  setup_.map = map;
  setup_.spawn = spawn;
  build_world();
}

void Simulation::set_targets(std::shared_ptr<TargetKind> kind, std::size_t count) {
  setup_.target_kind = std::move(kind);
  setup_.targets = count;
  place_targets();
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
  auto drones = [this] {
    timed(Phase::sense, [this] { sense(); });
    timed(Phase::decide, [this] { decide(); });
    timed(Phase::detect, [this] { dispatch_sightings(); });
  };
  if (setup_.decision_lag == 0) {
    drones();
    timed(Phase::act, [this] { act(); });
    timed(Phase::physics, [this] { physics(); });
  } else {
    // Last step's decisions go to Box2D, and while it steps the drones do their side. Nothing one side
    // writes is read by the other.
    timed(Phase::act, [this] { act(); });
    parallel_->overlap(positions_.size(), [this] { timed(Phase::physics, [this] { physics(); }); }, drones);
  }
  ++steps_;
  read_back();
  timed(Phase::detect, [this] { dispatch_contacts(); });
  timed(Phase::observe, [this] { observe(); });
}

// Sense: index the drones for neighbour queries, cast each drone's obstacle rays against static
// geometry and find the targets in its camera view. Neighbours are gathered per drone in `decide`,
// where they stay in cache.
void Simulation::sense() {
  const DroneConfig& cfg = setup_.drone;
  drone_grid_.build(positions_, cfg.detection_range / 2);  // 5×5 cells of R/2 cover less than 3×3 of R
  const std::size_t rays = ray_directions_.size();
  seen_.resize(positions_.size());
  sensed_time_ = time();
  const TargetKind* kind = targets_.empty() ? nullptr : setup_.target_kind.get();
  const double reach = kind ? cfg.camera_range + kind->radius() : 0;
  parallel_->for_each(drone_grid_.cell_order(), [&](std::uint32_t i, Scratch& s) {
    const Vec2 p = positions_[i];
    std::uint8_t count = 0;
    geometry_.candidates(p, cfg.obstacle_range, s.segment_ids);
    if (!s.segment_ids.empty())
      for (Vec2 direction : ray_directions_)
        if (auto hit = geometry_.ray_cast(p, direction, cfg.obstacle_range, s.segment_ids))
          hits_[i * rays + count++] = *hit;
    hit_counts_[i] = count;
    seen_[i].clear();
    if (kind)
      target_grid_.query(p, reach, [&](std::uint32_t t, Vec2, double d2) {
        if (const double d = std::sqrt(d2); kind->in_view(d, cfg.camera_range)) seen_[i].emplace_back(t, d);
      });
  });
}

Perception Simulation::perceive(std::uint32_t id, Scratch& s) const {
  const DroneConfig& cfg = setup_.drone;
  const Vec2 p = positions_[id];
  s.hits.clear();
  drone_grid_.gather(p, cfg.detection_range, s.hits);
  s.neighbours.clear();
  for (const auto& [j, d2] : s.hits)
    if (j != id) s.neighbours.push_back({positions_[j], velocities_[j], std::sqrt(d2), j});
  s.targets.clear();
  for (const auto& [t, d] : seen_[id]) s.targets.push_back({targets_[t].position, d, t, targets_[t].found()});
  const std::size_t rays = ray_directions_.size();
  Perception me;
  me.id = id;
  me.position = p;
  me.velocity = velocities_[id];
  me.max_speed = cfg.max_speed;
  me.max_force = cfg.max_force;
  me.radius = cfg.radius;
  me.mass = cfg.mass;
  me.camera_range = cfg.camera_range;
  me.obstacle_range = cfg.obstacle_range;
  me.detection_range = cfg.detection_range;
  me.dt = setup_.dt;
  me.time = time();
  me.neighbours = s.neighbours;
  me.obstacles = {hits_.data() + id * rays, hit_counts_[id]};
  me.targets = s.targets;
  me.world = this;
  return me;
}

// Decide: the behavior's shared state first (serial), then every drone in parallel. Each drone writes
// only its own steering slot and uses its own Rng stream, so any thread count gives the same result.
void Simulation::decide() {
  Behavior& behavior = *setup_.behavior;
  behavior.prepare(*this);
  parallel_->for_each(drone_grid_.cell_order(), [&](std::uint32_t i, Scratch& s) {
    steering_[i] = behavior.decide(perceive(i, s), rngs_[i]);
  });
}

// Act: clamp to max force and max speed, hand the velocity to Box2D.
void Simulation::act() {
  const DroneConfig& cfg = setup_.drone;
  for (std::size_t i = 0; i < positions_.size(); ++i) {
    const Vec2 a = steering_[i];
    if (!std::isfinite(a.x) || !std::isfinite(a.y))
      throw std::runtime_error("behavior returned a non-finite steering for drone " + std::to_string(i) +
                               " at t = " + std::to_string(time()) + " s");
    const Vec2 v = (velocities_[i] + a.clamped(cfg.max_force)).clamped(cfg.max_speed);
    commanded_[i] = v;
    physics_->bodies[i]->SetLinearVelocity(to_b2(v));
  }
}

void Simulation::physics() {
  physics_->step(setup_.dt, setup_.velocity_iterations, setup_.position_iterations);
}

void Simulation::read_back() {
  for (std::size_t i = 0; i < positions_.size(); ++i) {
    positions_[i] = from_b2(physics_->bodies[i]->GetPosition());
    velocities_[i] = from_b2(physics_->bodies[i]->GetLinearVelocity());
  }
}

namespace {
class Actions final : public ContactActions {
 public:
  Actions(std::vector<TargetState>& targets, std::size_t& found, double time) : targets_(targets), found_(found), time_(time) {}
  void mark_found(std::uint32_t target, std::uint32_t drone) override {
    if (target >= targets_.size() || targets_[target].found()) return;
    targets_[target].found_by = drone;
    targets_[target].found_time = time_;
    ++found_;
  }
  bool is_found(std::uint32_t target) const override { return target < targets_.size() && targets_[target].found(); }

 private:
  std::vector<TargetState>& targets_;
  std::size_t& found_;
  double time_;
};
}  // namespace

// Detect: events to the contact handlers, serially and in a fixed order: first the targets each drone
// had in view when it sensed (by drone), then the contacts Box2D began in its step (in its order).
void Simulation::dispatch_sightings() {
  const double sensed_at = sensed_time_;
  Actions actions(targets_, found_count_, sensed_at);
  for (std::uint32_t i = 0; i < seen_.size(); ++i)
    for (const auto& [t, d] : seen_[i]) {
      ++targets_[t].observations;
      const ContactEvent e{ContactKind::target_in_view, i, t, targets_[t].position, sensed_at};
      for (const auto& handler : setup_.contact_handlers) handler->on_contact(e, actions);
    }
}

void Simulation::dispatch_contacts() {
  Actions actions(targets_, found_count_, time());
  for (ContactEvent e : physics_->begun) {
    e.time = time();
    ++collisions_;
    for (const auto& handler : setup_.contact_handlers) handler->on_contact(e, actions);
  }
}

void Simulation::observe() {
  if (steps_ % setup_.log_every != 0) return;
  for (Observer* o : observers_) o->observe(*this);
}

std::vector<double> Simulation::nearest_neighbour_distances() const {
  const std::size_t n = positions_.size();
  std::vector<double> out(n, std::numeric_limits<double>::infinity());
  if (n < 2) return out;
  PointGrid grid;
  grid.build(positions_, setup_.drone.detection_range);
  const Rect& b = setup_.map.bounds;
  const double far = std::hypot(b.width(), b.height()) * 2;
  for (std::uint32_t i = 0; i < n; ++i) {
    for (double r = setup_.drone.detection_range; r <= far && std::isinf(out[i]); r *= 4)
      grid.query(positions_[i], r, [&](std::uint32_t j, Vec2, double d2) {
        if (j != i) out[i] = std::min(out[i], std::sqrt(d2));
      });
  }
  return out;
}

}  // namespace salsa
