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
#   ctest --test-dir build              # @NAME@_test (a short real simulation with the plugin), @NAME@_loads
#   cmake --install build               # into ~/.local/share/salsa/plugins: salsa and salsa-gui find it
# To share it, hand over this folder: it builds against any salsa @VERSION@.x.
cmake_minimum_required(VERSION 3.25)
project(@NAME@ VERSION 0.1.0 LANGUAGES CXX)
find_package(salsa @VERSION@ REQUIRED)
enable_testing()

salsa_add_plugin(@NAME@ @NAME@.cpp VERSION ${PROJECT_VERSION} AUTHOR "" BRIEF "@BRIEF@")
salsa_add_plugin_test(@NAME@_test @NAME@_test.cpp PLUGIN @NAME@)
)~~";

// Every test runs the real core (as `salsa run` does) on the plugin file the build made (SALSA_PLUGIN_FILE)
// plus salsa's built-in plugins.
const char* test_preamble = R"~~(#include <salsa/fixture.hpp>

#include <cstdio>

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
  // Each parameter once: name, default, min, max, unit, meaning (the GUI's sliders, the checks of a
  // test's JSON, sweeps). In decide() it is a plain double holding the current value.
  salsa::Param turn_rate{this, "turn_rate", 0.5, 0.0, 10.0, "rad/s", "how fast the heading drifts at random"};
  salsa::Param separation{this, "separation", 10.0, 0.0, 200.0, "m", "fly away from drones closer than this"};
  salsa::Param avoidance{this, "avoidance", 2.0, 0.0, 10.0, "", "weight of obstacle avoidance"};

 public:
  salsa::Vec2 decide(const salsa::Perception& me, @CLASS@Memory& h, salsa::Rng& rng) override {
    if (!h.chosen) h = {rng.angle(), true};
    h.angle += rng.uniform(-1.0, 1.0) * turn_rate * me.dt;
    // Steering terms, each at most max force; the core adds the sum to the velocity.
    return salsa::steer_towards(me, salsa::Vec2::polar(me.max_speed, h.angle)) +
           salsa::avoid_drones(me, separation) + avoidance * salsa::avoid_obstacles(me);
  }
  // decide() never looks at the targets in view: the core need not gather them.
  salsa::Senses senses() const override { return {.neighbours = true, .targets = false}; }
};

}  // namespace

SALSA_BEHAVIOR(@CLASS@, "@NAME@", "@BRIEF@")
)~~";

const char* behavior_test = R"~~(// @NAME@ in a real simulation: 8 drones for 30 s in a 300 m room. They stay inside and keep flying
// (drones that only drift on their start velocity fly about 120 m). Parameters as in a test file:
// "behavior": {"name": "@NAME@", "params": {"turn_rate": 2}}.
@PREAMBLE@
int main() {
  salsa::testing::Simulation sim(R"({"behavior": "@NAME@", "drones": 8, "seed": 1,
                                     "map": {"name": "empty", "params": {"size": 300}}})",
                                 {SALSA_PLUGIN_FILE});
  sim.run(30);
  for (salsa::Vec2 p : sim.positions()) CHECK(sim.world().bounds().contains(p));
  const double flown = sim.metric("mean_distance");  // m per drone: salsa's distance_flown metric
  std::printf("mean distance flown in 30 s: %.0f m\n", flown);
  CHECK(flown > 150);  // at most 10 m/s: 300 m
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
  // Each parameter once: name, default, min, max, unit, meaning; it reads as a double.
  salsa::Param radius_{this, "radius", 2.0, 0.1, 100.0, "m", "radius of a target"};
  salsa::Param visibility{this, "visibility", 0.5, 0.0, 1.0, "", "fraction of the camera range within which a target is seen"};

 public:
  double radius() const override { return radius_; }
  bool in_view(double distance, double camera_range) const override {
    return distance < visibility * camera_range + radius_;
  }
};

}  // namespace

SALSA_TARGET(@CLASS@, "@NAME@", "@BRIEF@")
)~~";

const char* target_test = R"~~(// @NAME@ targets in a real simulation: drones of salsa's built-in random_walk find some in 60 s, and
// more when they see as far as their cameras reach (visibility 1), on the same flight (same seed).
@PREAMBLE@
int main() {
  salsa::testing::Simulation sim(R"({"behavior": "random_walk", "drones": 10, "seed": 1,
                                     "map": {"name": "empty", "params": {"size": 400}},
                                     "targets": {"kind": "@NAME@", "count": 100}})",
                                 {SALSA_PLUGIN_FILE});
  salsa::testing::Simulation far(R"({"behavior": "random_walk", "drones": 10, "seed": 1,
                                     "map": {"name": "empty", "params": {"size": 400}},
                                     "targets": {"kind": "@NAME@", "count": 100, "params": {"visibility": 1}}})",
                                 {SALSA_PLUGIN_FILE});
  CHECK(sim.targets() == 100);
  sim.run(60);
  far.run(60);
  std::printf("found in 60 s: %zu of 100, %zu with visibility 1\n", sim.targets_found(), far.targets_found());
  CHECK(sim.targets_found() > 0);
  CHECK(far.targets_found() > sim.targets_found());
  std::puts("@NAME@_test: ok");
  return 0;
}
)~~";

// ---- map ----

const char* map_source = R"~~(// @NAME@: a salsa map. A square closed by walls with a grid of square pillars, none near the centre,
// where the drones start. generate() gets the test's parameters (the Param members) and an rng
// (unused here: the same parameters always give the same map); bad parameters throw salsa::MapError
// with one line.
#include <cmath>
#include <string>

#include <salsa/sdk.hpp>

namespace {

class @CLASS@ final : public salsa::MapGenerator {
  // Each parameter once: name, default, min, max, unit, meaning; it reads as a double.
  salsa::Param size{this, "size", 300.0, 20.0, 1e5, "m", "side of the square"};
  salsa::Param spacing{this, "spacing", 50.0, 5.0, 1e4, "m", "distance between pillar centres"};
  salsa::Param pillar{this, "pillar", 8.0, 0.5, 1e3, "m", "side of a pillar"};
  salsa::Param clear{this, "clear", 40.0, 0.0, 1e4, "m", "no pillar within this distance of the centre"};

 public:
  salsa::MapData generate(const std::string& /*file*/, salsa::Rng& /*rng*/) const override {
    const double half = pillar / 2;
    if (pillar >= spacing) throw salsa::MapError("pillar: must be smaller than spacing (" + salsa::Parameter::format(spacing) + " m)");
    if (std::pow(size / spacing, 2) > 1e6) throw salsa::MapError("spacing: more than 1,000,000 pillars (allowed: a larger spacing)");
    salsa::MapData map;
    map.bounds = {{0, 0}, {size, size}};
    map.spawn = map.bounds.centre();
    for (double x = spacing; x + half < size; x += spacing)
      for (double y = spacing; y + half < size; y += spacing)
        if (salsa::distance({x, y}, map.spawn) > clear + half * std::sqrt(2.0))
          map.obstacles.push_back({{x - half, y - half}, {x + half, y - half}, {x + half, y + half}, {x - half, y + half}});  // CCW
    return map;
  }
};

}  // namespace

SALSA_MAP(@CLASS@, "@NAME@", "@BRIEF@")
)~~";

const char* map_test = R"~~(// @NAME@ in a real simulation: the bounds its size gives, pillars on the grid and none at the centre,
// drones kept inside for 30 s; parameters it refuses fail the run with its message.
#include <cstring>
#include <stdexcept>

@PREAMBLE@
int main() {
  salsa::testing::Simulation sim(R"({"behavior": "random_walk", "drones": 8, "seed": 1,
                                     "map": {"name": "@NAME@", "params": {"size": 500}}})",
                                 {SALSA_PLUGIN_FILE});
  const salsa::Rect bounds = sim.world().bounds();
  CHECK((bounds == salsa::Rect{{0, 0}, {500, 500}}));
  CHECK(!sim.world().is_free({50, 50}, 0));          // a pillar (spacing 50 m)
  CHECK(sim.world().is_free(bounds.centre(), 40));   // clear around the centre
  sim.run(30);
  for (salsa::Vec2 p : sim.positions()) CHECK(bounds.contains(p));
  bool refused = false;
  try {
    salsa::testing::Simulation wide(R"({"behavior": "random_walk", "map": {"name": "@NAME@", "params": {"pillar": 60}}})",
                                    {SALSA_PLUGIN_FILE});
  } catch (const std::runtime_error& e) {
    refused = std::strstr(e.what(), "pillar: must be smaller than spacing") != nullptr;
  }
  CHECK(refused);
  std::puts("@NAME@_test: ok");
  return 0;
}
)~~";

// ---- contact handler ----

const char* contact_source = R"~~(// @NAME@: a salsa contact handler. A target counts as found only once `confirmations` different
// drones have had it in view (one drone's sighting may be a false detection). It replaces salsa's
// detect_targets (found at first sight) in a test that lists it: "contact_handlers": ["@NAME@"].
// Handlers are called serially, in the order the test lists them, with every event of a step.
#include <algorithm>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include <salsa/sdk.hpp>

namespace {

class @CLASS@ final : public salsa::ContactHandler {
  // Name, default, min, max, unit, meaning, step (1: a whole number); it reads as a double.
  salsa::Param confirmations{this, "confirmations", 2, 1, 100, "", "different drones that must see a target before it counts as found", 1};

 public:
  void on_contact(const salsa::ContactEvent& event, salsa::ContactActions& actions) override {
    if (event.kind != salsa::ContactKind::target_in_view || actions.is_found(event.other)) return;
    std::vector<std::uint32_t>& drones = seen_by_[event.other];
    if (std::find(drones.begin(), drones.end(), event.drone) == drones.end()) drones.push_back(event.drone);
    if (static_cast<double>(drones.size()) >= confirmations) actions.mark_found(event.other, event.drone);
  }

 private:
  std::unordered_map<std::uint32_t, std::vector<std::uint32_t>> seen_by_;  // target id -> drones that saw it
};

}  // namespace

SALSA_CONTACT_HANDLER(@CLASS@, "@NAME@", "@BRIEF@")
)~~";

const char* contact_test = R"~~(// @NAME@ in a real simulation: the same flight (salsa's random_walk, same seed) finds targets at first
// sight with salsa's detect_targets, and fewer, but some, when @NAME@ asks for 2 drones' sightings.
#include <string>

@PREAMBLE@
int main() {
  const std::string flight = R"("behavior": "random_walk", "drones": 10, "seed": 1,
                                "map": {"name": "empty", "params": {"size": 400}},
                                "targets": {"kind": "tree", "count": 200})";
  salsa::testing::Simulation first_sight("{" + flight + R"(, "contact_handlers": ["detect_targets"]})", {SALSA_PLUGIN_FILE});
  salsa::testing::Simulation confirmed("{" + flight + R"(, "contact_handlers": ["@NAME@"]})", {SALSA_PLUGIN_FILE});
  first_sight.run(30);
  confirmed.run(30);
  std::printf("found in 30 s: %zu at first sight, %zu confirmed\n", first_sight.targets_found(), confirmed.targets_found());
  CHECK(confirmed.targets_found() > 0);
  CHECK(confirmed.targets_found() < first_sight.targets_found());
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
  // Name, default, min, max, unit, meaning; it reads as a double.
  salsa::Param min_speed{this, "min_speed", 0.1, 0.0, 100.0, "m/s", "drones slower than this count as at rest"};

 public:
  std::vector<salsa::Column> step_columns() const override {  // name, unit, meaning, decimals
    return {{"polarisation", "", "length of the moving drones' mean unit velocity (1: all fly the same way)", 3}};
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
  double polarisation(const salsa::MetricView& world) const {
    salsa::Vec2 sum;
    std::size_t moving = 0;
    for (salsa::Vec2 v : world.drone_velocities())
      if (!v.is_zero() && v.length() > min_speed) sum += v.with_length(1), ++moving;
    return moving > 0 ? sum.length() / static_cast<double>(moving) : salsa::no_value;
  }
  double sum_ = 0;
  std::size_t steps_ = 0;  // steps with a moving drone
};

}  // namespace

SALSA_METRIC(@CLASS@, "@NAME@", "@BRIEF@")
)~~";

const char* metric_test = R"~~(// @NAME@ in a real simulation: after 30 s, drones of salsa's built-in flocking, weighted towards
// matching their neighbours' velocity, fly the same way (polarisation near 1); random_walk drones do not.
@PREAMBLE@
int main() {
  salsa::testing::Simulation flock(R"({"behavior": {"name": "flocking", "params": {"alignment_weight": 5}},
                                       "drones": 12, "seed": 1, "metrics": ["@NAME@"]})",
                                   {SALSA_PLUGIN_FILE});
  salsa::testing::Simulation walk(R"({"behavior": "random_walk", "drones": 12, "seed": 1, "metrics": ["@NAME@"]})",
                                  {SALSA_PLUGIN_FILE});
  flock.run(30);
  walk.run(30);
  const double aligned = flock.metric("polarisation"), random = walk.metric("polarisation");
  std::printf("polarisation after 30 s: flocking %.3f, random_walk %.3f\n", aligned, random);
  CHECK(aligned > 0.9 && aligned <= 1 + 1e-9);
  CHECK(random >= 0 && random < 0.6);
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
    {"contact-handler", "contact handler", "A target is found once several drones have seen it", contact_source, contact_test},
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

/// Names a plugin may not take although they are identifiers: C and C++ keywords (with the
/// alternative tokens) and standard names that are macros or would read as the language's own.
constexpr std::string_view language_names[] = {
    "alignas", "alignof", "and", "and_eq", "asm", "assert", "atomic_cancel", "atomic_commit", "atomic_noexcept", "auto",
    "bitand", "bitor", "bool", "break", "case", "catch", "char", "char8_t", "char16_t", "char32_t", "class", "co_await",
    "co_return", "co_yield", "compl", "complex", "concept", "const", "const_cast", "consteval", "constexpr", "constinit",
    "continue", "decltype", "default", "defined", "delete", "do", "double", "dynamic_cast", "else", "enum", "errno",
    "explicit", "export", "extern", "false", "final", "float", "for", "fortran", "friend", "goto", "if", "imaginary",
    "import", "inline", "int", "long", "main", "module", "mutable", "namespace", "new", "noexcept", "noreturn", "not",
    "not_eq", "nullptr", "offsetof", "operator", "or", "or_eq", "override", "private", "protected", "public", "reflexpr",
    "register", "reinterpret_cast", "requires", "restrict", "return", "salsa", "setjmp", "short", "signed", "sizeof",
    "static", "static_assert", "static_cast", "std", "stderr", "stdin", "stdout", "struct", "switch", "synchronized",
    "template", "this", "thread_local", "throw", "true", "try", "typedef", "typeid", "typename", "union", "unsigned",
    "using", "va_arg", "va_copy", "va_end", "va_start", "virtual", "void", "volatile", "wchar_t", "while", "xor", "xor_eq"};

/// Empty when `name` may name the plugin: it becomes the plugin's name, its files, CMake targets, and
/// (as MyName) a C++ class, so it must be a plain lowercase identifier that no compiler, standard
/// header or CMake reads as its own.
std::string name_problem(const std::string& name) {
  const std::string allowed =
      " (allowed: a lowercase letter, then lowercase letters, digits and single '_', 1 to 64 characters, not a C or C++ "
      "keyword or standard name; e.g. my_behavior)";
  auto letter = [](char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z'); };
  bool identifier = !name.empty() && (letter(name[0]) || name[0] == '_');
  for (char c : name) identifier = identifier && (letter(c) || (c >= '0' && c <= '9') || c == '_');
  std::string shown = name.size() > 70 ? name.substr(0, 70) + "..." : name;
  for (char& c : shown)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = '?';  // one line, whatever the input
  const std::string quoted = "\"" + shown + "\"";
  if (!identifier) return quoted + " is not a C identifier" + allowed;
  if (!letter(name[0])) return quoted + " starts with '_' (C and C++ reserve such names)" + allowed;
  if (name.size() > 64) return quoted + " is " + std::to_string(name.size()) + " characters long" + allowed;
  if (std::any_of(name.begin(), name.end(), [](char c) { return c >= 'A' && c <= 'Z'; }))
    return quoted + " has capital letters (C and C++ use such names for macros: NULL, EOF, NDEBUG...)" + allowed;
  if (name.find("__") != std::string::npos) return quoted + " holds '__' (C and C++ reserve such names)" + allowed;
  if (name.back() == '_') return quoted + " ends with '_'" + allowed;
  if (std::find(std::begin(language_names), std::end(language_names), name) != std::end(language_names))
    return quoted + " is a C or C++ keyword or standard name" + allowed;
  for (const char* reserved : {"all", "clean", "help", "install", "package", "package_source", "test", "edit_cache",
                               "rebuild_cache", "list_install_components", "preinstall"})
    if (name == reserved) return quoted + " is a name CMake reserves for its own targets" + allowed;
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
                 "Writes D/NAME/: NAME.cpp (a small working plugin of that kind), NAME_test.cpp (a short real\n"
                 "simulation with it: salsa/fixture.hpp) and a CMakeLists.txt that builds it against the\n"
                 "installed salsa, tests it (ctest) and installs it into ~/.local/share/salsa/plugins\n"
                 "(cmake --install).\n\n"
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
