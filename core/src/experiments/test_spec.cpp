// The TestSpec's own queries, the first of a list of tests that repeats an earlier one, and a test's expected wall time.
#include "salsa/core/experiments/test_spec.hpp"

#include "format.hpp"

#include <cmath>
#include <unordered_map>

#include "salsa/core/experiments/changes.hpp"

namespace salsa {

const char* salsa_version() { return SALSA_VERSION; }

std::size_t TestSpec::steps() const { return static_cast<std::size_t>(std::llround(time / dt)); }
std::size_t TestSpec::log_every() const {
  return std::max<std::size_t>(1, static_cast<std::size_t>(std::llround(log_interval / dt)));
}
std::size_t TestSpec::drone_total() const {
  std::size_t n = 0;
  for (const GroupSpec& g : groups) n += g.drones;
  return n;
}
int TestSpec::group_index(std::string_view wanted) const {
  for (std::size_t g = 0; g < groups.size(); ++g)
    if (groups[g].name == wanted) return static_cast<int>(g);
  return -1;
}
bool TestSpec::fleet() const {
  if (groups.size() > 1 || failures != FailureSetup{}) return true;
  for (const GroupSpec& g : groups)
    if (g.drone.battery_capacity > 0) return true;
  for (const Change& c : changes)
    if (c.key.starts_with("fail") || (c.key.ends_with("battery_capacity") && c.value > 0)) return true;
  return false;
}

bool TestSpec::return_to_base() const {
  for (const GroupSpec& g : groups)
    if (g.drone.return_to_base > 0) return true;
  for (const Change& c : changes)
    if (c.key.ends_with("drone.return_to_base") && c.value > 0) return true;
  return false;
}

namespace {

/// A hash of what `==` compares in a TestSpec, but its name, source and seed_given, through the
/// models' schemas: tests that differ anywhere a queue can vary them (conditions, sweep.set keys,
/// timed changes) fall in different buckets, so finding a repeated test stays linear.
std::size_t content_hash(const TestSpec& t) {
  std::size_t h = 0;
  auto mix = [&h](std::size_t v) { h ^= v + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2); };
  auto mix_double = [&](double v) { mix(std::hash<double>{}(v == 0 ? 0.0 : v)); };  // -0 == 0, as == says
  auto mix_text = [&](const std::string& v) { mix(std::hash<std::string>{}(v)); };
  auto mix_choice = [&](const PluginChoice& c) {
    mix_text(c.name);
    for (const auto& [name, value] : c.params.items()) mix_text(name), mix_double(value);
  };
  auto mix_fields = [&](const auto& schema, const auto& object) {
    for (const auto& field : schema) mix_double(field.get(object));
  };
  mix(t.seed), mix(t.repeat), mix(t.targets), mix(t.named_groups);
  for (const GroupSpec& g : t.groups) {
    mix_text(g.name), mix_choice(g.behavior), mix(g.drones), mix_text(g.drone.name);
    mix_fields(drone_schema(), g.drone);
    if (g.spawn) mix_double(g.spawn->x), mix_double(g.spawn->y);
    mix(static_cast<std::size_t>(g.spawn_mode)), mix_double(g.spawn_radius);
  }
  mix_fields(failure_schema(), t.failures), mix_fields(wind_schema(), t.wind), mix_fields(comm_schema(), t.comm);
  for (const PluginChoice* c : {&t.wind_field, &t.map, &t.target}) mix_choice(*c);
  for (const auto* list : {&t.contact_handlers, &t.metrics})
    for (const PluginChoice& c : *list) mix_choice(c);
  mix_text(t.map_file);
  for (const double v : {t.time, t.dt, t.log_interval}) mix_double(v);
  mix(static_cast<std::size_t>(t.velocity_iterations)), mix(static_cast<std::size_t>(t.position_iterations));
  mix(static_cast<std::size_t>(t.decision_lag)), mix(static_cast<std::size_t>(t.physics));
  for (const Change& c : t.changes) mix_double(c.time), mix_text(c.key), mix_double(c.value);
  mix_text(t.condition), mix_text(t.condition_label);
  return h;
}

}  // namespace

std::optional<std::pair<std::size_t, std::size_t>> first_same_test(const std::vector<const TestSpec*>& tests) {
  auto same = [](const TestSpec& a, const TestSpec& b) {
    TestSpec x = a;
    x.name = b.name, x.source = b.source, x.seed_given = b.seed_given, x.archive = b.archive;
    return x == b;
  };
  std::unordered_multimap<std::size_t, std::size_t> seen;
  seen.reserve(tests.size());
  for (std::size_t j = 0; j < tests.size(); ++j) {
    const std::size_t k = content_hash(*tests[j]);
    for (auto [it, end] = seen.equal_range(k); it != end; ++it)
      if (same(*tests[it->second], *tests[j])) return std::pair{it->second, j};
    seen.emplace(k, j);
  }
  return std::nullopt;
}

namespace {
using format::grouped;
constexpr auto sig = format::significant;
}  // namespace

std::string workload_warning(const TestSpec& t, const SimulationSetup& s) {
  // Wall time per drone-step on one core, measured with flocking (docs/architecture.md): about 1 µs,
  // plus 0.01 µs per neighbour (each is gathered, and the behavior looks at it).
  constexpr double per_drone_step = 1e-6, per_neighbour = 1e-8;
  const Rect& b = s.map.bounds;
  double free_area = b.area();
  for (const Polyline& poly : s.map.obstacles) {
    double twice = 0;  // shoelace
    for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) twice += poly[j].cross(poly[i]);
    free_area -= std::abs(twice) / 2;
  }
  free_area = std::max(free_area, b.area() / 100);
  auto neighbours_of = [&](double drones, double range) { return std::min(drones - 1, drones * pi * range * range / free_area); };
  // The timed changes may raise the drone count or the detection range: the test costs the sum of its
  // stretches, and the message describes its heaviest one.
  TestSpec now = t;
  double seconds = 0, heaviest = -1, drones = 0, range = 0, neighbours = 0;
  std::uint64_t from = 0;
  auto stretch = [&](std::uint64_t to) {
    double r = 0;
    for (const GroupSpec& g : now.groups) r = std::max(r, g.drone.detection_range);
    const double n = static_cast<double>(now.drone_total()), k = neighbours_of(n, r);
    const double per_step = n * (per_drone_step + per_neighbour * k);
    seconds += static_cast<double>(to - std::min(from, to)) * per_step;
    if (per_step > heaviest) heaviest = per_step, drones = n, range = r, neighbours = k;
    from = std::max(from, to);
  };
  const std::uint64_t steps = t.steps();
  for (const Change& c : t.changes) {
    const std::uint64_t at = std::min<std::uint64_t>(change_step(c.time, t.dt), steps);
    if (at > from) stretch(at);
    if (at >= steps) break;  // after the end: never applied
    apply_to_test(now, c);
  }
  stretch(steps);
  const double steps_per_second = 1 / t.dt;
  if (seconds < 3600) return {};
  const double hours = seconds / 3600;
  double first_range = 0;
  for (const GroupSpec& g : t.groups) first_range = std::max(first_range, g.drone.detection_range);
  const bool changed = drones != static_cast<double>(t.drone_total()) || range != first_range;
  return t.source + ": " + grouped(drones) + " drones" + (changed ? " (after its timed changes)" : "") + " with detection range " +
         sig(range, 6) + " m on a " + sig(b.width(), 6) + " m × " + sig(b.height(), 6) + " m map: ~" + grouped(neighbours) +
         " neighbours per drone, about " + sig(drones * neighbours * steps_per_second, 2) + " drone-neighbour checks per simulated second; " +
         sig(t.time, 6) + " s simulated: expect " +
         (hours < 48 ? "hours (about " + sig(hours, 2) + " h" : "days (about " + sig(hours / 24, 2) + " days") + " on one core)";
}

}  // namespace salsa
