// OUT/queue.json: the record of the queue that writes OUT, OUT claimed for it, and whether a folder holds salsa results.
#include "salsa/core/results/queue_summary.hpp"

#include <unistd.h>

#include <nlohmann/json.hpp>

#include <array>
#include <cerrno>
#include <cstring>
#include <functional>
#include <optional>
#include <unordered_map>

#include "salsa/core/files/csv_writer.hpp"
#include "salsa/core/run/output_folder.hpp"
#include "experiments/fnv1a.hpp"
#include "results/queue_folder.hpp"

namespace salsa {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

using detail::fnv1a64;
using detail::hex;
using detail::read_json;

void for_each_test_config(const std::vector<TestSpec>& tests, const PluginHost& host,
                          const std::function<void(std::size_t, const std::string&)>& fn) {
  // A queue's repeats differ in name, seed and repeat alone: each such group builds its config once
  // through the host (JSON: the costly part, ~50 µs), and its other tests get that text with their
  // three top-level lines ("name", "seed", "repeat": indented 2, nothing nested is) replaced.
  struct Template {
    const TestSpec* test;
    std::string text;
    std::array<std::pair<std::size_t, std::size_t>, 3> values;  // [begin, end) of name, seed, repeat
  };
  std::vector<Template> templates;
  std::unordered_multimap<std::size_t, std::size_t> groups;
  auto key = [](const TestSpec& t) {
    std::size_t h = std::hash<std::string>{}(t.groups[0].behavior.name);
    auto mix = [&h](std::size_t v) { h ^= v + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2); };
    mix(t.drone_total()), mix(t.targets), mix(std::hash<double>{}(t.time)), mix(std::hash<std::string>{}(t.map.name));
    std::vector<const PluginChoice*> choices{&t.map, &t.target};
    for (const GroupSpec& g : t.groups) choices.push_back(&g.behavior);
    for (const PluginChoice* c : choices)
      for (const auto& [name, value] : c->params.items()) mix(std::hash<double>{}(value));
    return h;
  };
  auto same_group = [](const TestSpec& a, const TestSpec& b) {
    TestSpec x = a;
    x.name = b.name, x.source = b.source, x.seed = b.seed, x.seed_given = b.seed_given, x.repeat = b.repeat;
    return x == b;
  };
  auto values_of = [](const TestSpec& t) {
    return std::array<std::string, 3>{json(t.name).dump(), std::to_string(t.seed), std::to_string(t.repeat)};
  };
  std::string text;
  for (std::size_t i = 0; i < tests.size(); ++i) {
    const TestSpec& t = tests[i];
    const std::size_t k = key(t);
    const Template* found = nullptr;
    for (auto [it, end] = groups.equal_range(k); it != end && !found; ++it)
      if (same_group(*templates[it->second].test, t)) found = &templates[it->second];
    if (found) {
      const auto values = values_of(t);
      text.clear();
      std::size_t at = 0;
      for (std::size_t v = 0; v < 3; ++v) {
        text.append(found->text, at, found->values[v].first - at).append(values[v]);
        at = found->values[v].second;
      }
      text.append(found->text, at);
      fn(i, text);
      continue;
    }
    Template made{&t, test_config(t, host), {}};
    const auto values = values_of(t);
    bool usable = true;
    std::size_t from = 0;
    for (std::size_t v = 0; v < 3 && usable; ++v) {  // in the order resolved_json writes them
      const std::string line = std::string("\n  \"") + (v == 0 ? "name" : v == 1 ? "seed" : "repeat") + "\": ";
      const std::size_t begin = made.text.find(line, from);
      usable = begin != std::string::npos && made.text.compare(begin + line.size(), values[v].size(), values[v]) == 0;
      if (usable) made.values[v] = {begin + line.size(), begin + line.size() + values[v].size()}, from = made.values[v].second;
    }
    fn(i, made.text);
    if (!usable) continue;  // not as expected: this group's tests are built one by one
    groups.emplace(k, templates.size());
    templates.push_back(std::move(made));
  }
}

QueueRecord queue_record(const std::vector<TestSpec>& tests, const PluginHost& host, std::vector<std::string> command) {
  QueueRecord r;
  r.tests.reserve(tests.size());
  for (const auto& t : tests) r.tests.push_back(t.name);
  std::uint64_t h = fnv1a64("");
  for_each_test_config(tests, host, [&](std::size_t, const std::string& config) { h = fnv1a64(config + '\0', h); });
  r.configs_hash = hex(h, 16);
  r.command = std::move(command);
  return r;
}

namespace {

json record_json(const QueueRecord& record) {
  json out = {{"tests", record.tests}, {"configs_hash", record.configs_hash}, {"command", record.command}};
  if (!record.reference.empty()) out["reference"] = record.reference;  // only then: queue.json as before references
  if (record.top > 0) out["top"] = record.top;
  if (!record.warnings.empty()) out["warnings"] = record.warnings;
  return out;
}

/// Whether OUT/queue.json exists, and then whether it records the same queue.
std::optional<bool> same_queue(const fs::path& file, const json& record, std::optional<json>& there) {
  std::error_code ec;
  if (!fs::exists(fs::symlink_status(file, ec))) return std::nullopt;
  there = read_json(file);
  return there && there->is_object() && there->value("tests", json()) == record["tests"] &&
         there->value("configs_hash", json()) == record["configs_hash"] && there->value("reference", json()) == record.value("reference", json()) &&
         there->value("top", json()) == record.value("top", json());
}

}  // namespace

void check_queue_folder(const fs::path& out, const QueueRecord& record, bool resume, bool force) {
  if (holds_tune(out))
    throw InputError(out.string() + ": holds a tune's results (tune.json), which salsa run never writes into, even with --resume or --force " +
                     "(allowed: another --out folder)");
  const fs::path file = out / "queue.json";
  const json text = record_json(record);
  std::optional<json> there;
  const auto same = same_queue(file, text, there);
  if (!same || *same || resume || force) return;
  std::string what = "holds the results of another queue";
  if (!there || !there->is_object() || !there->contains("tests")) what = "is not a queue record salsa wrote";
  else if (there->value("tests", json()) == text["tests"]) what = "holds the same tests with other settings (another seed, time, parameter...)";
  throw InputError(file.string() + ": " + what + " (allowed: another --out folder; --resume to keep its finished tests that match, --force to replace them)");
}

void claim_queue_folder(const fs::path& out, const QueueRecord& record, bool resume, bool force) {
  check_queue_folder(out, record, resume, force);
  const fs::path file = out / "queue.json";
  const json text = record_json(record);
  for (int attempt = 0; attempt < 2; ++attempt) {
    std::optional<json> there;
    if (const auto same = same_queue(file, text, there)) {
      if (*same) return;
      // Another queue's record: written meanwhile by another run (the second attempt) is refused like
      // one found at the start; only --resume or --force make it this queue's.
      if (attempt > 0) check_queue_folder(out, record, resume, force);
      replace_file(file, text.dump(2) + "\n");
      return;
    }
    // Absent: written under a temporary name and linked into place, so one of several shards wins.
    const fs::path tmp = file.string() + "." + std::to_string(::getpid()) + ".tmp";
    replace_file(tmp, text.dump(2) + "\n");
    const int linked = ::link(tmp.c_str(), file.c_str());
    const int error = errno;
    std::error_code ec;
    fs::remove(tmp, ec);
    if (linked == 0) return;
    if (error != EEXIST) throw WriteError(file.string() + ": cannot write (" + std::strerror(error) + ")");
  }
}

bool holds_tune(const fs::path& out) {
  std::error_code ec;
  if (!fs::is_regular_file(fs::symlink_status(out / "tune.json", ec))) return false;
  // A tune's record (its canonical tune file), not a file of the user's that happens to be named so.
  const auto record = read_json(out / "tune.json");
  return record && record->is_object() && record->contains("test") && record->contains("budget");
}

std::vector<std::string> write_comparison_notes(const fs::path& out) {
  std::vector<std::string> notes;
  if (const auto record = read_json(out / "queue.json"); record && record->is_object() && record->contains("warnings"))
    for (const auto& w : (*record)["warnings"])
      if (w.is_string()) notes.push_back(w.get<std::string>());
  const fs::path file = out / "comparison_notes.txt";
  if (notes.empty()) {
    std::error_code ec;
    fs::remove(file, ec);  // one left from an earlier queue goes
    return notes;
  }
  std::string text;
  for (const auto& n : notes) text += n + "\n";
  replace_file(file, text);
  return notes;
}

bool holds_results(const fs::path& out) {
  if (const auto record = read_json(out / "queue.json"); record && record->is_object() && record->contains("configs_hash")) return true;
  std::error_code ec;
  for (fs::directory_iterator it(out, ec), end; !ec && it != end; it.increment(ec))
    if (salsa_wrote(it->path())) return true;
  return false;
}

}  // namespace salsa
