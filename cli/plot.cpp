// salsa plot: PNG charts from the files salsa writes (bench JSON, summary.csv), so plots can be remade
// from data alone.
#include <boost/program_options.hpp>
#include <nlohmann/json.hpp>

#include <charconv>
#include <cmath>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>

#include "commands.hpp"
#include "salsa/core/test_spec.hpp"
#include "salsa/plots/chart.hpp"

namespace po = boost::program_options;
namespace fs = std::filesystem;
using salsa::InputError;

namespace {

salsa::plots::Chart bench_chart(const fs::path& file, const nlohmann::json& j) {
  if (!j.is_object() || !j.contains("cells") || !j.contains("workload")) throw InputError(file.string() + ": cells: missing (write it with 'salsa bench --json')");
  salsa::plots::Chart c;
  c.log_x = c.log_y = true;
  c.x_label = "drones";
  c.y_label = "RTF = wall time / simulated time (lower is faster)";
  c.title = "salsa bench " + j.at("workload").get<std::string>() + " (" + std::to_string(j.at("threads").get<int>()) + " threads)";
  // One line per target count for table1; scale has one target count per drone count.
  const bool scale = j.at("workload") == "scale";
  std::map<std::string, salsa::plots::Series> lines;
  if (!j.at("cells").is_array()) throw InputError(file.string() + ": cells: must be a list (write it with 'salsa bench --json')");
  for (const auto& cell : j.at("cells")) {
    const std::string key = scale ? "" : " (" + std::to_string(cell.at("targets").get<std::size_t>()) + " targets)";
    const double n = cell.at("drones").get<double>();
    auto& salsa_line = lines["salsa" + key];
    salsa_line.name = "salsa" + key;
    salsa_line.points.emplace_back(n, cell.at("rtf").get<double>());
    if (cell.contains("floor_rtf")) {
      auto& floor_line = lines["Box2D floor" + key];
      floor_line.name = "Box2D floor" + key;
      floor_line.points.emplace_back(n, cell.at("floor_rtf").get<double>());
    }
  }
  for (auto& [name, series] : lines) c.series.push_back(series);
  return c;
}

/// nlohmann's message without its "[json.exception.type_error.302] " tag.
std::string reason(const nlohmann::json::exception& e) {
  const std::string what = e.what();
  const auto tag_end = what.find("] ");
  return tag_end == std::string::npos ? what : what.substr(tag_end + 2);
}

salsa::plots::Chart bench_chart(const fs::path& file) {
  std::ifstream in(file);
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(file.string() + ": not a bench JSON file (" + reason(e) + ")");
  }
  try {
    return bench_chart(file, j);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(file.string() + ": not a bench JSON file as 'salsa bench --json' writes it (" + reason(e) + ")");
  }
}

/// A CSV cell as a number, or InputError naming the file, line and column.
double cell_number(const fs::path& file, std::size_t line, const std::string& column, const std::string& cell) {
  double v = 0;
  const auto [end, ec] = std::from_chars(cell.data(), cell.data() + cell.size(), v);
  if (ec != std::errc{} || end != cell.data() + cell.size() || !std::isfinite(v))
    throw InputError(file.string() + ": line " + std::to_string(line) + ": " + column + ": \"" + cell.substr(0, 40) +
                     "\" is not a finite number (allowed: a summary.csv as salsa run writes it)");
  return v;
}

salsa::plots::Chart csv_chart(const fs::path& file, const std::string& column) {
  std::ifstream in(file);
  if (!in) throw InputError(file.string() + ": cannot open file");
  std::string header;
  std::getline(in, header);
  std::vector<std::string> names;
  std::stringstream hs(header);
  for (std::string n; std::getline(hs, n, ',');) names.push_back(n);
  const auto col = std::find(names.begin(), names.end(), column);
  if (names.empty() || names[0] != "time" || col == names.end())
    throw InputError(file.string() + ": --column: '" + column + "' is not a column (allowed: " + header + ")");
  const auto k = static_cast<std::size_t>(col - names.begin());
  salsa::plots::Chart c;
  c.title = file.parent_path().filename().string() + ": " + column;
  c.x_label = "time (s)";
  c.y_label = column;
  salsa::plots::Series s{column, {}};
  std::size_t number = 1;
  for (std::string line; std::getline(in, line);) {
    ++number;
    std::stringstream ls(line);
    std::vector<std::string> cells;
    for (std::string v; std::getline(ls, v, ',');) cells.push_back(v);
    if (cells.size() > k && !cells[k].empty())
      s.points.emplace_back(cell_number(file, number, "time", cells[0]), cell_number(file, number, column, cells[k]));
  }
  c.series.push_back(std::move(s));
  return c;
}

}  // namespace

int cmd_plot(int argc, char** argv) {
  po::options_description o("plot options");
  o.add_options()("help,h", "show this help")("file", po::value<std::string>(), "a bench JSON file or a summary.csv")(
      "out,o", po::value<std::string>(), "PNG file to write")(
      "column", po::value<std::string>()->default_value("targets_found"), "summary.csv column to plot over time");
  po::positional_options_description pos;
  pos.add("file", 1);
  po::variables_map vm;
  po::store(po::command_line_parser(argc, argv).options(o).positional(pos).run(), vm);
  po::notify(vm);
  if (vm.count("help")) {
    std::cout << "usage: salsa plot FILE --out PNG [options]\n\n" << o;
    return 0;
  }
  if (!vm.count("file") || !vm.count("out")) throw InputError("plot: needs FILE and --out PNG (see 'salsa plot --help')");
  const fs::path file = vm["file"].as<std::string>();
  if (fs::is_directory(file)) throw InputError(file.string() + ": is a folder (allowed: a bench JSON file or a summary.csv)");
  // The PNG goes to a file in an existing folder; say so before drawing anything.
  const fs::path png = vm["out"].as<std::string>();
  const fs::path png_folder = png.parent_path().empty() ? fs::path(".") : png.parent_path();
  if (png.filename().empty() || fs::is_directory(png))
    throw InputError("--out: " + png.string() + " is a folder (allowed: a PNG file name, e.g. found.png)");
  if (!fs::is_directory(png_folder))
    throw InputError("--out: " + png.string() + ": the folder " + png_folder.string() + " does not exist (allowed: a file in an existing folder)");
  const salsa::plots::Chart chart =
      file.extension() == ".csv" ? csv_chart(file, vm["column"].as<std::string>()) : bench_chart(file);
  salsa::plots::save_png(chart, png);
  return 0;
}
