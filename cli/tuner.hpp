#pragma once
// salsa tune's Tuner: the tune loop (tuner.cpp), its output files and report (tune_report.cpp).
#include <chrono>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "salsa/core/experiments/tune_file.hpp"
#include "mpi.hpp"
#include "queue_run.hpp"
#include "tune_search.hpp"

namespace salsa::cli {

using Clock = std::chrono::steady_clock;

/// A score as the output files and the progress lines show it: six significant digits.
std::string six(double v);

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
  std::string tune();

  /// The best few and the defaults on the held-out worlds.
  void validate();

  /// Writes tune.csv, candidates.csv, best.json, the report and the plots; returns the report.
  std::string finish(const std::string& why, const std::string& command, bool draw);

 private:
  // ---- The search space: the unit cube, mapped to each range (log scale, whole numbers).

  std::vector<double> decode(const Point& x) const;
  Point encode(const std::vector<double>& values) const;

  // ---- Budget

  std::size_t left() const;
  /// The least a new candidate costs: its first block of worlds.
  std::size_t block() const { return spec_.racing.on ? spec_.racing.first_test : spec_.worlds; }
  bool out_of_time();
  bool exhausted();

  // ---- Tests

  std::string name_of(std::size_t candidate, std::size_t world) const;
  TestSpec test_of(const Candidate& c, std::size_t world) const;

  /// Runs tests side by side (the queue runner: --jobs, MPI ranks), refusing first what may not be written.
  void run(const std::vector<TestSpec>& tests, const std::string& label);

  /// A finished (or failed) test's objective values, from its folder.
  Evaluation read(const TestSpec& test, std::size_t candidate, std::size_t world, bool validation) const;

  // ---- Evaluating candidates: worlds in blocks, racing between them.

  /// The minimised form of objective `o`'s value.
  double minimised(std::size_t o, double v) const { return spec_.objectives[o].maximise ? -v : v; }
  double aggregate(const Candidate& c, std::size_t o, std::size_t worlds) const;

  /// The fitness of each list of values (one per objective, minimised), running what is new.
  std::vector<Point> evaluate_values(const std::vector<std::vector<double>>& asked);
  bool out_of_time_checked();

  /// After `seen` worlds: drops each racing candidate that a one-sided paired t-test finds worse than
  /// the best so far (the best of the racing ones and the incumbent, by mean on those worlds).
  void race(std::vector<std::size_t>& racing, std::size_t seen);

  /// Per objective, the worst minimised value any world gave so far (0 when none did).
  std::vector<double> worst() const;

  /// The best complete candidate so far by the first objective (the lowest id of equals).
  std::optional<std::size_t> incumbent() const;

  /// The complete candidates, best first: by the first objective; with several, the Pareto front
  /// (by the first objective) before the rest.
  std::vector<std::size_t> ranking() const;
  bool dominates(std::size_t a, std::size_t b) const;
  bool on_front(std::size_t c) const;
  std::size_t best() const;

  /// The score in the objective's own sense (maximised ones back to their sign).
  double shown(std::size_t o, double minimised_value) const { return spec_.objectives[o].maximise ? -minimised_value : minimised_value; }

  // ---- Progress

  std::string progress_label() const;
  /// After each generation: its line, and tune.csv and candidates.csv so far (what the desktop's Tune
  /// page draws while the tune runs; rewritten whole, replaced atomically, by rank 0 only).
  void generation_done() const;
  void say_generation() const;

  // ---- Output files (tune_report.cpp)

  /// CSV fields appended after a comma each (one at a time: GCC 12 warns falsely about "," + string).
  static void add(std::string& row, std::string_view field);
  std::string header_values() const;
  std::string header_objectives() const;
  void write_tune_csv() const;
  void write_candidates_csv() const;

  /// best.json: the winner on the tuning worlds, as a queue `salsa run` reruns byte for byte (the
  /// tune's seed, one repeat per world: the same paired seeds). With several objectives also
  /// front/<rank>.json, each member of the Pareto front the same way, ranked as best.json's winner is
  /// chosen (by the first objective): front/1.json is best.json's candidate.
  void write_best(std::size_t winner) const;
  std::string describe(const Candidate& c) const;
  std::string report(const std::string& why, std::size_t winner, const std::string& command) const;

  /// tune_plots.json: what the plots need besides candidates.csv (each objective's goal, each
  /// parameter's scale, the winner, the Pareto front), so that they can be redrawn from files alone.
  void write_plot_record(std::size_t winner) const;
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

}  // namespace salsa::cli
