// libFuzzer target for the plugin-file check: any bytes must give an answer (a reason or ok), never
// a crash, a read outside the buffer or a hang.
#include <cstddef>
#include <cstdint>

#include "plugins/elf_check.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  (void)salsa::elf_problem(data, size);
  return 0;
}
