#include "salsa/core/csv_writer.hpp"

#include <charconv>
#include <stdexcept>

namespace salsa {

namespace {
constexpr std::size_t handover_bytes = 1 << 20;
constexpr auto handover_period = std::chrono::seconds(2);
}  // namespace

CsvWriter::CsvWriter(const std::filesystem::path& file, const std::string& header) : path_(file) {
  file_ = std::fopen(file.c_str(), "wb");
  if (!file_) throw std::runtime_error(file.string() + ": cannot create file");
  buffer_ = header + "\n";
  last_handover_ = std::chrono::steady_clock::now();
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
  char text[64];
  if (value == 0) value = 0;  // no "-0.0000"
  auto [end, ec] = std::to_chars(text, text + sizeof text, value, std::chars_format::fixed, decimals);
  row_.append(text, ec == std::errc{} ? end : text);
  return *this;
}

CsvWriter& CsvWriter::field(std::uint64_t value) {
  if (!first_field_) row_ += ',';
  first_field_ = false;
  row_ += std::to_string(value);
  return *this;
}

CsvWriter& CsvWriter::empty_field() {
  if (!first_field_) row_ += ',';
  first_field_ = false;
  return *this;
}

void CsvWriter::end_row() {
  row_ += '\n';
  buffer_ += row_;
  row_.clear();
  first_field_ = true;
  hand_over(false);
}

void CsvWriter::hand_over(bool force) {
  const auto now = std::chrono::steady_clock::now();
  if (!force && buffer_.size() < handover_bytes && now - last_handover_ < handover_period) return;
  last_handover_ = now;
  std::lock_guard lock(mutex_);
  pending_ += buffer_;
  buffer_.clear();
  wake_.notify_one();
}

void CsvWriter::run() {
  std::string writing;
  std::unique_lock lock(mutex_);
  for (;;) {
    wake_.wait(lock, [this] { return stop_ || !pending_.empty(); });
    writing.swap(pending_);
    const bool stopping = stop_;
    lock.unlock();
    if (!writing.empty()) {
      const bool ok = std::fwrite(writing.data(), 1, writing.size(), file_) == writing.size() && std::fflush(file_) == 0;
      writing.clear();
      lock.lock();
      failed_ = failed_ || !ok;
    } else {
      lock.lock();
    }
    if (stopping && pending_.empty()) return;
  }
}

void CsvWriter::close() {
  if (!file_) return;
  hand_over(true);
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_one();
  thread_.join();
  const bool ok = std::fclose(file_) == 0 && !failed_;
  file_ = nullptr;
  if (!ok) throw std::runtime_error(path_.string() + ": write failed (disk full?)");
}

}  // namespace salsa
