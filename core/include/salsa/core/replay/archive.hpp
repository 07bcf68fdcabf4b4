#pragma once
// The trajectory archive, trajectories.nc: the drones' state columns (archive_columns and those asked
// for by name) at every logged time, and the targets, in one compressed netCDF-4 file (HDF5 underneath, CF-1.8 attributes),
// which xarray, h5py and the netCDF tools open directly (docs/output-format.md, "trajectories.nc").
// Written here once, read back here once (read_archive, for load_recording).
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "salsa/core/model/columns.hpp"
#include "salsa/core/replay/recording.hpp"
#include "salsa/metric.hpp"  // TargetState

namespace salsa {

/// The archive's name in a test's folder.
inline constexpr const char* archive_name = "trajectories.nc";
/// The state columns an archive holds (those the simulation keeps): drones.csv's, what a replay draws,
/// and the battery. Any other is added by name (`salsa run --drone-columns`, as for drones.csv): the
/// per-step ones, steering and commanded, would double the archive.
inline constexpr std::string_view archive_columns[] = {"position",     "velocity",    "group",        "status", "status_since",
                                                       "camera_works", "energy_used", "battery_left", "errand", "charging_time"};
/// The archive format's version, its global attribute salsa_archive_version: a reader refuses a newer one.
inline constexpr int archive_version = 1;

/// What the archive records about the test that wrote it (its global attributes).
struct ArchiveProvenance {
  std::string test_name, salsa_version;
  std::string config;  ///< the test's config.json text
  std::uint64_t seed = 0;
  double dt = 0, log_interval = 0;  ///< s
  std::vector<std::string> groups;  ///< group names by index
  /// The most drone ids the run can have (timed changes that add drones included): the chunks are
  /// shaped for it. More is written correctly, only slower.
  std::size_t drones = 0;
  /// The columns the run asked to record (archive_columns and those named), in the global attribute
  /// salsa_drone_columns: `--resume` reruns a test whose archive was not asked for a column named now
  /// (one asked for is in the file once the simulation kept it).
  std::vector<std::string> columns;
};

/// Writes one archive while its test runs: a frame per logged step, the targets at the end. The file
/// is written as `<file>.part` and renamed to `file` by close(), so a run cut short leaves no file of
/// the archive's name. Throws WriteError naming the file.
class ArchiveWriter {
 public:
  ArchiveWriter(std::filesystem::path file, ArchiveProvenance provenance);
  ~ArchiveWriter();  ///< without close(): the frames so far stay in `<file>.part`
  ArchiveWriter(const ArchiveWriter&) = delete;
  ArchiveWriter& operator=(const ArchiveWriter&) = delete;

  /// The drones' state at `time`: every column of `columns` (Simulation::columns()), a column first
  /// seen now recorded from now on (earlier frames hold its fill value). A removed drone (status 3)
  /// has the fill value in every column but status.
  void frame(double time, const std::vector<StateColumn>& columns);
  /// Writes the targets, closes the file and gives it its name.
  void close(const std::vector<TargetState>& targets, double target_radius);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Reads `file` into `into`: times, drones, columns, targets, found_time, found_by, target_radius,
/// test_name, seed, salsa_version, dt, log_interval and source. Throws InputError with one line naming
/// the file and what is wrong (not a netCDF-4 file, corrupt or truncated, from a newer salsa, a
/// variable missing or of the wrong shape). Writes nothing.
void read_archive(const std::filesystem::path& file, Recording& into);

/// Those of `wanted` (state column names) that `file`'s run was not asked to record, comma-separated;
/// "" when it was asked for all. An archive without salsa_drone_columns recorded archive_columns. An
/// unreadable file lacks them all.
std::string archive_lacks(const std::filesystem::path& file, const std::vector<std::string>& wanted);

}  // namespace salsa
