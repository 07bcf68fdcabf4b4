// Why a plugin file or registration is refused, in words: errno and exception text, name and parameter rules, toolchains.
#include <cxxabi.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <new>
#include <tuple>

#include "plugins/loading.hpp"
#include "format.hpp"

namespace salsa::detail {

namespace {


constexpr std::size_t max_plugin_name = 64;

}  // namespace

std::string errno_text(int error) {
  switch (error) {
    case ELOOP: return "symbolic link loop";
    case EACCES: case EPERM: return "permission denied";
    default: {
      std::string s = std::strerror(error);
      if (!s.empty()) s[0] = static_cast<char>(std::tolower(static_cast<unsigned char>(s[0])));
      return s;
    }
  }
}

std::string one_line(const char* text) {
  std::string s = text ? text : "";
  std::replace_if(s.begin(), s.end(), [](char c) { return c == '\n' || c == '\r'; }, ' ');
  return s;
}

std::string shown(std::string_view name) {
  std::string s(name.substr(0, 60));
  for (char& c : s)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = '?';
  return '"' + s + (name.size() > 60 ? "...\"" : "\"");
}

std::string current_exception_text() {
  try {
    throw;
  } catch (const std::bad_alloc&) {
    return "out of memory (std::bad_alloc)";
  } catch (const std::exception& e) {
    return one_line(e.what());
  } catch (const char* text) {
    return one_line(text);
  } catch (...) {
    const std::type_info* type = abi::__cxa_current_exception_type();
    if (!type) return "an unknown exception";
    int status = 0;
    char* name = abi::__cxa_demangle(type->name(), nullptr, nullptr, &status);
    std::string out = "an exception of type " + std::string(status == 0 && name ? name : type->name()) +
                      " (not a std::exception)";
    std::free(name);
    return out;
  }
}

bool identifier_like(std::string_view name) {
  auto letter = [](char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z'); };
  if (name.empty() || name.size() > max_plugin_name || !letter(name.front())) return false;
  return std::all_of(name.begin(), name.end(),
                     [&](char c) { return letter(c) || (c >= '0' && c <= '9') || c == '_' || c == '-'; });
}
std::string name_rule() {
  return "a name starts with a letter and uses only letters, digits, '_' and '-', 1 to " +
         std::to_string(max_plugin_name) + " characters";
}

std::string parameters_problem(const Parameters& params) {
  for (std::size_t i = 0; i < params.size(); ++i) {
    const Parameter& p = params[i];
    if (!identifier_like(p.name)) return "parameter " + shown(p.name) + ": not a valid name: " + name_rule();
    const std::string at = "parameter '" + p.name + "': ";
    for (std::size_t j = 0; j < i; ++j)
      if (params[j].name == p.name) return at + "declared twice";
    for (auto [what, v] : {std::pair{"default", p.value}, {"min", p.min}, {"max", p.max}, {"step", p.step}})
      if (!std::isfinite(v)) return at + what + " " + format::number(v) + " is not a finite number";
    if (p.min > p.max) return at + "min " + format::number(p.min) + " is greater than max " + format::number(p.max);
    if (p.step < 0) return at + "step " + format::number(p.step) + " is negative";
    if (p.value < p.min || p.value > p.max)
      return at + "default " + format::number(p.value) + " is outside [" + format::number(p.min) + ", " + format::number(p.max) + "]";
    if (!p.check(p.value).empty()) return at + "default " + format::number(p.value) + " is not a whole number (step 1)";
  }
  return {};
}

std::string toolchain_difference(std::uint32_t theirs, std::uint32_t ours) {
  std::vector<std::string> facts;
  if ((theirs & 1) != (ours & 1))
    facts.push_back((theirs & 1) ? "built with the new C++ ABI (_GLIBCXX_USE_CXX11_ABI=1), this salsa uses the old one"
                                 : "built with the old C++ ABI (_GLIBCXX_USE_CXX11_ABI=0), this salsa uses the new one");
  // The layout of toolchain_tag(): sizeof std::string << 16 | std::function << 8 | std::vector << 1.
  for (auto [type, shift, mask] : {std::tuple{"std::string", 16u, 0xffffu}, {"std::function", 8u, 0xffu},
                                   {"std::vector", 1u, 0x7fu}}) {
    const std::uint32_t there = theirs >> shift & mask, here = ours >> shift & mask;
    if (there != here)
      facts.push_back(std::string(type) + " is " + std::to_string(there) + " bytes there, " + std::to_string(here) + " here");
  }
  std::string out = "incompatible C++ standard library: ";
  if (facts.empty()) return out + "toolchain tag " + std::to_string(theirs) + ", expected " + std::to_string(ours);
  for (std::size_t i = 0; i < facts.size(); ++i) out += (i ? "; " : "") + facts[i];
  return out + " (rebuild it with the compiler and standard library salsa was built with)";
}

}  // namespace salsa::detail
