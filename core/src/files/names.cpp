#include "salsa/core/files/names.hpp"

namespace salsa {

std::string name_problem(std::string_view name) {
  auto alnum = [](char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9'); };
  bool ok = !name.empty() && name.size() <= max_name_length && alnum(name.front());
  for (char c : name) ok = ok && (alnum(c) || c == '_' || c == '-' || c == '.');
  if (ok) return {};
  std::string shown(name.substr(0, 60));
  for (char& c : shown)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = '?';  // one line, whatever the input
  if (name.size() > 60) shown += "...";
  return "\"" + shown + "\"" + (name.size() > max_name_length ? " is " + std::to_string(name.size()) + " characters long" : "") +
         " (allowed: 1 to " + std::to_string(max_name_length) +
         " letters, digits, '_', '-' and '.', starting with a letter or digit; it names a folder)";
}

std::string test_name_problem(std::string_view name) {
  if (std::string why = name_problem(name); !why.empty()) return why;
  std::string lower(name);
  for (char& c : lower)
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  std::string list;
  bool reserved = false;
  for (const std::string_view r : reserved_names) {
    if (!list.empty()) list.append(", ");
    list.append(r);
    reserved = reserved || lower == r || (lower.size() > r.size() && lower.starts_with(r) && lower[r.size()] == '.');
  }
  if (!reserved) return {};
  std::string why = "\"";
  why.append(name);
  why.append("\" is a name salsa uses for its own files in the output folder (allowed: any other name; reserved: ");
  why.append(list);
  why.append(" and those names followed by '.')");
  return why;
}

}  // namespace salsa
