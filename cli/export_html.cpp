// salsa export --html DIR: the run as a web page that replays it offline: index.html and replay.js
// (cli/web/, embedded into salsa) and data.js, the run itself. The data is a script, not JSON, because
// a page opened from file:// may not fetch files beside it.
#include <bit>
#include <cmath>
#include <cstdint>
#include <algorithm>
#include <fstream>
#include <iostream>
#include <numbers>
#include <string_view>

#include <nlohmann/json.hpp>

#include "export.hpp"
#include "salsa/core/files/input_error.hpp"

namespace fs = std::filesystem;

namespace salsa::cli {
namespace {

/// The most drone-frames a page holds: ~15 bytes each in data.js, so ~180 MB, where a string past
/// 512 MB is more than Chromium's JavaScript holds. A run with more keeps one frame in k (and the
/// last), with a warning.
constexpr std::size_t most_drone_frames = 12'000'000;

/// Bytes as base64 (RFC 4648): the page decodes them with atob() into typed arrays. Written here, as
/// neither the standard library nor a library salsa links has an encoder it exports.
std::string base64(const std::vector<std::uint8_t>& bytes) {
  static constexpr char digits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::size_t n = std::min<std::size_t>(3, bytes.size() - i);
    std::uint32_t v = std::uint32_t{bytes[i]} << 16;
    if (n > 1) v |= std::uint32_t{bytes[i + 1]} << 8;
    if (n > 2) v |= bytes[i + 2];
    for (std::size_t k = 0; k < 4; ++k) out += k <= n ? digits[(v >> (18 - 6 * k)) & 63] : '=';
  }
  return out;
}

/// Little-endian bytes, as typed arrays read them on every platform browsers run on.
template <class T, class U>
void put(std::vector<std::uint8_t>& out, U value) {
  using Bits = std::conditional_t<sizeof(T) == 8, std::uint64_t, std::uint32_t>;
  const auto bits = std::bit_cast<Bits>(static_cast<T>(value));
  for (std::size_t k = 0; k < sizeof(T); ++k) out.push_back(static_cast<std::uint8_t>(bits >> (8 * k)));
}

nlohmann::json polylines(const std::vector<Polyline>& lines) {
  nlohmann::json out = nlohmann::json::array();
  for (const Polyline& line : lines) {
    nlohmann::json xy = nlohmann::json::array();
    for (Vec2 p : line) xy.push_back(p.x), xy.push_back(p.y);
    out.push_back(std::move(xy));
  }
  return out;
}

/// The run as the page reads it (replay.js says what each field holds).
nlohmann::json page_data(const Recording& r) {
  if (r.groups.size() > 254) throw InputError("--html: " + std::to_string(r.groups.size()) + " groups (the page draws up to 254)");
  const RecordedColumn* position = r.column("position");
  const RecordedColumn *velocity = r.column("velocity"), *group = r.column("group"), *camera = r.column("camera_works");
  if (!position) throw InputError("--html: " + r.source.string() + " has no positions");
  std::vector<std::size_t> frames;
  const std::size_t stride = r.drones == 0 ? 1 : std::max<std::size_t>(1, (r.frames() * r.drones + most_drone_frames - 1) / most_drone_frames);
  for (std::size_t f = 0; f < r.frames(); f += stride) frames.push_back(f);
  if (!frames.empty() && frames.back() != r.frames() - 1) frames.push_back(r.frames() - 1);
  if (stride > 1)
    std::cerr << "salsa: warning: --html: " << r.drones << " drones over " << r.frames() << " frames is more than a browser opens quickly: "
              << "the page keeps one frame in " << stride << " (a longer log_interval keeps them all)\n";
  std::vector<std::uint8_t> times, xy, heading, look, groups, targets, found;
  for (const std::size_t f : frames) {
    put<double>(times, r.times[f]);
    for (std::size_t d = 0; d < r.drones; ++d) {
      const Vec2 p = r.position(f, d);
      put<float>(xy, p.x), put<float>(xy, p.y);
      const double vx = velocity ? r.at(*velocity, f, d, 0) : 0, vy = velocity ? r.at(*velocity, f, d, 1) : 0;
      const bool moving = std::hypot(vx, vy) > 1e-9;  // NaN: no
      const double turns = std::atan2(vy, vx) / (2 * std::numbers::pi);
      heading.push_back(moving ? static_cast<std::uint8_t>(static_cast<int>(std::lround((turns + 1) * 240)) % 240) : 255);
      const bool camera_failed = camera && r.at(*camera, f, d) == 0;
      look.push_back(static_cast<std::uint8_t>(r.status(f, d) + (camera_failed ? 4 : 0)));
      const double g = group ? r.at(*group, f, d) : 0;
      groups.push_back(g >= 0 && g < static_cast<double>(r.groups.size()) ? static_cast<std::uint8_t>(g) : 255);
    }
  }
  for (std::size_t t = 0; t < r.targets.size(); ++t) {
    put<float>(targets, r.targets[t].x), put<float>(targets, r.targets[t].y);
    put<double>(found, t < r.found_time.size() ? r.found_time[t] : std::nan(""));
  }
  nlohmann::json g = nlohmann::json::array();
  for (const RecordedGroup& group_ : r.groups)
    g.push_back({{"name", group_.name}, {"radius", group_.radius}, {"base", {group_.base.x, group_.base.y}}});
  const Rect& b = r.map.bounds;
  return {{"format", 1},
          {"test", r.test_name},
          {"seed", r.seed},
          {"salsa", r.salsa_version},
          {"duration", r.duration},
          {"bounds", {b.min.x, b.min.y, b.max.x, b.max.y}},
          {"obstacles", polylines(r.map.obstacles)},
          {"hollow", polylines(r.map.hollow)},
          {"lines", polylines(r.map.lines)},
          {"groups", std::move(g)},
          {"drones", r.drones},
          {"frames", frames.size()},
          {"times", base64(times)},
          {"position", base64(xy)},
          {"heading", base64(heading)},
          {"look", base64(look)},
          {"group", base64(groups)},
          {"target_radius", r.target_radius},
          {"targets", base64(targets)},
          {"found", base64(found)}};
}

/// Writes `text` to `file` through a temporary beside it, so a failed export leaves no half page.
void write(const fs::path& file, std::string_view text) {
  const fs::path part = file.string() + ".part";
  {
    std::ofstream out(part, std::ios::binary);
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
    if (!out.flush()) throw InputError("--html: cannot write " + part.string());
  }
  std::error_code ec;
  fs::rename(part, file, ec);
  if (ec) throw InputError("--html: cannot write " + file.string() + " (" + ec.message() + ")");
}

}  // namespace

void export_html(const Recording& recording, const fs::path& dir) {
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
    throw InputError("--html: " + dir.string() + " is a file (allowed: a folder, made when missing)");
  fs::create_directories(dir, ec);
  if (ec) throw InputError("--html: cannot make the folder " + dir.string() + " (" + ec.message() + ")");
  const std::string data = "// The run replay.js shows, written by salsa export --html.\nwindow.SALSA_RUN = " + page_data(recording).dump() + ";\n";
  write(dir / "data.js", data);
  for (const char* file : {"replay.js", "index.html"}) write(dir / file, web_file(file));
}

}  // namespace salsa::cli
