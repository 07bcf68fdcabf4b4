// Reading a tune file: strict JSON, every field checked against what the base test and the plugins
// declare, before anything runs.
#include "salsa/core/experiments/tune_file.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <variant>

#include "salsa/core/experiments/queue.hpp"
#include "salsa/core/experiments/test_models.hpp"
#include "salsa/core/model/drone_config.hpp"
#include "test_reader.hpp"
#include "salsa/core/experiments/metric_list.hpp"
#include "strict_json.hpp"
#include "format.hpp"

namespace salsa {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

namespace {

std::string show(const json& v) { return strict_json::shown(v); }

/// One-line refusals: "<file>: <field>: <message>".
struct Refuse {
  std::string file;
  [[noreturn]] void operator()(const std::string& field, const std::string& message) const {
    throw InputError(file + ": " + field + ": " + strict_json::printable(message, 1000));
  }
  void only_keys(const json& obj, const std::string& field, std::initializer_list<const char*> allowed) const {
    std::string list;
    for (const char* a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
    if (!obj.is_object()) (*this)(field, show(obj) + " must be an object with: " + list);
    for (const auto& item : obj.items())
      if (std::none_of(allowed.begin(), allowed.end(), [&](const char* a) { return item.key() == a; }))
        (*this)((field.empty() ? "" : field + ".") + strict_json::printable(item.key()), "unknown key (allowed: " + list + ")");  // a key is user text
  }
  double number(const json& v, const std::string& field, double lo, double hi) const {
    const std::string range = "[" + format::number(lo) + ", " + format::number(hi) + "]";
    if (!v.is_number()) (*this)(field, show(v) + " is not a number (allowed: " + range + ")");
    const double x = v.get<double>();
    if (!(x >= lo && x <= hi)) (*this)(field, show(v) + " is out of range (allowed: " + range + ")");
    return x;
  }
  std::uint64_t whole(const json& v, const std::string& field, double lo, double hi) const {
    const std::string range = "whole number in [" + format::number(lo) + ", " + format::number(hi) + "]";
    if (!v.is_number() || v.get<double>() != std::floor(v.get<double>()))
      (*this)(field, show(v) + " is not a whole number (allowed: " + range + ")");
    if (!(v.get<double>() >= lo && v.get<double>() <= hi) || detail::Reader::past(v, hi)) (*this)(field, show(v) + " is out of range (allowed: " + range + ")");
    return v.is_number_unsigned() ? v.get<std::uint64_t>() : static_cast<std::uint64_t>(v.get<double>());
  }
  std::string string(const json& v, const std::string& field, const std::string& allowed) const {
    if (!v.is_string() || v.get<std::string>().empty()) (*this)(field, show(v) + " must be a non-empty string (allowed: " + allowed + ")");
    return v.get<std::string>();
  }
};

/// A tunable number of the test: its declaration and the base test's value.
struct Declared {
  Parameter spec;
  double value = 0;
};

std::string names_of(const Parameters& schema) {
  std::string out;
  for (const Parameter& p : schema) out += (out.empty() ? "" : ", ") + p.name;
  return out.empty() ? "none" : out;
}

/// What `key` names in `test`, or why it names no tunable number. The keys are sweep.set's (and
/// timed changes'), plus map.params.<p>, targets.count and targets.params.<p>.
std::variant<Declared, std::string> declared(const TestSpec& test, const std::string& key, const PluginHost& host) {
  auto in_schema = [&](const Parameters& schema, std::string_view name, const ParameterValues& values,
                       const std::string& owner) -> std::variant<Declared, std::string> {
    for (const Parameter& p : schema)
      if (p.name == name) return Declared{p, values.has(p.name) ? values.get(p.name) : p.value};
    return "unknown parameter of " + owner + " (declared: " + names_of(schema) + ")";
  };
  std::string_view rest = key;
  const GroupSpec* group = test.groups.size() == 1 ? &test.groups[0] : nullptr;
  if (rest.starts_with("groups.")) {
    rest.remove_prefix(7);
    const std::string name(rest.substr(0, rest.find('.')));
    const int g = test.group_index(name);
    if (g < 0) return "unknown group '" + name + "'";
    group = &test.groups[static_cast<std::size_t>(g)];
    rest.remove_prefix(std::min(rest.size(), name.size() + 1));
  }
  const bool group_key = rest == "drones" || rest.starts_with("behavior.params.") || rest.starts_with("drone.");
  if (group_key && !group) return "the test has " + std::to_string(test.groups.size()) + " groups: say whose, groups.<name>." + std::string(rest);
  if (rest.starts_with("behavior.params."))
    return in_schema(host.behavior(group->behavior.name).factory.parameters, rest.substr(16), group->behavior.params,
                     "behavior '" + group->behavior.name + "'");
  if (rest == "drones") return Declared{{"drones", 0, 1, 1e6, "", "", 1}, static_cast<double>(group->drones)};
  if (rest.starts_with("drone.")) {
    const DroneProperty* p = drone_schema().find(rest.substr(6));
    if (!p) return "unknown drone property (allowed: " + drone_schema().names() + ")";
    return Declared{p->spec, p->get(group->drone)};
  }
  if (key != rest) return "unknown key (allowed: groups.<name>.drones, groups.<name>.drone.<property>, groups.<name>.behavior.params.<p>)";
  if (rest.starts_with("wind.field.params.")) {
    if (test.wind_field.name.empty()) return "the test has no wind field";
    return in_schema(host.wind(test.wind_field.name).factory.parameters, rest.substr(18), test.wind_field.params,
                     "wind '" + test.wind_field.name + "'");
  }
  if (const TestModel* m = model_of_key(rest)) {
    const ModelField* f = m->find(rest.substr(m->key.size() + 1));
    if (!f) return "unknown " + m->key + " key (allowed: " + m->key + "." + m->names() + (m->other_forms.empty() ? "" : ", " + m->other_forms) + ")";
    if (!m->changes_while_off && !m->in_use(test))
      return "the test has no \"" + m->key + "\" (allowed: " + m->key + ".<field> in a test with a \"" + m->key + "\" object)";
    return Declared{f->spec, f->get(test)};
  }
  if (rest.starts_with("map.params."))
    return in_schema(host.map(test.map.name).factory.parameters, rest.substr(11), test.map.params, "map '" + test.map.name + "'");
  if (rest == "targets.count") return Declared{{"count", 0, 0, 1e7, "", "", 1}, static_cast<double>(test.targets)};
  if (rest.starts_with("targets.params."))
    return in_schema(host.target_kind(test.target.name).factory.parameters, rest.substr(15), test.target.params,
                     "target kind '" + test.target.name + "'");
  return "not a number of the test that can be tuned (allowed: behavior.params.<p>, drones, drone.<property>, "
         "groups.<name>.<any of those>, comm.<field>, wind.<property>, wind.field.params.<p>, failures.<field>, "
         "map.params.<p>, targets.count, targets.params.<p>)";
}

/// The rule for a scale nobody chose: a range of positive numbers spanning a factor of 100 or more is
/// searched on a log scale (0.1 to 100 s: each decade as likely as the next), others linearly.
bool log_by_default(const Parameter& p) { return p.min > 0 && p.max / p.min >= 100 && !p.is_integer(); }

Objective read_objective(const json& v, const std::string& field, const Refuse& refuse, const DataColumns& columns, const TestSpec& base,
                         bool time_given) {
  refuse.only_keys(v, field, {"column", "goal", "at", "aggregate"});
  Objective o;
  if (!v.contains("column")) refuse(field + ".column", "missing (a column of outcome.csv or summary.csv, e.g. \"targets_found\")");
  o.column = refuse.string(v["column"], field + ".column", "a column of outcome.csv or summary.csv");
  if (v.contains("goal")) {
    const std::string goal = refuse.string(v["goal"], field + ".goal", "max, min");
    if (goal != "max" && goal != "min") refuse(field + ".goal", show(v["goal"]) + " is not a goal (allowed: max, min)");
    o.maximise = goal == "max";
  }
  if (v.contains("at")) {
    if (time_given && v["at"].is_number() && v["at"].get<double>() > base.time)
      refuse(field + ".at", show(v["at"]) + " is past the end of the test, --time " + format::number(base.time) + " (allowed: [0, " +
                                format::number(base.time) + "], or a longer --time)");
    o.at = refuse.number(v["at"], field + ".at", 0, base.time);
  }
  if (v.contains("aggregate")) {
    const json& a = v["aggregate"];
    if (a == "mean") o.aggregate = Objective::Aggregate::mean;
    else if (a == "median") o.aggregate = Objective::Aggregate::median;
    else if (a.is_object() && a.contains("quantile") && a.size() == 1) {
      o.aggregate = Objective::Aggregate::quantile;
      o.quantile = refuse.number(a["quantile"], field + ".aggregate.quantile", 0, 1);
    } else {
      refuse(field + ".aggregate", show(a) + " is not an aggregate (allowed: \"mean\", \"median\", {\"quantile\": q} with q in [0, 1])");
    }
  }
  auto has = [&](const std::vector<std::string>& list) { return std::find(list.begin(), list.end(), o.column) != list.end(); };
  auto listed = [](const std::vector<std::string>& list) {
    std::string out;
    for (const std::string& c : list) out += (out.empty() ? "" : ", ") + c;
    return out;
  };
  if (o.at) {
    if (!has(columns.summary))
      refuse(field + ".column", show(v["column"]) + " is not a column of summary.csv, which \"at\" reads (allowed: " + listed(columns.summary) + ")");
    o.from_summary = true;
  } else if (!has(columns.outcome)) {
    if (!has(columns.summary) || o.column == "time")
      refuse(field + ".column", show(v["column"]) + " is not a column of outcome.csv or summary.csv for this test (allowed: " +
                                    listed(columns.outcome) + "; or of summary.csv: " + listed(columns.summary) + ")");
    o.from_summary = true;
  }
  return o;
}

/// "a, b, c", the first 20 of `names` ("..., and 12 more" past them).
std::string first_names(const std::vector<std::string>& names) {
  std::string out;
  for (std::size_t i = 0; i < names.size() && i < 20; ++i) out += (i ? ", " : "") + names[i];
  if (names.size() > 20) out += ", and " + std::to_string(names.size() - 20) + " more";
  return out;
}

/// The tune file's "world": {"queue", "condition", "test"}, the test object the queue makes of that test
/// under that condition. `spec.world` says which, `spec.base_dir` becomes the queue's folder (its tests'
/// paths are relative to it) and `seed` the queue's seed.
json queue_world(const json& w, const Refuse& refuse, TuneSpec& spec, const PluginHost& host, std::optional<std::uint64_t>& seed) {
  refuse.only_keys(w, "world", {"queue", "condition", "test"});
  if (!w.contains("queue")) refuse("world.queue", "missing (a queue file's path, relative to the tune file)");
  const fs::path path = spec.base_dir / refuse.string(w["queue"], "world.queue", "a queue file's path, relative to the tune file");
  const std::string shown = strict_json::printable(path.string(), 200);
  QueueTests queue;
  try {
    queue = queue_tests(path, host);
  } catch (const InputError& e) {
    throw InputError(spec.source + ": world.queue: " + e.what());
  }
  std::string condition;
  if (w.contains("condition")) {
    condition = refuse.string(w["condition"], "world.condition", queue.conditions.empty() ? "none" : first_names(queue.conditions));
    if (queue.conditions.empty()) refuse("world.condition", show(w["condition"]) + ": " + shown + " has no conditions (allowed: leave it out)");
    if (std::find(queue.conditions.begin(), queue.conditions.end(), condition) == queue.conditions.end())
      refuse("world.condition", show(w["condition"]) + " is not a condition of " + shown + " (allowed: " + first_names(queue.conditions) + ")");
  } else if (queue.conditions.size() > 1) {
    refuse("world.condition", "missing: " + shown + " has " + std::to_string(queue.conditions.size()) + " conditions (allowed: " + first_names(queue.conditions) + ")");
  } else if (!queue.conditions.empty()) {
    condition = queue.conditions.front();
  }
  std::vector<const QueueTest*> tests;
  std::vector<std::string> names;
  for (const QueueTest& t : queue.tests)
    if (t.condition == condition) tests.push_back(&t), names.push_back(t.name);
  const std::string under = condition.empty() ? "" : " under condition " + condition;
  const QueueTest* chosen = tests.size() == 1 ? tests.front() : nullptr;
  if (w.contains("test")) {
    const std::string name = refuse.string(w["test"], "world.test", first_names(names));
    chosen = nullptr;
    for (const QueueTest* t : tests)
      if (t->name == name) chosen = t;
    if (!chosen) refuse("world.test", show(w["test"]) + " is not a test of " + shown + under + " (allowed: " + first_names(names) + ")");
  } else if (!chosen) {
    refuse("world.test", "missing: " + shown + " has " + std::to_string(tests.size()) + " tests" + under + " (allowed: " + first_names(names) + ")");
  }
  spec.world = shown + ": test " + chosen->name + (condition.empty() ? "" : ", condition " + condition);
  spec.base_dir = path.parent_path();
  seed = queue.seed;
  return json::parse(chosen->json);
}

}  // namespace

std::string Objective::name() const { return at ? column + "@" + format::number(*at) : column; }

std::string Objective::aggregate_name() const {
  switch (aggregate) {
    case Aggregate::mean: return "mean";
    case Aggregate::median: return "median";
    case Aggregate::quantile: return "quantile " + format::number(quantile);
  }
  return "";
}

double Objective::aggregate_of(std::vector<double> v) const {
  if (v.empty()) return std::nan("");
  if (aggregate == Aggregate::mean) {
    double sum = 0;
    for (const double x : v) sum += x;
    return sum / static_cast<double>(v.size());
  }
  std::sort(v.begin(), v.end());
  const double where = (aggregate == Aggregate::median ? 0.5 : quantile) * static_cast<double>(v.size() - 1);
  const auto below = static_cast<std::size_t>(std::floor(where));
  const std::size_t above = std::min(below + 1, v.size() - 1);
  return v[below] + (where - static_cast<double>(below)) * (v[above] - v[below]);
}

std::vector<TunableNumber> tunable_numbers(const TestSpec& test, const PluginHost& host) {
  std::vector<std::string> keys;
  for (const GroupSpec& g : test.groups) {
    const std::string prefix = test.groups.size() == 1 ? "" : "groups." + g.name + ".";
    for (const Parameter& p : host.behavior(g.behavior.name).factory.parameters) keys.push_back(prefix + "behavior.params." + p.name);
    keys.push_back(prefix + "drones");
    for (const DroneProperty& p : drone_schema()) keys.push_back(prefix + "drone." + p.spec.name);
  }
  for (const TestModel& m : test_models())  // a model in use, or one a change can start (failures, wind)
    if (m.in_use(test) || m.changes_while_off)
      for (const ModelField& f : m.fields) keys.push_back(m.key + "." + f.spec.name);
  if (!test.wind_field.name.empty())
    for (const Parameter& p : host.wind(test.wind_field.name).factory.parameters) keys.push_back("wind.field.params." + p.name);
  for (const Parameter& p : host.map(test.map.name).factory.parameters) keys.push_back("map.params." + p.name);
  keys.push_back("targets.count");
  for (const Parameter& p : host.target_kind(test.target.name).factory.parameters) keys.push_back("targets.params." + p.name);
  std::vector<TunableNumber> out;
  for (std::string& key : keys) {
    const auto found = declared(test, key, host);
    if (const auto* d = std::get_if<Declared>(&found))  // a flag (comm.line_of_sight) is no number to tune
      if (!(d->spec.is_integer() && d->spec.min == 0 && d->spec.max == 1)) out.push_back({std::move(key), d->spec, d->value, log_by_default(d->spec)});
  }
  return out;
}

const std::vector<std::string>& tune_algorithms() {
  static const std::vector<std::string> names{"random", "lhs", "grid", "cmaes", "xnes", "pso", "de", "nsga2", "bobyqa", "neldermead"};
  return names;
}

TuneSpec load_tune(const fs::path& file, const PluginHost& host, const TuneOverrides& overrides) {
  TuneSpec spec;
  spec.source = strict_json::printable(file.string(), 200);
  const Refuse refuse{spec.source};
  json j;
  try {
    j = strict_json::read_file<json>(file, "a tune file {\"test\", \"parameters\", \"objective\", \"algorithm\", \"budget\", ...}");
  } catch (const strict_json::Error& e) {
    throw InputError(e.what());
  }
  refuse.only_keys(j, "", {"test", "world", "parameters", "objective", "objectives", "algorithm", "population", "local", "seed", "budget",
                           "worlds", "validation", "racing"});

  // ---- The base test: an object, a test file beside the tune file, or a queue's test under one of its conditions.
  spec.base_dir = file.parent_path();
  if (j.contains("test") == j.contains("world"))
    refuse("test", j.contains("test") ? "given with \"world\" (allowed: one or the other)"
                                      : "missing (the test to tune: a test object, a test file's path, or \"world\": a queue's test under one of its conditions)");
  std::optional<std::uint64_t> queue_seed;
  json test = j.contains("world") ? queue_world(j["world"], refuse, spec, host, queue_seed) : j["test"];
  const std::string test_field = j.contains("world") ? "world.test" : "test";
  std::string test_where = j.contains("world") ? spec.source + ": world (" + spec.world + ")" : spec.source + ": test";
  if (test.is_string()) {
    const fs::path path = spec.base_dir / refuse.string(test, "test", "a test file's path");
    try {
      test = strict_json::read_file<json>(path, "a test object");
    } catch (const strict_json::Error& e) {
      throw InputError(spec.source + ": test: " + e.what());
    }
    spec.base_dir = path.parent_path();
    test_where = strict_json::printable(path.string(), 200);
  }
  if (!test.is_object() || test.contains("tests") || test.contains("sweep"))
    refuse("test", "must be one test object (a queue or a list of tests cannot be tuned; tune one test, its worlds are the repeats)");
  if (test.contains("seed")) refuse(test_field + ".seed", show(test["seed"]) + " would give every world the same seed (allowed: no seed; the tune's \"seed\" pairs the worlds)");
  if (test.contains("repeat")) refuse(test_field + ".repeat", "given (allowed: none; the tune's worlds are the repeats)");
  if (!test.contains("name")) test["name"] = file.stem().string();
  spec.base = parse_test(test.dump(), test_where, host, spec.base_dir);
  if (overrides.time) {
    // As salsa run --time: the test's time, and the timed changes past the new end dropped (they never apply).
    const double t = *overrides.time;
    if (!(t >= spec.base.dt && t <= 1e7))
      throw InputError("--time: " + format::number(t) + " is out of range (allowed: [" + format::number(spec.base.dt) + ", 10000000] s for " + test_where + ")");
    test["time"] = t == std::floor(t) ? json(static_cast<std::int64_t>(t)) : json(t);
    if (test.contains("changes") && test["changes"].is_array()) {
      json kept = json::array();
      for (const json& c : test["changes"])
        if (!(c.is_object() && c.contains("time") && c["time"].is_number() && c["time"].get<double>() > t)) kept.push_back(c);
      test["changes"] = kept;
    }
    spec.base = parse_test(test.dump(), test_where, host, spec.base_dir);
  }
  spec.test_json = test.dump();

  // ---- Parameters: the given keys with their ranges, or every declared parameter of the behavior.
  json params = j.value("parameters", json());
  if (params.is_null()) {
    if (spec.base.groups.size() != 1) refuse("parameters", "missing (the test has groups: name the parameters to tune, e.g. groups.<name>.behavior.params.<p>)");
    params = json::object();
    for (const Parameter& p : host.behavior(spec.base.groups[0].behavior.name).factory.parameters)
      params["behavior.params." + p.name] = json::object();
    if (params.empty()) refuse("parameters", "missing, and behavior '" + spec.base.groups[0].behavior.name + "' declares no parameters");
  }
  if (!params.is_object() || params.empty())
    refuse("parameters", show(params) + " must be an object of dotted keys, e.g. {\"behavior.params.cohesion_weight\": {\"min\": 0, \"max\": 5}}");
  for (const auto& item : params.items()) {
    const std::string& key = item.key();
    const std::string field = "parameters." + strict_json::printable(key);
    const auto found = declared(spec.base, key, host);
    if (const auto* why = std::get_if<std::string>(&found)) refuse(field, *why);
    const Declared& d = std::get<Declared>(found);
    refuse.only_keys(item.value(), field, {"min", "max", "log"});
    TuneParameter p{key, d.spec.min, d.spec.max, d.spec.is_integer(), log_by_default(d.spec), d.value, d.spec.unit};
    const std::string declared_range = d.spec.range();
    for (const char* end : {"min", "max"}) {
      if (!item.value().contains(end)) continue;
      const json& v = item.value()[end];
      if (!v.is_number()) refuse(field + "." + end, show(v) + " is not a number (allowed: " + declared_range + ")");
      if (const std::string why = d.spec.check(v.get<double>()); !why.empty())
        refuse(field + "." + end, show(v) + " is outside the declared range (allowed: " + declared_range + ")");
      (std::string(end) == "min" ? p.min : p.max) = v.get<double>();
    }
    if (!(p.min < p.max))
      refuse(field, "[" + format::number(p.min) + ", " + format::number(p.max) + "] is an empty range (allowed: min < max within " + declared_range + ")");
    if (item.value().contains("log")) {
      if (!item.value()["log"].is_boolean()) refuse(field + ".log", show(item.value()["log"]) + " is not true or false");
      p.log = item.value()["log"].get<bool>();
      if (p.log && !(p.min > 0)) refuse(field + ".log", "true needs a range of positive numbers, and min is " + format::number(p.min) + " (allowed: min > 0)");
    }
    if (spec.parameters.size() == 64) refuse("parameters", "more than 64 parameters (allowed: at most 64)");
    spec.parameters.push_back(p);
  }

  // ---- Objectives: one, or a list (two or more: a Pareto front).
  if (j.contains("objective") == j.contains("objectives"))
    refuse("objective", j.contains("objective") ? "given with \"objectives\" (allowed: one or the other)"
                                                : "missing (e.g. {\"column\": \"targets_found\", \"goal\": \"max\"})");
  const DataColumns columns = data_columns(spec.base, host);
  if (j.contains("objective")) {
    spec.objectives.push_back(read_objective(j["objective"], "objective", refuse, columns, spec.base, overrides.time.has_value()));
  } else {
    const json& list = j["objectives"];
    if (!list.is_array() || list.size() < 2 || list.size() > 8)
      refuse("objectives", show(list) + (list.is_array() ? " has " + std::to_string(list.size()) + (list.size() == 1 ? " entry" : " entries") : std::string()) +
                               " (allowed: a list of 2 to 8 objectives, a Pareto front; one objective is given as \"objective\")");
    for (std::size_t i = 0; i < list.size(); ++i)
      spec.objectives.push_back(read_objective(list[i], "objectives[" + std::to_string(i) + "]", refuse, columns, spec.base, overrides.time.has_value()));
  }
  const bool several = spec.objectives.size() > 1;

  // ---- The algorithm and its settings.
  auto algorithm_of = [&](const json& v, const std::string& field) {
    std::string allowed;
    for (const std::string& a : tune_algorithms()) allowed += (allowed.empty() ? "" : ", ") + a;
    const std::string name = refuse.string(v, field, allowed);
    if (std::find(tune_algorithms().begin(), tune_algorithms().end(), name) == tune_algorithms().end())
      refuse(field, show(v) + " is not an algorithm (allowed: " + allowed + ")");
    return name;
  };
  spec.algorithm = j.contains("algorithm") ? algorithm_of(j["algorithm"], "algorithm") : several ? "nsga2" : "cmaes";
  if (several && spec.algorithm != "nsga2" && spec.algorithm != "random" && spec.algorithm != "lhs" && spec.algorithm != "grid")
    refuse("algorithm", "\"" + spec.algorithm + "\" optimises one objective, and the file has " + std::to_string(spec.objectives.size()) +
                            " (allowed with several: nsga2, random, lhs, grid)");
  if (!several && spec.algorithm == "nsga2") refuse("algorithm", "\"nsga2\" needs two or more objectives (allowed with one: cmaes, xnes, pso, de, bobyqa, neldermead, random, lhs, grid)");
  if (j.contains("population")) {
    spec.population = refuse.whole(j["population"], "population", 5, 10000);
    if (spec.algorithm == "nsga2" && spec.population % 4 != 0)
      refuse("population", show(j["population"]) + " is not a multiple of 4 (allowed for nsga2: 8, 12, 16, ...)");
  }
  if (j.contains("local")) {
    const json& l = j["local"];
    refuse.only_keys(l, "local", {"algorithm", "evaluations"});
    if (several) refuse("local", "a local finish optimises one objective, and the file has " + std::to_string(spec.objectives.size()));
    if (!l.contains("algorithm") || !l.contains("evaluations")) refuse("local", "needs \"algorithm\" (bobyqa, neldermead) and \"evaluations\"");
    spec.local = algorithm_of(l["algorithm"], "local.algorithm");
    if (spec.local != "bobyqa" && spec.local != "neldermead") refuse("local.algorithm", show(l["algorithm"]) + " is not a local method (allowed: bobyqa, neldermead)");
    spec.local_evaluations = refuse.whole(l["evaluations"], "local.evaluations", 1, 1e9);
  }
  if (queue_seed) spec.seed = *queue_seed;  // world w is the queue's repeat w
  if (j.contains("seed")) spec.seed = refuse.whole(j["seed"], "seed", 0, static_cast<double>(max_seed));
  if (overrides.seed) spec.seed = *overrides.seed;

  // ---- Budget, worlds, validation, racing.
  if (!j.contains("budget")) refuse("budget", "missing (e.g. {\"evaluations\": 400} or {\"seconds\": 3600}, or both)");
  refuse.only_keys(j["budget"], "budget", {"evaluations", "seconds"});
  const json& budget = j["budget"];
  if (budget.empty()) refuse("budget", "{} gives no budget (allowed: \"evaluations\", \"seconds\" or both)");
  if (budget.contains("evaluations")) spec.evaluations = refuse.whole(budget["evaluations"], "budget.evaluations", 1, 1e9);
  if (budget.contains("seconds")) {
    spec.seconds = refuse.number(budget["seconds"], "budget.seconds", 0, 1e9);
    if (spec.seconds == 0) refuse("budget.seconds", "0 is no budget (allowed: a number of seconds > 0)");
  }
  if (j.contains("worlds")) spec.worlds = refuse.whole(j["worlds"], "worlds", 1, 100000);
  if (j.contains("validation")) {
    refuse.only_keys(j["validation"], "validation", {"worlds", "candidates"});
    const json& v = j["validation"];
    if (v.contains("worlds")) spec.validation_worlds = refuse.whole(v["worlds"], "validation.worlds", 0, 100000);
    if (v.contains("candidates")) spec.validation_candidates = refuse.whole(v["candidates"], "validation.candidates", 1, 100);
  }
  spec.racing.on = !several && spec.worlds > 1;
  if (j.contains("racing")) {
    const json& r = j["racing"];
    if (r.is_boolean()) {
      spec.racing.on = r.get<bool>();
    } else {
      refuse.only_keys(r, "racing", {"level", "first_test"});
      spec.racing.on = true;
      if (r.contains("level")) spec.racing.level = refuse.number(r["level"], "racing.level", 1e-6, 0.5);
      if (r.contains("first_test")) spec.racing.first_test = refuse.whole(r["first_test"], "racing.first_test", 2, 100000);
    }
    if (spec.racing.on && several) refuse("racing", "racing compares one objective, and the file has " + std::to_string(spec.objectives.size()) + " (allowed: false)");
    if (spec.racing.on && spec.worlds < 2) refuse("racing", "racing needs 2 or more worlds, and \"worlds\" is " + std::to_string(spec.worlds));
  }
  spec.racing.first_test = std::min(spec.racing.first_test, spec.worlds);
  if (overrides.evaluations) {
    const double n = *overrides.evaluations, least = static_cast<double>(spec.worlds + spec.local_evaluations);
    if (!(n >= least && n <= 1e9) || n != std::floor(n))
      throw InputError("--evaluations: " + format::number(n) + " is out of range (allowed: a whole number in [" + format::number(least) +
                       ", 1000000000] for " + spec.source + ": the defaults run first on its " + std::to_string(spec.worlds) + " tuning worlds" +
                       (spec.local_evaluations ? ", then local.evaluations" : "") + ")");
    spec.evaluations = static_cast<std::size_t>(n);
  }
  if (spec.evaluations == 0) {
    // Without a count of evaluations these would never end, or know their size.
    if (spec.algorithm == "lhs" || spec.algorithm == "grid")
      refuse("budget", "\"" + spec.algorithm + "\" sizes its design from budget.evaluations, and there is none (allowed: give \"evaluations\")");
    if (!spec.local.empty()) refuse("budget", "a local finish takes its share of budget.evaluations, and there is none (allowed: give \"evaluations\")");
  }
  // The defaults run first on every tuning world, racing or not (they are the line racing and the
  // report measure against): a budget short of that tunes nothing.
  if (spec.evaluations > 0 && spec.evaluations < spec.worlds + spec.local_evaluations)
    refuse("budget.evaluations", std::to_string(spec.evaluations) + " cannot run the defaults, which run first on every tuning world (allowed: at least " +
                                     std::to_string(spec.worlds + spec.local_evaluations) + ": " + std::to_string(spec.worlds) + " worlds" +
                                     (spec.local_evaluations ? " plus local.evaluations" : "") + ")");

  // Every candidate must make a test the reader accepts: the defaults, and each range's ends.
  std::vector<double> values;
  for (const TuneParameter& p : spec.parameters) values.push_back(p.base);
  candidate_test(spec, values, "check", 0, host);
  for (std::size_t k = 0; k < spec.parameters.size(); ++k)
    for (const double end : {spec.parameters[k].min, spec.parameters[k].max}) {
      std::vector<double> v = values;
      v[k] = end;
      candidate_test(spec, v, "check", 0, host);
    }

  // What OUT/tune.json records: the tune as it runs (the test in full, its seed, the command line's
  // overrides applied and listed), so that --resume with other values is refused.
  json canonical = j;
  canonical["test"] = json::parse(spec.test_json);
  canonical["seed"] = spec.seed;
  if (overrides.time || overrides.evaluations) {
    json& line = canonical["command_line"] = json::object();
    if (overrides.time) line["time"] = canonical["test"]["time"];
    if (overrides.evaluations) line["evaluations"] = canonical["budget"]["evaluations"] = spec.evaluations;
  }
  spec.canonical = canonical.dump(2);
  return spec;
}

TestSpec candidate_test(const TuneSpec& spec, const std::vector<double>& values, const std::string& name, std::size_t world,
                        const PluginHost& host) {
  std::vector<std::pair<std::string, double>> set;
  for (std::size_t k = 0; k < spec.parameters.size(); ++k) set.emplace_back(spec.parameters[k].key, values[k]);
  json test = json::parse(set_numbers(spec.test_json, set, spec.source + ": parameters"));
  test["name"] = name;
  TestSpec t = parse_test(test.dump(), spec.source + ": test (" + name + ")", host, spec.base_dir);
  t.repeat = world;
  t.seed = paired_seed(spec.seed, world, world_key(t));
  return t;
}

}  // namespace salsa
