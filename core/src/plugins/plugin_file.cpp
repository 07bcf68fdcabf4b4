// A plugin file before it is mapped: the folder entry checked, its bytes read and hashed, the private copy, dlopen's complaint.
#include <dlfcn.h>
#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <ctime>
#include <mutex>

#include <openssl/evp.h>

#include "plugins/elf_check.hpp"
#include "plugins/loading.hpp"

namespace salsa::detail {

std::string entry_problem(const fs::path& file) {
  std::error_code ec;
  const fs::file_status link = fs::symlink_status(file, ec);
  if (ec && link.type() != fs::file_type::not_found) return "cannot be read: " + errno_text(ec.value());
  if (link.type() == fs::file_type::not_found) return "no such file";
  const fs::file_status target = fs::status(file, ec);
  if (ec && ec.value() == ELOOP) return "symbolic link loop";
  if (target.type() == fs::file_type::not_found && fs::is_symlink(link)) {
    std::error_code read_ec;
    const fs::path to = fs::read_symlink(file, read_ec);
    return "broken symbolic link to " + (read_ec ? std::string("a missing file") : to.string());
  }
  if (ec) return "cannot be read: " + errno_text(ec.value());
  if (fs::is_directory(target)) return "a folder, not a shared library";
  if (!fs::is_regular_file(target)) return "not a regular file (a pipe, socket or device), not a shared library";
  return {};
}

std::string sha256_hex(const std::vector<unsigned char>& bytes) {
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int size = 0;
  if (EVP_Digest(bytes.data(), bytes.size(), digest, &size, EVP_sha256(), nullptr) != 1) return {};
  static constexpr char hex[] = "0123456789abcdef";
  std::string out;
  for (unsigned int i = 0; i < size; ++i) (out += hex[digest[i] >> 4]) += hex[digest[i] & 15];
  return out;
}

std::string read_whole(const fs::path& file, std::vector<unsigned char>& out) {
  const int fd = ::open(file.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return "cannot be read: " + errno_text(errno);
  struct stat st {};
  std::string why;
  if (::fstat(fd, &st) != 0) why = "cannot be read: " + errno_text(errno);
  else if (!S_ISREG(st.st_mode)) why = "not a regular file, not a shared library";
  else {
    try {
      out.resize(static_cast<std::size_t>(st.st_size));
    } catch (const std::exception&) {
      why = "too large to load (" + std::to_string(st.st_size) + " bytes)";
    }
    std::size_t got = 0;
    while (why.empty() && got < out.size()) {
      const ssize_t n = ::read(fd, out.data() + got, out.size() - got);
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) why = "cannot be read: " + errno_text(errno);
      else if (n == 0) out.resize(got);  // shrank while read: check what there is
      else got += static_cast<std::size_t>(n);
    }
  }
  ::close(fd);
  return why;
}

namespace {

constexpr const char* snapshot_prefix = "salsa-plugin-";

/// Copies left by a process that died while loading (a plugin crashing in its static constructors):
/// their folder is no longer locked. Young folders are left alone: their owner may not have locked
/// them yet.
void sweep_stale_snapshots(const fs::path& tmp) {
  std::error_code ec;
  for (fs::directory_iterator it(tmp, ec), end; !ec && it != end; it.increment(ec)) {
    if (it->path().filename().string().rfind(snapshot_prefix, 0) != 0) continue;
    struct stat st {};
    if (::lstat(it->path().c_str(), &st) != 0 || !S_ISDIR(st.st_mode) || st.st_uid != ::geteuid() ||
        std::time(nullptr) - st.st_mtime < 60)
      continue;
    const int fd = ::open(it->path().c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
    if (fd < 0) continue;
    std::error_code remove_ec;
    if (::flock(fd, LOCK_EX | LOCK_NB) == 0) fs::remove_all(it->path(), remove_ec);
    ::close(fd);
  }
}

}  // namespace

Snapshot::~Snapshot() {
  std::error_code ec;
  if (!copy_.empty()) fs::remove(copy_, ec);
  if (!folder_.empty()) fs::remove(folder_, ec);
  if (lock_ >= 0) ::close(lock_);
}

std::string Snapshot::make(const fs::path& original, const std::vector<unsigned char>& bytes) {
  std::error_code ec;
  const fs::path tmp = fs::temp_directory_path(ec);
  if (ec) {
    const char* env = std::getenv("TMPDIR");
    return std::string("no temporary folder for its private copy (") + (env ? "$TMPDIR " + std::string(env) : "/tmp") +
           ": " + errno_text(ec.value()) + ")";
  }
  static std::once_flag swept;
  std::call_once(swept, [&] { sweep_stale_snapshots(tmp); });
  std::string folder = (tmp / (std::string(snapshot_prefix) + "XXXXXX")).string();
  if (!::mkdtemp(folder.data())) return "cannot make its private copy in " + tmp.string() + ": " + errno_text(errno);
  folder_ = folder;
  lock_ = ::open(folder_.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (lock_ >= 0) ::flock(lock_, LOCK_EX);
  const fs::path copy = folder_ / original.filename();
  const int fd = ::open(copy.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0700);
  if (fd < 0) return "cannot make its private copy in " + tmp.string() + ": " + errno_text(errno);
  copy_ = copy;
  int error = 0;
  for (std::size_t written = 0; written < bytes.size() && !error;) {
    const ssize_t n = ::write(fd, bytes.data() + written, bytes.size() - written);
    if (n > 0) written += static_cast<std::size_t>(n);
    else if (n == 0 || errno != EINTR) error = n == 0 ? EIO : errno;
  }
  if (::close(fd) != 0 && !error) error = errno;  // a full disk may show only here
  if (error) return "cannot make its private copy in " + tmp.string() + ": " + errno_text(error);
  return {};
}

StagedFile stage(const fs::path& file) {
  StagedFile staged{file, {}, {}, {}};
  if (staged.why = entry_problem(file); !staged.why.empty()) return staged;
  std::vector<unsigned char> bytes;
  if (staged.why = read_whole(file, bytes); !staged.why.empty()) return staged;
  staged.sha256 = sha256_hex(bytes);  // of the bytes that get mapped: two builds of one version differ here
  if (staged.why = elf_problem(bytes.data(), bytes.size()); !staged.why.empty()) return staged;
  auto snapshot = std::make_unique<Snapshot>();
  if (staged.why = snapshot->make(file, bytes); !staged.why.empty()) return staged;
  staged.snapshot = std::move(snapshot);
  return staged;
}

std::string dlopen_problem(const fs::path& copy, const fs::path& original) {
  const char* raw = ::dlerror();
  std::string text = one_line(raw ? raw : "unknown dlopen error");
  for (std::size_t at; (at = text.find(copy.string())) != std::string::npos;)
    text.replace(at, copy.string().size(), original.string());
  if (text.rfind(original.string() + ": ", 0) == 0) text.erase(0, original.string().size() + 2);
  if (text.find("failed to map segment") != std::string::npos)
    text += " (is " + copy.parent_path().parent_path().string() + " mounted noexec? set TMPDIR to another folder)";
  return "cannot be loaded: " + text;
}

}  // namespace salsa::detail
