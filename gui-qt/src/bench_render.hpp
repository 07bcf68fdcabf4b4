#pragma once
// `salsa-gui --bench-render`: frame times of the sandbox view at 1920×1080 for 1,000 drones and 50,000
// targets with trails on, and the simulation's speed in the GUI against headless (docs/gui.md).
#include <ostream>

#include "salsa/core/plugins/plugin_host.hpp"

namespace salsa::gui {

/// Prints the report to `out`; returns the process exit status.
int bench_render(const PluginHost& host, std::ostream& out, int frames = 300);

}  // namespace salsa::gui
