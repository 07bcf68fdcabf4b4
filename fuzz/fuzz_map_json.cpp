// libFuzzer target: map files through the json map plugin and the core's checks of what it returns.
#include <cstdint>

#include "fuzz_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto file = salsa_fuzz::write("map.json", data, size);
  try {
    salsa::load_map_file(file, salsa_fuzz::host());
  } catch (const salsa::InputError& e) {
    salsa_fuzz::check_message(e);
  }
  return 0;
}
