#include "salsa/core/files/names.hpp"

namespace salsa {

namespace {
// Empty when `name` is 1 to max_name_length letters, digits, '_', '-' (and '.' with `dots`) starting
// with a letter or digit, else the name shown on one line and `rules`.
std::string name_check(std::string_view name, bool dots, const std::string& rules) {
  auto alnum = [](char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9'); };
  bool ok = !name.empty() && name.size() <= max_name_length && alnum(name.front());
  for (char c : name) ok = ok && (alnum(c) || c == '_' || c == '-' || (dots && c == '.'));
  if (ok) return {};
  std::string shown(name.substr(0, 60));
  for (char& c : shown)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = '?';  // one line, whatever the input
  if (name.size() > 60) shown += "...";
  return "\"" + shown + "\"" + (name.size() > max_name_length ? " is " + std::to_string(name.size()) + " characters long" : "") + " (allowed: 1 to " +
         std::to_string(max_name_length) + rules + ")";
}
}  // namespace

std::string name_problem(std::string_view name) {
  return name_check(name, true, " letters, digits, '_', '-' and '.', starting with a letter or digit; it names a folder");
}

std::string group_name_problem(std::string_view name) {
  return name_check(name, false,
                    " letters, digits, '_' and '-', starting with a letter or digit; it names the group's columns, and keys such as "
                    "groups.<name>.drones split at dots");
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
