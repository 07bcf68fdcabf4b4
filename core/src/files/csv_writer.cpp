#include "salsa/core/files/csv_writer.hpp"

#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cstring>

namespace salsa {

namespace {
// Wake the writer early when this much is waiting, so memory stays bounded with many drones.
constexpr std::size_t wake_bytes = 1 << 20;
}  // namespace

std::string write_failure(int error) {
  switch (error) {
    case ENOSPC: return "disk full";
    case EDQUOT: return "disk quota exceeded";
    case EACCES:
    case EPERM: return "permission denied";
    case EROFS: return "read-only file system";
    case EIO: return "input/output error";
    default: return std::strerror(error);
  }
}

void append_number(std::string& out, double value, int decimals) {
  char text[64];
  auto [end, ec] = std::to_chars(text, text + sizeof text, value, std::chars_format::fixed, decimals);
  // Too long in fixed form (|value| ≳ 1e57 with 4 decimals): the shortest exponent form that reads back.
  if (ec != std::errc{}) end = std::to_chars(text, text + sizeof text, value, std::chars_format::scientific).ptr;
  out.append(text, end);
}

CsvWriter::CsvWriter(const std::filesystem::path& file, const std::string& header) : path_(file) {
  file_ = std::fopen(file.c_str(), "wb");
  if (!file_) throw WriteError(file.string() + ": cannot create file (" + write_failure(errno) + ")");
  pending_ = header + "\n";
  thread_ = std::thread([this] { run(); });
}

CsvWriter::~CsvWriter() {
  try {
    close();
  } catch (...) {
  }
}

CsvWriter& CsvWriter::field(double value, int decimals) {
  if (!first_field_) row_ += ',';
  first_field_ = false;
  if (value == 0) value = 0;  // no "-0.0000"
  append_number(row_, value, decimals);
  return *this;
}

CsvWriter& CsvWriter::field(std::uint64_t value) {
  if (!first_field_) row_ += ',';
  first_field_ = false;
  row_ += std::to_string(value);
  return *this;
}

CsvWriter& CsvWriter::text(std::string_view value) {
  if (!first_field_) row_ += ',';
  first_field_ = false;
  row_ += value;
  return *this;
}

CsvWriter& CsvWriter::empty_field() {
  if (!first_field_) row_ += ',';
  first_field_ = false;
  return *this;
}

void CsvWriter::end_row() {
  row_ += '\n';
  first_field_ = true;
  std::lock_guard lock(mutex_);
  if (failed_) fail();
  pending_ += row_;
  row_.clear();
  if (pending_.size() >= wake_bytes) wake_.notify_one();
}

void CsvWriter::fail() const {
  throw WriteError(path_.string() + ": write failed (" + write_failure(error_) + ")");
}

// The writer thread: every flush_period (or when woken) it takes the rows ended so far and writes them.
// Whole rows only; yet a process killed mid-write can leave the last one cut, because the kernel stops a
// write() part way for a killed process. Only a .partial folder can hold such a file: --resume redoes it.
void CsvWriter::run() {
  std::string writing;
  std::unique_lock lock(mutex_);
  for (;;) {
    wake_.wait_for(lock, flush_period, [this] { return stop_ || pending_.size() >= wake_bytes; });
    writing.swap(pending_);
    const bool stopping = stop_;
    lock.unlock();
    bool ok = true;
    int error = 0;
    if (!writing.empty() && !failed_) {
      errno = 0;
      ok = std::fwrite(writing.data(), 1, writing.size(), file_) == writing.size() && std::fflush(file_) == 0;
      error = errno;
    }
    writing.clear();
    lock.lock();
    if (!ok && !failed_) failed_ = true, error_ = error ? error : EIO;
    if (stopping) return;
  }
}

void CsvWriter::close() {
  if (!file_) return;
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_one();
  thread_.join();
  // Synced before the test's folder is renamed into place: a complete folder stays complete.
  if (!failed_ && std::fflush(file_) == 0 && ::fsync(fileno(file_)) != 0 && errno != EINVAL) failed_ = true, error_ = errno;
  if (std::fclose(file_) != 0 && !failed_) failed_ = true, error_ = errno;
  file_ = nullptr;
  if (failed_) fail();
}

}  // namespace salsa
