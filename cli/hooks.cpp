// The steps other parts of salsa take after a test or a queue is written, wired in one place.
#include "queue_run.hpp"

#include "salsa/core/comparison.hpp"
#include "salsa/plots/results.hpp"

namespace salsa::cli {

Hooks& hooks() {
  static Hooks h = [] {
    Hooks wired;
    wired.start_plotting = plots::start_plotting;
    wired.draw_test_plots = plots::draw_test_plots;
    wired.draw_queue_plots = plots::draw_queue_plots;
    wired.write_comparison = [](const std::filesystem::path& out) { write_comparison(out); };
    return wired;
  }();
  return h;
}

}  // namespace salsa::cli
