// The trajectory archive through the netCDF-C library: one netCDF-4 file (HDF5 underneath) whose
// variables are the drones' state columns over (time, drone), compressed with shuffle + deflate and
// chunked along the unlimited time and drone dimensions (the drones may grow by a timed change).
// Lengths and speeds are packed as whole millimetres (CF's scale_factor, which xarray undoes).
#include "salsa/core/replay/archive.hpp"

#include <netcdf.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <string_view>
#include <system_error>

#include "salsa/core/files/csv_writer.hpp"  // WriteError
#include "salsa/core/files/input_error.hpp"

namespace salsa {

namespace fs = std::filesystem;

namespace {
/// netCDF-C is not thread-safe, and `salsa run --jobs` writes and checks archives from several worker
/// threads at once: every call into it holds this lock (recursive: a writer's methods call each other).
std::recursive_mutex& netcdf_lock() {
  static std::recursive_mutex lock;
  return lock;
}
}  // namespace

namespace {

constexpr double nan = std::numeric_limits<double>::quiet_NaN();
/// Deflate level 1: level 4 makes the archive 6 % smaller and its writing as costly as drones.csv's,
/// level 9 8 % at many times the time (docs/benchmarks.md, "Trajectory archive").
constexpr int deflate_level = 1;
/// A packed column's resolution: 1 mm (mm/s), five times finer than Box2D's contact tolerance (its
/// linear slop, 5 mm). Doubles' last digits are noise that no compressor shrinks: as whole millimetres
/// the archive is 5× smaller than drones.csv (docs/benchmarks.md, "Trajectory archive").
constexpr double packed_resolution = 1e-3;
constexpr int packed_fill = NC_FILL_INT;
/// Values per chunk (about 512 KB of doubles): the chunk holds as many frames as make it up.
constexpr std::size_t chunk_values = 65536;
constexpr std::size_t max_chunk_frames = 1024;
/// Drone rows held before they are written, whatever the chunks (about 50 MB with every column).
constexpr std::size_t max_pending_rows = 4 * chunk_values;

/// A length or a speed: packed as whole millimetres (per second).
bool packed(const StateColumn& c) { return c.type == StateColumn::Type::f64 && (c.unit == "m" || c.unit == "m/s"); }

/// The column's type in the file and its fill value, which marks "no value" (a removed drone, a frame
/// before the column was kept) and reads back as NaN.
nc_type nc_type_of(StateColumn::Type t) { return t == StateColumn::Type::u8 ? NC_UBYTE : t == StateColumn::Type::u32 ? NC_UINT : NC_DOUBLE; }
double fill_of(StateColumn::Type t) {
  return t == StateColumn::Type::u8 ? NC_FILL_UBYTE : t == StateColumn::Type::u32 ? static_cast<double>(NC_FILL_UINT) : nan;
}

bool alphabetic(std::string_view s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](unsigned char c) { return std::isalpha(c); });
}

/// salsa's unit as CF/UDUNITS writes it: "m/s" → "m s-1", "1/s" → "s-1"; others as they are.
std::string cf_unit(std::string_view u) {
  const auto slash = u.find('/');
  if (slash == std::string_view::npos || !alphabetic(u.substr(slash + 1))) return std::string(u);
  const std::string_view num = u.substr(0, slash);
  return (num == "1" ? std::string() : std::string(num) + " ") + std::string(u.substr(slash + 1)) + "-1";
}

/// cf_unit's inverse.
std::string salsa_unit(std::string_view u) {
  if (!u.ends_with("-1")) return std::string(u);
  const auto space = u.rfind(' ');
  std::string_view den = u.substr(space == std::string_view::npos ? 0 : space + 1);
  den.remove_suffix(2);
  if (!alphabetic(den)) return std::string(u);
  return (space == std::string_view::npos ? std::string("1") : std::string(u.substr(0, space))) + "/" + std::string(den);
}

}  // namespace

// ---- Writing

struct ArchiveWriter::Impl {
  fs::path file, part;
  ArchiveProvenance provenance;
  int nc = -1;
  int time_dim = -1, drone_dim = -1, xy_dim = -1;
  int time_var = -1, drone_var = -1;
  std::size_t chunk_drones = 0, chunk_frames = 0;

  /// A state column's variable and its frames not yet written (a chunk's worth is written at once).
  struct Var {
    std::string name;
    int id = -1;
    StateColumn::Type type = StateColumn::Type::f64;
    std::size_t width = 1;
    bool packed = false;          ///< stored as whole millimetres (packed_resolution)
    std::vector<double> pending;  ///< the pending frames' values, each frame rows[f] × width
  };
  std::vector<Var> vars;
  std::size_t written = 0;         ///< frames in the file
  std::vector<double> times;       ///< the pending frames' times
  std::vector<std::size_t> rows;   ///< the pending frames' drones

  ~Impl() {
    if (nc >= 0) nc_close(nc);
  }

  void check(int status, const std::string& what) const {
    if (status != NC_NOERR) throw WriteError(part.string() + ": " + what + " (" + nc_strerror(status) + ")");
  }
  void text(int var, const char* name, std::string_view value) const {
    check(nc_put_att_text(nc, var, name, value.size(), value.data()), std::string("cannot write attribute ") + name);
  }
  void redef() const {
    if (const int s = nc_redef(nc); s != NC_EINDEFINE) check(s, "cannot define a variable");
  }

  void open() {
    check(nc_create(part.c_str(), NC_NETCDF4 | NC_CLOBBER, &nc), "cannot create file");
    check(nc_def_dim(nc, "time", NC_UNLIMITED, &time_dim), "cannot define dimension time");
    check(nc_def_dim(nc, "drone", NC_UNLIMITED, &drone_dim), "cannot define dimension drone");
    check(nc_def_dim(nc, "xy", 2, &xy_dim), "cannot define dimension xy");
    check(nc_def_var(nc, "time", NC_DOUBLE, 1, &time_dim, &time_var), "cannot define variable time");
    const std::size_t coordinate_chunk = 1024;
    check(nc_def_var_chunking(nc, time_var, NC_CHUNKED, &coordinate_chunk), "cannot chunk variable time");
    check(nc_def_var_deflate(nc, time_var, 1, 1, deflate_level), "cannot compress variable time");
    text(time_var, "units", "s");
    text(time_var, "long_name", "simulated time");
    text(time_var, "axis", "T");
    check(nc_def_var(nc, "drone", NC_UINT, 1, &drone_dim, &drone_var), "cannot define variable drone");
    check(nc_def_var_chunking(nc, drone_var, NC_CHUNKED, &coordinate_chunk), "cannot chunk variable drone");
    check(nc_def_var_deflate(nc, drone_var, 1, 1, deflate_level), "cannot compress variable drone");
    text(drone_var, "long_name", "drone id");
    int xy_var = -1;
    check(nc_def_var(nc, "xy", NC_STRING, 1, &xy_dim, &xy_var), "cannot define variable xy");
    text(xy_var, "long_name", "a vector's component");

    const ArchiveProvenance& p = provenance;
    text(NC_GLOBAL, "Conventions", "CF-1.8");
    text(NC_GLOBAL, "title", "salsa test " + p.test_name + ": the drones' state over time");
    text(NC_GLOBAL, "source", "salsa " + p.salsa_version);
    text(NC_GLOBAL, "salsa_version", p.salsa_version);
    const int version = archive_version;
    check(nc_put_att_int(nc, NC_GLOBAL, "salsa_archive_version", NC_INT, 1, &version), "cannot write attribute salsa_archive_version");
    text(NC_GLOBAL, "test_name", p.test_name);
    const unsigned long long seed = p.seed;
    check(nc_put_att_ulonglong(nc, NC_GLOBAL, "seed", NC_UINT64, 1, &seed), "cannot write attribute seed");
    check(nc_put_att_double(nc, NC_GLOBAL, "dt", NC_DOUBLE, 1, &p.dt), "cannot write attribute dt");
    check(nc_put_att_double(nc, NC_GLOBAL, "log_interval", NC_DOUBLE, 1, &p.log_interval), "cannot write attribute log_interval");
    text(NC_GLOBAL, "config", p.config);
    std::string columns;
    for (const std::string& c : p.columns) columns += (columns.empty() ? "" : ",") + c;
    if (!columns.empty()) text(NC_GLOBAL, "salsa_drone_columns", columns);
    check(nc_enddef(nc), "cannot write the file's definitions");
    const char* names[] = {"x", "y"};
    const std::size_t start = 0, count = 2;
    check(nc_put_vara_string(nc, xy_var, &start, &count, names), "cannot write variable xy");
  }

  Var& define(const StateColumn& c, std::size_t drones) {
    if (chunk_drones == 0) {  // the first column fixes the chunks' shape: whole frames while they fit
      chunk_drones = std::clamp<std::size_t>(std::max(drones, provenance.drones), 1, chunk_values);
      chunk_frames = std::clamp<std::size_t>(chunk_values / chunk_drones, 1, max_chunk_frames);
    }
    Var v{std::string(c.name), -1, c.type, c.width, packed(c), {}};
    redef();
    const int dims[] = {time_dim, drone_dim, xy_dim};
    const int ndims = c.width == 2 ? 3 : 2;
    check(nc_def_var(nc, v.name.c_str(), v.packed ? NC_INT : nc_type_of(c.type), ndims, dims, &v.id), "cannot define variable " + v.name);
    const std::size_t chunks[] = {chunk_frames, chunk_drones, 2};
    check(nc_def_var_chunking(nc, v.id, NC_CHUNKED, chunks), "cannot chunk variable " + v.name);
    check(nc_def_var_deflate(nc, v.id, 1, 1, deflate_level), "cannot compress variable " + v.name);
    if (v.packed) {
      check(nc_def_var_fill(nc, v.id, NC_FILL, &packed_fill), "cannot set the fill value of " + v.name);
      check(nc_put_att_double(nc, v.id, "scale_factor", NC_DOUBLE, 1, &packed_resolution), "cannot write attribute scale_factor");
    } else if (c.type == StateColumn::Type::f64) check(nc_def_var_fill(nc, v.id, NC_FILL, &nan), "cannot set the fill value of " + v.name);
    else if (c.type == StateColumn::Type::u32) {
      const unsigned int fill = NC_FILL_UINT;
      check(nc_def_var_fill(nc, v.id, NC_FILL, &fill), "cannot set the fill value of " + v.name);
    } else {
      const unsigned char fill = NC_FILL_UBYTE;
      check(nc_def_var_fill(nc, v.id, NC_FILL, &fill), "cannot set the fill value of " + v.name);
    }
    text(v.id, "long_name", c.meaning);
    if (!c.unit.empty()) text(v.id, "units", cf_unit(c.unit));
    text(v.id, "salsa_model", c.model);
    // The codes' names, as CF flags: status's, and the groups' (their names hold no spaces).
    if (v.name == "status") {
      const unsigned char codes[] = {0, 1, 2, 3};
      check(nc_put_att_uchar(nc, v.id, "flag_values", NC_UBYTE, 4, codes), "cannot write attribute flag_values");
      text(v.id, "flag_meanings", "flying landed failed removed");
    } else if (v.name == "group" && c.type == StateColumn::Type::u32) {
      std::vector<unsigned int> codes;
      std::string meanings;
      for (const std::string& g : provenance.groups) {
        codes.push_back(static_cast<unsigned int>(codes.size()));
        meanings += (meanings.empty() ? "" : " ") + g;
      }
      check(nc_put_att_uint(nc, v.id, "flag_values", NC_UINT, codes.size(), codes.data()), "cannot write attribute flag_values");
      text(v.id, "flag_meanings", meanings);
    }
    check(nc_enddef(nc), "cannot write the definition of " + v.name);
    v.pending.assign(pending_rows() * v.width, fill_of(c.type));  // the frames pending from before it
    return vars.emplace_back(std::move(v));
  }

  /// Drones over the frames pending so far (a column first seen now has the fill value in them).
  std::size_t pending_rows() const {
    std::size_t n = 0;
    for (const std::size_t r : rows) n += r;
    return n;
  }

  /// `value` of `v` in whole millimetres; NaN (no value) as the fill value.
  int pack(const Var& v, double value) const {
    if (std::isnan(value)) return packed_fill;
    const double mm = std::nearbyint(value / packed_resolution);
    if (!(std::abs(mm) < -static_cast<double>(packed_fill))) {
      char shown[32];
      std::snprintf(shown, sizeof shown, "%g", value);
      throw WriteError(part.string() + ": " + v.name + " " + shown + " is beyond what the archive holds (allowed: within ±2147483 m or m/s, whole millimetres in 32 bits)");
    }
    return static_cast<int>(mm);
  }

  std::vector<int> packed_block;  ///< flush()'s block of a packed column

  void flush() {
    if (times.empty()) return;
    const std::size_t frames = times.size();
    const std::size_t drones = *std::max_element(rows.begin(), rows.end());
    const std::size_t start[] = {written, 0, 0};
    check(nc_put_vara_double(nc, time_var, start, &frames, times.data()), "cannot write variable time");
    std::vector<double> block;
    for (Var& v : vars) {
      // The frames as one block: a frame with fewer drones than the block is padded with the fill value.
      block.assign(frames * drones * v.width, fill_of(v.type));
      std::size_t at = 0;
      for (std::size_t f = 0; f < frames; ++f) {
        std::copy_n(v.pending.begin() + static_cast<std::ptrdiff_t>(at), rows[f] * v.width,
                    block.begin() + static_cast<std::ptrdiff_t>(f * drones * v.width));
        at += rows[f] * v.width;
      }
      const std::size_t count[] = {frames, drones, 2};
      if (v.packed) {
        packed_block.resize(block.size());
        for (std::size_t k = 0; k < block.size(); ++k) packed_block[k] = pack(v, block[k]);
        check(nc_put_vara_int(nc, v.id, start, count, packed_block.data()), "cannot write variable " + v.name);
      } else
        check(nc_put_vara_double(nc, v.id, start, count, block.data()), "cannot write variable " + v.name);
      v.pending.clear();
    }
    written += frames;
    times.clear();
    rows.clear();
  }
};

ArchiveWriter::ArchiveWriter(fs::path file, ArchiveProvenance provenance) : impl_(std::make_unique<Impl>()) {
  const std::lock_guard lock(netcdf_lock());
  impl_->file = std::move(file);
  impl_->part = impl_->file;
  impl_->part += ".part";
  impl_->provenance = std::move(provenance);
  impl_->open();
}

ArchiveWriter::~ArchiveWriter() {
  const std::lock_guard lock(netcdf_lock());
  if (impl_->nc >= 0) try {
      impl_->flush();  // the frames so far, in the .part file
    } catch (const WriteError&) {  // a full disk: the run reports its own failure
    }
  impl_.reset();  // closes the file under the lock
}

void ArchiveWriter::frame(double time, const std::vector<StateColumn>& columns) {
  const std::lock_guard lock(netcdf_lock());
  Impl& m = *impl_;
  std::size_t drones = 0;
  StateColumn status;
  for (const StateColumn& c : columns) {
    drones = std::max(drones, c.rows);
    if (c.name == "status" && c.type == StateColumn::Type::u8) status = c;
  }
  auto removed = [&](std::size_t i) {
    return status.data && i < status.rows && static_cast<const std::uint8_t*>(status.data)[i] == static_cast<std::uint8_t>(DroneStatus::removed);
  };
  std::vector<char> seen(m.vars.size() + columns.size(), 0);
  for (const StateColumn& c : columns) {
    if (!c.data) continue;
    std::size_t k = 0;
    while (k < m.vars.size() && m.vars[k].name != c.name) ++k;
    if (k == m.vars.size()) m.define(c, drones);
    seen[k] = 1;
    Impl::Var& v = m.vars[k];
    const double fill = fill_of(c.type);
    const bool keeps_removed = c.name == "status";  // a removed drone's status says so
    for (std::size_t i = 0; i < drones; ++i)
      for (std::size_t j = 0; j < c.width; ++j) {
        const std::size_t at = i * c.width + j;
        if (i >= c.rows || (!keeps_removed && removed(i))) v.pending.push_back(fill);
        else if (c.type == StateColumn::Type::u8) v.pending.push_back(static_cast<const std::uint8_t*>(c.data)[at]);
        else if (c.type == StateColumn::Type::u32) v.pending.push_back(static_cast<const std::uint32_t*>(c.data)[at]);
        else v.pending.push_back(static_cast<const double*>(c.data)[at]);
      }
  }
  for (std::size_t k = 0; k < m.vars.size(); ++k)  // a column the simulation no longer keeps
    if (!seen[k]) m.vars[k].pending.insert(m.vars[k].pending.end(), drones * m.vars[k].width, fill_of(m.vars[k].type));
  m.times.push_back(time);
  m.rows.push_back(drones);
  // A chunk's frames, or fewer once the drones grew (a timed change) so much that they would fill memory.
  if (m.times.size() >= m.chunk_frames || m.pending_rows() >= max_pending_rows) m.flush();
}

void ArchiveWriter::close(const std::vector<TargetState>& targets, double target_radius) {
  const std::lock_guard lock(netcdf_lock());
  Impl& m = *impl_;
  m.flush();
  const int nc = m.nc;
  const std::size_t n = targets.size();
  m.redef();
  int target_dim = -1, position = -1, found_time = -1, found_by = -1;
  m.check(nc_def_dim(nc, "target", n, &target_dim), "cannot define dimension target");
  const int dims[] = {target_dim, m.xy_dim};
  m.check(nc_def_var(nc, "target_position", NC_DOUBLE, 2, dims, &position), "cannot define variable target_position");
  m.check(nc_def_var(nc, "target_found_time", NC_DOUBLE, 1, dims, &found_time), "cannot define variable target_found_time");
  m.check(nc_def_var(nc, "target_found_by", NC_INT64, 1, dims, &found_by), "cannot define variable target_found_by");
  for (const int v : {position, found_time, found_by}) m.check(nc_def_var_deflate(nc, v, 1, 1, deflate_level), "cannot compress the targets");
  m.check(nc_def_var_fill(nc, found_time, NC_FILL, &nan), "cannot set the fill value of target_found_time");
  const long long nobody = -1;
  m.check(nc_def_var_fill(nc, found_by, NC_FILL, &nobody), "cannot set the fill value of target_found_by");
  m.text(position, "long_name", "where the target was placed");
  m.text(position, "units", "m");
  m.text(found_time, "long_name", "when a drone found the target (NaN: never)");
  m.text(found_time, "units", "s");
  m.text(found_by, "long_name", "the drone that found the target (-1: none)");
  m.check(nc_put_att_double(nc, NC_GLOBAL, "target_radius", NC_DOUBLE, 1, &target_radius), "cannot write attribute target_radius");
  m.check(nc_enddef(nc), "cannot write the targets' definitions");
  if (n > 0) {
    std::vector<double> xy(2 * n), time(n);
    std::vector<long long> by(n);
    for (std::size_t i = 0; i < n; ++i) {
      xy[2 * i] = targets[i].position.x, xy[2 * i + 1] = targets[i].position.y;
      time[i] = targets[i].found() ? targets[i].found_time : nan;
      by[i] = targets[i].found_by;
    }
    const std::size_t start[] = {0, 0}, count[] = {n, 2};
    m.check(nc_put_vara_double(nc, position, start, count, xy.data()), "cannot write variable target_position");
    m.check(nc_put_vara_double(nc, found_time, start, count, time.data()), "cannot write variable target_found_time");
    m.check(nc_put_vara_longlong(nc, found_by, start, count, by.data()), "cannot write variable target_found_by");
  }
  std::size_t drones = 0;
  m.check(nc_inq_dimlen(nc, m.drone_dim, &drones), "cannot read dimension drone");
  if (drones > 0) {
    std::vector<unsigned int> ids(drones);
    for (std::size_t i = 0; i < drones; ++i) ids[i] = static_cast<unsigned int>(i);
    const std::size_t start = 0;
    m.check(nc_put_vara_uint(nc, m.drone_var, &start, &drones, ids.data()), "cannot write variable drone");
  }
  m.nc = -1;
  m.check(nc_close(nc), "cannot close file");
  std::error_code ec;
  fs::rename(m.part, m.file, ec);
  if (ec) throw WriteError(m.file.string() + ": cannot move " + m.part.string() + " there (" + ec.message() + ")");
}

// ---- Reading

namespace {

/// An open archive for reading, closed on every way out.
struct Reading {
  fs::path file;
  int nc = -1;
  ~Reading() {
    if (nc >= 0) nc_close(nc);
  }
  [[noreturn]] void fail(const std::string& what) const { throw InputError(file.string() + ": " + what); }
  /// A failed read of data that the file's structure promised: the file is damaged.
  void check(int status, const std::string& what) const {
    if (status != NC_NOERR) fail("corrupt or truncated: " + what + " cannot be read (" + nc_strerror(status) + ")");
  }
  bool has_att(int var, const char* name) const { return nc_inq_att(nc, var, name, nullptr, nullptr) == NC_NOERR; }
  std::string text(int var, const char* name) const {
    nc_type type = NC_NAT;
    std::size_t length = 0;
    if (nc_inq_att(nc, var, name, &type, &length) != NC_NOERR) return {};
    if (type != NC_CHAR) fail(std::string("attribute ") + name + " is not text");
    std::string out(length, '\0');
    check(nc_get_att_text(nc, var, name, out.data()), std::string("attribute ") + name);
    return out;
  }
  double number(const char* name) const {
    double v = nan;
    if (!has_att(NC_GLOBAL, name)) fail(std::string("lacks the attribute ") + name + " (every salsa archive has it)");
    check(nc_get_att_double(nc, NC_GLOBAL, name, &v), std::string("attribute ") + name);
    return v;
  }
  int dim(const char* name) const {
    int id = -1;
    if (nc_inq_dimid(nc, name, &id) != NC_NOERR) fail(std::string("lacks the dimension ") + name + " (every salsa archive has it)");
    return id;
  }
  std::size_t length(int dim_id) const {
    std::size_t n = 0;
    check(nc_inq_dimlen(nc, dim_id, &n), "a dimension's length");
    return n;
  }
  int var(const char* name) const {
    int id = -1;
    if (nc_inq_varid(nc, name, &id) != NC_NOERR) fail(std::string("lacks the variable ") + name + " (every salsa archive has it)");
    return id;
  }
  /// The whole of variable `id` as doubles, its fill value as NaN, packed values unpacked (CF's
  /// scale_factor and add_offset).
  std::vector<double> values(int id, const std::string& name, std::size_t count) const {
    std::vector<double> out;
    try {
      out.resize(count);
    } catch (const std::exception&) {  // a damaged file's dimensions can claim anything
      fail("variable " + name + " holds " + std::to_string(count) + " values, more than this machine can hold");
    }
    if (count == 0) return out;
    check(nc_get_var_double(nc, id, out.data()), "variable " + name);
    double fill = nan;
    if (nc_get_att_double(nc, id, "_FillValue", &fill) == NC_NOERR && !std::isnan(fill))
      std::replace(out.begin(), out.end(), fill, nan);
    double scale = 1, offset = 0;
    const bool scaled = has_att(id, "scale_factor"), offset_by = has_att(id, "add_offset");
    if (scaled) check(nc_get_att_double(nc, id, "scale_factor", &scale), "attribute scale_factor of " + name);
    if (offset_by) check(nc_get_att_double(nc, id, "add_offset", &offset), "attribute add_offset of " + name);
    if (scaled || offset_by)
      for (double& v : out) v = v * scale + offset;
    return out;
  }
};

}  // namespace

void read_archive(const fs::path& file, Recording& into) {
  const std::lock_guard lock(netcdf_lock());
  Reading r{file};
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) r.fail("missing (no such file)");
  if (const int s = nc_open(file.c_str(), NC_NOWRITE, &r.nc); s != NC_NOERR) {
    r.nc = -1;
    if (s == NC_ENOTNC) r.fail("not a netCDF file (a trajectory archive is netCDF-4, written by salsa run --archive)");
    r.fail("cannot be opened: corrupt or truncated (" + std::string(nc_strerror(s)) + ")");
  }
  int format = 0;
  r.check(nc_inq_format(r.nc, &format), "the file's format");
  if (format != NC_FORMAT_NETCDF4) r.fail("a netCDF file, but not netCDF-4 (not a salsa trajectory archive)");
  int version = 0;
  if (!r.has_att(NC_GLOBAL, "salsa_archive_version")) r.fail("not a salsa trajectory archive (no salsa_archive_version attribute)");
  r.check(nc_get_att_int(r.nc, NC_GLOBAL, "salsa_archive_version", &version), "attribute salsa_archive_version");
  into.salsa_version = r.text(NC_GLOBAL, "salsa_version");
  if (version > archive_version)
    r.fail("written by salsa " + into.salsa_version + " in archive version " + std::to_string(version) + ", newer than this salsa reads (allowed: versions up to " +
           std::to_string(archive_version) + "; update salsa to read it)");
  if (version < 1) r.fail("salsa_archive_version " + std::to_string(version) + " is no archive version (allowed: 1 … " + std::to_string(archive_version) + ")");
  into.source = file;
  into.test_name = r.text(NC_GLOBAL, "test_name");
  if (!r.has_att(NC_GLOBAL, "seed")) r.fail("lacks the attribute seed (every salsa archive has it)");
  unsigned long long seed = 0;
  r.check(nc_get_att_ulonglong(r.nc, NC_GLOBAL, "seed", &seed), "attribute seed");
  into.seed = seed;
  into.dt = r.number("dt");
  into.log_interval = r.number("log_interval");
  into.target_radius = r.number("target_radius");

  const int time_dim = r.dim("time"), drone_dim = r.dim("drone"), xy_dim = r.dim("xy");
  const std::size_t frames = r.length(time_dim);
  into.drones = r.length(drone_dim);
  into.times = r.values(r.var("time"), "time", frames);
  for (std::size_t f = 0; f < frames; ++f)
    if (!std::isfinite(into.times[f]) || (f > 0 && into.times[f] < into.times[f - 1]))
      r.fail("time[" + std::to_string(f) + "] is " + std::to_string(into.times[f]) + ", not after the frame before it");

  // The state columns: the variables salsa_model marks, in the order they were written.
  into.columns.clear();
  int nvars = 0;
  r.check(nc_inq_nvars(r.nc, &nvars), "the list of variables");
  for (int id = 0; id < nvars; ++id) {
    if (!r.has_att(id, "salsa_model")) continue;
    char name[NC_MAX_NAME + 1] = {};
    nc_type type = NC_NAT;
    int ndims = 0;
    int dims[NC_MAX_VAR_DIMS] = {};
    r.check(nc_inq_var(r.nc, id, name, &type, &ndims, dims, nullptr), "a variable's definition");
    RecordedColumn c;
    c.name = name;
    if (ndims < 2 || ndims > 3 || dims[0] != time_dim || dims[1] != drone_dim || (ndims == 3 && dims[2] != xy_dim))
      r.fail("variable " + c.name + " is not over (time, drone) or (time, drone, xy)");
    c.width = ndims == 3 ? 2 : 1;
    if (type == NC_DOUBLE || (type == NC_INT && r.has_att(id, "scale_factor"))) c.type = StateColumn::Type::f64;
    else if (type == NC_UINT) c.type = StateColumn::Type::u32;
    else if (type == NC_UBYTE) c.type = StateColumn::Type::u8;
    else r.fail("variable " + c.name + " is of a type salsa does not write (allowed: double, int with a scale_factor, uint, ubyte)");
    c.unit = salsa_unit(r.text(id, "units"));
    c.meaning = r.text(id, "long_name");
    c.model = r.text(id, "salsa_model");
    if (into.drones > 0 && frames > std::numeric_limits<std::size_t>::max() / 2 / into.drones)
      r.fail("variable " + c.name + " claims " + std::to_string(frames) + " × " + std::to_string(into.drones) + " values, more than any file holds");
    c.values = r.values(id, c.name, frames * into.drones * c.width);
    into.columns.push_back(std::move(c));
  }
  for (const char* wanted : {"position", "velocity", "group", "status"}) {
    const auto c = std::find_if(into.columns.begin(), into.columns.end(), [&](const RecordedColumn& k) { return k.name == wanted; });
    if (c == into.columns.end()) r.fail(std::string("lacks the variable ") + wanted + " (every salsa archive has position, velocity, group and status)");
    if ((c->width == 2) != (c->name == "position" || c->name == "velocity")) r.fail("variable " + c->name + " has the wrong shape");
  }

  const std::size_t targets = r.length(r.dim("target"));
  const std::vector<double> xy = r.values(r.var("target_position"), "target_position", 2 * targets);
  into.found_time = r.values(r.var("target_found_time"), "target_found_time", targets);
  const std::vector<double> by = r.values(r.var("target_found_by"), "target_found_by", targets);
  into.targets.resize(targets);
  into.found_by.resize(targets);
  for (std::size_t i = 0; i < targets; ++i) {
    into.targets[i] = {xy[2 * i], xy[2 * i + 1]};
    into.found_by[i] = std::isnan(by[i]) ? -1 : static_cast<std::int64_t>(by[i]);
  }
}

std::string archive_lacks(const fs::path& file, const std::vector<std::string>& wanted) {
  const std::lock_guard lock(netcdf_lock());
  std::vector<std::string> asked(std::begin(archive_columns), std::end(archive_columns));
  int nc = -1;
  bool readable = nc_open(file.c_str(), NC_NOWRITE, &nc) == NC_NOERR;
  if (readable) {
    std::size_t length = 0;
    if (nc_inq_attlen(nc, NC_GLOBAL, "salsa_drone_columns", &length) == NC_NOERR) {
      std::string text(length, '\0');
      readable = nc_get_att_text(nc, NC_GLOBAL, "salsa_drone_columns", text.data()) == NC_NOERR;
      asked.clear();
      for (std::size_t at = 0; at < text.size();) {
        const std::size_t comma = std::min(text.find(',', at), text.size());
        asked.push_back(text.substr(at, comma - at));
        at = comma + 1;
      }
    }
    nc_close(nc);
  }
  std::string lacks;
  for (const std::string& name : wanted)
    if (!readable || std::find(asked.begin(), asked.end(), name) == asked.end()) lacks += (lacks.empty() ? "" : ", ") + name;
  return lacks;
}

}  // namespace salsa
