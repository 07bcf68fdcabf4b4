#pragma once
// PNG line charts drawn with Qt Charts offscreen: no display needed. Used by the CLI and the GUI; the
// input is plain data, so plots can be remade later from the CSV/JSON files alone.
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace salsa::plots {

struct Series {
  std::string name;
  std::vector<std::pair<double, double>> points;  ///< (x, y)
};

struct Chart {
  std::string title, x_label, y_label;
  bool log_x = false, log_y = false;
  std::vector<Series> series;
};

/// Draws `chart` into a PNG file of `width` × `height` pixels. Throws std::runtime_error naming the file.
void save_png(const Chart& chart, const std::filesystem::path& file, int width = 960, int height = 600);

}  // namespace salsa::plots
