#pragma once
// salsa export: a finished test shared without salsa (export.cpp reads the folder once; one file
// per format writes it).
#include <filesystem>

#include "salsa/core/replay/recording.hpp"

namespace salsa::cli {

/// The run as MCAP with Foxglove's JSON schemas (export_mcap.cpp).
void export_mcap(const Recording& recording, const std::filesystem::path& file);

/// The run as a self-contained web page: DIR/index.html, its script and the data (export_html.cpp).
void export_html(const Recording& recording, const std::filesystem::path& dir);

struct VideoOptions {
  int width = 1280, height = 720;  ///< px
  double fps = 30;                 ///< frames per second of video
  double speed = 1;                ///< simulated seconds per second of video
};

/// The run drawn as the desktop draws it into an MP4 with ffmpeg, without a display (export_video.cpp).
void export_video(const Recording& recording, const std::filesystem::path& file, const VideoOptions& options);

}  // namespace salsa::cli
