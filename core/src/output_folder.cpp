#include "salsa/core/output_folder.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include "salsa/core/names.hpp"

namespace salsa {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

/// Writes a whole small file and syncs it; WriteError naming the file on any failure.
void write_file(const fs::path& file, const std::string& text) {
  const int fd = ::open(file.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw WriteError(file.string() + ": cannot create file (" + std::strerror(errno) + ")");
  std::size_t done = 0;
  int error = 0;
  while (done < text.size() && !error) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n > 0) done += static_cast<std::size_t>(n);
    else if (n < 0 && errno != EINTR) error = errno;
  }
  if (!error && ::fsync(fd) != 0 && errno != EINVAL) error = errno;
  if (::close(fd) != 0 && !error) error = errno;
  if (error) throw WriteError(file.string() + ": write failed (disk full?): " + std::strerror(error));
}

void sync_folder(const fs::path& folder) {
  const int fd = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  ::fsync(fd);
  ::close(fd);
}

// ---- Output folders: only folders carrying the marker are ever removed or replaced.

const char* const marker_text = "This folder was written by salsa run (docs/output-format.md); salsa may replace it with --force.\n";

fs::path partial_folder(const fs::path& out, const std::string& name) { return out / ("." + name + ".partial"); }

bool exists_at_all(const fs::path& p) {
  std::error_code ec;
  return fs::exists(fs::symlink_status(p, ec));
}

/// A real folder (not a symbolic link) holding the marker file.
bool salsa_wrote(const fs::path& folder) {
  std::error_code ec;
  return fs::is_directory(fs::symlink_status(folder, ec)) && fs::is_regular_file(fs::symlink_status(folder / folder_marker, ec));
}

void remove_ours(const fs::path& folder) {
  if (!salsa_wrote(folder)) throw InputError(folder.string() + ": salsa did not write this folder (no " + folder_marker + " file), so it is left alone (remove or rename it yourself)");
  std::error_code ec;
  fs::remove_all(folder, ec);
  if (ec) throw WriteError(folder.string() + ": cannot remove folder (" + ec.message() + ")");
}

/// Why a leftover .partial folder cannot be cleaned up ("" when it can, or is absent).
std::string partial_problem(const fs::path& work) {
  if (!exists_at_all(work) || salsa_wrote(work)) return {};
  std::error_code ec;
  if (fs::is_directory(fs::symlink_status(work, ec)) && fs::is_empty(work, ec) && !ec) return {};  // cut off before its marker
  return work.string() + ": salsa did not write this (no " + folder_marker + " file), so it is left alone (remove or rename it yourself)";
}

void clean_partial(const fs::path& work) {
  if (const std::string why = partial_problem(work); !why.empty()) throw InputError(why);
  if (!exists_at_all(work)) return;
  std::error_code ec;
  fs::remove_all(work, ec);
  if (ec) throw WriteError(work.string() + ": cannot remove folder (" + ec.message() + ")");
}

// ---- --resume: a finished test is kept only when it is the test asked for now.

namespace {

std::string shown(const json& v) {
  if (v.is_object()) return "an object";
  if (v.is_array()) return "a list";
  const std::string s = v.dump();
  return s.size() > 40 ? s.substr(0, 37) + "..." : s;
}

}  // namespace

/// The first difference between a finished test's config (there) and the one asked for (now), as
/// "seed is 3 there, 4 now", or "" when they are the same. Walks `now` (whose depth salsa made), so
/// a deeply nested file there cannot exhaust the stack.
std::string first_difference(const json& there, const json& now, const std::string& field) {
  const std::string name = field.empty() ? "the file" : field;
  if (now.is_object()) {
    if (!there.is_object()) return name + " is " + shown(there) + " there, an object now";
    for (const auto& [key, value] : now.items()) {
      const std::string sub = field.empty() ? key : field + "." + key;
      if (!there.contains(key)) return sub + " is missing there, " + shown(value) + " now";
      if (std::string d = first_difference(there[key], value, sub); !d.empty()) return d;
    }
    for (const auto& [key, value] : there.items())
      if (!now.contains(key)) return (field.empty() ? key : field + "." + key) + " is " + shown(value) + " there, not set now";
    return {};
  }
  if (now.is_array()) {
    if (!there.is_array()) return name + " is " + shown(there) + " there, a list now";
    if (there.size() != now.size())
      return name + " has " + std::to_string(there.size()) + " entries there, " + std::to_string(now.size()) + " now";
    for (std::size_t i = 0; i < now.size(); ++i)
      if (std::string d = first_difference(there[i], now[i], name + "[" + std::to_string(i) + "]"); !d.empty()) return d;
    return {};
  }
  if (there.is_structured() || there != now) return name + " is " + shown(there) + " there, " + shown(now) + " now";
  return {};
}

/// For a finished test's folder under --resume: "" when it holds the test asked for now (skip it),
/// else why it does not.
std::string resume_difference(const fs::path& folder, const std::string& config_now) {
  const fs::path file = folder / "config.json";
  std::ifstream in(file, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  if (!in) return file.string() + ": cannot be read";
  if (text.str() == config_now) return {};
  json there;
  try {
    there = json::parse(text.str());
  } catch (const std::exception&) {
    return file.string() + ": not valid JSON, so it cannot be the same test";
  }
  // Where a plugin was found is not what ran (its hash is): a moved plugin folder still resumes. In
  // place: a copy of a deeply nested file would recurse as deep.
  auto drop_plugin_paths = [](json& config) {
    if (config.is_object() && config.contains("versions") && config["versions"].is_object())
      for (auto& [kind, v] : config["versions"].items()) {
        if (v.is_object()) v.erase("file");
        if (v.is_array())
          for (json& e : v)
            if (e.is_object()) e.erase("file");
      }
  };
  json now = json::parse(config_now);
  drop_plugin_paths(there);
  drop_plugin_paths(now);
  const std::string d = first_difference(there, now, "");
  return d.empty() ? "" : file.string() + ": " + d;
}

/// Why this test may not write its folder ("" when it may, or when --resume will skip it).
std::string refusal(const TestSpec& test, const std::string& config, const RunOptions& options) {
  if (const std::string why = name_problem(test.name); !why.empty()) return test.source + ": name: " + why;
  const fs::path folder = options.out / test.name;
  if (const std::string why = partial_problem(partial_folder(options.out, test.name)); !why.empty()) return why;
  if (!exists_at_all(folder)) return {};
  const std::string replace = salsa_wrote(folder) ? "use --force to replace it"
                                                  : std::string("salsa did not write it (no ") + folder_marker + " file), so it is left alone";
  if (options.resume) {
    if (!exists_at_all(folder / "config.json")) {
      if (options.force && salsa_wrote(folder)) return {};
      return folder.string() + ": holds no finished test (no config.json), so --resume cannot skip it (" + replace + ")";
    }
    const std::string diff = resume_difference(folder, config);
    if (diff.empty() || (options.force && salsa_wrote(folder))) return {};
    return diff + "; --resume keeps only identical tests (" + replace + ")";
  }
  if (options.force) {
    if (salsa_wrote(folder)) return {};
    return folder.string() + ": --force replaces only folders salsa wrote, and this one has no " + folder_marker +
           " file (remove or rename it yourself)";
  }
  return folder.string() + ": already exists (allowed: a new folder; use --resume to skip finished tests or --force to replace them)";
}

/// What config.json holds. A map file's path is made absolute: a relative one would resolve against
/// config.json's own folder when it is rerun, not against the folder it was given in.
std::string test_config(const TestSpec& test, const PluginHost& host) {
  if (test.map_file.empty() || fs::path(test.map_file).is_absolute()) return resolved_json(test, host);
  TestSpec copy = test;
  copy.map_file = fs::absolute(test.map_file).lexically_normal().string();
  return resolved_json(copy, host);
}


void check_outputs(const std::vector<TestSpec>& tests, const PluginHost& host, const RunOptions& options) {
  const fs::path& out = options.out;
  if (out.empty()) throw InputError("--out: \"\" is empty (allowed: a folder, created if missing)");
  std::error_code ec;
  if (const auto st = fs::status(out, ec); fs::exists(st) && !fs::is_directory(st))
    throw InputError("--out: " + out.string() + " is a file (allowed: a folder, created if missing)");
  for (const auto& t : tests)
    if (const std::string why = refusal(t, test_config(t, host), options); !why.empty()) throw InputError(why);
  fs::create_directories(out, ec);
  if (ec) throw InputError("--out: " + out.string() + ": cannot create folder (" + ec.message() + ")");
}

void record_failure(const fs::path& out, const std::string& name, const std::string& line) {
  const fs::path work = partial_folder(out, name);
  if (!salsa_wrote(work)) return;
  std::string text = line;
  for (char& c : text)
    if (c == '\n' || c == '\r') c = ' ';
  try {
    write_file(work / "error.txt", text + "\n");
  } catch (const WriteError&) {  // a full disk: the failure is still reported on stderr
  }
}

bool already_done(const TestSpec& test, const PluginHost& host, const RunOptions& options) {
  const fs::path folder = options.out / test.name;
  return options.resume && name_problem(test.name).empty() && exists_at_all(folder / "config.json") &&
         resume_difference(folder, test_config(test, host)).empty();
}

}  // namespace salsa

