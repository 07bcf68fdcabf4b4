// libFuzzer target: test JSON through parse_test (the reader of test files, queues and config.json),
// with the built-in plugins. What it accepts must come back from its config.json unchanged.
#include <cstdint>
#include <string>

#include "fuzz_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const salsa::PluginHost& host = salsa_fuzz::host();
  std::string config;
  try {
    config = salsa::resolved_json(salsa::parse_test(text, "fuzz.json", host, salsa_fuzz::scratch()), host);
  } catch (const salsa::InputError& e) {
    salsa_fuzz::check_message(e);
    return 0;
  }
  // config.json reruns the test exactly: it reads back to the very same text.
  if (salsa::resolved_json(salsa::parse_test(config, "config.json", host), host) != config) std::abort();
  return 0;
}
