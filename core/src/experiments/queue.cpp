// Reading a queue file into its tests: explicit and swept, counted, paired, seeded, repeated and uniquely named.
#include "salsa/core/experiments/queue.hpp"

#include "format.hpp"

#include <algorithm>
#include <map>
#include <optional>
#include <unordered_map>

#include "experiments/queue_reader.hpp"

namespace salsa {

using detail::behavior_name;
using detail::Condition;
using detail::fitted;
using detail::join;
using detail::json;
using detail::leaf_paths;
using detail::merged;
using detail::name_after_file;
using detail::name_safe;
using detail::place;
using detail::Point;
using detail::read_shared;
using detail::read_sweep;
using detail::Reader;
using detail::Shared;
using detail::show;
using detail::Sweep;
using detail::SweptPlugin;
namespace fs = std::filesystem;

namespace {

using format::grouped;

/// A configuration: one test before it is repeated.
struct Config {
  TestSpec test;
  std::string where;  // for messages about the seed and the repeat keys
  std::string name;   // without the repeat suffix; empty: keep test.name
  std::string at;     // a sweep's test: the axis values it was made of ("behaviors[1], drones[0]")
  QueueTest object;   // the test object before it was read, for queue_tests
};

/// One test of a sweep before it is read: sweep.test with one value of each axis set.
struct Swept {
  json test;
  std::string name;  // without the repeat suffix, not yet fitted
  std::string at;    // the axis values it was made of: "behaviors[1], set.drones[0]"
  std::string bare;       // the name without the condition's
  std::string condition;  // the condition's name, "" without conditions
};

/// Visits the sweep's tests in the order they run within a repeat, one at a time (a million test objects
/// at once would take gigabytes): maps outer, then drone configurations, drone counts, targets,
/// sweep.set's keys (the last faster), conditions, and behaviors fastest, so that the tests of one world
/// are neighbours.
template <class Visit>
void multiply(const Sweep& sweep, const Reader& r, Visit visit) {
  auto points = [](const std::vector<SweptPlugin>& entries, const char* key) {
    std::vector<Point> out;
    for (const auto& e : entries)
      for (auto& p : e.points(key)) out.push_back(std::move(p));
    return out;
  };
  const std::vector<Point> none{Point{json::object(), "", ""}};
  const std::vector<Point> behaviors = sweep.behaviors.empty() ? none : points(sweep.behaviors, "behavior");
  const std::vector<Point> maps = sweep.maps.empty() ? none : points(sweep.maps, "map");
  const std::vector<Point>& drone = sweep.drone.empty() ? none : sweep.drone;
  const std::vector<Point>& drones = sweep.drones.empty() ? none : sweep.drones;
  const std::vector<Point>& targets = sweep.targets.empty() ? none : sweep.targets;
  std::vector<Point> sets = none;  // sweep.set's axes as one: their product
  for (const std::vector<Point>& axis : sweep.set) {
    std::vector<Point> product;
    product.reserve(sets.size() * axis.size());
    for (const Point& outer : sets)
      for (const Point& p : axis) {
        Point both = outer;
        both.set.update(p.set);
        join(both.token, p.token, "_");
        join(both.at, p.at, ", ");
        product.push_back(std::move(both));
      }
    sets = std::move(product);
  }
  const std::string prefix = sweep.base.contains("name") && sweep.base["name"].is_string() ? sweep.base["name"].get<std::string>() : "";
  for (const Point& m : maps)
    for (const Point& dc : drone)
      for (const Point& n : drones)
        for (const Point& tg : targets)
          for (const Point& st : sets)
            for (const Condition& c : sweep.conditions)
            for (const Point& b : behaviors) {
              Swept t{sweep.base, prefix, "", "", ""};
              for (const Point* p : {&b, &n, &tg, &m, &dc}) {
                for (const auto& [key, value] : p->set.items()) {
                  if (key == "targets" && value.size() == 1 && value.contains("count") && t.test.contains("targets") && t.test["targets"].is_object())
                    t.test["targets"]["count"] = value["count"];  // a count: kind and parameters from sweep.test
                  else
                    t.test[key] = value;
                }
              }
              for (const auto& [key, value] : st.set.items()) place(t.test, key, r, Reader::join("sweep.set", key), "sweep.test") = value;
              c.apply(t.test, r, "sweep.test");
              join(t.name, b.token.empty() ? behavior_name(t.test) : b.token, "_");
              for (const Point* p : {&n, &tg, &m, &dc, &st}) join(t.name, p->token, "_");
              t.bare = t.name;
              t.condition = c.name;
              join(t.name, c.name, "_");
              for (const Point* p : {&b, &n, &tg, &m, &dc, &st}) join(t.at, p->at, ", ");
              join(t.at, c.at, ", ");
              visit(std::move(t));
            }
}

}  // namespace

namespace {

/// The queue `j` read from `shown_file` (as messages name it), its relative paths from `dir`, a test
/// without a name named after `stem`.
Queue read_queue(const json& j, const std::string& shown_file, const fs::path& dir, const std::string& stem,
                 const PluginHost& host, const QueueOptions& options, std::vector<QueueTest>* objects = nullptr) {
  const Reader r(shown_file, dir);
  Queue queue;
  queue.source = shown_file;

  // ---- The file's shape: a queue object, a list of tests, or one test.
  const bool is_queue = j.is_object() && (j.contains("tests") || j.contains("sweep") || j.contains("repeats") || j.contains("conditions"));
  const json* tests = nullptr;
  std::string list_field;  // "tests", or "" for a top-level list
  std::size_t repeats = 1;
  if (is_queue) {
    r.only_keys(j, "", {"seed", "repeats", "base", "conditions", "reference", "top", "tests", "sweep"});
    if (!j.contains("tests") && !j.contains("sweep"))
      r.fail("tests", "missing (a queue holds \"tests\", a \"sweep\", or both)");
    if (j.contains("seed")) queue.seed = r.integer(j["seed"], "seed", 0, static_cast<double>(max_seed));
    if (j.contains("repeats")) repeats = r.integer(j["repeats"], "repeats", 1, static_cast<double>(max_queue_tests));
    if (j.contains("tests")) {
      tests = &j["tests"];
      list_field = "tests";
      if (!tests->is_array()) r.fail("tests", show(*tests) + " must be a list of tests");
    }
  } else if (j.is_array()) {
    tests = &j;
  }
  const Shared shared = is_queue ? read_shared(j, r) : Shared{};
  if (options.seed) queue.seed = *options.seed;
  if (tests && tests->empty()) throw InputError(shown_file + ": " + (list_field.empty() ? "the list" : list_field) + " holds no tests");

  // ---- The explicit tests, then the sweep's axes (checked before anything is multiplied out).
  std::vector<Config> configs;
  if (!is_queue && !tests) {
    Config c{detail::parse_test(j, r, host), shown_file, "", "", {}};
    c.test.source = shown_file;
    name_after_file(c.test, stem);
    c.object.name = c.test.name;
    if (objects) {
      json test = j;
      test["name"] = c.test.name;
      c.object.json = test.dump();
    }
    configs.push_back(std::move(c));
  }
  if (tests)
    for (std::size_t i = 0; i < tests->size(); ++i) {
      // The test laid over the base, under each condition (conditions vary faster).
      const std::string at = list_field + "[" + std::to_string(i) + "]";
      const json& own = (*tests)[i];
      std::vector<std::string> leaves;
      leaf_paths(own, "", leaves);
      std::vector<std::pair<std::string, std::string>> own_paths;  // what the test sets itself
      for (const std::string& leaf : leaves) own_paths.emplace_back(leaf, at + "." + leaf);
      if (shared.named() && own.is_object() && own.contains("condition"))
        r.fail(at + ".condition", "set by the queue's conditions (allowed: leave it out)");
      for (const Condition& condition : shared.conditions) {
        const std::string where = shown_file + ": " + at + (condition.name.empty() ? "" : " (" + condition.at + ")");
        const Reader reader(where, dir);
        json test = j.contains("base") ? merged(shared.base, own, true) : own;
        if (!condition.name.empty()) {
          condition.check_apart(own_paths, r);
          condition.apply(test, reader, at);
        }
        Config c{detail::parse_test(test, reader, host), where, "", "", {}};
        c.test.source = where;
        name_after_file(c.test, stem + "-" + std::to_string(i + 1));
        c.object.name = c.test.name;
        c.object.condition = condition.name;
        if (!condition.name.empty()) c.test.name = fitted(c.test.name + "_" + condition.name, "");
        if (objects) {
          test["name"] = c.test.name;
          c.object.json = test.dump();
        }
        configs.push_back(std::move(c));
      }
    }
  std::optional<Sweep> sweep;
  if (is_queue && j.contains("sweep")) sweep = read_sweep(j["sweep"], r, host, shared);

  const double per_repeat = static_cast<double>(configs.size()) + (sweep ? sweep->size() : 0);
  const double total = per_repeat * static_cast<double>(repeats);
  const std::string count = "the queue expands to " + grouped(total) + " tests (" +
                            (repeats > 1 ? grouped(per_repeat) + " × " + grouped(static_cast<double>(repeats)) + " repeats; " : "");
  if (total > static_cast<double>(max_queue_tests))
    throw InputError(shown_file + ": " + count + "allowed: at most " + grouped(max_queue_tests) +
                     " in one queue, even with --yes): split it into several files");
  if (total > static_cast<double>(options.max_tests) && !options.yes)
    throw InputError(shown_file + ": " + count + "allowed: " + grouped(static_cast<double>(options.max_tests)) +
                     " without --yes): check the sweep, or pass --yes to run them all");

  // ---- The sweep multiplied out, each test read: with sweep.set, a test's messages name the values it was made of.
  if (sweep) {
    const std::string base_where = shown_file + ": sweep.test";
    const Reader base_reader(base_where, dir);
    multiply(*sweep, r, [&](Swept&& s) {
      const Reader reader = s.at.empty() || (sweep->set.empty() && !shared.named()) ? base_reader
                                                                                 : Reader(shown_file + ": sweep (" + s.at + ")", dir);
      Config c{detail::parse_test(s.test, reader, host), base_where, std::move(s.name), s.at, {name_safe(s.bare), s.condition, ""}};
      if (objects) {
        s.test["name"] = fitted(name_safe(c.name), "");
        c.object.json = s.test.dump();
      }
      c.test.source = shown_file + ": sweep" + (s.at.empty() ? "" : " (" + s.at + ")");
      configs.push_back(std::move(c));
    });
  }

  // ---- A label names one variant: two under one name would be pooled in the comparison and the plots.
  std::map<std::string, std::string> labelled;  // the variant as shown → as its parameters make it
  for (const Config& c : configs) {
    TestSpec bare = c.test;
    for (GroupSpec& g : bare.groups) g.behavior.label.clear();
    const std::string shown = variant(c.test, host), made = variant(bare, host);
    if (const auto [it, fresh] = labelled.emplace(shown, made); !fresh && it->second != made)
      throw InputError(c.test.source + ": behavior.label: \"" + shown + "\" names two variants, " + it->second + " and " + made +
                       " (allowed: each label on one variant)");
  }

  // ---- The comparison's pairs: each variant against a reference (a variant of the queue, or a
  // behavior's name for its defaults), or every pair of the `top` best. Not both: each is a whole
  // choice of pairs, and which variants rank best is known only after the run.
  std::vector<std::string> labels;
  if (is_queue && (j.contains("reference") || j.contains("top")))
    for (const Config& c : configs)
      if (std::string v = variant(c.test, host); std::find(labels.begin(), labels.end(), v) == labels.end()) labels.push_back(std::move(v));
  if (is_queue && j.contains("top")) {
    if (j.contains("reference"))
      r.fail("top", show(j["top"]) + " given with \"reference\" (allowed: one of them; \"top\" compares the best variants with each other, "
                                     "\"reference\" every variant with one)");
    if (labels.size() < 2) r.fail("top", show(j["top"]) + ": the queue has one variant, nothing to compare (allowed: leave it out)");
    queue.top = r.integer(j["top"], "top", 2, static_cast<double>(labels.size()));
  }
  if (is_queue && j.contains("reference")) {
    const std::string given = r.string(j["reference"], "reference");
    for (const std::string& wanted : {given, variant_label(given, {})})
      if (queue.reference.empty() && std::find(labels.begin(), labels.end(), wanted) != labels.end()) queue.reference = wanted;
    if (queue.reference.empty()) {
      std::string allowed;
      for (std::size_t i = 0; i < labels.size() && i < 20; ++i) allowed += (i ? "; " : "") + labels[i];
      r.fail("reference", show(j["reference"]) + " names no variant of the queue (allowed: " + allowed +
                              (labels.size() > 20 ? "; ..." : "") + "; or a behavior's name for its defaults)");
    }
  }

  // ---- Seeds: the paired seed unless the test gives its own (--seed overrides those too).
  std::vector<std::string> keys;
  keys.reserve(configs.size());
  for (const Config& c : configs) keys.push_back(world_key(c.test));
  auto seed_of = [&](const TestSpec& t, std::size_t i) {
    if (options.seed) return paired_seed(*options.seed, t.repeat, keys[i]);
    return t.seed_given ? t.seed : paired_seed(queue.seed, t.repeat, keys[i]);
  };
  for (std::size_t i = 0; i < configs.size(); ++i) {
    TestSpec& t = configs[i].test;
    t.seed = seed_of(t, i);
    if (repeats > 1 && t.repeat != 0)
      throw InputError(configs[i].where + ": repeat: " + std::to_string(t.repeat) + " is given, and the queue has \"repeats\": " +
                       std::to_string(repeats) + " (allowed: one or the other)");
    if (repeats > 1 && t.seed_given && !options.seed)
      throw InputError(configs[i].where + ": seed: " + std::to_string(t.seed) + " would be the seed of every repeat (\"repeats\": " +
                       std::to_string(repeats) + "), all the same test (allowed: no seed, for paired seeds; or --seed)");
  }

  // ---- The same test twice is a mistake: same world, same seed, same data.
  {
    std::vector<const TestSpec*> specs;
    specs.reserve(configs.size());
    for (const Config& c : configs) specs.push_back(&c.test);
    if (const auto same = first_same_test(specs))
      throw InputError(configs[same->second].test.source + ": the same test as " + configs[same->first].test.source +
                       " (the same world, seed and behavior give the same data; give one a \"seed\", or use the queue's \"repeats\")");
  }

  // ---- Repeats, interleaved: repeat 0 of every configuration before repeat 1 of any.
  queue.tests.reserve(configs.size() * repeats);
  for (std::size_t k = 0; k < repeats; ++k)
    for (std::size_t i = 0; i < configs.size(); ++i) {
      TestSpec t = configs[i].test;
      if (repeats > 1) {
        t.repeat = k;
        t.seed = seed_of(t, i);
        const std::string& at = configs[i].at;
        t.source = configs[i].at.empty() ? t.source + " (repeat " + std::to_string(k) + ")"
                                         : shown_file + ": sweep (" + at + ", repeat " + std::to_string(k) + ")";
      }
      const std::string suffix = "_r" + std::to_string(t.repeat);
      if (!configs[i].name.empty()) t.name = fitted(name_safe(configs[i].name), suffix);
      else if (repeats > 1) t.name = fitted(t.name, suffix);
      queue.tests.push_back(std::move(t));
    }

  std::unordered_map<std::string, std::size_t> names;
  for (std::size_t i = 0; i < queue.tests.size(); ++i) {
    const TestSpec& t = queue.tests[i];
    if (const auto [it, fresh] = names.emplace(t.name, i); !fresh)
      throw InputError(t.source + ": name: \"" + t.name + "\" is already used by " + queue.tests[it->second].source +
                       " (each test writes to a folder of its name)");
  }
  if (objects)
    for (Config& c : configs) objects->push_back(std::move(c.object));
  return queue;
}

}  // namespace

Queue load_queue(const fs::path& file, const PluginHost& host, const QueueOptions& options) {
  const json j = detail::read_json_file(file, "a test, a list of tests, or a queue {\"tests\": [...], \"sweep\": {...}}");
  return read_queue(j, strict_json::printable(file.string(), 200), file.parent_path(), file.stem().string(), host, options);
}

Queue parse_queue(const std::string& json_text, const std::string& where, const PluginHost& host, const QueueOptions& options,
                  const fs::path& base_dir, const std::string& stem) {
  json j;
  try {
    j = strict_json::parse<json>(json_text, where);
  } catch (const strict_json::Error& e) {
    throw InputError(e.what());
  }
  return read_queue(j, where, base_dir, stem, host, options);
}

QueueTests queue_tests(const fs::path& file, const PluginHost& host) {
  const json j = detail::read_json_file(file, "a test, a list of tests, or a queue {\"tests\": [...], \"sweep\": {...}}");
  QueueOptions options;
  options.yes = true;  // only the configurations are kept, not the repeats
  QueueTests out;
  out.seed = read_queue(j, strict_json::printable(file.string(), 200), file.parent_path(), file.stem().string(), host, options, &out.tests).seed;
  for (const QueueTest& t : out.tests)
    if (!t.condition.empty() && std::find(out.conditions.begin(), out.conditions.end(), t.condition) == out.conditions.end())
      out.conditions.push_back(t.condition);
  return out;
}

std::vector<SweptTest> expand_sweep(const fs::path& file, const PluginHost& host) {
  const json j = detail::read_json_file(file, "a queue {\"sweep\": {...}}");
  const Reader r(strict_json::printable(file.string(), 200), file.parent_path());
  if (!j.is_object() || !j.contains("sweep")) r.fail("sweep", "missing (a queue with a \"sweep\")");
  const Sweep sweep = read_sweep(j["sweep"], r, host, read_shared(j, r));
  if (sweep.size() > static_cast<double>(max_queue_tests))
    r.fail("sweep", "expands to " + grouped(sweep.size()) + " tests (allowed: at most " + grouped(max_queue_tests) + ")");
  std::vector<SweptTest> out;
  multiply(sweep, r, [&](Swept&& s) { out.push_back({s.test.dump(), name_safe(s.name), s.at}); });
  return out;
}

std::vector<TestSpec> load_tests(const fs::path& file, const PluginHost& host) { return load_queue(file, host, {}).tests; }

}  // namespace salsa
