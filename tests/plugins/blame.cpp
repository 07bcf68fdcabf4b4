// One plugin of every kind that throws on request from a chosen call site, each message on three
// lines: a failure must name the plugin that threw (kind, name, file), the test and the time, on one
// line, never another plugin (docs/reliability.md, "every failure names its plugin").
#include <stdexcept>
#include <string>

#include <salsa/sdk.hpp>

namespace {

constexpr const char* three_lines = "first line\nsecond line\nthird line";

/// Flies straight; configure() refuses `gain` above `limit` (a combination, not a range); decide throws
/// for every drone from id `throw_from` on (in parallel: the lowest id's failure must be the one told);
/// inspect throws on request.
class BlameBehavior final : public salsa::Behavior {
 public:
  static salsa::Parameters declare() {
    return {{"gain", 1, 0, 10, "", "any value up to limit"},
            {"limit", 10, 0, 10, "", "the largest gain configure() accepts"},
            {"throw_from", -1, -1, 1e6, "", "decide throws for drones with this id and above (-1: never)", 1},
            {"inspect_throws", 0, 0, 1, "", "1: inspect throws", 1}};
  }
  std::string inspect(std::uint32_t) const override {
    if (param("inspect_throws") == 1) throw std::runtime_error(three_lines);
    return "fine";
  }
  salsa::Vec2 decide(const salsa::Perception& me, salsa::Rng&) override {
    if (param("throw_from") >= 0 && me.id >= param("throw_from"))
      throw std::runtime_error("drone " + std::to_string(me.id) + " threw");
    return salsa::Vec2{me.max_speed, 0} - me.velocity;
  }

 protected:
  void configure() override {
    if (param("gain") > param("limit")) throw std::invalid_argument("gain above limit\n(refused by configure)");
  }
};

/// mode 1: in_view throws; 2: place throws; 3: view_range throws; 4: radius throws.
class BlameTarget final : public salsa::TargetKind {
 public:
  static salsa::Parameters declare() { return {{"mode", 0, 0, 4, "", "call site that throws (0: none)", 1}}; }
  double radius() const override {
    if (mode() == 4) throw std::runtime_error(three_lines);
    return 1;
  }
  bool in_view(double distance, double camera_range) const override {
    if (mode() == 1) throw std::runtime_error(three_lines);
    return distance < camera_range;
  }
  double view_range(double camera_range) const override {
    if (mode() == 3) throw std::runtime_error(three_lines);
    return camera_range;
  }
  std::vector<salsa::Vec2> place(std::size_t count, const salsa::WorldView& world, salsa::Rng& rng) const override {
    if (mode() == 2) throw std::runtime_error(three_lines);
    return TargetKind::place(count, world, rng);
  }

 private:
  int mode() const { return static_cast<int>(param("mode")); }
};

/// mode 1: on_contact throws; 2: reset throws; 3: reset throws from the second call on (a live change).
class BlameHandler final : public salsa::ContactHandler {
 public:
  static salsa::Parameters declare() { return {{"mode", 0, 0, 3, "", "call site that throws (0: none)", 1}}; }
  void reset(const salsa::WorldView&) override {
    if (param("mode") == 2 || (param("mode") == 3 && resets_ > 0)) throw std::runtime_error(three_lines);
    ++resets_;
  }
  void on_contact(const salsa::ContactEvent&, salsa::ContactActions&) override {
    if (param("mode") == 1) throw std::runtime_error(three_lines);
  }

 private:
  int resets_ = 0;
};

/// mode 1: step_columns throws; 2: reset throws; 3: observe throws; 4: finish throws.
class BlameMetric final : public salsa::Metric {
 public:
  static salsa::Parameters declare() { return {{"mode", 0, 0, 4, "", "call site that throws (0: none)", 1}}; }
  std::vector<salsa::Column> step_columns() const override {
    if (param("mode") == 1) throw std::runtime_error(three_lines);
    return {{"blame_value", "", "always 1", 0}};
  }
  void reset(const salsa::MetricView&) override {
    if (param("mode") == 2) throw std::runtime_error(three_lines);
  }
  void observe(const salsa::MetricView&, std::span<double> values) override {
    if (param("mode") == 3) throw std::runtime_error(three_lines);
    values[0] = 1;
  }
  void finish(const salsa::MetricView&, std::span<double>) override {
    if (param("mode") == 4) throw std::runtime_error(three_lines);
  }
};

/// generate() throws a MapError (as for bad input) or, with mode 2, a std::runtime_error.
class BlameMap final : public salsa::MapGenerator {
 public:
  static salsa::Parameters declare() { return {{"mode", 1, 1, 2, "", "1: MapError; 2: std::runtime_error", 1}}; }
  salsa::MapData generate(const std::string&, salsa::Rng&) const override {
    if (param("mode") == 1) throw salsa::MapError(three_lines);
    throw std::runtime_error(three_lines);
  }
};

}  // namespace

SALSA_BEHAVIOR(BlameBehavior, "blame_behavior", "Flies straight; configure() refuses gain above limit")
SALSA_TARGET(BlameTarget, "blame_target", "Throws from a chosen call site")
SALSA_CONTACT_HANDLER(BlameHandler, "blame_handler", "Throws from a chosen call site")
SALSA_METRIC(BlameMetric, "blame_metric", "Throws from a chosen call site")
SALSA_MAP(BlameMap, "blame_map", "generate() throws a three-line message")
