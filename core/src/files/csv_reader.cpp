#include "salsa/core/files/csv_reader.hpp"

#include <charconv>
#include <cmath>

#include "salsa/core/files/input_error.hpp"
#include "strict_json.hpp"

namespace salsa {

CsvReader::CsvReader(const std::filesystem::path& file) : path_(file) {
  file_ = std::fopen(file.c_str(), "rb");
  if (!file_) throw InputError(strict_json::printable(file.string(), 200) + ": cannot open file");
  if (!read_record() || (ends_.size() == 1 && cells_.empty()))
    throw InputError(strict_json::printable(file.string(), 200) + ": empty (allowed: a CSV written by salsa with a header row)");
  for (std::size_t i = 0; i < ends_.size(); ++i) header_.emplace_back((*this)[i]);
}

CsvReader::~CsvReader() {
  if (file_) std::fclose(file_);
}

std::optional<std::size_t> CsvReader::find(std::string_view column) const {
  for (std::size_t i = 0; i < header_.size(); ++i)
    if (header_[i] == column) return i;
  return std::nullopt;
}

std::size_t CsvReader::column(std::string_view name) const {
  if (auto i = find(name)) return *i;
  std::string all;
  for (const auto& h : header_) all += (all.empty() ? "" : ",") + h;
  throw InputError(strict_json::printable(path_.string(), 200) + ": no column '" + strict_json::printable(name) +
                   "' (the header is " + strict_json::printable(all, 200) + ")");
}

bool CsvReader::next() {
  while (read_record())
    if (!(ends_.size() == 1 && cells_.empty())) return true;  // blank lines are no rows
  return false;
}

// One record, which may span lines inside quotes. getc_unlocked keeps this near memory speed.
bool CsvReader::read_record() {
  cells_.clear();
  ends_.clear();
  line_ = next_line_;
  int c = getc_unlocked(file_);
  if (c == EOF) return false;
  const auto field_start = [&] { return ends_.empty() ? std::size_t{0} : ends_.back(); };
  for (bool quoted = false;; c = getc_unlocked(file_)) {
    if (quoted) {
      if (c == EOF)
        throw InputError(strict_json::printable(path_.string(), 200) + ": line " + std::to_string(line_) + ": a quoted field never ends");
      if (c != '"') {
        if (c == '\n') ++next_line_;
        cells_ += static_cast<char>(c);
        continue;
      }
      c = getc_unlocked(file_);
      if (c == '"') {  // "" inside quotes is one quote
        cells_ += '"';
        continue;
      }
      quoted = false;  // c is the character after the closing quote
    }
    if (c == EOF || c == '\n') {
      if (c == '\n') ++next_line_;
      if (cells_.size() > field_start() && cells_.back() == '\r') cells_.pop_back();
      ends_.push_back(cells_.size());
      return true;
    }
    if (c == ',') ends_.push_back(cells_.size());
    else if (c == '"' && cells_.size() == field_start()) quoted = true;
    else cells_ += static_cast<char>(c);
  }
}

std::string_view CsvReader::operator[](std::size_t i) const {
  if (i >= ends_.size()) return {};
  const std::size_t begin = i == 0 ? 0 : ends_[i - 1];
  return std::string_view(cells_).substr(begin, ends_[i] - begin);
}

std::optional<double> CsvReader::optional_number(std::size_t i) const {
  const std::string_view cell = (*this)[i];
  if (cell.empty()) return std::nullopt;
  double v = 0;
  const auto [end, ec] = std::from_chars(cell.data(), cell.data() + cell.size(), v);
  if (ec != std::errc() || end != cell.data() + cell.size() || !std::isfinite(v))
    throw InputError(strict_json::printable(path_.string(), 200) + ": line " + std::to_string(line_) + ", column " +
                     strict_json::printable(i < header_.size() ? header_[i] : std::to_string(i + 1)) + ": '" +
                     strict_json::printable(cell) + "' is not a number (allowed: finite numbers)");
  return v;
}

double CsvReader::number(std::size_t i) const {
  if (auto v = optional_number(i)) return *v;
  throw InputError(strict_json::printable(path_.string(), 200) + ": line " + std::to_string(line_) + ", column " +
                   strict_json::printable(i < header_.size() ? header_[i] : std::to_string(i + 1)) +
                   ": empty (allowed: finite numbers)");
}

std::string csv_field(std::string_view text) {
  if (text.find_first_of(",\"\r\n") == std::string_view::npos) return std::string(text);
  std::string out = "\"";
  for (char c : text) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + '"';
}

}  // namespace salsa
