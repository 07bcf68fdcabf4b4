#pragma once
// CSV files written by a background thread: the simulation hands each row over as soon as it ends, and
// the thread writes what it holds at least every 2 s (sooner when much is waiting), so an interrupted
// run loses at most that window whatever the log interval, and a file never ends in half a row.
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <filesystem>
#include <mutex>
#include <stdexcept>
#include <string>
#include <string_view>
#include <thread>

namespace salsa {

/// A file could not be created or written (disk full, no permission); the message names the file.
struct WriteError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// What a failed write's errno means, for WriteError's message: "disk full", "permission denied",
/// "read-only file system", ... (so a read-only folder is not reported as a full disk).
std::string write_failure(int error);
/// `value` with `decimals` fixed decimals, or, when that would not fit in 63 characters (finite values
/// of about 1e57 and above), in the shortest exponent form that reads back ("1e+300"): every finite
/// number is written; empty stays reserved for "no value".
void append_number(std::string& out, double value, int decimals);

class CsvWriter {
 public:
  /// The longest a finished row waits in memory before it is written.
  static constexpr auto flush_period = std::chrono::seconds(2);

  CsvWriter(const std::filesystem::path& file, const std::string& header);
  ~CsvWriter();
  CsvWriter(const CsvWriter&) = delete;
  CsvWriter& operator=(const CsvWriter&) = delete;

  /// Appends fields of the current row; end it with `end_row()`.
  CsvWriter& field(double value, int decimals);
  CsvWriter& field(std::uint64_t value);
  CsvWriter& empty_field();
  /// A name as it is (names in salsa hold no comma, quote or line break).
  CsvWriter& text(std::string_view value);
  /// Hands the row to the writer thread; throws WriteError once a write has failed.
  void end_row();
  /// Writes every ended row, syncs the file to disk and closes it; throws WriteError on an I/O error.
  /// An unfinished row is dropped.
  void close();

 private:
  void run();
  [[noreturn]] void fail() const;

  std::filesystem::path path_;
  std::FILE* file_ = nullptr;
  std::string row_;
  bool first_field_ = true;
  std::mutex mutex_;  // guards pending_, stop_ and failed_
  std::condition_variable wake_;
  std::string pending_;  // ended rows not yet written
  bool stop_ = false, failed_ = false;
  int error_ = 0;  // errno of the failed write
  std::thread thread_;
};

}  // namespace salsa
