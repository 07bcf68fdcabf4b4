// salsa tune FILE: tunes a test's parameters (docs/tuning.md). Every evaluation is an ordinary test run
// into OUT/<candidate>_<world>/ by the queue runner (--jobs, MPI ranks), so a tune has the provenance
// of any run, and --resume works as a queue's does: the tune is a deterministic function of its tests'
// results, so a resumed tune replays itself, finds the finished tests on disk, and runs only the rest.
#include <unistd.h>

#include <boost/math/distributions/students_t.hpp>
#include <nlohmann/json.hpp>
#include <oneapi/tbb/info.h>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <optional>
#include <sstream>

#include "salsa/core/experiments/comparison.hpp"
#include "salsa/core/experiments/queue.hpp"
#include "salsa/core/experiments/queue_summary.hpp"
#include "salsa/core/files/csv_reader.hpp"
#include "salsa/core/files/csv_writer.hpp"
#include "salsa/core/files/output_folder.hpp"
#include "salsa/plots/results.hpp"
#include "salsa/plots/tune.hpp"
#include "strict_json.hpp"
#include "commands.hpp"
#include "mpi.hpp"
#include "options.hpp"
#include "queue_run.hpp"
#include "salsa/core/experiments/tune_file.hpp"
#include "tune_search.hpp"

namespace fs = std::filesystem;
using namespace salsa;
using namespace salsa::cli;
using json = nlohmann::ordered_json;

namespace {

using Clock = std::chrono::steady_clock;
constexpr double nan_value = std::numeric_limits<double>::quiet_NaN();

/// Numbers in the output files: six significant digits (scores), or the shortest exact text (values).
std::string six(double v) {
  if (std::isnan(v)) return "";
  if (v == 0) v = 0;
  char buf[32];
  return {buf, std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general, 6).ptr};
}
std::string exact(double v) { return Parameter::format(v == 0 ? 0.0 : v); }

/// The tuning stopped: a signal, or a write that failed; the exit status says which.
struct Stopped {
  int status;
};

struct Candidate {
  std::size_t id = 0;
  std::size_t generation = 0;
  std::vector<double> values;               ///< the parameters, in the spec's order
  std::vector<std::vector<double>> worlds;  ///< objective values on tuning worlds 0, 1, ... (run so far)
  std::vector<std::vector<double>> held_out;  ///< on the validation worlds (empty: not validated or failed)
  enum Status { running, complete, dropped, failed, cut } status = running;
  std::vector<double> score;                ///< minimised, one per objective (set when it ends)
  std::size_t ended_at = 0;                 ///< evaluations used when it ended
};

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

/// One test run: a row of tune.csv.
struct Evaluation {
  std::size_t candidate = 0, world = 0;
  bool validation = false;
  std::uint64_t seed = 0;
  std::string test;
  std::vector<double> objectives;  ///< empty: failed
  std::string status;              ///< ok, failed, no value
};

class Tuner {
 public:
  /// `chatty`: a line per generation on stdout (not under --quiet, and from rank 0 only).
  Tuner(const TuneSpec& spec, const PluginHost& host, RunOptions run_options, QueueRunOptions queue, MpiRun* mpi, bool chatty)
      : spec_(spec), host_(host), options_(std::move(run_options)), queue_(std::move(queue)), mpi_(mpi), chatty_(chatty),
        start_(Clock::now()) {}

  /// The defaults (the base test's values), then the search, then the local finish.
  std::string tune() {
    std::vector<double> base;
    for (const TuneParameter& p : spec_.parameters) base.push_back(p.base);
    evaluate_values({base});
    generation_done();
    SearchHooks hooks;
    hooks.dim = spec_.parameters.size();
    hooks.objectives = spec_.objectives.size();
    hooks.seed = spec_.seed;
    hooks.population = spec_.population;
    hooks.start = encode(base);
    hooks.evaluate = [&](const std::vector<Point>& points) {
      std::vector<std::vector<double>> values;
      for (const Point& x : points) values.push_back(decode(x));
      std::vector<Point> out = evaluate_values(values);
      generation_done();
      return out;
    };
    hooks.exhausted = [&] { return exhausted(); };
    hooks.points_left = [&] { return left() / spec_.worlds; };
    cap_ = spec_.evaluations ? spec_.evaluations - spec_.local_evaluations : 0;
    std::string why = run_search(spec_.algorithm, hooks);
    if (!spec_.local.empty()) {
      cap_ = spec_.evaluations;
      over_ = false;
      hooks.start = encode(candidates_[best()].values);
      why = run_search(spec_.local, hooks) + " (local finish: " + spec_.local + ")";
    }
    return why;
  }

  /// The best few and the defaults on the held-out worlds.
  void validate() {
    if (spec_.validation_worlds == 0) return;
    std::vector<std::size_t> chosen = ranking();
    if (chosen.size() > spec_.validation_candidates) chosen.resize(spec_.validation_candidates);
    if (std::find(chosen.begin(), chosen.end(), 0) == chosen.end()) chosen.push_back(0);
    std::vector<TestSpec> tests;
    std::vector<std::pair<std::size_t, std::size_t>> which;  // (candidate, world)
    for (const std::size_t c : chosen)
      for (std::size_t v = 0; v < spec_.validation_worlds; ++v) {
        const std::size_t world = spec_.worlds + v;
        tests.push_back(test_of(candidates_[c], world));
        which.emplace_back(c, world);
      }
    run(tests, "validation: ");
    for (std::size_t i = 0; i < tests.size(); ++i) {
      Evaluation e = read(tests[i], which[i].first, which[i].second, true);
      candidates_[which[i].first].held_out.push_back(e.objectives);
      evaluations_.push_back(std::move(e));
    }
    validated_ = chosen;
  }

  /// Writes tune.csv, candidates.csv, best.json, the report and the plots; returns the report.
  std::string finish(const std::string& why, const std::string& command, bool draw) {
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

 private:
  // ---- The search space: the unit cube, mapped to each range (log scale, whole numbers).

  std::vector<double> decode(const Point& x) const {
    std::vector<double> out;
    for (std::size_t k = 0; k < spec_.parameters.size(); ++k) {
      const TuneParameter& p = spec_.parameters[k];
      const double u = std::clamp(x[k], 0.0, 1.0);
      double v = p.log ? std::exp(std::log(p.min) + u * (std::log(p.max) - std::log(p.min))) : p.min + u * (p.max - p.min);
      if (p.whole) {
        v = std::round(v);
      } else {  // five significant digits: readable files, finer than any score tells apart
        char buf[32];
        const auto end = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general, 5).ptr;
        std::from_chars(buf, end, v);
      }
      out.push_back(std::clamp(v, p.min, p.max));
    }
    return out;
  }

  Point encode(const std::vector<double>& values) const {
    Point x;
    for (std::size_t k = 0; k < spec_.parameters.size(); ++k) {
      const TuneParameter& p = spec_.parameters[k];
      const double v = std::clamp(values[k], p.min, p.max);
      x.push_back(p.log ? (std::log(v) - std::log(p.min)) / (std::log(p.max) - std::log(p.min)) : (v - p.min) / (p.max - p.min));
    }
    return x;
  }

  // ---- Budget

  std::size_t left() const {
    if (!cap_) return std::numeric_limits<std::size_t>::max() / 2;
    return used_ >= cap_ ? 0 : cap_ - used_;
  }
  /// The least a new candidate costs: its first block of worlds.
  std::size_t block() const { return spec_.racing.on ? spec_.racing.first_test : spec_.worlds; }
  bool out_of_time() {
    bool late = spec_.seconds > 0 && std::chrono::duration<double>(Clock::now() - start_).count() > spec_.seconds;
    if (mpi_) late = mpi_->agree(late);  // rank 0's clock decides for every rank
    return late;
  }
  bool exhausted() {
    if (over_ || left() < block() || out_of_time()) over_ = true;
    return over_;
  }

  // ---- Tests

  std::string name_of(std::size_t candidate, std::size_t world) const {
    char text[64];
    std::snprintf(text, sizeof text, "c%04zu_w%02zu", candidate, world);
    return text;
  }
  TestSpec test_of(const Candidate& c, std::size_t world) const {
    return candidate_test(spec_, c.values, name_of(c.id, world), world, host_);
  }

  /// Runs tests side by side (the queue runner: --jobs, MPI ranks), refusing first what may not be written.
  void run(const std::vector<TestSpec>& tests, const std::string& label) {
    if (tests.empty()) return;
    if (!mpi_ || mpi_->rank() == 0) check_outputs(tests, host_, options_);
    QueueRunOptions q = queue_;
    q.expected = mpi_ ? (mpi_->rank() == 0 ? tests.size() : 0) : tests.size();
    q.jobs = std::min(q.jobs, mpi_ ? q.jobs : tests.size());
    q.label = label;
    std::unique_ptr<Dispatch> dispatch;
    if (mpi_) {
      dispatch = mpi_->dispatch(tests.size());
    } else {
      std::vector<std::size_t> all(tests.size());
      for (std::size_t i = 0; i < all.size(); ++i) all[i] = i;
      dispatch = std::make_unique<ListDispatch>(all);
    }
    const QueueResult result = run_queue(tests, host_, options_, q, *dispatch);
    if (mpi_) mpi_->barrier();  // every rank's tests are on disk before any rank reads them
    if (result.write_failed) throw Stopped{1};
    if (result.status != 0 && result.status != 1) throw Stopped{result.status};
  }

  /// A finished (or failed) test's objective values, from its folder.
  Evaluation read(const TestSpec& test, std::size_t candidate, std::size_t world, bool validation) const {
    Evaluation e{candidate, world, validation, test.seed, test.name, {}, "failed"};
    const fs::path folder = options_.out / test.name;
    if (!fs::exists(folder / "config.json")) return e;
    std::vector<double> values;
    for (const Objective& o : spec_.objectives) {
      CsvReader csv(folder / (o.from_summary ? "summary.csv" : "outcome.csv"));
      const std::size_t column = csv.column(o.column);
      std::optional<double> value;
      while (csv.next()) {
        if (o.at && csv.number(0) > *o.at + 1e-9) break;
        value = csv.optional_number(column);
      }
      if (!value) {
        e.status = "no value";
        return e;
      }
      values.push_back(*value);
    }
    e.objectives = std::move(values);
    e.status = "ok";
    return e;
  }

  // ---- Evaluating candidates: worlds in blocks, racing between them.

  /// The minimised form of objective `o`'s value.
  double minimised(std::size_t o, double v) const { return spec_.objectives[o].maximise ? -v : v; }
  double aggregate(const Candidate& c, std::size_t o, std::size_t worlds) const {
    std::vector<double> v;
    for (std::size_t w = 0; w < worlds && w < c.worlds.size(); ++w) v.push_back(c.worlds[w][o]);
    return minimised(o, spec_.objectives[o].aggregate_of(v));
  }

  /// The fitness of each list of values (one per objective, minimised), running what is new.
  std::vector<Point> evaluate_values(const std::vector<std::vector<double>>& asked) {
    ++generation_;
    std::vector<std::size_t> ids, racing;
    for (const auto& values : asked) {
      auto [it, fresh] = index_.emplace(values, candidates_.size());
      if (fresh) {
        Candidate c;
        c.id = candidates_.size();
        c.generation = generation_ - 1;
        c.values = values;
        candidates_.push_back(std::move(c));
        racing.push_back(it->second);
      }
      ids.push_back(it->second);
    }
    dropped_now_ = 0;
    std::size_t next = 0;  // the next tuning world to run
    while (!racing.empty() && next < spec_.worlds) {
      const std::size_t end = spec_.racing.on ? std::max(next + 1, std::min(spec_.worlds, next == 0 ? spec_.racing.first_test : next + 1)) : spec_.worlds;
      // What the budget allows: whole candidates' blocks, in order; the rest are cut.
      std::vector<std::size_t> go;
      for (const std::size_t c : racing) {
        if (!out_of_time_checked() && (go.size() + 1) * (end - next) <= left()) go.push_back(c);
        else candidates_[c].status = Candidate::cut, over_ = true;
      }
      std::vector<TestSpec> tests;
      for (const std::size_t c : go)
        for (std::size_t w = next; w < end; ++w) tests.push_back(test_of(candidates_[c], w));
      run(tests, progress_label());
      std::size_t i = 0;
      for (const std::size_t c : go)
        for (std::size_t w = next; w < end; ++w, ++i) {
          Evaluation e = read(tests[i], c, w, false);
          ++used_;
          Candidate& cand = candidates_[c];
          if (e.objectives.empty()) cand.status = Candidate::failed;
          else if (cand.status == Candidate::running) cand.worlds.push_back(e.objectives);
          evaluations_.push_back(std::move(e));
        }
      racing.clear();
      for (const std::size_t c : go)
        if (candidates_[c].status == Candidate::running) racing.push_back(c);
      next = end;
      if (spec_.racing.on && next < spec_.worlds) race(racing, next);
      for (const std::size_t c : go)
        if (candidates_[c].status != Candidate::running && !candidates_[c].ended_at) candidates_[c].ended_at = used_;
    }
    for (const std::size_t c : racing) {
      candidates_[c].status = Candidate::complete;
      candidates_[c].ended_at = used_;
    }
    // Scores: the complete ones first (the estimates of the others refer to the best of them).
    for (Candidate& c : candidates_)
      if (c.score.empty() && c.status == Candidate::complete)
        for (std::size_t o = 0; o < spec_.objectives.size(); ++o) c.score.push_back(aggregate(c, o, spec_.worlds));
    const std::optional<std::size_t> reference = incumbent();
    for (Candidate& c : candidates_) {
      if (!c.score.empty() || c.status == Candidate::running || c.status == Candidate::complete) continue;
      if (c.status == Candidate::dropped && reference) {
        // Dropped by racing: the reference's score plus the candidate's paired difference to it on
        // the worlds it ran, so that its fitness is on the scale of the complete ones.
        const Candidate& r = candidates_[*reference];
        const std::size_t n = c.worlds.size();
        c.score.push_back(r.score[0] + aggregate(c, 0, n) - aggregate(r, 0, n));
      } else {
        c.score = worst();  // failed, or cut by the budget: scored as the worst value seen
      }
    }
    std::vector<Point> out;
    for (const std::size_t id : ids) out.push_back(candidates_[id].score);
    return out;
  }

  bool out_of_time_checked() {
    if (!over_ && out_of_time()) over_ = true;
    return over_;
  }

  /// After `seen` worlds: drops each racing candidate that a one-sided paired t-test finds worse than
  /// the best so far (the best of the racing ones and the incumbent, by mean on those worlds).
  void race(std::vector<std::size_t>& racing, std::size_t seen) {
    if (seen < spec_.racing.first_test || racing.empty()) return;
    std::vector<std::size_t> field = racing;
    if (const auto inc = incumbent()) field.push_back(*inc);
    auto mean = [&](std::size_t c) {
      double s = 0;
      for (std::size_t w = 0; w < seen; ++w) s += minimised(0, candidates_[c].worlds[w][0]);
      return s / static_cast<double>(seen);
    };
    const std::size_t leader = *std::min_element(field.begin(), field.end(), [&](std::size_t a, std::size_t b) {
      const double ma = mean(a), mb = mean(b);
      return ma < mb || (ma == mb && a < b);
    });
    const boost::math::students_t t(static_cast<double>(seen - 1));
    const double critical = boost::math::quantile(boost::math::complement(t, spec_.racing.level));
    std::erase_if(racing, [&](std::size_t c) {
      if (c == leader) return false;
      std::vector<double> d;
      for (std::size_t w = 0; w < seen; ++w)
        d.push_back(minimised(0, candidates_[c].worlds[w][0]) - minimised(0, candidates_[leader].worlds[w][0]));
      double m = 0, ss = 0;
      for (const double x : d) m += x;
      m /= static_cast<double>(seen);
      for (const double x : d) ss += (x - m) * (x - m);
      const double sd = std::sqrt(ss / static_cast<double>(seen - 1));
      const bool worse = m > 0 && (sd == 0 || m / (sd / std::sqrt(static_cast<double>(seen))) > critical);
      if (worse) {
        candidates_[c].status = Candidate::dropped;
        ++dropped_now_;
      }
      return worse;
    });
  }

  /// Per objective, the worst minimised value any world gave so far (0 when none did).
  std::vector<double> worst() const {
    std::vector<double> w(spec_.objectives.size(), -std::numeric_limits<double>::infinity());
    for (const Evaluation& e : evaluations_)
      if (!e.validation)
        for (std::size_t o = 0; o < e.objectives.size(); ++o) w[o] = std::max(w[o], minimised(o, e.objectives[o]));
    for (double& x : w)
      if (!std::isfinite(x)) x = 0;
    return w;
  }

  /// The best complete candidate so far by the first objective (the lowest id of equals).
  std::optional<std::size_t> incumbent() const {
    std::optional<std::size_t> best;
    for (const Candidate& c : candidates_)
      if (c.status == Candidate::complete && !c.score.empty() && (!best || c.score[0] < candidates_[*best].score[0])) best = c.id;
    return best;
  }

  /// The complete candidates, best first: by the first objective; with several, the Pareto front
  /// (by the first objective) before the rest.
  std::vector<std::size_t> ranking() const {
    std::vector<std::size_t> out;
    for (const Candidate& c : candidates_)
      if (c.status == Candidate::complete) out.push_back(c.id);
    std::stable_sort(out.begin(), out.end(), [&](std::size_t a, std::size_t b) {
      const bool fa = on_front(a), fb = on_front(b);
      if (fa != fb) return fa;
      return candidates_[a].score[0] < candidates_[b].score[0];
    });
    return out;
  }
  bool dominates(std::size_t a, std::size_t b) const {
    bool better = false;
    for (std::size_t o = 0; o < spec_.objectives.size(); ++o) {
      if (candidates_[a].score[o] > candidates_[b].score[o]) return false;
      better = better || candidates_[a].score[o] < candidates_[b].score[o];
    }
    return better;
  }
  bool on_front(std::size_t c) const {
    if (spec_.objectives.size() < 2) return true;
    for (const Candidate& other : candidates_)
      if (other.status == Candidate::complete && dominates(other.id, c)) return false;
    return true;
  }
  std::size_t best() const {
    const std::vector<std::size_t> r = ranking();
    return r.empty() ? 0 : r.front();
  }

  /// The score in the objective's own sense (maximised ones back to their sign).
  double shown(std::size_t o, double minimised_value) const { return spec_.objectives[o].maximise ? -minimised_value : minimised_value; }

  // ---- Progress

  std::string progress_label() const {
    std::ostringstream s;
    s << "tune " << used_;
    if (spec_.evaluations) s << "/" << spec_.evaluations;
    s << " evaluations, generation " << generation_ - 1;
    if (const auto inc = incumbent()) s << ", best " << six(shown(0, candidates_[*inc].score[0]));
    s << " | ";
    return s.str();
  }
  /// After each generation: its line, and tune.csv and candidates.csv so far (what the desktop's Tune
  /// page draws while the tune runs; rewritten whole, replaced atomically, by rank 0 only).
  void generation_done() const {
    if (!mpi_ || mpi_->rank() == 0) {
      write_tune_csv();
      write_candidates_csv();
    }
    say_generation();
  }
  void say_generation() const {
    if (!chatty_) return;
    std::size_t count = 0;
    for (const Candidate& c : candidates_) count += c.generation == generation_ - 1;
    std::ostringstream s;
    s << "generation " << generation_ - 1 << ": " << count << " new candidates";
    if (dropped_now_) s << ", " << dropped_now_ << " dropped by racing";
    s << "; " << used_ << (spec_.evaluations ? "/" + std::to_string(spec_.evaluations) : std::string()) << " evaluations";
    if (const auto inc = incumbent())
      s << "; best c" << *inc << " " << spec_.objectives[0].name() << " " << six(shown(0, candidates_[*inc].score[0]));
    if (!candidates_.empty() && !candidates_[0].score.empty())
      s << " (defaults " << six(shown(0, candidates_[0].score[0])) << ")";
    std::cout << s.str() << std::endl;
  }

  // ---- Output files

  /// CSV fields appended after a comma each (one at a time: GCC 12 warns falsely about "," + string).
  static void add(std::string& row, std::string_view field) {
    row += ',';
    row += field;
  }
  std::string header_values() const {
    std::string out;
    for (const TuneParameter& p : spec_.parameters) add(out, csv_field(p.key));
    return out;
  }
  std::string header_objectives() const {
    std::string out;
    for (const Objective& o : spec_.objectives) add(out, csv_field(o.name()));
    return out;
  }

  void write_tune_csv() const {
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

  void write_candidates_csv() const {
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

  /// best.json: the winner on the tuning worlds, as a queue `salsa run` reruns byte for byte (the
  /// tune's seed, one repeat per world: the same paired seeds). With several objectives also
  /// front/<rank>.json, each member of the Pareto front the same way, ranked as best.json's winner is
  /// chosen (by the first objective): front/1.json is best.json's candidate.
  void write_best(std::size_t winner) const {
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

  std::string describe(const Candidate& c) const {
    std::string out;
    for (std::size_t k = 0; k < c.values.size(); ++k) out += (k ? ", " : "") + spec_.parameters[k].key + " = " + exact(c.values[k]);
    return out;
  }

  std::string report(const std::string& why, std::size_t winner, const std::string& command) const {
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

  /// tune_plots.json: what the plots need besides candidates.csv (each objective's goal, each
  /// parameter's scale, the winner, the Pareto front), so that they can be redrawn from files alone.
  void write_plot_record(std::size_t winner) const {
    json objectives = json::array(), parameters = json::array(), front = json::array();
    for (const Objective& o : spec_.objectives) objectives.push_back({{"name", o.name()}, {"goal", o.maximise ? "max" : "min"}});
    for (const TuneParameter& p : spec_.parameters) parameters.push_back({{"key", p.key}, {"log", p.log}});
    if (spec_.objectives.size() > 1)
      for (const std::size_t c : ranking())
        if (on_front(c)) front.push_back(c);
    const json record = {{"objectives", objectives}, {"parameters", parameters}, {"winner", winner}, {"front", front}};
    replace_file(options_.out / "tune_plots.json", record.dump(2) + "\n");
  }

  const TuneSpec& spec_;
  const PluginHost& host_;
  RunOptions options_;
  QueueRunOptions queue_;
  MpiRun* mpi_;
  bool chatty_;
  Clock::time_point start_;
  std::vector<Candidate> candidates_;
  std::map<std::vector<double>, std::size_t> index_;
  std::vector<Evaluation> evaluations_;
  std::vector<std::size_t> validated_;
  std::size_t used_ = 0, cap_ = 0, generation_ = 0, dropped_now_ = 0;
  bool over_ = false;
};

po::options_description tune_options() {
  po::options_description o("tune options");
  o.add_options()("file", po::value<std::string>(), "the tune file")(
      "out,o", po::value<std::string>()->default_value("tune"), "output folder: one test folder per evaluation, tune.csv, best.json, report.txt, plots/")(
      "jobs,j", po::value<std::string>(), "tests run at once (default: all cores; 1 per rank under mpirun)")(
      "threads", po::value<std::string>()->default_value("0"), "threads for each simulation's decide phase (0: all cores; default 1 when tests run side by side)")(
      "resume", "continue an interrupted tune in OUT: finished tests are read back, the rest run")(
      "force", "replace what an earlier tune wrote in OUT")(
      "no-plots", "do not draw the tune's plots");
  return o;
}

/// OUT/tune.json records the tune file that writes OUT: another tune is refused, the same one needs --resume.
void claim_tune_folder(const fs::path& out, const TuneSpec& spec, bool resume, bool force) {
  const fs::path record = out / "tune.json";
  if (fs::exists(record) && !force) {
    std::ifstream in(record);
    std::stringstream text;
    text << in.rdbuf();
    if (text.str() != spec.canonical + "\n")
      throw InputError(out.string() + ": holds another tune (its tune.json differs from " + spec.source +
                       "; allowed: the same tune file and seed with --resume, or --force to replace it, or another --out)");
    if (!resume) throw InputError(out.string() + ": holds this tune already (allowed: --resume to continue it, --force to start again, or another --out)");
  } else if (!fs::exists(record) && holds_results(out) && !force) {
    throw InputError(out.string() + ": holds results that no tune wrote (allowed: another --out, or --force)");
  }
  replace_file(record, spec.canonical + "\n");
}

}  // namespace

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

int cmd_tune(int argc, char** argv) {
  po::variables_map vm;
  if (!parse(argc, argv, "tune", "FILE [options]", tune_options(), vm, plugin_options | queue_options, positional("file", 1))) return 0;
  if (!vm.count("file")) throw InputError("tune: missing FILE (a tune file, see docs/tuning.md)");
  const bool quiet = vm.count("quiet");
  install_signal_handlers();
  const bool mpi = under_mpirun();
  if (mpi && !mpi_built())
    throw InputError("salsa runs under mpirun but was built without MPI: install libopenmpi-dev (Debian) and rebuild, or run without mpirun");
  if (vm.count("resume") && vm.count("force")) throw InputError("--resume and --force: one or the other");
  PluginHost host;
  load_plugins(host, vm, true);
  std::optional<std::uint64_t> seed;
  if (vm.count("seed")) seed = queue_settings(vm).seed;
  const TuneSpec spec = load_tune(vm["file"].as<std::string>(), host, seed);

  RunOptions options;
  options.out = vm["out"].as<std::string>();
  options.force = vm.count("force");
  options.resume = !options.force;  // a test folder in OUT is this tune's (tune.json says so): read back, not rerun
  options.threads = static_cast<int>(whole_option(vm, "threads", 1024, "; 0 means all cores"));
  options.drones_csv = false;  // the largest file, and no objective reads it
  std::size_t jobs = vm.count("jobs") ? whole_option(vm, "jobs", 1024, "; 0 means all cores") : mpi ? 1 : 0;
  if (jobs == 0) jobs = static_cast<std::size_t>(std::max(1, tbb::info::default_concurrency()));
  if (jobs > 1 && vm["threads"].defaulted()) options.threads = 1;

  std::optional<MpiRun> world;
  if (mpi) world.emplace();
  const bool root = !world || world->rank() == 0;
  std::vector<std::string> command{"salsa"};
  command.insert(command.end(), argv, argv + argc);
  std::string line;
  for (const auto& a : command) line += (line.empty() ? "" : " ") + a;
  OutputLock lock;
  if (!claimed_on_rank0(world ? &*world : nullptr, [&] {
        lock = claim_output(options.out, 0, 1, line);
        claim_tune_folder(options.out, spec, vm.count("resume"), options.force);
      }))
    return 2;  // rank 0 said why

  QueueRunOptions queue;
  queue.jobs = jobs;
  queue.quiet = quiet || !root || !::isatty(STDOUT_FILENO);  // a terminal shows the bar; elsewhere one line per generation
  queue.plots = false;  // per-test plots of hundreds of evaluations: `salsa plot OUT/<test>` draws any of them
  queue.terminal = !world && ::isatty(STDOUT_FILENO);
  stop_may_exit(false);
  Tuner tuner(spec, host, options, queue, world ? &*world : nullptr, !quiet && root);
  try {
    const std::string why = tuner.tune();
    tuner.validate();
    if (!root) return 0;
    const bool draw = !vm.count("no-plots");
    if (draw) plots::start_plotting();
    const std::string text = tuner.finish(why, line, draw);
    if (!quiet) std::cout << text;
  } catch (const Stopped& s) {
    if (s.status >= 128 && root) std::cerr << "salsa: tune stopped; 'salsa tune " << spec.source << " --out " << options.out.string()
                                            << " --resume' continues it exactly" << std::endl;
    return s.status;
  }
  return 0;
}
