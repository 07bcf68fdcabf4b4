// salsa export --video (being built).
#include "export.hpp"

#include "salsa/core/files/input_error.hpp"

namespace salsa::cli {

void export_video(const Recording&, const std::filesystem::path& file, const VideoOptions&) {
  throw InputError("--video: " + file.string() + ": not in this build yet");
}

}  // namespace salsa::cli
