// salsa plot: PNG charts from the files salsa writes (bench JSON, summary.csv), so plots can be remade
// from data alone.
#include <boost/program_options.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>

#include "salsa/core/results/queue_summary.hpp"
#include "commands.hpp"
#include "options.hpp"
#include "salsa/core/results/comparison.hpp"
#include "salsa/core/experiments/queue.hpp"
#include "salsa/core/experiments/test_spec.hpp"
#include "salsa/plots/chart.hpp"
#include "salsa/plots/results.hpp"
#include "strict_json.hpp"

namespace po = boost::program_options;
namespace fs = std::filesystem;
using salsa::InputError;

namespace {

salsa::plots::Chart bench_chart(const fs::path& file) {
  using nlohmann::json;
  json j;
  try {
    j = salsa::strict_json::read_file<json>(file, "a bench JSON file (written by 'salsa bench --json')");
  } catch (const salsa::strict_json::Error& e) {
    throw InputError(e.what());
  }
  const std::string name = salsa::strict_json::printable(file.string(), 200);
  // A member of an object, of the kind asked for; refused in one line otherwise.
  auto get = [&](const json& object, const std::string& at, const char* key, const char* kind, bool ok(const json&)) -> const json& {
    const std::string field = at.empty() ? key : at + "." + key;
    if (!object.contains(key)) throw InputError(name + ": " + field + ": missing (a bench JSON file, written by 'salsa bench --json')");
    const json& v = object[key];
    if (!ok(v)) throw InputError(name + ": " + field + ": " + salsa::strict_json::shown(v) + " is not " + kind);
    return v;
  };
  auto is_positive = [](const json& v) { return v.is_number() && v.get<double>() > 0; };
  if (!j.is_object()) throw InputError(name + ": " + salsa::strict_json::shown(j) + " is not a bench JSON object (write it with 'salsa bench --json')");
  const std::string workload = get(j, "", "workload", "a string (table1 or scale)", [](const json& v) { return v.is_string(); }).get<std::string>();
  const json& threads = get(j, "", "threads", "a whole number", [](const json& v) { return v.is_number_integer(); });
  const json& cells = get(j, "", "cells", "a list of cells", [](const json& v) { return v.is_array(); });
  salsa::plots::Chart c;
  c.log_x = c.log_y = true;
  c.x_label = "drones";
  c.y_label = "RTF = wall time / simulated time (lower is faster)";
  c.title = "salsa bench " + salsa::strict_json::printable(workload) + " (" + threads.dump() + " threads)";
  // One line per target count for table1; scale has one target count per drone count.
  const bool scale = workload == "scale";
  std::map<std::string, salsa::plots::Series> lines;
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const json& cell = cells[i];
    const std::string at = "cells[" + std::to_string(i) + "]";
    if (!cell.is_object()) throw InputError(name + ": " + at + ": " + salsa::strict_json::shown(cell) + " is not an object");
    const std::string key =
        scale ? "" : " (" + get(cell, at, "targets", "a whole number", [](const json& v) { return v.is_number_unsigned(); }).dump() + " targets)";
    const double n = get(cell, at, "drones", "a number above 0", is_positive).get<double>();
    auto& salsa_line = lines["salsa" + key];
    salsa_line.name = "salsa" + key;
    salsa_line.points.emplace_back(n, get(cell, at, "rtf", "a number above 0", is_positive).get<double>());
    if (cell.contains("floor_rtf")) {
      auto& floor_line = lines["Box2D floor" + key];
      floor_line.name = "Box2D floor" + key;
      floor_line.points.emplace_back(n, get(cell, at, "floor_rtf", "a number above 0", is_positive).get<double>());
    }
  }
  for (auto& [line, series] : lines) c.series.push_back(series);
  return c;
}

salsa::plots::Chart csv_chart(const fs::path& file, const std::string& column) {
  // Whatever the file and the option hold is shown printable (escaped, cut short): one line.
  const std::string shown_file = salsa::strict_json::printable(file.string(), 200);
  std::ifstream in(file);
  if (!in) throw InputError(shown_file + ": cannot open file");
  std::string header;
  std::getline(in, header);
  if (!header.empty() && header.back() == '\r') header.pop_back();
  if (header.empty()) throw InputError(shown_file + ": empty (allowed: a CSV written by salsa with a header row)");
  std::vector<std::string> names;
  std::stringstream hs(header);
  for (std::string n; std::getline(hs, n, ',');) names.push_back(n);
  if (names.empty() || names[0] != "time")
    throw InputError(shown_file + ": the first column is '" + salsa::strict_json::printable(names.empty() ? "" : names[0]) +
                     "', not 'time' (allowed: a CSV written by salsa whose first column is time, e.g. summary.csv)");
  const auto col = std::find(names.begin(), names.end(), column);
  if (col == names.end()) {
    constexpr std::size_t shown_columns = 20;  // a header may hold thousands
    std::string allowed;
    for (std::size_t i = 0; i < names.size() && i < shown_columns; ++i)
      allowed += (i ? ", " : "") + salsa::strict_json::printable(names[i]);
    if (names.size() > shown_columns) allowed += ", ... (" + std::to_string(names.size()) + " columns in all)";
    throw InputError(shown_file + ": --column: '" + salsa::strict_json::printable(column) + "' is not a column (allowed: " +
                     allowed + ")");
  }
  const auto k = static_cast<std::size_t>(col - names.begin());
  salsa::plots::Chart c;
  c.title = file.parent_path().filename().string() + ": " + column;
  c.x_label = "time (s)";
  c.y_label = column;
  salsa::plots::Series s{column, {}};
  std::size_t row = 1;
  // A cell as a finite number, or one line naming the row and column.
  auto number = [&](const std::string& cell, const std::string& name) {
    double v = 0;
    const auto [end, ec] = std::from_chars(cell.data(), cell.data() + cell.size(), v);
    if (ec != std::errc() || end != cell.data() + cell.size() || !std::isfinite(v))
      throw InputError(salsa::strict_json::printable(file.string(), 200) + ": line " + std::to_string(row) + ", column " + name +
                       ": '" + salsa::strict_json::printable(cell) + "' is not a number (allowed: finite numbers)");
    return v;
  };
  for (std::string line; std::getline(in, line);) {
    ++row;
    std::stringstream ls(line);
    std::vector<std::string> cells;
    for (std::string v; std::getline(ls, v, ',');) cells.push_back(v);
    if (cells.size() > k && !cells[k].empty()) s.points.emplace_back(number(cells[0], "time"), number(cells[k], column));
  }
  c.series.push_back(std::move(s));
  return c;
}

// A results folder: a test folder (config.json), a tune folder (its tune.json record and
// candidates.csv) or a queue folder (test folders, and summary.csv when the queue wrote one).
// Everything is redrawn from the files alone.
// --reference VARIANT or --top K for a queue folder, checked as the queue file's "reference" and "top"
// are (the same variants, a behavior's name for its defaults, K from 2 to the variants), before
// anything in the folder is written; nullopt when neither is given: queue.json's choice.
std::optional<salsa::Pairing> pairing_option(const po::variables_map& vm, const fs::path& folder) {
  const bool reference = vm.count("reference"), top = vm.count("top");
  if (!reference && !top) return std::nullopt;
  if (reference && top)
    throw InputError("--top: given with --reference (allowed: one of them; --top compares the best variants with each other, "
                     "--reference every variant with one)");
  const std::vector<std::string> variants = salsa::queue_variants(folder);
  salsa::Pairing p;
  if (top) {
    const std::string text = vm["top"].as<std::string>();
    const std::string allowed = " (allowed: a whole number from 2 to " + std::to_string(variants.size()) + ", the variants of " + folder.string() + ")";
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), p.top);
    if (text.empty() || ec == std::errc::invalid_argument || end != text.data() + text.size())
      throw InputError("--top: '" + salsa::strict_json::printable(text) + "' is not a whole number" + allowed);
    if (ec == std::errc::result_out_of_range || p.top < 2 || p.top > variants.size())
      throw InputError("--top: " + text + " is out of range" + allowed);
    return p;
  }
  const std::string given = vm["reference"].as<std::string>();
  for (const std::string& wanted : {given, salsa::variant_label(given, {})})
    if (p.reference.empty() && std::find(variants.begin(), variants.end(), wanted) != variants.end()) p.reference = wanted;
  if (p.reference.empty()) {
    std::string allowed;
    for (std::size_t i = 0; i < variants.size() && i < 20; ++i) allowed += (i ? "; " : "") + variants[i];
    throw InputError("--reference: '" + salsa::strict_json::printable(given) + "' names no variant of " + folder.string() + " (allowed: " +
                     allowed + (variants.size() > 20 ? "; ..." : "") + "; or a behavior's name for its defaults)");
  }
  return p;
}

void plot_folder(const fs::path& folder, const std::string& metric, const po::variables_map& vm) {
  const bool repair = vm.count("reference") || vm.count("top");
  std::error_code ec;
  if (repair && (fs::is_regular_file(folder / "config.json", ec) || !fs::is_regular_file(folder / "summary.csv", ec) || !salsa::holds_results(folder)))
    throw InputError(std::string(vm.count("reference") ? "--reference" : "--top") + ": " + folder.string() +
                     " is not a queue's folder (allowed: a folder 'salsa run' wrote a queue's summary.csv into)");
  if (fs::is_regular_file(folder / "config.json", ec)) {
    salsa::plots::draw_test_plots(folder);
    std::cout << "plots in " << (folder / "plots").string() << "\n";
    return;
  }
  // The tune's own plots, as salsa tune drew them; its evaluations' folders keep none (salsa plot OUT/<test>).
  // Only in a folder salsa wrote results into (a finished tune always did), as for a queue below.
  if (fs::is_regular_file(folder / "tune.json", ec) && fs::is_regular_file(folder / "candidates.csv", ec) && salsa::holds_results(folder)) {
    salsa::plots::start_plotting();
    salsa::cli::draw_tune_folder(folder);
    std::cout << "tune plots in " << (folder / "plots").string() << "\n";
    return;
  }
  std::vector<fs::path> tests;  // sorted, so the order (and any first error) is the same every time
  for (const auto& entry : fs::directory_iterator(folder, ec))
    if (entry.is_directory(ec) && !entry.path().filename().string().starts_with(".") &&
        fs::is_regular_file(entry.path() / "config.json", ec))
      tests.push_back(entry.path());
  std::sort(tests.begin(), tests.end());
  // A queue folder salsa wrote: a summary.csv of the user's own is not a queue's, and comparison.csv stays theirs.
  const bool queue = fs::is_regular_file(folder / "summary.csv", ec) && salsa::holds_results(folder);
  if (tests.empty() && !queue)
    throw InputError(salsa::strict_json::printable(folder.string(), 200) +
                     ": neither a test folder (no config.json) nor a results folder (no test folders, no summary.csv in a folder salsa wrote)");
  // First: a bad summary.csv, --reference or --top is refused before anything is written or drawn.
  if (queue) salsa::write_comparison(folder, metric, pairing_option(vm, folder));
  for (const auto& test : tests) salsa::plots::draw_test_plots(test);
  if (queue) salsa::plots::draw_queue_plots(folder);
  std::cout << "plots of " << tests.size() << " test" << (tests.size() == 1 ? "" : "s") << " in <test>/plots"
            << (queue ? ", queue plots in " + (folder / "plots").string() + ", comparison in " + (folder / "comparison.csv").string() : "")
            << "\n";
}

}  // namespace

int cmd_plot(int argc, char** argv) {
  po::options_description o("plot options");
  o.add_options()("file", po::value<std::string>(), "a results folder, a test folder, a bench JSON file or a summary.csv")(
      "out,o", po::value<std::string>(), "PNG file to write (for a FILE)")(
      "column", po::value<std::string>()->default_value("targets_found"), "summary.csv column to plot over time")(
      "metric", po::value<std::string>()->default_value("fraction_found"), "queue summary.csv column compared in comparison.csv (FOLDER)")(
      "reference", po::value<std::string>(), "pair each variant with VARIANT in comparison.csv and did.csv instead of the queue's choice (FOLDER)")(
      "top", po::value<std::string>(), "pair the K best variants of each condition with each other instead (FOLDER)");
  po::variables_map vm;
  if (!salsa::cli::parse(argc, argv, "plot",
                         "FOLDER          redraw the plots of a results folder (every test's, the queue's,\n"
                         "                                  comparison.csv), of a tune folder or of one test folder, from their files alone\n"
                         "       salsa plot FILE --out PNG  chart a bench JSON file or a summary.csv column",
                         o, vm, salsa::cli::help_only, salsa::cli::positional("file", 1)))
    return 0;
  if (!vm.count("file")) throw InputError("plot: needs a FOLDER, or a FILE and --out PNG (see 'salsa plot --help')");
  const fs::path file = vm["file"].as<std::string>();
  std::error_code ec;  // a link loop or an unreadable folder is "not a folder" here; reading it says why
  if (fs::is_directory(file, ec)) {
    if (vm.count("out")) throw InputError("--out: " + vm["out"].as<std::string>() + ": not for a folder (its plots go into FOLDER/plots)");
    plot_folder(file, vm["metric"].as<std::string>(), vm);
    return 0;
  }
  for (const char* option : {"reference", "top"})
    if (vm.count(option)) throw InputError(std::string("--") + option + ": " + file.string() + " is not a queue's folder (allowed: a folder 'salsa run' wrote a queue's summary.csv into)");
  if (!vm.count("out")) throw InputError("plot: needs FILE and --out PNG (see 'salsa plot --help')");
  // The PNG goes to a file in an existing folder; say so before drawing anything.
  const fs::path png = vm["out"].as<std::string>();
  const fs::path png_folder = png.parent_path().empty() ? fs::path(".") : png.parent_path();
  if (png.filename().empty() || fs::is_directory(png, ec))
    throw InputError("--out: " + png.string() + " is a folder (allowed: a PNG file name, e.g. found.png)");
  if (!fs::is_directory(png_folder, ec))
    throw InputError("--out: " + png.string() + ": the folder " + png_folder.string() + " does not exist (allowed: a file in an existing folder)");
  const salsa::plots::Chart chart =
      file.extension() == ".csv" ? csv_chart(file, vm["column"].as<std::string>()) : bench_chart(file);
  salsa::plots::save_png(chart, png);
  return 0;
}
