#pragma once
// The trajectory archive: a test's drone state columns over time as one netCDF-4 (HDF5) file.
#include <filesystem>

#include "salsa/core/replay/recording.hpp"

namespace salsa {

/// The archive's name in a test folder.
inline constexpr const char* archive_name = "trajectories.nc";

/// Reads the archive `file` into `into`'s times, drones, columns, targets and provenance. Throws
/// InputError (one line naming the file).
void read_archive(const std::filesystem::path& file, Recording& into);

}  // namespace salsa
