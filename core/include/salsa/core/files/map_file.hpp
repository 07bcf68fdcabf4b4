#pragma once
// Writing a map in the map file format the json map plugin reads (docs/maps.md): a test's map.json
// and the map creator's saves. One shape per line.
#include <filesystem>
#include <string>

#include "salsa/map.hpp"

namespace salsa {

/// `map` with its spawn replaced by `spawn` (the point the drones started around) as map file text.
/// Numbers are the shortest text that reads back to the same double, so the json map plugin gives
/// back the same MapData and the same map gives the same bytes on every run.
std::string map_json(const MapData& map, Vec2 spawn);

/// Reads a map file's geometry (bounds, obstacles, hollow, lines, spawn) as map_json writes it: a
/// test folder's map.json for replay and export, without the json map plugin. Throws InputError (one
/// line naming the file and the field).
MapData read_map_file(const std::filesystem::path& file);

}  // namespace salsa
