#pragma once
// Saving a file the way the desktop saves every file salsa reads (queues, maps).
#include <filesystem>
#include <functional>
#include <string>

namespace salsa::gui {

/// Saves `text` as `file` only if it reads back: written to `.NAME.saving` beside `file`, checked by
/// `read_back(aside)` ("" or why; it may throw), then renamed over `file`. So a file salsa would refuse
/// never replaces the old one. Returns "" or the one-line reason, naming `file`.
std::string save_checked(const std::filesystem::path& file, const std::string& text,
                         const std::function<std::string(const std::filesystem::path& aside)>& read_back);

}  // namespace salsa::gui
