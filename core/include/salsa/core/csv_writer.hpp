#pragma once
// CSV files written by a background thread: the simulation appends whole rows to a buffer and hands
// it over at least every couple of seconds, so an interrupted run loses at most that window and a file
// never ends in half a row.
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <filesystem>
#include <mutex>
#include <string>
#include <thread>

namespace salsa {

class CsvWriter {
 public:
  CsvWriter(const std::filesystem::path& file, const std::string& header);
  ~CsvWriter();
  CsvWriter(const CsvWriter&) = delete;
  CsvWriter& operator=(const CsvWriter&) = delete;

  /// Appends fields of the current row; end it with `end_row()`.
  CsvWriter& field(double value, int decimals);
  CsvWriter& field(std::uint64_t value);
  CsvWriter& empty_field();
  void end_row();
  /// Writes everything still buffered and closes the file; throws on an I/O error.
  void close();

 private:
  void hand_over(bool force);
  void run();

  std::filesystem::path path_;
  std::FILE* file_ = nullptr;
  std::string row_, buffer_, pending_;
  bool first_field_ = true;
  std::chrono::steady_clock::time_point last_handover_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false, failed_ = false;
  std::thread thread_;
};

}  // namespace salsa
