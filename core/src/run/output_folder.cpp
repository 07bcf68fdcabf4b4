#include "salsa/core/run/output_folder.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <utility>

#include "salsa/core/files/names.hpp"
#include "salsa/core/experiments/test_models.hpp"
#include "salsa/core/model/simulation.hpp"
#include "salsa/core/replay/archive.hpp"

namespace salsa {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

/// Writes a whole small file and syncs it; WriteError naming the file on any failure.
void write_file(const fs::path& file, const std::string& text) {
  const int fd = ::open(file.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw WriteError(file.string() + ": cannot create file (" + write_failure(errno) + ")");
  std::size_t done = 0;
  int error = 0;
  while (done < text.size() && !error) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n > 0) done += static_cast<std::size_t>(n);
    else if (n < 0 && errno != EINTR) error = errno;
  }
  if (!error && ::fsync(fd) != 0 && errno != EINVAL) error = errno;
  if (::close(fd) != 0 && !error) error = errno;
  if (error) throw WriteError(file.string() + ": write failed (" + write_failure(error) + ")");
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
  if (!exists_at_all(work)) return {};
  if (salsa_wrote(work)) return nested_results(work);  // removed next: never with other results inside
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
  if (const std::string why = test_name_problem(test.name); !why.empty()) return test.source + ": name: " + why;
  const fs::path folder = options.out / test.name;
  if (const std::string why = partial_problem(partial_folder(options.out, test.name)); !why.empty()) return why;
  if (!exists_at_all(folder)) return {};
  const bool ours = salsa_wrote(folder);
  const std::string replace = ours ? "use --force to replace it"
                                   : std::string("salsa did not write it (no ") + folder_marker + " file), so it is left alone";
  // Replacing a folder salsa wrote deletes it: never with other results inside.
  auto replaced = [&] { return nested_results(folder); };
  if (options.resume) {
    if (!exists_at_all(folder / "config.json")) {
      if (options.force && ours) return replaced();
      return folder.string() + ": holds no finished test (no config.json), so --resume cannot skip it (" + replace + ")";
    }
    const std::string diff = resume_difference(folder, config);
    if (diff.empty()) {
      // The same test: kept when its data is whole, rerun (replaced) when salsa wrote it.
      const std::string missing = data_problem(folder, options.drones_csv, options.drone_columns, test.archive);
      if (missing.empty()) return {};
      if (ours) return replaced();
      return missing + "; --resume would rerun the test, but " + replace;
    }
    if (options.force && ours) return replaced();
    return diff + "; --resume keeps only identical tests (" + replace + ")";
  }
  if (options.force) {
    if (ours) return replaced();
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
  if (const std::string why = nesting_problem(out); !why.empty()) throw InputError(why);
  // A test's config (JSON built through the host) only where --resume compares it with a finished one:
  // a queue of 10^6 new tests is checked with a few file-system calls each.
  for (const auto& t : tests) {
    const bool compared = options.resume && name_problem(t.name).empty() && exists_at_all(out / t.name / "config.json");
    if (const std::string why = refusal(t, compared ? test_config(t, host) : std::string(), options); !why.empty())
      throw InputError(why);
  }
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
  return options.resume && test_name_problem(test.name).empty() && exists_at_all(folder / "config.json") &&
         resume_difference(folder, test_config(test, host)).empty() && data_problem(folder, options.drones_csv, options.drone_columns, test.archive).empty();
}

// ---- Locks, nesting and what a finished test holds

namespace {

/// Opens `file` and flocks it with `op` (LOCK_EX or LOCK_SH) without waiting. Returns the descriptor,
/// -1 when another process holds a conflicting lock, or throws InputError when the file cannot be
/// opened. A lock file is removed by its last holder, so the one locked must still be the one at
/// `file` (else it was removed meanwhile: try again).
int open_locked(const fs::path& file, int op, const std::string& what) {
  for (int attempt = 0; attempt < 1000; ++attempt) {
    const int fd = ::open(file.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0644);
    if (fd < 0)
      throw InputError(what + ": cannot create the lock file " + file.string() + " (" + write_failure(errno) +
                       "; salsa writes it to keep other runs out while this one writes)");
    if (::flock(fd, op | LOCK_NB) != 0) {
      const int error = errno;
      ::close(fd);
      if (error == EWOULDBLOCK || error == EINTR) return -1;
      throw InputError(what + ": cannot lock " + file.string() + " (" + std::strerror(error) + ")");
    }
    struct stat held {}, now {};
    if (::fstat(fd, &held) == 0 && ::stat(file.c_str(), &now) == 0 && held.st_ino == now.st_ino && held.st_dev == now.st_dev)
      return fd;
    ::close(fd);
  }
  throw InputError(what + ": cannot lock " + file.string() + " (it keeps being replaced)");
}

std::string read_fd(int fd) {
  std::string text;
  char buffer[4096];
  for (off_t at = 0; text.size() < 4096;) {
    const ssize_t n = ::pread(fd, buffer, sizeof buffer, at);
    if (n <= 0) break;
    text.append(buffer, static_cast<std::size_t>(n)), at += n;
  }
  if (const auto nl = text.find('\n'); nl != std::string::npos) text.resize(nl);
  return text;
}

std::string read_small(const fs::path& file) {
  const int fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC | O_NOFOLLOW);
  if (fd < 0) return {};
  std::string text = read_fd(fd);
  ::close(fd);
  return text;
}

/// "pid 123 on host h: salsa run q.json --out o", one line.
std::string holder_text(const std::string& command) {
  char host[256] = "?";
  ::gethostname(host, sizeof host - 1);
  std::string text = "pid " + std::to_string(::getpid()) + " on host " + host + ": " + command;
  for (char& c : text)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = ' ';
  if (text.size() > 300) text = text.substr(0, 297) + "...";
  return text;
}

void write_holder(int fd, const std::string& text) {
  if (::ftruncate(fd, 0) != 0) return;  // the lock holds anyway; only the note of who holds it is lost
  const std::string line = text + "\n";
  [[maybe_unused]] const ssize_t n = ::pwrite(fd, line.data(), line.size(), 0);
}

const std::string shard_prefix = ".salsa-shard-";

/// The shard lock files held right now in OUT, as their notes ("2/4 pid ..."), at most `limit`.
std::vector<std::string> held_shards(const fs::path& out, std::size_t limit, const fs::path& mine = {}) {
  std::vector<std::string> held;
  std::error_code ec;
  for (fs::directory_iterator it(out, ec), end; !ec && it != end && held.size() < limit; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (!name.starts_with(shard_prefix) || !name.ends_with(".lock") || it->path() == mine) continue;
    const int fd = ::open(it->path().c_str(), O_RDONLY | O_CLOEXEC | O_NOFOLLOW);
    if (fd < 0) continue;
    if (::flock(fd, LOCK_SH | LOCK_NB) != 0) held.push_back(read_fd(fd));  // its holder is alive
    ::close(fd);
  }
  return held;
}

/// A queue's output folder: its queue.json is a record salsa wrote (a queue file of the same name is not).
bool is_queue_folder(const fs::path& folder) {
  std::error_code ec;
  const fs::path file = folder / "queue.json";
  if (!fs::is_regular_file(fs::symlink_status(file, ec))) return exists_at_all(folder / lock_file_name);
  std::ifstream in(file, std::ios::binary);
  std::string text(4096, '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  text.resize(static_cast<std::size_t>(in.gcount()));
  return text.find("\"configs_hash\"") != std::string::npos && text.find("\"tests\"") != std::string::npos;
}

}  // namespace

OutputLock::OutputLock(OutputLock&& other) noexcept { *this = std::move(other); }

OutputLock& OutputLock::operator=(OutputLock&& other) noexcept {
  if (this != &other) {
    release();
    out_ = std::move(other.out_);
    main_fd_ = std::exchange(other.main_fd_, -1);
    shard_fd_ = std::exchange(other.shard_fd_, -1);
    shard_file_ = std::move(other.shard_file_);
    exclusive_ = other.exclusive_;
    created_ = std::exchange(other.created_, false);
  }
  return *this;
}

OutputLock::~OutputLock() { release(); }

void OutputLock::release() {
  if (shard_fd_ >= 0) {
    ::unlink(shard_file_.c_str());  // still ours: removed while locked, so no one else holds this one
    ::close(shard_fd_);
    shard_fd_ = -1;
  }
  if (main_fd_ >= 0) {
    // The last holder removes it: a shared holder only when no other shard holds it still.
    if (exclusive_ || ::flock(main_fd_, LOCK_EX | LOCK_NB) == 0) ::unlink((out_ / lock_file_name).c_str());
    ::close(main_fd_);
    main_fd_ = -1;
  }
  if (created_) {
    std::error_code ec;
    fs::remove(out_, ec);  // only when empty: a run refused before it wrote anything leaves no trace
    created_ = false;
  }
}

OutputLock OutputLock::take(const fs::path& out, std::size_t shard, std::size_t shards, const std::string& command) {
  OutputLock lock;
  lock.out_ = out;
  const std::string what = "--out: " + out.string();
  const std::string allowed = " (allowed: one run per output folder at a time; wait for it to end, or give another --out)";
  lock.exclusive_ = shards <= 1;
  lock.main_fd_ = open_locked(out / lock_file_name, lock.exclusive_ ? LOCK_EX : LOCK_SH, what);
  if (lock.main_fd_ < 0) {
    std::string holder = read_small(out / lock_file_name);
    if (const auto shards_held = held_shards(out, 2); !shards_held.empty()) holder = "shard " + shards_held.front();
    throw InputError(what + " is being written by another salsa run (" + (holder.empty() ? "its holder is unknown" : holder) + ")" +
                     allowed);
  }
  if (lock.exclusive_) {
    write_holder(lock.main_fd_, holder_text(command));
    return lock;
  }
  // A shard: the shared lock lets the other shards of the split in; its own file keeps out a second
  // run of the same shard, and shards of another split (other n) are refused.
  lock.shard_file_ = out / (shard_prefix + std::to_string(shard) + ".lock");
  lock.shard_fd_ = open_locked(lock.shard_file_, LOCK_EX, what);
  if (lock.shard_fd_ < 0) {
    const std::string holder = read_small(lock.shard_file_);
    throw InputError(what + ": shard " + std::to_string(shard) + "/" + std::to_string(shards) + " is being run already (shard " +
                     (holder.empty() ? "holder unknown" : holder) + ")" + allowed);
  }
  const std::string split = "/" + std::to_string(shards) + " ";
  write_holder(lock.shard_fd_, std::to_string(shard) + split + holder_text(command));
  for (const std::string& other : held_shards(out, std::numeric_limits<std::size_t>::max(), lock.shard_file_))
    if (other.find(split) == std::string::npos || other.find(split) > other.find(' '))
      throw InputError(what + ": shard " + other.substr(0, other.find(' ')) + " of another split is running (shard " + other +
                       "; allowed: every shard of one run gives the same n in i/n)");
  return lock;
}

void OutputLock::share_with_children(const fs::path& out) {
  std::error_code ec;
  const fs::path where = fs::weakly_canonical(fs::absolute(out), ec);
  ::setenv("SALSA_OUTPUT_LOCK", (std::to_string(::getpid()) + ":" + where.string()).c_str(), 1);
}

bool OutputLock::held_by_parent(const fs::path& out) {
  const char* value = std::getenv("SALSA_OUTPUT_LOCK");
  if (!value) return false;
  const std::string text = value;
  const auto colon = text.find(':');
  std::error_code ec;
  const fs::path where = fs::weakly_canonical(fs::absolute(out), ec);
  // The parent must be the one that holds it, alive (it is our parent) and locking this folder.
  return colon != std::string::npos && text.substr(0, colon) == std::to_string(::getppid()) && text.substr(colon + 1) == where.string();
}

OutputLock claim_output(const fs::path& out, std::size_t shard, std::size_t shards, const std::string& command) {
  if (out.empty()) throw InputError("--out: \"\" is empty (allowed: a folder, created if missing)");
  std::error_code ec;
  if (const auto st = fs::status(out, ec); fs::exists(st) && !fs::is_directory(st))
    throw InputError("--out: " + out.string() + " is a file (allowed: a folder, created if missing)");
  if (const std::string why = nesting_problem(out); !why.empty()) throw InputError(why);
  const bool existed = exists_at_all(out);
  fs::create_directories(out, ec);
  if (ec) throw InputError("--out: " + out.string() + ": cannot create folder (" + ec.message() + ")");
  OutputLock lock;
  try {
    lock = OutputLock::take(out, shard, shards, command);
  } catch (...) {
    if (!existed) fs::remove(out, ec);
    throw;
  }
  if (!existed) lock.created_folder();
  return lock;
}

std::string nesting_problem(const fs::path& out) {
  std::error_code ec;
  const fs::path path = fs::weakly_canonical(fs::absolute(out, ec), ec);
  if (ec) return {};
  const std::string allowed = " (allowed: a folder outside the folders salsa writes; to rerun a test, give --out another folder)";
  for (fs::path at = path;; at = at.parent_path()) {
    if (salsa_wrote(at))
      return "--out: " + out.string() + (at == path ? " is" : " is inside " + at.string() + ",") + " a test folder salsa wrote" + allowed;
    if (at != path && is_queue_folder(at))
      return "--out: " + out.string() + " is inside " + at.string() + ", the output folder of a queue salsa wrote" + allowed;
    if (at == at.parent_path() || at.empty()) break;
  }
  return {};
}

std::string nested_results(const fs::path& folder) {
  std::error_code ec;
  for (fs::recursive_directory_iterator it(folder, fs::directory_options::skip_permission_denied, ec), end; !ec && it != end;
       it.increment(ec)) {
    if (!it->is_directory(ec) || it->is_symlink(ec)) continue;
    if (salsa_wrote(it->path()) || is_queue_folder(it->path()))
      return folder.string() + ": holds salsa results of its own (" + it->path().string() +
             "), which replacing it would delete (allowed: move them out first)";
  }
  return {};
}

void write_manifest(const fs::path& work, const std::string& config) {
  json files = json::object();
  std::vector<std::pair<std::string, std::uintmax_t>> found;
  std::error_code ec;
  for (fs::directory_iterator it(work, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    // timing.json is not data (its size may differ between identical runs; the manifest may not).
    if (name == folder_marker || name == manifest_name || name == "error.txt" || name == "config.json" || name == "timing.json" ||
        !it->is_regular_file(ec))
      continue;
    found.emplace_back(name, fs::file_size(it->path(), ec));
  }
  found.emplace_back("config.json", config.size());  // written after this file, as the last one
  std::sort(found.begin(), found.end());
  for (const auto& [name, size] : found) files[name] = size;
  write_file(work / manifest_name, json{{"files", files}}.dump(2) + "\n");
}

std::vector<std::string> drone_column_headers(const std::vector<std::string>& names) {
  const std::vector<StateColumn> declared = declared_drone_columns();
  std::vector<std::string> out;
  for (const std::string& name : names) {
    const auto c = std::find_if(declared.begin(), declared.end(), [&](const StateColumn& d) { return d.name == name; });
    if (c != declared.end() && c->width == 2) out.insert(out.end(), {name + "_x", name + "_y"});
    else out.push_back(name);
  }
  return out;
}

namespace {

/// Which of `wanted` drones.csv's header lacks ("" when none).
std::string lacking_columns(const fs::path& drones, const std::vector<std::string>& wanted) {
  std::ifstream in(drones, std::ios::binary);
  std::string header;
  std::getline(in, header);
  std::string lacking;
  for (const std::string& column : drone_column_headers(wanted))
    if (("," + header + ",").find("," + column + ",") == std::string::npos) lacking += (lacking.empty() ? "" : ", ") + column;
  return lacking;
}

std::string data_problem_at(const fs::path& folder, bool drones_wanted, bool archive_wanted);

}  // namespace

std::string data_problem(const fs::path& folder, bool drones_wanted, const std::vector<std::string>& drone_columns, bool archive_wanted) {
  if (std::string problem = data_problem_at(folder, drones_wanted, archive_wanted); !problem.empty()) return problem;
  if (drones_wanted && !drone_columns.empty())
    if (const std::string lacking = lacking_columns(folder / "drones.csv", drone_columns); !lacking.empty())
      return (folder / "drones.csv").string() + " lacks " + lacking + " (asked for by --drone-columns)";
  if (archive_wanted && !drone_columns.empty())
    if (const std::string lacking = archive_lacks(folder / archive_name, drone_columns); !lacking.empty())
      return (folder / archive_name).string() + " lacks " + lacking + " (asked for by --drone-columns)";
  return {};
}

namespace {

std::string data_problem_at(const fs::path& folder, bool drones_wanted, bool archive_wanted) {
  std::error_code ec;
  const fs::path manifest = folder / manifest_name;
  json files;
  if (exists_at_all(manifest)) {
    try {
      std::ifstream in(manifest, std::ios::binary);
      files = json::parse(in).at("files");
    } catch (const std::exception&) {
      return manifest.string() + ": not the list of files salsa wrote, so the test's data cannot be checked";
    }
    if (!files.is_object()) return manifest.string() + ": not the list of files salsa wrote, so the test's data cannot be checked";
    for (const auto& [name, size] : files.items()) {
      if (name.find('/') != std::string::npos || !size.is_number_unsigned()) return manifest.string() + ": names \"" + name + "\" oddly";
      const fs::path file = folder / name;
      const auto st = fs::symlink_status(file, ec);
      if (!fs::is_regular_file(st)) return file.string() + " is missing (it was written)";
      if (const auto now = fs::file_size(file, ec); now != size.get<std::uintmax_t>())
        return file.string() + " is " + std::to_string(now) + " bytes (" + std::to_string(size.get<std::uintmax_t>()) + " when it was written)";
    }
    if (drones_wanted && !files.contains("drones.csv"))
      return folder.string() + ": was run with --no-drones-csv and drones.csv is wanted now";
    if (archive_wanted && !files.contains(archive_name))
      return folder.string() + ": was run without the archive and " + archive_name + " is wanted now";
    return {};
  }
  // A folder from before manifests: the data files must be there and hold their header at least.
  std::vector<std::string> wanted{"map.json", "summary.csv", "targets.csv", "outcome.csv"};
  if (drones_wanted) wanted.push_back("drones.csv");
  if (archive_wanted) wanted.push_back(archive_name);
  for (const auto& name : wanted) {
    const fs::path file = folder / name;
    if (!fs::is_regular_file(fs::symlink_status(file, ec))) return file.string() + " is missing";
    if (fs::file_size(file, ec) == 0) return file.string() + " is empty";
  }
  return {};
}

}  // namespace

}  // namespace salsa
