#pragma once
// The output-folder protocol (docs/output-format.md, docs/reliability.md): what makes a folder one
// salsa wrote, how a test's folder is written and replaced, and what --resume keeps.
//
// A test writes to OUT/.<name>.partial/ and renames it to OUT/<name>/ when complete. Both carry a
// marker file (folder_marker) written before anything else, and salsa removes or replaces only
// folders that carry it: never a path computed from user text alone.
#include <filesystem>
#include <string>
#include <vector>

#include "salsa/core/plugins/plugin_host.hpp"
#include "salsa/core/run/runner.hpp"
#include "salsa/core/experiments/test_spec.hpp"

namespace salsa {

/// The file that marks a folder as one salsa wrote (a test's folder or its .partial folder).
inline constexpr const char* folder_marker = ".salsa-test";

/// What the marker file says.
extern const char* const marker_text;

/// Writes a whole small file and syncs it; WriteError naming the file on any failure.
void write_file(const std::filesystem::path& file, const std::string& text);

/// fsync of a folder (its entries), best effort.
void sync_folder(const std::filesystem::path& folder);

/// OUT/.<name>.partial: where a test is written until it is complete.
std::filesystem::path partial_folder(const std::filesystem::path& out, const std::string& name);

/// Whether anything (a dangling symbolic link too) is at `p`.
bool exists_at_all(const std::filesystem::path& p);

/// A real folder (not a symbolic link) holding the marker file.
bool salsa_wrote(const std::filesystem::path& folder);

/// Removes `folder` when salsa wrote it, else InputError; WriteError when it cannot.
void remove_ours(const std::filesystem::path& folder);

/// Why a leftover .partial folder cannot be cleaned up ("" when it can, or is absent).
std::string partial_problem(const std::filesystem::path& work);

/// Removes a leftover .partial folder (an interrupted run), or InputError saying why it may not.
void clean_partial(const std::filesystem::path& work);

/// For a finished test's folder under --resume: "" when it holds the test asked for now (its
/// config.json is the same test), else why it does not.
std::string resume_difference(const std::filesystem::path& folder, const std::string& config_now);

/// Why this test may not write its folder ("" when it may, or when --resume will skip it).
std::string refusal(const TestSpec& test, const std::string& config, const RunOptions& options);

/// Before anything runs: refuses (InputError, one line) a bad output folder, names that fail
/// name_problem(), and tests whose folders may not be written: an existing folder without --resume
/// or --force, a finished test that differs from the one asked for (--resume, naming the first
/// difference), a folder salsa did not write (--force). Creates OUT when all is well.
void check_outputs(const std::vector<TestSpec>& tests, const PluginHost& host, const RunOptions& options);

/// What the test's config.json holds (the resolved test, a map file's path made absolute).
std::string test_config(const TestSpec& test, const PluginHost& host);

/// Writes `line` to OUT/.<name>.partial/error.txt (when salsa wrote that folder): why the test
/// failed. run_test does this itself for TestFailure and WriteError.
void record_failure(const std::filesystem::path& out, const std::string& name, const std::string& line);

/// Whether `run_test` would skip this test (--resume and its folder holds the identical test).
bool already_done(const TestSpec& test, const PluginHost& host, const RunOptions& options);

/// The lock file in OUT, held (flock) by the run writing OUT for as long as it runs (docs/output-format.md).
inline constexpr const char* lock_file_name = ".salsa.lock";

/// A finished test's list of the files it holds and their sizes, written before config.json.
inline constexpr const char* manifest_name = "manifest.json";

/// One writer per output folder, enforced by the system: an flock on OUT/.salsa.lock, released when
/// the process ends however it ends. A whole run holds it exclusively; shards i/n of one split
/// share it and each holds OUT/.salsa-shard-<i>.lock exclusively. The lock files hold a note naming
/// their holder (pid, host, command) and are removed by their last holder.
class OutputLock {
 public:
  OutputLock() = default;
  OutputLock(OutputLock&& other) noexcept;
  OutputLock& operator=(OutputLock&& other) noexcept;
  ~OutputLock();

  /// Takes OUT's lock (OUT exists) for shard `shard` of `shards` (1: the whole queue), or InputError
  /// (one line) naming the folder and the holder.
  static OutputLock take(const std::filesystem::path& out, std::size_t shard, std::size_t shards, const std::string& command);
  /// OUT was created for this run: removed on release when the run left it empty (it was refused).
  void created_folder() { created_ = true; }
  /// Lets this process's --isolate children write `out` under the lock this process holds, or that
  /// holds for it (MPI rank 0's, for the other ranks): SALSA_OUTPUT_LOCK, checked against their
  /// parent's pid.
  static void share_with_children(const std::filesystem::path& out);
  /// Whether the parent process holds OUT's lock and shared it (an --isolate child).
  static bool held_by_parent(const std::filesystem::path& out);
  void release();

 private:
  std::filesystem::path out_, shard_file_;
  int main_fd_ = -1, shard_fd_ = -1;
  bool exclusive_ = false, created_ = false;
};

/// Before a run checks anything else in OUT: refuses (InputError, one line) an OUT that is empty
/// text, a file, or inside a folder salsa wrote (nesting_problem), creates it when missing, and takes
/// its lock for shard `shard` of `shards` (OutputLock::take; `command` names this run to others).
/// A refused run's OUT, when created here, is removed again when the lock is released empty.
OutputLock claim_output(const std::filesystem::path& out, std::size_t shard, std::size_t shards, const std::string& command);

/// Why OUT may not be an output folder because it is, or is inside, a folder salsa wrote (a test
/// folder, a .partial folder, or a queue's output folder), "" when it may.
std::string nesting_problem(const std::filesystem::path& out);

/// Why `folder` (about to be replaced) may not be: it holds salsa output folders of its own; "" when
/// it may.
std::string nested_results(const std::filesystem::path& folder);

/// Writes work/manifest.json: every file of the finished test and its size, config.json's given.
void write_manifest(const std::filesystem::path& work, const std::string& config);

/// Why a finished test's folder does not hold its whole data ("" when it does): a file its manifest
/// lists is missing or of another size, drones.csv or the archive (trajectories.nc) is wanted and was
/// not written; for a folder without a manifest, a data file missing or empty.
/// With `drone_columns` (RunOptions::drone_columns), drones.csv must also hold those columns.
std::string data_problem(const std::filesystem::path& folder, bool drones_wanted, const std::vector<std::string>& drone_columns = {},
                         bool archive_wanted = false);
/// drones.csv's header for the state columns `names`: a vector's as <name>_x, <name>_y.
std::vector<std::string> drone_column_headers(const std::vector<std::string>& names);

}  // namespace salsa
