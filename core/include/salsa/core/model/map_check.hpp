#pragma once
// The map rules, in one place: what is wrong with a map as drawn. The map creator lists these live and
// draws the shapes they name in red; a map file is refused by them wherever it is used (the json map
// plugin reads the file's shape only; docs/maps.md); a plugin's map meets the structure rules.
#include <cstddef>
#include <string>
#include <vector>

#include "salsa/core/model/static_geometry.hpp"  // inside_polygon
#include "salsa/map.hpp"

namespace salsa {

struct MapProblem {
  enum class Part { bounds, obstacle, hollow, line, spawn };
  Part part;
  std::size_t index = 0;  ///< which obstacle, outline or line (0 for bounds and spawn)
  std::string field;      ///< as in a map file's errors: "obstacles[2]", "lines[0][1]", "spawn"
  std::string message;    ///< what is wrong and what is allowed
};

/// Which rules: `structure` is what the simulation needs of any map, whoever made it (a plugin, a
/// file, the creator): finite bounds with max above min, shapes with enough points, every point finite
/// and within the bounds, a finite spawn point. `drawing` adds what a drawn or saved map promises: no
/// polygon whose edges cross, a spawn point within the bounds and in free space.
enum class MapRules { structure, drawing };

/// The map's problems, in file order (bounds, obstacles, hollow outlines, lines, spawn), at most `most`
/// of them, each with its field, the value and what is allowed: the one wording of the map rules, for
/// the map creator's list and the simulation's refusal alike. Empty: the map saves and loads.
/// `drone_radius` m: the spawn point needs that much free space around it.
std::vector<MapProblem> map_problems(const MapData& map, double drone_radius = 1, MapRules rules = MapRules::drawing,
                                     std::size_t most = static_cast<std::size_t>(-1));

/// Whether the segments a-b and c-d share a point (touching and overlapping count).
bool segments_touch(Vec2 a, Vec2 b, Vec2 c, Vec2 d);
/// The first pair of edges (i, j), i < j, of the closed polygon `poly` that cross, other than
/// neighbours meeting at their shared vertex; {0, 0} when it is simple. O(n log n)-like for polygons
/// whose edges are spread out (a grid of edges), whatever their count.
std::pair<std::size_t, std::size_t> crossing_edges(const Polyline& poly);

}  // namespace salsa
