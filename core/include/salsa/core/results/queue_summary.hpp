#pragma once
// The queue folder: OUT/queue.json says which queue wrote OUT, OUT/summary.csv has one row per test,
// made from the test folders alone (docs/output-format.md).
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "salsa/core/plugins/plugin_host.hpp"
#include "salsa/core/experiments/test_spec.hpp"

namespace salsa {

/// What OUT/queue.json holds: the queue's test names in order, a hash of their configs (what
/// config.json would hold) and the command that wrote it.
struct QueueRecord {
  std::vector<std::string> tests;
  std::string configs_hash;  ///< 16 hex digits
  std::vector<std::string> command;
  std::string reference;  ///< the queue's "reference" (the comparison's); "": none
  std::size_t top = 0;    ///< the queue's "top" (the comparison's); 0: none
  /// What the run warned about the queue as a whole (shared_state_warning), for the comparison's
  /// readers: written as "warnings" when there are any; not part of what makes two queues the same.
  std::vector<std::string> warnings;
};

QueueRecord queue_record(const std::vector<TestSpec>& tests, const PluginHost& host, std::vector<std::string> command);
/// fn(i, test_config(tests[i], host)) for every test, in order: the same text, built once per group of
/// tests that differ only in name, seed and repeat (a queue's repeats), so 10^6 tests take seconds.
void for_each_test_config(const std::vector<TestSpec>& tests, const PluginHost& host,
                          const std::function<void(std::size_t, const std::string&)>& fn);

/// Refuses (InputError, one line) a tune's OUT (holds_tune), whatever `resume` and `force` say, and an
/// OUT whose queue.json records another queue (other test names, or other configs), unless `resume`
/// or `force`. Writes nothing.
void check_queue_folder(const std::filesystem::path& out, const QueueRecord& record, bool resume, bool force);

/// check_queue_folder, then writes OUT/queue.json when absent or (with --resume or --force) when it
/// records another queue. Shards of one queue may call this at once: the first to write it wins.
void claim_queue_folder(const std::filesystem::path& out, const QueueRecord& record, bool resume, bool force);

/// Writes OUT/summary.csv from the test folders alone: the tests listed in OUT/queue.json in its order
/// (else every test folder, by name), each with status ok (OUT/<name>/config.json), failed
/// (OUT/.<name>.partial/error.txt) or missing, every input from config.json and outcome.csv's columns;
/// and OUT/timing.csv: name and wall seconds (timing.json) of each finished test, apart because they
/// are the only numbers that differ between identical runs. `host`, when given, decides which parameters are non-default (for the
/// variant column); without it, the parameters that vary within the queue are. Throws WriteError.
/// Writes `file` whole or not at all (a temporary file in the same folder, renamed over it), so a
/// reader never sees half of it; WriteError naming the file.
void replace_file(const std::filesystem::path& file, const std::string& text);

/// Refuses (InputError) an OUT that holds no salsa results (no queue.json record, no marked folder).
void write_queue_summary(const std::filesystem::path& out, const PluginHost* host = nullptr);

/// The warnings OUT/queue.json records (QueueRecord::warnings), and OUT/comparison_notes.txt: one a
/// line beside comparison.csv, or no file when there are none. Returns them. Throws WriteError.
std::vector<std::string> write_comparison_notes(const std::filesystem::path& out);

/// Whether OUT holds salsa results: a queue.json record salsa wrote or a test folder with the marker.
bool holds_results(const std::filesystem::path& out);

/// Whether OUT is a tune's folder: salsa tune records its tune file (a JSON object with "test" and
/// "budget") in OUT/tune.json before anything
/// else. A folder holds one kind of results: salsa run and salsa summarize refuse a tune's, salsa tune
/// refuses one holding results without it.
bool holds_tune(const std::filesystem::path& out);

/// 12 hex digits naming a test's experimental condition apart from its behavior: a hash of its
/// config.json without behavior, name, seed, repeat, the behavior's version and the plugin files' paths.
std::string cell_of(const std::string& config_json);

}  // namespace salsa
