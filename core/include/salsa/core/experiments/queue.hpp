#pragma once
// A queue: the tests of one file, explicit and swept, repeated and in the order they run, each with
// its paired seed. See docs/test-format.md ("Queues and sweeps", "Seeds: the paired rule").
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "salsa/core/experiments/test_spec.hpp"

namespace salsa {

struct QueueOptions {
  std::optional<std::uint64_t> seed;  ///< --seed: the queue seed of every file, over the files' seeds and the tests'
  bool yes = false;                   ///< --yes: allow more than max_tests tests
  std::size_t max_tests = 10000;      ///< a larger queue is refused unless `yes`
};

/// No queue holds more tests than this, --yes or not: each test is held in memory before the first runs.
inline constexpr std::size_t max_queue_tests = 1'000'000;

struct Queue {
  /// Interleaved: repeat 0 of every configuration (the explicit tests in file order, then the sweep's)
  /// before repeat 1 of any. Within a repeat the sweep's behaviors vary fastest, so the tests of one
  /// world are neighbours and a queue stopped midway leaves whole groups to compare.
  std::vector<TestSpec> tests;
  std::uint64_t seed = 1;  ///< the queue seed (the file's "seed", or QueueOptions::seed)
  std::string source;      ///< the file, as messages name it
  std::string reference;   ///< the file's "reference": the variant the comparison sets the others against; "": the default
  std::size_t top = 0;     ///< the file's "top": the comparison pairs only the `top` best variants of each cell; 0: not given
};

/// Reads a queue file: {"seed", "repeats", "base", "conditions", "reference", "top", "tests", "sweep"}, or a plain test file (one test object, a
/// list of tests, {"tests": [...]}). Every test is validated as a test file's; names are unique; the
/// count is checked before the sweep is expanded. Throws InputError (one line: file, position, key,
/// value, what is allowed).
Queue load_queue(const std::filesystem::path& file, const PluginHost& host, const QueueOptions& options);
/// load_queue of JSON text rather than a file (the Python package's dicts): `where` names it in messages
/// as the file would be, relative paths are from `base_dir`, and a test without a "name" is named `stem`.
Queue parse_queue(const std::string& json_text, const std::string& where, const PluginHost& host, const QueueOptions& options,
                  const std::filesystem::path& base_dir = {}, const std::string& stem = "test");

/// One configuration of a queue (one test under one condition, before the repeats) as a test object.
struct QueueTest {
  std::string name;       ///< as the queue names it without the condition's and the repeat's suffixes: "flocking_sd250"
  std::string condition;  ///< the condition's name; "" in a queue without conditions
  std::string json;       ///< the test object: the queue's base, the test and the condition laid over each other, named
                          ///< as the queue names the test (without the repeat's suffix)
};

/// A queue file's configurations, for a tune's "world" (docs/tuning.md).
struct QueueTests {
  std::vector<QueueTest> tests;         ///< in the queue's order (repeat 0)
  std::vector<std::string> conditions;  ///< the conditions' names in the file's order; none without conditions
  std::uint64_t seed = 1;               ///< the queue seed
};

/// Reads and checks a queue file as load_queue does (any size up to max_queue_tests) and keeps each
/// configuration's test object. Throws InputError.
QueueTests queue_tests(const std::filesystem::path& file, const PluginHost& host);

/// One test of a sweep before the test reader sees it.
struct SweptTest {
  std::string json;  ///< the test object: sweep.test with one value of each axis set
  std::string name;  ///< its name before the repeat suffix (and the cut past 128 characters)
  std::string at;    ///< the axis values it was made of: "behaviors[1], set.drone.max_speed[0]"
};

/// The tests of a queue file's sweep in their order within a repeat, as test objects: the sweep is
/// checked (as load_queue does), the tests are not read (their values' ranges are the test reader's).
/// Throws InputError.
std::vector<SweptTest> expand_sweep(const std::filesystem::path& file, const PluginHost& host);

/// The test object `test_json` (JSON text) with each dotted key set to its number exactly as sweep.set
/// sets it, for `salsa tune`'s candidates. The values are checked when the test is read. Throws
/// InputError (naming `where`) where a key cannot lead to a number of the test.
std::string set_numbers(const std::string& test_json, const std::vector<std::pair<std::string, double>>& values,
                        const std::string& where);

/// The seed of a test without its own: the same for every behavior facing the same world in the same
/// repeat, whatever else the queue holds. In [0, 2^53), so that JSON holds it exactly:
///   splitmix64(fnv1a64(world_key) ^ splitmix64(queue_seed ^ splitmix64(repeat))) & (2^53 - 1)
/// where fnv1a64 is 64-bit FNV-1a over the key's bytes and splitmix64(x) is the output function of
/// Vigna's SplitMix64 generator applied to x + 0x9e3779b97f4a7c15.
std::uint64_t paired_seed(std::uint64_t queue_seed, std::size_t repeat, const std::string& world_key);

/// The keys that define a test's world, as canonical JSON (sorted keys, no spaces): the map (name,
/// every parameter, the file's name without its folder), the spawn (mode, radius, point), the drone
/// configuration's fields (not its name), the drone count, and the targets (count; kind and
/// parameters when there are any). Never the behavior, its parameters, the name or the position.
std::string world_key(const TestSpec& test);

/// A plugin choice and its parameters that differ from `schema`'s defaults: "forest(clusters=20)".
std::string describe_choice(const PluginChoice& choice, const Parameters& schema);
/// How a variant reads in summary.csv, comparison.csv and the plots: a behavior and its parameters that
/// differ from the declared defaults (name, value as text), "flocking (defaults)",
/// "flocking: cohesion_weight = 2, alignment_weight = 0.5".
std::string variant_label(const std::string& behavior, const std::vector<std::pair<std::string, std::string>>& changed);
/// The test's variant: variant_label of its behavior, in declaration order; with groups, each group's
/// as "scouts=flocking (defaults) / base=random_walk: speed = 2".
std::string variant(const TestSpec& test, const PluginHost& host);

}  // namespace salsa
