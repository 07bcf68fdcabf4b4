#include "salsa/core/run/bench.hpp"

#include "model/physics_world.hpp"

#include <array>
#include <chrono>
#include <cmath>
#include <ctime>
#include <fstream>
#include <string>

namespace salsa::bench {

namespace {
/// A behavior that flies as `inner` does and broadcasts its position and velocity every step; it reads
/// every message it gets (their payloads summed into its steering times zero), as a behavior using them would.
class Broadcasting final : public Behavior {
 public:
  explicit Broadcasting(std::shared_ptr<Behavior> inner) : inner_(std::move(inner)) {}
  void prepare(const WorldView& world) override { inner_->prepare(world); }
  Vec2 decide(const Perception& me, Rng& rng) override {
    const std::array<double, 4> state{me.position.x, me.position.y, me.velocity.x, me.velocity.y};
    me.broadcast(state);
    double heard = 0;
    for (const Message& m : me.messages) heard += m.payload[0] * 0 + m.range() * 0;
    return inner_->decide(me, rng) + Vec2{heard, 0};
  }
  void reset(std::size_t drones) override { inner_->reset(drones); }
  void resize(std::size_t drones) override { inner_->resize(drones); }
  Senses senses() const override { return inner_->senses(); }
  std::size_t message_size() const override { return 4; }

 private:
  std::shared_ptr<Behavior> inner_;
};

/// Flies at max speed to `goal` (a pile's centre), sensing nothing.
class ToPoint final : public Behavior {
 public:
  explicit ToPoint(Vec2 goal) : goal_(goal) {}
  Vec2 decide(const Perception& me, Rng&) override {
    const Vec2 to = goal_ - me.position;
    return (to.length() > 1e-9 ? to.with_length(me.max_speed) : Vec2{}) - me.velocity;
  }
  Senses senses() const override { return {false, false}; }  // the pile's cost is the physics', not the sensing's

 private:
  Vec2 goal_;
};
}  // namespace

SimulationSetup table1(const PluginHost& host, const Workload& w) {
  SimulationSetup s;
  s.map.bounds = {{0, 0}, {w.side, w.side}};
  s.map.spawn = w.spawn;
  GroupSetup& g = s.groups.front();
  g.spawn_mode = w.spawn_mode;
  g.drone = builtin_drone_configs().front();  // "small"
  g.drones = w.drones;
  const auto& behavior = host.behavior(w.behavior);
  ParameterValues params(behavior.factory.parameters);
  if (w.behavior == "flocking") {
    params.set("separation_distance", 250);
    params.set("alignment_weight", 1.6);
    params.set("cohesion_weight", 1.0);
    params.set("separation_weight", 3.0);
    params.set("obstacle_avoidance_weight", 4.0);
  }
  g.behavior = PluginHost::create(behavior, params);
  if (w.comm_range > 0) {
    s.comm.on = true;
    s.comm.range = w.comm_range;
    s.comm.line_of_sight = true;
    g.behavior = std::make_shared<Broadcasting>(g.behavior);
  }
  if (w.fleet) {
    // Two groups of half the swarm each, batteries that last the run and failures at a rate that takes
    // a few drones: all of the fleet model's per-step work. Both groups draw from the spawn disc of the
    // whole swarm, in turn from the one spawn stream, so the drones start exactly where the one-group
    // cell's do.
    g.drone.battery_capacity = 100;
    g.spawn_radius = static_cast<double>(w.drones) * g.drone.radius;
    s.failures = {3600, 3600};
    GroupSetup second = g;
    second.name = "second";
    g.drones = w.drones / 2;
    second.drones = w.drones - g.drones;
    second.behavior = PluginHost::create(behavior, params);
    s.groups.push_back(std::move(second));
  }
  if (w.pile) {
    g.behavior = std::make_shared<ToPoint>(w.spawn);
    g.spawn_mode = SpawnMode::disc;
    GroupSetup large = g;
    large.name = "large";
    large.drone.radius *= 2;
    large.drone.mass *= 4;
    large.behavior = std::make_shared<ToPoint>(w.spawn);
    g.drones = w.drones / 2;
    large.drones = w.drones - g.drones;
    const double bodies = pi * (static_cast<double>(g.drones) * g.drone.radius * g.drone.radius +
                                static_cast<double>(large.drones) * large.drone.radius * large.drone.radius);
    g.spawn_radius = large.spawn_radius = std::sqrt(bodies / (disc_packing * pi));
    s.groups.push_back(std::move(large));
  }
  if (w.wind) s.wind = {Vec2::polar(3, pi / 6), 1, 10};  // act in wind, air velocities and gusts every step
  const auto& tree = host.target_kind("tree");
  ParameterValues tree_params(tree.factory.parameters);
  tree_params.set("radius", 5);
  s.target_kind = PluginHost::create(tree, tree_params);
  s.targets = w.targets;
  const auto& detect = host.contact_handler("detect_targets");
  s.contact_handlers.push_back(PluginHost::create(detect, ParameterValues(detect.factory.parameters)));
  s.dt = 1.0 / 60;
  s.velocity_iterations = 8;
  s.position_iterations = 3;
  s.physics = w.physics;
  s.seed = w.seed;
  s.threads = w.threads;
  s.log_every = 50;
  return s;
}

Workload scale(std::size_t drones, std::uint64_t seed, int threads) {
  Workload w;
  w.drones = drones;
  w.targets = 10 * drones;
  w.side = 2000 * std::sqrt(static_cast<double>(drones) / 1000.0);
  w.spawn = {w.side / 2, w.side / 2};
  w.spawn_mode = SpawnMode::uniform;
  w.seed = seed;
  w.threads = threads;
  return w;
}

SimulationSetup abm_flocking(const PluginHost& host, bool large, std::uint64_t seed) {
  const double side = large ? 150 : 100, visual = large ? 15 : 5;
  SimulationSetup s;
  s.map.bounds = {{0, 0}, {side, side}};
  s.map.spawn = {side / 2, side / 2};
  GroupSetup& g = s.groups.front();
  g.spawn_mode = SpawnMode::uniform;
  g.drone = builtin_drone_configs().front();
  g.drone.radius = 1;
  g.drone.max_speed = 1;
  g.drone.detection_range = visual;
  g.drone.camera_range = 0;
  g.drone.obstacle_range = 0;
  g.drone.obstacle_rays = 0;
  g.drones = large ? 400 : 200;
  const auto& behavior = host.behavior("abm_flocking");
  ParameterValues params(behavior.factory.parameters);
  params.set("visual_distance", visual);
  g.behavior = PluginHost::create(behavior, params);
  s.dt = 1;
  s.physics = PhysicsMode::light;
  s.seed = seed;
  s.threads = 1;
  s.log_every = 5;
  return s;
}

Floor::Floor(std::size_t drones, std::size_t steps) : drones_(drones) { commands_.reserve(2 * drones * steps); }

void Floor::record(const Simulation& sim) {
  for (Vec2 v : sim.commanded_velocities()) {
    commands_.push_back(static_cast<float>(v.x));
    commands_.push_back(static_cast<float>(v.y));
  }
}

double Floor::replay_seconds(const SimulationSetup& setup, bool cpu) const {
  // The same drones in the same places as salsa spawned them: take them from a Simulation without
  // targets, then step a world of our own.
  SimulationSetup copy = setup;
  copy.target_kind = nullptr;
  copy.targets = 0;
  copy.contact_handlers.clear();
  Simulation spawned(copy);
  const auto positions = spawned.drone_positions();

  PhysicsWorld world(spawned.geometry());
  for (std::size_t i = 0; i < positions.size(); ++i)
    world.add_drone(static_cast<std::uint32_t>(i), positions[i], {}, setup.groups[spawned.drone_groups()[i]].drone);
  const std::size_t steps = drones_ ? commands_.size() / (2 * drones_) : 0;
  const double start = seconds_now(cpu);
  const float* v = commands_.data();
  for (std::size_t k = 0; k < steps; ++k) {
    for (b2Body* body : world.bodies) {
      body->SetLinearVelocity(b2Vec2(v[0], v[1]));
      v += 2;
    }
    world.step(setup.dt, setup.velocity_iterations, setup.position_iterations);
  }
  return seconds_now(cpu) - start;
}

double seconds_now(bool cpu) {
  if (timespec t; cpu && clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t) == 0) return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

std::size_t peak_rss_bytes() {
  std::ifstream status("/proc/self/status");
  for (std::string line; std::getline(status, line);)
    if (line.rfind("VmHWM:", 0) == 0) return static_cast<std::size_t>(std::stoull(line.substr(6))) * 1024;
  return 0;
}

void reset_peak_rss() {
  std::ofstream("/proc/self/clear_refs") << "5";
}

}  // namespace salsa::bench
