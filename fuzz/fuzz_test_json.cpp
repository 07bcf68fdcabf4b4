// libFuzzer target: test JSON as a file (load_tests: one test, a list or a queue, names from the file
// name) and as text (parse_test, which also reads config.json), with the built-in plugins. Every test
// accepted has a name fit for a folder, and its config.json reads back to the very same text.
#include <cstdint>
#include <string>
#include <vector>

#include "fuzz_common.hpp"
#include "salsa/core/files/names.hpp"

namespace {

void check_accepted(const salsa::TestSpec& t) {
  const salsa::PluginHost& host = salsa_fuzz::host();
  if (!salsa::name_problem(t.name).empty()) std::abort();
  const std::string config = salsa::resolved_json(t, host);
  if (salsa::resolved_json(salsa::parse_test(config, "config.json", host), host) != config) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const salsa::PluginHost& host = salsa_fuzz::host();
  try {
    for (const auto& t : salsa::load_tests(salsa_fuzz::write("queue.json", data, size), host)) check_accepted(t);
  } catch (const salsa::InputError& e) {
    salsa_fuzz::check_message(e);
  }
  try {
    check_accepted(salsa::parse_test(std::string(reinterpret_cast<const char*>(data), size), "fuzz.json", host,
                                     salsa_fuzz::scratch()));
  } catch (const salsa::InputError& e) {
    salsa_fuzz::check_message(e);
  }
  return 0;
}
