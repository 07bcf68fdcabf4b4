// salsa export TEST_FOLDER: the finished test read once (archive or drones.csv), then written as each
// format asked for. Nothing is written into the folder being read.
#include "export.hpp"

#include <boost/program_options.hpp>

#include <iostream>

#include "commands.hpp"
#include "options.hpp"
#include "salsa/core/files/input_error.hpp"

namespace po = boost::program_options;
namespace fs = std::filesystem;
using salsa::InputError;

namespace {

/// Whether `path` is `folder` or inside it (both as they resolve on disk).
bool inside(const fs::path& path, const fs::path& folder) {
  std::error_code ec;
  const fs::path p = fs::weakly_canonical(fs::absolute(path), ec), f = fs::weakly_canonical(fs::absolute(folder), ec);
  auto [end, rest] = std::mismatch(f.begin(), f.end(), p.begin(), p.end());
  return end == f.end();
}

}  // namespace

int cmd_export(int argc, char** argv) {
  po::options_description o("export options");
  o.add_options()("folder", po::value<std::string>(), "a finished test's folder")(
      "mcap", po::value<std::string>(), "write the run as MCAP (Foxglove, Lichtblick) to FILE")(
      "html", po::value<std::string>(), "write a web page that replays the run offline into folder DIR")(
      "video", po::value<std::string>(), "draw the run into the MP4 FILE (ffmpeg)")(
      "size", po::value<std::string>()->default_value("1280x720"), "video frame size WxH in pixels (16 … 7680 each)")(
      "fps", po::value<std::string>()->default_value("30"), "video frames per second (1 … 120)")(
      "speed", po::value<std::string>()->default_value("1"), "simulated seconds per second of video (0.01 … 1000)");
  po::variables_map vm;
  if (!salsa::cli::parse(argc, argv, "export",
                         "TEST_FOLDER [--mcap FILE] [--html DIR] [--video FILE.mp4]\n"
                         "                                  share a finished test: as MCAP, a web page or a video",
                         o, vm, salsa::cli::help_only, salsa::cli::positional("folder", 1)))
    return 0;
  if (!vm.count("folder")) throw InputError("export: needs a TEST_FOLDER (see 'salsa export --help')");
  if (!vm.count("mcap") && !vm.count("html") && !vm.count("video"))
    throw InputError("export: nothing to write (allowed: --mcap FILE, --html DIR, --video FILE.mp4)");
  const fs::path folder = vm["folder"].as<std::string>();
  for (const char* option : {"mcap", "html", "video"})
    if (vm.count(option) && inside(vm[option].as<std::string>(), folder))
      throw InputError(std::string("--") + option + ": " + vm[option].as<std::string>() + " is inside " + folder.string() +
                       " (nothing is written into the folder being read: name a path outside it)");
  salsa::cli::VideoOptions video;
  if (vm.count("video")) {
    const std::string size = vm["size"].as<std::string>();
    const auto x = size.find('x');
    const auto w = x == std::string::npos ? std::nullopt : salsa::cli::decimal(size.substr(0, x));
    const auto h = x == std::string::npos ? std::nullopt : salsa::cli::decimal(size.substr(x + 1));
    if (!w || !h || *w != std::floor(*w) || *h != std::floor(*h) || *w < 16 || *h < 16 || *w > 7680 || *h > 7680)
      throw InputError("--size: '" + size + "' (allowed: WxH in pixels, each a whole number 16 … 7680, e.g. 1280x720)");
    video.width = static_cast<int>(*w), video.height = static_cast<int>(*h);
    const auto fps = salsa::cli::decimal(vm["fps"].as<std::string>());
    if (!fps || *fps < 1 || *fps > 120) throw InputError("--fps: '" + vm["fps"].as<std::string>() + "' (allowed: 1 … 120)");
    video.fps = *fps;
    const auto speed = salsa::cli::decimal(vm["speed"].as<std::string>());
    if (!speed || *speed < 0.01 || *speed > 1000) throw InputError("--speed: '" + vm["speed"].as<std::string>() + "' (allowed: 0.01 … 1000)");
    video.speed = *speed;
  }
  const salsa::Recording recording = salsa::load_recording(folder);
  if (vm.count("mcap")) salsa::cli::export_mcap(recording, vm["mcap"].as<std::string>());
  if (vm.count("html")) salsa::cli::export_html(recording, vm["html"].as<std::string>());
  if (vm.count("video")) salsa::cli::export_video(recording, vm["video"].as<std::string>(), video);
  return 0;
}
