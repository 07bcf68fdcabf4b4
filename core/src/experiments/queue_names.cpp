// How a queue names its tests: safe characters, values as tokens, the file's name for a test without one, names cut to fit.
#include <cctype>
#include <cstdio>

#include "salsa/core/files/names.hpp"
#include "experiments/fnv1a.hpp"
#include "experiments/queue_reader.hpp"
#include "format.hpp"

namespace salsa::detail {

std::string name_safe(std::string text) {
  for (char& c : text)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-' && c != '.') c = '_';
  return text;
}

std::string number_token(double v) {
  std::string s = format::number(v);
  std::erase(s, '+');
  return s;
}

std::string short_name(const Parameters& schema, const std::string& name) {
  auto initials = [](const std::string& n) {
    if (n.find('_') == std::string::npos) return n;
    std::string out;
    for (std::size_t i = 0; i < n.size(); ++i)
      if (n[i] != '_' && (i == 0 || n[i - 1] == '_')) out += n[i];
    return out;
  };
  const std::string mine = initials(name);
  for (const Parameter& p : schema)
    if (p.name != name && initials(p.name) == mine) return name;
  return mine;
}

std::string fitted(const std::string& name, const std::string& suffix) {
  if (name.size() + suffix.size() <= max_name_length) return name + suffix;
  char hash[12];
  std::snprintf(hash, sizeof hash, "_%08x", static_cast<unsigned>(fnv1a64(name) >> 32));
  return name.substr(0, max_name_length - suffix.size() - 9) + hash + suffix;
}

void name_after_file(TestSpec& t, const std::string& name) {
  if (!t.name.empty()) return;
  if (const std::string why = test_name_problem(name); !why.empty())
    throw InputError(t.source + ": name: missing, and the file name cannot stand in for it: " + why + "; give the test a \"name\"");
  t.name = name;
}

void join(std::string& to, const std::string& part, const char* separator) {
  if (!part.empty()) to += (to.empty() ? "" : separator) + part;
}

std::string behavior_name(const json& test) {
  if (test.contains("behavior")) return entry_name(test["behavior"]);
  std::string out;
  if (test.contains("groups") && test["groups"].is_array())
    for (const json& group : test["groups"])
      if (group.is_object() && group.contains("behavior")) {
        if (!out.empty()) out += '+';  // not "+" + string: GCC 12 warns falsely about that here (-Wrestrict)
        out += entry_name(group["behavior"]);
      }
  return out;
}

}  // namespace salsa::detail
