#pragma once
// Saving a file the way the desktop saves every file salsa reads (queues, maps).
#include <filesystem>
#include <functional>
#include <string>

#include <QString>

class QWidget;

namespace salsa::gui {

/// A save dialog that refuses a bad target while it is open: a folder that cannot be written is named
/// in the dialog as soon as it is entered, and Save keeps the dialog open with the reason when the
/// folder is not writable or `check(file)` says why not ("" = fine). Returns the file, or "" on Cancel.
/// `folder`: an output folder, new (typed) or existing (clicked, e.g. a stopped run's to resume it).
QString ask_save_file(QWidget* parent, const QString& title, const QString& suggested, const QString& filter,
                      const std::function<std::string(const QString& file)>& check = {}, bool folder = false);

/// Saves `text` as `file` only if it reads back: written to `.NAME.saving` beside `file`, checked by
/// `read_back(aside)` ("" or why; it may throw), then renamed over `file`. So a file salsa would refuse
/// never replaces the old one. Returns "" or the one-line reason, naming `file`.
std::string save_checked(const std::filesystem::path& file, const std::string& text,
                         const std::function<std::string(const std::filesystem::path& aside)>& read_back);

}  // namespace salsa::gui
