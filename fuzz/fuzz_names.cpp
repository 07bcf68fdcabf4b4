// Names that become paths: whatever the text, the check answers in one line, and what it accepts
// cannot leave the folder it is joined to.
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "salsa/core/files/names.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view name(reinterpret_cast<const char*>(data), size);
  const std::string why = salsa::name_problem(name);
  if (why.empty() && (name.find('/') != name.npos || name == "." || name == ".." || name.empty())) std::abort();
  if (why.find('\n') != why.npos) std::abort();
  return 0;
}
