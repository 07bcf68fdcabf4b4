#pragma once
// Reads the CSV files salsa writes, one row at a time (drones.csv can hold millions of rows): RFC 4180
// quoting, a header row, fields as views into the current row. Bad content is an InputError naming
// the file, the line and the column.
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace salsa {

class CsvReader {
 public:
  /// Opens `file` and reads its header. Throws InputError when it cannot be opened or is empty.
  explicit CsvReader(const std::filesystem::path& file);
  ~CsvReader();
  CsvReader(const CsvReader&) = delete;
  CsvReader& operator=(const CsvReader&) = delete;

  const std::vector<std::string>& header() const { return header_; }
  std::optional<std::size_t> find(std::string_view column) const;
  /// The column's index; throws InputError naming the file and the columns there are.
  std::size_t column(std::string_view name) const;

  /// Reads the next row; false at the end of the file.
  bool next();
  std::size_t size() const { return ends_.size(); }
  /// Field `i` of the current row; empty when the row is shorter.
  std::string_view operator[](std::size_t i) const;
  /// Field `i` as a finite number; throws InputError naming the file, line and column.
  double number(std::size_t i) const;
  /// Field `i` as a number, or nullopt when empty.
  std::optional<double> optional_number(std::size_t i) const;
  std::size_t line() const { return line_; }
  const std::filesystem::path& file() const { return path_; }

 private:
  bool read_record();

  std::filesystem::path path_;
  std::FILE* file_ = nullptr;
  std::vector<std::string> header_;
  std::string cells_;               // the current row's fields, unquoted, back to back
  std::vector<std::size_t> ends_;   // where each field ends in cells_
  std::size_t line_ = 0, next_line_ = 1;  // first line of the current row / of the next one
};

/// `text` as a CSV field: quoted when it holds a comma, a quote or a line break.
std::string csv_field(std::string_view text);

}  // namespace salsa
