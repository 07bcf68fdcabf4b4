#pragma once
// `salsa-gui --bench-replay FOLDER`: what replay in the desktop costs on a finished test: loading it,
// a seek to a random time (the frame's snapshot made and drawn at 1920×1080, as a view shows it after
// the timeline is dragged), and playback (consecutive frames, each made and drawn) in frames per second.
#include <filesystem>
#include <ostream>

namespace salsa::gui {

/// Prints the report to `out`; returns the process exit status (2: `folder` is not a finished test).
int bench_replay(const std::filesystem::path& folder, std::ostream& out, int seeks = 200);

}  // namespace salsa::gui
