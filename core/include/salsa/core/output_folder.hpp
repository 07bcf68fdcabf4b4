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

#include "salsa/core/plugin_host.hpp"
#include "salsa/core/runner.hpp"
#include "salsa/core/test_spec.hpp"

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

}  // namespace salsa
