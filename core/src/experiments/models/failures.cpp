// The failures model: a test's random failures of drones and cameras ("failures": {...}).
#include "models.hpp"

#include "salsa/core/experiments/test_spec.hpp"

namespace salsa::models {

TestModel failures() {
  return {
      .key = "failures",
      .meaning = "failures: a test's random failures (\"failures\": {...}; absent: no drone fails on its own). Each drone's\n"
                 "failure times come from the seed alone, so every behavior of a repeat loses the same drones at the\n"
                 "same times. Timed changes and sweeps set them as failures.<name>.",
      .fields = bound_fields<&TestSpec::failures>(failure_schema()),
      .in_use = [](const TestSpec& t) { return t.failures != FailureSetup{}; },
      .apply = [](Simulation& sim, const TestSpec& t) { sim.set_failures(t.failures); },
  };
}

}  // namespace salsa::models
