#pragma once
// What the plots of a run share (plot_helpers.cpp): the run's files read, values drawn as lines and bands on a Figure.
#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "figure.hpp"

namespace salsa::plots {

/// A path as messages show it.
std::string name_of(const std::filesystem::path& p);
/// A JSON file read strictly; InputError (one line naming the file) when it cannot be.
nlohmann::json read_json(const std::filesystem::path& file, const char* what);
bool is_file(const std::filesystem::path& p);

/// Values over x as a line, broken where a value is NaN.
void draw_line(Figure& f, const std::vector<double>& x, const std::vector<double>& y, const QColor& colour, double width = 2.5,
               Qt::PenStyle style = Qt::SolidLine);
/// The band between `lo` and `hi` over x, filled.
void draw_band(Figure& f, const std::vector<double>& x, const std::vector<double>& lo, const std::vector<double>& hi, QColor colour);
/// The smallest and the largest value that is not NaN; [0, 1] when there is none.
std::pair<double, double> range_of(const std::vector<double>& v);

}  // namespace salsa::plots
