#pragma once
// The plots of a run, drawn from its files alone (see docs/plots.md): per test into TEST/plots/, per
// queue into OUT/plots/. PNGs of 1200 × 800 pixels (taller for long labels), rendered offscreen with
// QPainter on QImage. Call start_plotting() on the main thread first (it creates Qt's application object); then
// draw_test_plots may run on several threads at once. Throws salsa::InputError (one line naming the
// file) on bad input.
#include <algorithm>
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace salsa::plots {

inline constexpr int plot_width = 1200, plot_height = 800;
/// comparison.png grows with its rows: 1200 × max(400, 180 + 50 · rows).
inline int comparison_plot_height(std::size_t rows) { return std::max(400, 180 + 50 * static_cast<int>(rows)); }

/// Sets Qt up for offscreen drawing; call on the main thread before any drawing on other threads.
void start_plotting();

/// Writes TEST/plots/*.png from config.json, summary.csv, drones.csv, targets.csv and map.json (each
/// plot whose data is there): drawn into TEST/.plots.partial/ and renamed to TEST/plots/ when all are
/// written, so TEST/plots/ is never half drawn.
void draw_test_plots(const std::filesystem::path& test_folder);
/// Whether TEST/plots/ is absent: never drawn, or the drawing was cut off (--resume draws them).
bool test_plots_missing(const std::filesystem::path& test_folder);

/// Writes OUT/plots/*.png from OUT/summary.csv, OUT/comparison.csv and the test folders' summary.csv.
void draw_queue_plots(const std::filesystem::path& out);

/// One estimate of an interval plot: under `heading`, `label` on the left, the mean with its 95 % interval
/// (absent: not drawn), `note` on the right.
struct Estimate {
  std::string heading, label, note;
  std::optional<double> mean, lo, hi;
};
/// An interval plot (comparison.png's kind) of `rows`, grouped under their headings in order of first
/// appearance, against a dashed line at 0; salsa suite's report draws its differences with it.
void draw_estimates(const std::vector<Estimate>& rows, const std::string& title, const std::string& x_label,
                    const std::filesystem::path& file);

/// The condition each ok test of OUT/summary.csv is plotted under, in file order: its queue condition
/// and the value of every other setting the queue varies between tests of one variant, swarm size and
/// repeat (a sweep.set key), e.g. "dropout, failures.drone_mtbf = 3000"; "" for neither. So the plots
/// keep apart what a sweep varies, never pooling it.
std::vector<std::string> plotted_conditions(const std::filesystem::path& out);

struct Rect {
  double x0 = 0, y0 = 0, x1 = 1, y1 = 1;
};

/// The area a test's drones flew in: the map's bounds (map.json in the folder, or the json map's file
/// named in config.json), else the extent of the drones' and targets' positions.
Rect test_area(const std::filesystem::path& test_folder);

/// Drone positions binned into square cells over `area`: `columns` across, as many rows as the
/// aspect needs; row 0 at y0. Values are counts scaled so the largest is 100 (all 0 when empty).
/// Positions outside `area` are left out.
struct HeatGrid {
  Rect area;
  int columns = 0, rows = 0;
  double cell = 1;             ///< side of a cell, m
  std::vector<double> values;  ///< rows × columns, row-major
  int index_of(double x, double y) const;  ///< -1 outside the area
};
HeatGrid bin_positions(const std::vector<std::pair<double, double>>& positions, const Rect& area, int columns);

/// Round tick values covering [lo, hi]: steps of 1, 2 or 5 × 10^k, first ≤ lo, last ≥ hi.
std::vector<double> nice_ticks(double lo, double hi, int max_ticks = 8);

/// Five-number summary with Tukey whiskers (the furthest values within 1.5 IQR of the quartiles;
/// quartiles by linear interpolation) and the values beyond them.
struct BoxStats {
  double q1 = 0, median = 0, q3 = 0, low = 0, high = 0;
  std::vector<double> outliers;
};
BoxStats box_stats(std::vector<double> values);

/// Text order with the numbers in it compared as numbers: "alpha = 1.4" < "alpha = 10", "d5" < "d20"
/// (how the queue plots order variants and lines).
bool natural_less(std::string_view a, std::string_view b);

}  // namespace salsa::plots
