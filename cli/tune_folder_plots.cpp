// A tune folder's plots (convergence, each parameter, the Pareto front), drawn from tune_plots.json and candidates.csv.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <limits>

#include "salsa/core/experiments/test_spec.hpp"
#include "salsa/core/files/csv_reader.hpp"
#include "salsa/plots/tune.hpp"
#include "strict_json.hpp"
#include "commands.hpp"

namespace fs = std::filesystem;
using namespace salsa;
using json = nlohmann::ordered_json;

void salsa::cli::draw_tune_folder(const fs::path& out) {
  // ---- tune_plots.json: the objectives, the parameters, the winner and the front.
  const fs::path record_file = out / "tune_plots.json";
  const std::string where = strict_json::printable(record_file.string(), 200);
  json record;
  try {
    record = strict_json::read_file<json>(record_file, "the tune's plot record, written by salsa tune");
  } catch (const strict_json::Error& e) {
    throw InputError(e.what());
  }
  const auto field = [&](const json& object, const std::string& at, const char* key, const char* kind, bool ok(const json&)) -> const json& {
    const std::string name = at.empty() ? key : at + "." + key;
    if (!object.is_object() || !object.contains(key)) throw InputError(where + ": " + name + ": missing (allowed: " + kind + "; rerun salsa tune --resume to rewrite it)");
    if (!ok(object[key])) throw InputError(where + ": " + name + ": " + strict_json::shown(object[key]) + " is not " + kind);
    return object[key];
  };
  const auto is_list = [](const json& v) { return v.is_array() && !v.empty(); };
  const json& objectives = field(record, "", "objectives", "a list of objectives", is_list);
  const json& parameters = field(record, "", "parameters", "a list of parameters", is_list);
  const std::size_t winner = field(record, "", "winner", "a candidate number", [](const json& v) { return v.is_number_unsigned(); }).get<std::size_t>();
  std::vector<std::size_t> front;
  for (const json& c : field(record, "", "front", "a list of candidate numbers", [](const json& v) { return v.is_array(); })) {
    if (!c.is_number_unsigned()) throw InputError(where + ": front: " + strict_json::shown(c) + " is not a candidate number");
    front.push_back(c.get<std::size_t>());
  }
  std::vector<std::string> names;
  for (std::size_t o = 0; o < objectives.size(); ++o) {
    const std::string at = "objectives[" + std::to_string(o) + "]";
    names.push_back(field(objectives[o], at, "name", "a column name", [](const json& v) { return v.is_string(); }).get<std::string>());
    field(objectives[o], at, "goal", "max or min", [](const json& v) { return v == "max" || v == "min"; });
  }
  plots::TunePlot p;
  p.objective = names[0];
  p.maximise = objectives[0]["goal"] == "max";
  for (std::size_t k = 0; k < parameters.size(); ++k) {
    const std::string at = "parameters[" + std::to_string(k) + "]";
    const std::string key = field(parameters[k], at, "key", "a dotted key", [](const json& v) { return v.is_string(); }).get<std::string>();
    p.parameters.push_back({key, field(parameters[k], at, "log", "true or false", [](const json& v) { return v.is_boolean(); }).get<bool>(), {}});
  }
  if (names.size() > 1) p.second_objective = names[1];

  // ---- candidates.csv: the scored candidates (complete, or dropped by racing at their estimate).
  CsvReader csv(out / "candidates.csv");
  const std::size_t c_id = csv.column("candidate"), c_status = csv.column("status"), c_used = csv.column("evaluations");
  std::vector<std::size_t> c_values, c_scores;
  for (const auto& param : p.parameters) c_values.push_back(csv.column(param.key));
  for (std::size_t o = 0; o < std::min<std::size_t>(names.size(), 2); ++o) c_scores.push_back(csv.column(names[o]));
  p.winner = std::numeric_limits<std::size_t>::max();
  std::vector<std::pair<double, double>> ended;  // (evaluations used when it ended, score) of the complete ones
  while (csv.next()) {
    const double id = csv.number(c_id);
    const std::string_view status = csv[c_status];
    if (id == 0)
      if (const auto score = csv.optional_number(c_scores[0])) p.defaults = *score;
    if (status != "complete" && status != "dropped") continue;
    for (std::size_t k = 0; k < c_values.size(); ++k) p.parameters[k].values.push_back(csv.number(c_values[k]));
    p.scores.push_back(csv.number(c_scores[0]));
    p.dropped.push_back(status == "dropped");
    if (id == static_cast<double>(winner)) p.winner = p.scores.size() - 1;
    if (c_scores.size() > 1) {
      p.second.push_back(csv.number(c_scores[1]));
      p.on_front.push_back(std::find(front.begin(), front.end(), static_cast<std::size_t>(id)) != front.end());
    }
    if (status == "complete") ended.emplace_back(csv.number(c_used), p.scores.back());
  }
  std::stable_sort(ended.begin(), ended.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  for (const auto& [used, score] : ended) {
    const bool better = p.best_so_far.empty() || (p.maximise ? score > p.best_so_far.back().second : score < p.best_so_far.back().second);
    p.best_so_far.emplace_back(used, better ? score : p.best_so_far.back().second);
  }
  plots::draw_tune_plots(out / "plots", p);
}
