#pragma once
// The plots of a tune (salsa tune, docs/tuning.md): best score so far against evaluations with the
// defaults' level, each parameter against the score, and the Pareto front of two objectives. PNGs of
// plots::plot_width × plot_height, drawn offscreen; call start_plotting() first.
#include <cstddef>
#include <filesystem>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace salsa::plots {

struct TunePlot {
  std::string objective;  ///< the first objective's name (the y axis)
  bool maximise = true;
  double defaults = std::numeric_limits<double>::quiet_NaN();  ///< the defaults' score
  std::vector<std::pair<double, double>> best_so_far;          ///< (evaluations used, best score then)
  struct Parameter {
    std::string key;
    bool log = false;
    std::vector<double> values;  ///< one per scored candidate
  };
  std::vector<Parameter> parameters;
  std::vector<double> scores;  ///< the scored candidates' first objective (a dropped one's: its estimate)
  std::vector<bool> dropped;   ///< per scored candidate: dropped by racing (drawn as a ring)
  std::size_t winner = 0;      ///< index into scores
  std::string second_objective;  ///< two objectives or more: the second's name, its scores, the front
  std::vector<double> second;
  std::vector<bool> on_front;
};

/// Writes FOLDER/convergence.png, FOLDER/parameter_<key>.png for each parameter and (two objectives or
/// more) FOLDER/pareto.png.
/// Throws std::runtime_error naming a file that cannot be written.
void draw_tune_plots(const std::filesystem::path& folder, const TunePlot& plot);

}  // namespace salsa::plots
