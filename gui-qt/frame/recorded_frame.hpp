#pragma once
// A recorded run's frames as snapshots (the Recording of a finished test, core/replay): what replay
// in the desktop, video export and the Python package draw, through the same renderer as a live run.
#include <cstddef>
#include <memory>
#include <utility>
#include <vector>

#include "salsa/core/replay/recording.hpp"
#include "snapshot.hpp"

namespace salsa::gui {

/// The recording's scene: its map, each group's base, the targets (where they were placed) and their radius.
std::shared_ptr<const Scene> scene_of(const Recording& recording);

/// What `recording` shows at `frame`: its time, the groups, every drone's position, velocity, group,
/// status and camera, the targets found by then, and trails of the last `trail_length` frames (0: none).
/// The scene is `scene` (scene_of, made once). The step is the frame's time in the test's steps.
Snapshot recorded_snapshot(const Recording& recording, std::shared_ptr<const Scene> scene, std::size_t frame, std::size_t trail_length);

/// Drone `id` at `frame` as the inspector shows it: its group, position, status (with the fleet's
/// columns recorded), every recorded state column, and the flying drones within its detection range
/// then. What a run does not record (obstacle hits, messages, a behavior's memory) is left out.
Inspection recorded_inspection(const Recording& recording, std::size_t frame, std::uint32_t id);

/// With a `wind` column recorded: the wind the flying drones flew in at `frame`, averaged on the live
/// view's grid (Snapshot::wind). Empty without one.
std::vector<std::pair<Vec2, Vec2>> recorded_wind(const Recording& recording, std::size_t frame);

}  // namespace salsa::gui
