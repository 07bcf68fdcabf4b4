#pragma once
// A recorded run's frames as snapshots (the Recording of a finished test, core/replay): what replay
// in the desktop, video export and the Python package draw, through the same renderer as a live run.
#include <cstddef>
#include <memory>

#include "salsa/core/replay/recording.hpp"
#include "snapshot.hpp"

namespace salsa::gui {

/// The recording's scene: its map, each group's base, the targets (where they were placed) and their radius.
std::shared_ptr<const Scene> scene_of(const Recording& recording);

/// What `recording` shows at `frame`: its time, the groups, every drone's position, velocity, group,
/// status and camera, the targets found by then, and trails of the last `trail_length` frames (0: none).
/// The scene is `scene` (scene_of, made once). The step is the frame's time in the test's steps.
Snapshot recorded_snapshot(const Recording& recording, std::shared_ptr<const Scene> scene, std::size_t frame, std::size_t trail_length);

}  // namespace salsa::gui
