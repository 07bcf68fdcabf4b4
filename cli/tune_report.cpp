// A tune's output files: tune.csv, candidates.csv, best.json and front/, report.txt and tune_plots.json.
#include <nlohmann/json.hpp>

#include <charconv>
#include <cmath>
#include <limits>
#include <sstream>

#include "salsa/core/results/comparison.hpp"
#include "salsa/core/results/queue_summary.hpp"
#include "salsa/core/files/csv_reader.hpp"
#include "salsa/core/files/csv_writer.hpp"
#include "salsa/core/run/output_folder.hpp"
#include "commands.hpp"
#include "tuner.hpp"

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

namespace salsa::cli {

std::string six(double v) {
  if (std::isnan(v)) return "";
  if (v == 0) v = 0;
  char buf[32];
  return {buf, std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general, 6).ptr};
}

namespace {

constexpr double nan_value = std::numeric_limits<double>::quiet_NaN();

/// Parameter values and objective values in the output files: the shortest exact text.
std::string exact(double v) { return Parameter::format(v == 0 ? 0.0 : v); }

const char* status_name(Candidate::Status s) {
  switch (s) {
    case Candidate::running: return "running";
    case Candidate::complete: return "complete";
    case Candidate::dropped: return "dropped";
    case Candidate::failed: return "failed";
    case Candidate::cut: return "cut";
  }
  return "";
}

}  // namespace

std::string Tuner::finish(const std::string& why, const std::string& command, bool draw) {
  write_tune_csv();
  write_candidates_csv();
  const std::size_t winner = best();
  write_best(winner);
  write_plot_record(winner);
  const std::string text = report(why, winner, command);
  write_file(options_.out / "report.txt", text);
  write_queue_summary(options_.out, &host_);
  if (draw) draw_tune_folder(options_.out);  // from the files just written, as `salsa plot OUT` draws them
  return text;
}

// ---- Output files

void Tuner::add(std::string& row, std::string_view field) {
  row += ',';
  row += field;
}

std::string Tuner::header_values() const {
  std::string out;
  for (const TuneParameter& p : spec_.parameters) add(out, csv_field(p.key));
  return out;
}

std::string Tuner::header_objectives() const {
  std::string out;
  for (const Objective& o : spec_.objectives) add(out, csv_field(o.name()));
  return out;
}

void Tuner::write_tune_csv() const {
  std::string text = "evaluation,candidate,phase,world,seed" + header_values() + header_objectives() + ",status,test\n";
  for (std::size_t i = 0; i < evaluations_.size(); ++i) {
    const Evaluation& e = evaluations_[i];
    text += std::to_string(i);
    add(text, std::to_string(e.candidate));
    add(text, e.validation ? "validation" : "tuning");
    add(text, std::to_string(e.world));
    add(text, std::to_string(e.seed));
    for (const double v : candidates_[e.candidate].values) add(text, exact(v));
    for (std::size_t o = 0; o < spec_.objectives.size(); ++o) add(text, e.objectives.empty() ? "" : exact(e.objectives[o]));
    add(text, e.status);
    add(text, e.test);
    text += '\n';
  }
  replace_file(options_.out / "tune.csv", text);
}

void Tuner::write_candidates_csv() const {
  std::string text = "candidate,generation" + header_values() + ",status,worlds,evaluations" + header_objectives() + "\n";
  for (const Candidate& c : candidates_) {
    text += std::to_string(c.id);
    add(text, std::to_string(c.generation));
    for (const double v : c.values) add(text, exact(v));
    add(text, status_name(c.status));
    add(text, std::to_string(c.worlds.size()));
    add(text, std::to_string(c.ended_at));
    for (std::size_t o = 0; o < spec_.objectives.size(); ++o)
      add(text, c.status == Candidate::complete || c.status == Candidate::dropped ? six(shown(o, c.score[o])) : "");
    text += '\n';
  }
  replace_file(options_.out / "candidates.csv", text);
}

void Tuner::write_best(std::size_t winner) const {
  const auto write = [&](std::size_t candidate, const std::string& name, const fs::path& file) {
    json test = json::parse(test_config(test_of(candidates_[candidate], 0), host_));
    test.erase("seed");
    test.erase("repeat");
    test["name"] = name;
    json queue = {{"seed", spec_.seed}, {"repeats", spec_.worlds}, {"tests", json::array({test})}};
    replace_file(file, queue.dump(2) + "\n");
  };
  write(winner, "best", options_.out / "best.json");
  const fs::path front = options_.out / "front";
  std::error_code ec;
  fs::remove_all(front, ec);  // an earlier run's front (another seed, a --force restart) is not this one's
  if (spec_.objectives.size() < 2) return;
  fs::create_directories(front, ec);
  if (ec) throw WriteError(front.string() + ": cannot create the folder (" + ec.message() + ")");
  std::size_t rank = 0;
  for (const std::size_t c : ranking())
    if (on_front(c)) ++rank, write(c, "front_" + std::to_string(rank), front / (std::to_string(rank) + ".json"));
}

std::string Tuner::describe(const Candidate& c) const {
  std::string out;
  for (std::size_t k = 0; k < c.values.size(); ++k) out += (k ? ", " : "") + spec_.parameters[k].key + " = " + exact(c.values[k]);
  return out;
}

std::string Tuner::report(const std::string& why, std::size_t winner, const std::string& command) const {
  std::ostringstream s;
  std::size_t complete = 0, dropped = 0, failed = 0, cut = 0;
  for (const Candidate& c : candidates_) {
    complete += c.status == Candidate::complete;
    dropped += c.status == Candidate::dropped;
    failed += c.status == Candidate::failed;
    cut += c.status == Candidate::cut;
  }
  s << "salsa tune " << spec_.source << ": " << spec_.algorithm << (spec_.local.empty() ? "" : " + " + spec_.local) << ", "
    << spec_.parameters.size() << " parameters, seed " << spec_.seed << "\n";
  s << "command: " << command << "\n";
  if (!spec_.world.empty()) s << "world: " << spec_.world << "\n";
  for (const Objective& o : spec_.objectives)
    s << "objective: " << o.name() << ", " << (o.maximise ? "maximised" : "minimised") << ", " << o.aggregate_name() << " over "
      << spec_.worlds << " tuning worlds\n";
  s << "evaluations: " << used_ << (spec_.evaluations ? " of " + std::to_string(spec_.evaluations) : std::string()) << "; "
    << candidates_.size() << " candidates: " << complete << " complete, " << dropped << " dropped by racing";
  if (spec_.racing.on)
    s << " (paired t-test, one-sided level " << exact(spec_.racing.level) << ", from world " << spec_.racing.first_test << ")";
  s << ", " << failed << " failed, " << cut << " cut by the budget; stopped: " << why << "\n";
  auto scores = [&](const Candidate& c) {
    std::string out;
    for (std::size_t o = 0; o < spec_.objectives.size(); ++o)
      out += (o ? ", " : "") + spec_.objectives[o].name() + " " + (c.score.empty() ? "-" : six(shown(o, c.score[o])));
    return out;
  };
  s << "defaults:  c0, " << scores(candidates_[0]) << " (" << describe(candidates_[0]) << ")\n";
  s << "best:      c" << winner << ", " << scores(candidates_[winner]) << " (" << describe(candidates_[winner]) << ")\n";
  if (spec_.objectives.size() > 1) {
    s << "Pareto front:";
    for (const std::size_t c : ranking())
      if (on_front(c)) s << " c" << c;
    s << "\n";
  }
  if (!validated_.empty()) {
    s << "validation on " << spec_.validation_worlds << " held-out worlds (repeats " << spec_.worlds << " to "
      << spec_.worlds + spec_.validation_worlds - 1 << ", never used for tuning); the winner was chosen on the tuning worlds:\n";
    const Candidate& d = candidates_[0];
    for (const std::size_t id : validated_) {
      const Candidate& c = candidates_[id];
      s << "  c" << id << (id == winner ? " (best)" : id == 0 ? " (defaults)" : "");
      for (std::size_t o = 0; o < spec_.objectives.size(); ++o) {
        const Objective& obj = spec_.objectives[o];
        std::vector<double> mine, diffs;
        for (std::size_t v = 0; v < c.held_out.size(); ++v) {
          if (c.held_out[v].empty()) continue;
          mine.push_back(c.held_out[v][o]);
          if (v < d.held_out.size() && !d.held_out[v].empty()) diffs.push_back(c.held_out[v][o] - d.held_out[v][o]);
        }
        s << (o ? "; " : ": ") << obj.name() << " " << obj.aggregate_name() << " " << six(obj.aggregate_of(mine));
        if (mine.size() < spec_.validation_worlds) s << " (" << spec_.validation_worlds - mine.size() << " failed)";
        if (id != 0 && !diffs.empty()) {
          double m = 0, ss = 0;
          for (const double x : diffs) m += x;
          m /= static_cast<double>(diffs.size());
          for (const double x : diffs) ss += (x - m) * (x - m);
          const double sd = diffs.size() > 1 ? std::sqrt(ss / static_cast<double>(diffs.size() - 1)) : nan_value;
          const double h = t_half_width(diffs.size(), sd);
          s << ", against the defaults " << (m >= 0 ? "+" : "") << six(m) << " (95 % interval " << six(m - h) << " to " << six(m + h)
            << ", " << diffs.size() << " paired worlds)";
        }
      }
      s << "\n";
    }
  }
  s << "files: tune.csv (one row per evaluation), candidates.csv, best.json ('salsa run " << (options_.out / "best.json").string()
    << "' reruns the best on the tuning worlds), "
    << (spec_.objectives.size() > 1 ? "front/<rank>.json (each member of the Pareto front, the same way; 1 is the best), " : "") << "plots/\n";
  return s.str();
}

void Tuner::write_plot_record(std::size_t winner) const {
  json objectives = json::array(), parameters = json::array(), front = json::array();
  for (const Objective& o : spec_.objectives) objectives.push_back({{"name", o.name()}, {"goal", o.maximise ? "max" : "min"}});
  for (const TuneParameter& p : spec_.parameters) parameters.push_back({{"key", p.key}, {"log", p.log}});
  if (spec_.objectives.size() > 1)
    for (const std::size_t c : ranking())
      if (on_front(c)) front.push_back(c);
  const json record = {{"objectives", objectives}, {"parameters", parameters}, {"winner", winner}, {"front", front}};
  replace_file(options_.out / "tune_plots.json", record.dump(2) + "\n");
}

}  // namespace salsa::cli
