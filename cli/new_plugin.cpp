// salsa new-plugin KIND NAME [--dir D]: writes D/NAME/, a plugin folder that builds, tests and installs
// against the installed salsa (find_package(salsa) + salsa_add_plugin). The templates are below, one
// plugin and one test per kind; @NAME@, @CLASS@ and @VERSION@ are filled in.
#include <boost/program_options.hpp>

#include <unistd.h>

#include <array>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <string_view>
#include <vector>

#include "salsa/core/test_spec.hpp"
#include "commands.hpp"

namespace po = boost::program_options;
namespace fs = std::filesystem;

namespace {

// ---- What every kind shares ----

const char* cmake_template = R"~~(# @NAME@: a salsa @KIND@ plugin, written by `salsa new-plugin`.
#   cmake -B build                      # add -DCMAKE_PREFIX_PATH=<prefix> if salsa is not in /usr or /usr/local
#   cmake --build build
#   ctest --test-dir build              # @NAME@_test, and @NAME@_loads: the installed salsa loads and runs it
#   cmake --install build               # into ~/.local/share/salsa/plugins: salsa and salsa-gui find it
# To share it, hand over this folder: it builds against any salsa @VERSION@.x.
cmake_minimum_required(VERSION 3.25)
project(@NAME@ VERSION 0.1.0 LANGUAGES CXX)
find_package(salsa @VERSION@ REQUIRED)
enable_testing()

salsa_add_plugin(@NAME@ @NAME@.cpp VERSION ${PROJECT_VERSION} AUTHOR "" BRIEF "@BRIEF@")

add_executable(@NAME@_test @NAME@_test.cpp)
target_link_libraries(@NAME@_test PRIVATE salsa::sdk)
target_compile_options(@NAME@_test PRIVATE -Wall -Wextra)
add_test(NAME @NAME@_test COMMAND @NAME@_test)
)~~";

const char* test_preamble = R"~~(#include <cstdio>

#include "@NAME@.cpp"  // the plugin is one file: compiled in here to reach its class

#define CHECK(condition)                                                                \
  do {                                                                                  \
    if (!(condition)) {                                                                 \
      std::fprintf(stderr, "%s:%d: CHECK(%s) failed\n", __FILE__, __LINE__, #condition); \
      return 1;                                                                         \
    }                                                                                   \
  } while (0)
)~~";

// ---- behavior ----

const char* behavior_source = R"~~(// @NAME@: a salsa behavior. Each drone keeps a heading of its own that drifts at random, and steers
// away from drones too close and from obstacles. decide() runs once per drone per step, possibly in
// parallel: it writes only its drone's memory and draws only from the rng it is given.
// The whole contract: plugins.md (installed in /usr/share/doc/salsa/).
#include <salsa/sdk.hpp>

namespace {

struct @CLASS@Memory {  // per-drone memory, one slot per drone, owned by the core
  double angle = 0;       // rad: the heading
  bool chosen = false;
};

class @CLASS@ final : public salsa::BehaviorWithMemory<@CLASS@Memory> {
 public:
  // Name, default, min, max, unit, meaning: the GUI's sliders, the checks of a test's JSON, sweeps.
  static salsa::Parameters declare() {
    return {{"turn_rate", 0.5, 0.0, 10.0, "rad/s", "how fast the heading drifts at random"},
            {"separation", 10.0, 0.0, 200.0, "m", "fly away from drones closer than this"},
            {"avoidance", 2.0, 0.0, 10.0, "", "weight of obstacle avoidance"}};
  }
  salsa::Vec2 decide(const salsa::Perception& me, @CLASS@Memory& h, salsa::Rng& rng) override {
    if (!h.chosen) h = {rng.angle(), true};
    h.angle += rng.uniform(-1.0, 1.0) * param("turn_rate") * me.dt;
    // Steering terms, each at most max force; the core adds the sum to the velocity.
    return salsa::steer_towards(me, salsa::Vec2::polar(me.max_speed, h.angle)) +
           salsa::avoid_drones(me, param("separation")) + param("avoidance") * salsa::avoid_obstacles(me);
  }
  // decide() never looks at the targets in view: the core need not gather them.
  salsa::Senses senses() const override { return {.neighbours = true, .targets = false}; }
};

}  // namespace

SALSA_BEHAVIOR(@CLASS@, "@NAME@", "@BRIEF@")
)~~";

const char* behavior_test = R"~~(// @NAME@'s decide() on hand-made perceptions (salsa::testing::Scene), no simulation needed.
#include <salsa/testing.hpp>

@PREAMBLE@
int main() {
  {  // An obstacle 5 m east of a drone at rest: whatever its heading, it steers west.
    salsa::testing::Scene scene;
    scene.at({0, 0}).obstacle({5, 0});
    @CLASS@ behavior;  // declared defaults are filled in on first use
    CHECK(scene.decide(behavior).x < 0);
  }
  {  // A drone 3 m east pushes it west: the same heading (same seed) with and without the neighbour.
    salsa::testing::Scene alone, crowded;
    crowded.neighbour({3, 0});
    @CLASS@ a, b;
    CHECK(crowded.decide(b, 7).x < alone.decide(a, 7).x);
  }
  {  // Each term is at most max force: the sum at most (1 + 1 + avoidance) max force.
    salsa::testing::Scene scene;
    scene.at({0, 0}, {3, 4}).neighbour({1, 1}).obstacle({2, 0}).obstacle({0, -2});
    @CLASS@ behavior;
    CHECK(scene.decide(behavior).length() <= (1 + 1 + 2.0 /* avoidance */) * scene.me().max_force + 1e-9);
  }
  {  // The same seed gives the same steering; another seed another heading.
    salsa::testing::Scene s1, s2, s3;
    @CLASS@ a, b, c;
    const salsa::Vec2 first = s1.decide(a, 1), again = s2.decide(b, 1), other = s3.decide(c, 2);
    CHECK(first.x == again.x && first.y == again.y);
    CHECK(first.x != other.x || first.y != other.y);
  }
  std::puts("@NAME@_test: ok");
  return 0;
}
)~~";

// ---- target ----

const char* target_source = R"~~(// @NAME@: a salsa target kind. Targets are discs that drones search for; these are small or hidden,
// so a drone sees one only within `visibility` × its camera range. Placement is the default:
// uniform over free space (override place() to cluster them).
#include <salsa/sdk.hpp>

namespace {

class @CLASS@ final : public salsa::TargetKind {
 public:
  static salsa::Parameters declare() {
    return {{"radius", 2.0, 0.1, 100.0, "m", "radius of a target"},
            {"visibility", 0.5, 0.0, 1.0, "", "fraction of the camera range within which a target is seen"}};
  }
  double radius() const override { return radius_; }
  bool in_view(double distance, double camera_range) const override {
    return distance < visibility_ * camera_range + radius_;
  }

 protected:
  void configure() override {  // after every change of the parameters: cache them
    radius_ = param("radius");
    visibility_ = param("visibility");
  }

 private:
  double radius_ = 2, visibility_ = 0.5;
};

}  // namespace

SALSA_TARGET(@CLASS@, "@NAME@", "@BRIEF@")
)~~";

const char* target_test = R"~~(// @NAME@'s radius and visibility, with its declared defaults and with changed parameters.
@PREAMBLE@
int main() {
  @CLASS@ kind;
  salsa::ParameterValues values(@CLASS@::declare());
  kind.set_parameters(values);
  CHECK(kind.radius() == 2);
  CHECK(kind.in_view(9, 15));    // within 0.5 × 15 m + 2 m
  CHECK(!kind.in_view(10, 15));
  values.set("visibility", 1);
  kind.set_parameters(values);
  CHECK(kind.in_view(16, 15));
  for (const salsa::Parameter& p : @CLASS@::declare()) CHECK(p.check(p.value).empty());  // defaults in range
  std::puts("@NAME@_test: ok");
  return 0;
}
)~~";

// ---- map ----

const char* map_source = R"~~(// @NAME@: a salsa map. A square closed by walls with a grid of square pillars, none near the centre,
// where the drones start. generate() gets the test's parameters and an rng (unused here: the same
// parameters always give the same map); bad parameters throw salsa::MapError with one line.
#include <cmath>
#include <string>

#include <salsa/sdk.hpp>

namespace {

class @CLASS@ final : public salsa::MapGenerator {
 public:
  static salsa::Parameters declare() {
    return {{"size", 300.0, 20.0, 1e5, "m", "side of the square"},
            {"spacing", 50.0, 5.0, 1e4, "m", "distance between pillar centres"},
            {"pillar", 8.0, 0.5, 1e3, "m", "side of a pillar"},
            {"clear", 40.0, 0.0, 1e4, "m", "no pillar within this distance of the centre"}};
  }
  salsa::MapData generate(const std::string& /*file*/, salsa::Rng& /*rng*/) const override {
    const double size = param("size"), spacing = param("spacing"), half = param("pillar") / 2;
    if (2 * half >= spacing) throw salsa::MapError("pillar: must be smaller than spacing (" + salsa::Parameter::format(spacing) + " m)");
    if (std::pow(size / spacing, 2) > 1e6) throw salsa::MapError("spacing: more than 1,000,000 pillars (allowed: a larger spacing)");
    salsa::MapData map;
    map.bounds = {{0, 0}, {size, size}};
    map.spawn = map.bounds.centre();
    for (double x = spacing; x + half < size; x += spacing)
      for (double y = spacing; y + half < size; y += spacing)
        if (salsa::distance({x, y}, map.spawn) > param("clear") + half * std::sqrt(2.0))
          map.obstacles.push_back({{x - half, y - half}, {x + half, y - half}, {x + half, y + half}, {x - half, y + half}});  // CCW
    return map;
  }
};

}  // namespace

SALSA_MAP(@CLASS@, "@NAME@", "@BRIEF@")
)~~";

const char* map_test = R"~~(// @NAME@'s map: pillars inside the bounds, none at the spawn point; bad parameters refused.
@PREAMBLE@
int main() {
  @CLASS@ generator;
  salsa::ParameterValues values(@CLASS@::declare());
  generator.set_parameters(values);
  salsa::Rng rng(1);
  const salsa::MapData map = generator.generate("", rng);
  CHECK(!map.obstacles.empty());
  CHECK(map.bounds.contains(map.spawn));
  for (const salsa::Polyline& pillar : map.obstacles) {
    CHECK(pillar.size() == 4);
    for (salsa::Vec2 p : pillar) CHECK(map.bounds.contains(p));
    CHECK(salsa::distance((pillar[0] + pillar[2]) / 2, map.spawn) > values.get("clear"));
  }
  values.set("pillar", 60);  // wider than the spacing
  generator.set_parameters(values);
  bool refused = false;
  try {
    generator.generate("", rng);
  } catch (const salsa::MapError&) {
    refused = true;
  }
  CHECK(refused);
  std::puts("@NAME@_test: ok");
  return 0;
}
)~~";

// ---- contact handler ----

const char* contact_source = R"~~(// @NAME@: a salsa contact handler. A target counts as found only once drones have had it in view for
// `sightings` drone-steps in all (one glimpse may be a false detection). Handlers are called serially,
// in the order the test lists them, with every event of a step.
#include <cstdint>
#include <unordered_map>

#include <salsa/sdk.hpp>

namespace {

class @CLASS@ final : public salsa::ContactHandler {
 public:
  static salsa::Parameters declare() {
    return {{"sightings", 3, 1, 1000, "", "drone-steps a target must be in view before it counts as found", 1}};
  }
  void on_contact(const salsa::ContactEvent& event, salsa::ContactActions& actions) override {
    if (event.kind != salsa::ContactKind::target_in_view || actions.is_found(event.other)) return;
    if (++seen_[event.other] >= param("sightings")) actions.mark_found(event.other, event.drone);
  }

 private:
  std::unordered_map<std::uint32_t, int> seen_;  // target id -> drone-steps in view so far
};

}  // namespace

SALSA_CONTACT_HANDLER(@CLASS@, "@NAME@", "@BRIEF@")
)~~";

const char* contact_test = R"~~(// @NAME@ against a recording stand-in for the simulation's ContactActions.
#include <map>

@PREAMBLE@
namespace fake {
struct Actions final : salsa::ContactActions {
  std::map<std::uint32_t, std::uint32_t> found;  // target -> the drone that found it
  void mark_found(std::uint32_t target, std::uint32_t drone) override { found.emplace(target, drone); }
  bool is_found(std::uint32_t target) const override { return found.count(target) > 0; }
};
}  // namespace fake

int main() {
  @CLASS@ handler;
  handler.set_parameters(salsa::ParameterValues(@CLASS@::declare()));  // sightings: 3
  fake::Actions actions;
  auto seen = [&](std::uint32_t drone, std::uint32_t target) {
    handler.on_contact({salsa::ContactKind::target_in_view, drone, target, {0, 0}, 0.0}, actions);
  };
  handler.on_contact({salsa::ContactKind::drone_drone, 1, 2, {0, 0}, 0.0}, actions);  // not a sighting
  seen(1, 7);
  seen(2, 7);
  seen(1, 8);
  CHECK(actions.found.empty());
  seen(4, 7);  // the third sighting of target 7
  CHECK(actions.found.size() == 1 && actions.found.at(7) == 4);
  std::puts("@NAME@_test: ok");
  return 0;
}
)~~";

// ---- metric ----

const char* metric_source = R"~~(// @NAME@: a salsa metric. The swarm's polarisation (0: the drones' headings cancel out, 1: all fly
// the same way) at each row of a test's summary.csv, and its mean over every step in outcome.csv.
// A test lists it in "metrics"; calls come from the stepping thread: reset at time 0, step after
// every step, observe at each logged row, finish once at the end.
#include <cmath>
#include <cstddef>
#include <span>
#include <vector>

#include <salsa/sdk.hpp>

namespace {

class @CLASS@ final : public salsa::Metric {
 public:
  std::vector<salsa::Column> step_columns() const override {  // name, unit, meaning, decimals
    return {{"polarisation", "", "length of the drones' mean unit velocity (1: all fly the same way)", 3}};
  }
  std::vector<salsa::Column> final_columns() const override {
    return {{"mean_polarisation", "", "polarisation averaged over every step", 3}};
  }
  void reset(const salsa::MetricView&) override { sum_ = 0, steps_ = 0; }
  void step(const salsa::MetricView& world) override {  // 60 times per simulated second: keep it cheap
    if (const double p = polarisation(world); std::isfinite(p)) sum_ += p, ++steps_;
  }
  void observe(const salsa::MetricView& world, std::span<double> values) override { values[0] = polarisation(world); }
  void finish(const salsa::MetricView&, std::span<double> values) override {
    if (steps_ > 0) values[0] = sum_ / static_cast<double>(steps_);  // else no_value: an empty field
  }

 private:
  static double polarisation(const salsa::MetricView& world) {
    salsa::Vec2 sum;
    std::size_t moving = 0;
    for (salsa::Vec2 v : world.drone_velocities())
      if (!v.is_zero()) sum += v.with_length(1), ++moving;
    return moving > 0 ? sum.length() / static_cast<double>(moving) : salsa::no_value;
  }
  double sum_ = 0;
  std::size_t steps_ = 0;  // steps with a moving drone
};

}  // namespace

SALSA_METRIC(@CLASS@, "@NAME@", "@BRIEF@")
)~~";

const char* metric_test = R"~~(// @NAME@ on a stand-in world whose drone velocities the test sets.
@PREAMBLE@
namespace fake {
struct World final : salsa::MetricView {
  std::vector<salsa::Vec2> positions, velocities;
  salsa::DroneProperties properties;
  salsa::Rect bounds() const override { return {{0, 0}, {100, 100}}; }
  double time() const override { return 0; }
  double dt() const override { return 1.0 / 60; }
  std::span<const salsa::Vec2> drone_positions() const override { return positions; }
  std::span<const salsa::Vec2> drone_velocities() const override { return velocities; }
  bool is_free(salsa::Vec2, double) const override { return true; }
  std::optional<salsa::ObstacleHit> ray_cast(salsa::Vec2, salsa::Vec2) const override { return std::nullopt; }
  std::span<const salsa::TargetState> targets() const override { return {}; }
  std::size_t targets_found() const override { return 0; }
  std::uint64_t collisions() const override { return 0; }
  const salsa::DroneProperties& drone() const override { return properties; }
};
}  // namespace fake

int main() {
  @CLASS@ metric;
  CHECK(metric.step_columns().size() == 1 && metric.final_columns().size() == 1);
  fake::World world;
  world.positions = {{0, 0}, {1, 1}, {2, 2}};
  world.velocities = {{0, 0}, {0, 0}, {0, 0}};
  metric.reset(world);
  metric.step(world);  // nobody moves: no polarisation, not counted
  double row[1] = {salsa::no_value};
  metric.observe(world, row);
  CHECK(std::isnan(row[0]));
  world.velocities = {{3, 0}, {10, 0}, {0.5, 0}};  // all east, whatever the speed
  metric.step(world);
  metric.observe(world, row);
  CHECK(std::abs(row[0] - 1) < 1e-12);
  world.velocities = {{3, 0}, {-3, 0}, {0, 0}};  // two opposite, one at rest
  metric.step(world);
  metric.observe(world, row);
  CHECK(std::abs(row[0]) < 1e-12);
  double outcome[1] = {salsa::no_value};
  metric.finish(world, outcome);
  CHECK(std::abs(outcome[0] - 0.5) < 1e-12);  // (1 + 0) / 2 steps with moving drones
  std::puts("@NAME@_test: ok");
  return 0;
}
)~~";

struct Kind {
  std::string_view name;     // on the command line
  std::string_view words;    // in comments
  std::string_view brief;
  const char* source;
  const char* test;
};

const std::array<Kind, 5> kinds{{
    {"behavior", "behavior", "Own heading drifting at random, avoids drones and obstacles", behavior_source, behavior_test},
    {"target", "target kind", "Small targets, seen within part of the camera range", target_source, target_test},
    {"map", "map", "Square with a grid of pillars, clear around the centre", map_source, map_test},
    {"contact-handler", "contact handler", "A target is found after several sightings", contact_source, contact_test},
    {"metric", "metric", "Polarisation of the swarm: 1 when all fly the same way", metric_source, metric_test},
}};

std::string replace_all(std::string text, std::string_view from, std::string_view to) {
  for (std::size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size()))
    text.replace(at, from.size(), to);
  return text;
}

/// my_great_behavior -> MyGreatBehavior
std::string class_name(const std::string& name) {
  std::string out;
  bool upper = true;
  for (char c : name) {
    if (c == '_') {
      upper = true;
      continue;
    }
    out += upper ? static_cast<char>(std::toupper(static_cast<unsigned char>(c))) : c;
    upper = false;
  }
  return out;
}

/// Empty when `name` may name the plugin (a C identifier the loader accepts and CMake does not reserve).
std::string name_problem(const std::string& name) {
  auto letter = [](char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z'); };
  bool identifier = !name.empty() && (letter(name[0]) || name[0] == '_');
  for (char c : name) identifier = identifier && (letter(c) || (c >= '0' && c <= '9') || c == '_');
  const std::string shown = name.size() > 70 ? name.substr(0, 70) + "..." : name;
  if (!identifier) return "\"" + shown + "\" is not a C identifier (allowed: letters, digits and '_', starting with a letter)";
  if (!letter(name[0])) return "\"" + shown + "\" starts with '_' (allowed: a letter first, as plugin names do)";
  if (name.size() > 64) return "\"" + shown + "\" is " + std::to_string(name.size()) + " characters long (allowed: 1 to 64)";
  for (const char* reserved : {"all", "clean", "help", "install", "package", "package_source", "test", "edit_cache",
                               "rebuild_cache", "list_install_components", "preinstall"})
    if (name == reserved) return "\"" + name + "\" is a name CMake reserves for its own targets";
  return {};
}

/// How to point CMake at this salsa, for the "next" lines.
std::string prefix_hint() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) return "";
  const fs::path prefix = exe.parent_path().parent_path();
  if (!fs::exists(prefix / SALSA_LIBDIR / "cmake/salsa/salsaConfig.cmake", ec))
    return " -DCMAKE_PREFIX_PATH=<where salsa is installed>";  // a build tree: install it first
  if (prefix == "/usr" || prefix == "/usr/local") return "";
  return " -DCMAKE_PREFIX_PATH=" + prefix.string();
}

void write_file(const fs::path& file, const std::string& text) {
  std::ofstream out(file, std::ios::binary);
  out << text;
  out.close();
  if (!out) throw std::runtime_error("new-plugin: cannot write " + file.string());
}

}  // namespace

int cmd_new_plugin(int argc, char** argv) {
  po::options_description o("new-plugin options");
  o.add_options()("help,h", "show this help")("dir", po::value<std::string>()->default_value("."),
                                              "create the folder NAME/ in this folder");
  po::options_description hidden;
  hidden.add_options()("args", po::value<std::vector<std::string>>(), "");
  po::options_description all;
  all.add(o).add(hidden);
  po::positional_options_description pos;
  pos.add("args", -1);
  po::variables_map vm;
  po::store(po::command_line_parser(argc, argv).options(all).positional(pos).run(), vm);
  po::notify(vm);
  if (vm.count("help")) {
    std::cout << "usage: salsa new-plugin behavior|target|map|contact-handler|metric NAME [--dir D]\n\n"
                 "Writes D/NAME/: NAME.cpp (a small working plugin of that kind), NAME_test.cpp and a\n"
                 "CMakeLists.txt that builds it against the installed salsa, tests it (ctest) and installs it\n"
                 "into ~/.local/share/salsa/plugins (cmake --install).\n\n"
              << o;
    return 0;
  }
  const auto args = vm.count("args") ? vm["args"].as<std::vector<std::string>>() : std::vector<std::string>{};
  const std::string allowed_kinds = "behavior, target, map, contact-handler, metric";
  if (args.empty()) throw salsa::InputError("new-plugin: missing KIND (allowed: " + allowed_kinds + ")");
  const Kind* kind = nullptr;
  for (const Kind& k : kinds)
    if (k.name == args[0]) kind = &k;
  if (!kind) throw salsa::InputError("new-plugin: unknown kind '" + args[0] + "' (allowed: " + allowed_kinds + ")");
  if (args.size() < 2) throw salsa::InputError("new-plugin: missing NAME (a C identifier, e.g. my_" + std::string(args[0] == "contact-handler" ? "handler" : args[0]) + ")");
  if (args.size() > 2) throw salsa::InputError("new-plugin: one NAME at a time (got '" + args[2] + "' too)");
  const std::string name = args[1];
  if (const std::string why = name_problem(name); !why.empty()) throw salsa::InputError("new-plugin: NAME: " + why);

  const fs::path parent = vm["dir"].as<std::string>();
  const fs::path folder = parent / name;
  std::error_code ec;
  if (fs::exists(fs::symlink_status(folder, ec)))
    throw salsa::InputError("new-plugin: " + folder.string() + " already exists (allowed: a folder that does not exist yet)");
  fs::create_directories(parent, ec);
  if (ec || !fs::create_directory(folder, ec) || ec)
    throw salsa::InputError("new-plugin: cannot create " + folder.string() + (ec ? " (" + ec.message() + ")" : ""));

  std::string version = salsa::salsa_version();  // major.minor: the package's versions that build it
  version = version.substr(0, version.find('.', version.find('.') + 1));
  auto fill = [&](std::string text) {
    text = replace_all(std::move(text), "@PREAMBLE@", test_preamble);
    text = replace_all(std::move(text), "@NAME@", name);
    text = replace_all(std::move(text), "@CLASS@", class_name(name));
    text = replace_all(std::move(text), "@KIND@", kind->words);
    text = replace_all(std::move(text), "@BRIEF@", kind->brief);
    return replace_all(std::move(text), "@VERSION@", version);
  };
  write_file(folder / (name + ".cpp"), fill(kind->source));
  write_file(folder / (name + "_test.cpp"), fill(kind->test));
  write_file(folder / "CMakeLists.txt", fill(cmake_template));
  write_file(folder / ".gitignore", "build/\n");

  const std::string f = folder.string();
  std::cout << "wrote " << f << "/: " << name << ".cpp (the " << kind->words << "), " << name << "_test.cpp, CMakeLists.txt\n"
            << "next:\n"
            << "  cmake -S " << f << " -B " << f << "/build" << prefix_hint() << "\n"
            << "  cmake --build " << f << "/build && ctest --test-dir " << f << "/build\n"
            << "  cmake --install " << f << "/build    # into ~/.local/share/salsa/plugins\n"
            << "  salsa describe " << name << "\n";
  return 0;
}
