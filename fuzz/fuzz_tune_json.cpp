// libFuzzer target: tune files (load_tune, core/src/experiments/tune_file.cpp) with the built-in plugins; the base test
// inline or as a path (scratch/flocking.json exists). load_tune reads the test at each range's ends;
// an accepted file's candidate in the middle of every range is read too, or refused in one line.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <optional>
#include <vector>

#include "fuzz_common.hpp"
#include "salsa/core/experiments/tune_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const salsa::PluginHost& host = salsa_fuzz::host();
  static const bool test_file = [] {
    const char test[] = R"({"behavior": "flocking", "drones": 5, "time": 5, "targets": {"count": 20}})";
    salsa_fuzz::write("flocking.json", reinterpret_cast<const uint8_t*>(test), std::strlen(test));
    return true;
  }();
  (void)test_file;
  std::optional<salsa::TuneSpec> spec;
  try {
    spec = salsa::load_tune(salsa_fuzz::write("tune.json", data, size), host);
  } catch (const salsa::InputError& e) {
    salsa_fuzz::check_message(e);
    return 0;
  }
  if (spec->parameters.empty() || spec->objectives.empty() || spec->canonical.empty()) std::abort();
  std::vector<double> middle;
  for (const salsa::TuneParameter& p : spec->parameters) {
    if (!(p.min < p.max)) std::abort();
    middle.push_back(p.whole ? std::floor((p.min + p.max) / 2) : (p.min + p.max) / 2);
  }
  try {
    salsa::candidate_test(*spec, middle, "middle", 1, host);
  } catch (const salsa::InputError& e) {
    salsa_fuzz::check_message(e);  // a combination the test refuses: allowed, in one line
  }
  return 0;
}
