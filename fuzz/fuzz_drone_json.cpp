// libFuzzer target: drone configuration files, read through a test that names them.
#include <cstdint>

#include "fuzz_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  salsa_fuzz::write("fleet.json", data, size);
  try {
    salsa::parse_test(R"({"behavior": "flocking", "drone_configs": "fleet.json"})", "fuzz.json", salsa_fuzz::host(),
                      salsa_fuzz::scratch());
  } catch (const salsa::InputError& e) {
    salsa_fuzz::check_message(e);
  }
  return 0;
}
