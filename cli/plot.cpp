// salsa plot: PNG charts from the files salsa writes (bench JSON, summary.csv), so plots can be remade
// from data alone.
#include <boost/program_options.hpp>
#include <nlohmann/json.hpp>

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

salsa::plots::Chart bench_chart(const fs::path& file) {
  std::ifstream in(file);
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const std::exception& e) {
    throw InputError(file.string() + ": not a bench JSON file (" + e.what() + ")");
  }
  if (!j.contains("cells") || !j.contains("workload")) throw InputError(file.string() + ": cells: missing (write it with 'salsa bench --json')");
  salsa::plots::Chart c;
  c.log_x = c.log_y = true;
  c.x_label = "drones";
  c.y_label = "RTF = wall time / simulated time (lower is faster)";
  c.title = "salsa bench " + j["workload"].get<std::string>() + " (" + std::to_string(j["threads"].get<int>()) + " threads)";
  // One line per target count for table1; scale has one target count per drone count.
  const bool scale = j["workload"] == "scale";
  std::map<std::string, salsa::plots::Series> lines;
  for (const auto& cell : j["cells"]) {
    const std::string key = scale ? "" : " (" + std::to_string(cell["targets"].get<std::size_t>()) + " targets)";
    const double n = cell["drones"].get<double>();
    auto& salsa_line = lines["salsa" + key];
    salsa_line.name = "salsa" + key;
    salsa_line.points.emplace_back(n, cell["rtf"].get<double>());
    if (cell.contains("floor_rtf")) {
      auto& floor_line = lines["Box2D floor" + key];
      floor_line.name = "Box2D floor" + key;
      floor_line.points.emplace_back(n, cell["floor_rtf"].get<double>());
    }
  }
  for (auto& [name, series] : lines) c.series.push_back(series);
  return c;
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
  for (std::string line; std::getline(in, line);) {
    std::stringstream ls(line);
    std::vector<std::string> cells;
    for (std::string v; std::getline(ls, v, ',');) cells.push_back(v);
    if (cells.size() > k && !cells[k].empty()) s.points.emplace_back(std::stod(cells[0]), std::stod(cells[k]));
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
  const salsa::plots::Chart chart =
      file.extension() == ".csv" ? csv_chart(file, vm["column"].as<std::string>()) : bench_chart(file);
  salsa::plots::save_png(chart, vm["out"].as<std::string>());
  return 0;
}
