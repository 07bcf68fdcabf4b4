// The tune loop: candidates run on the tuning worlds in blocks, raced, scored and ranked within the budget, then validated.
#include <boost/math/distributions/students_t.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <iostream>
#include <limits>
#include <sstream>

#include "salsa/core/files/csv_reader.hpp"
#include "tuner.hpp"

namespace fs = std::filesystem;

namespace salsa::cli {

std::string Tuner::tune() {
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

void Tuner::validate() {
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

// ---- The search space: the unit cube, mapped to each range (log scale, whole numbers).

std::vector<double> Tuner::decode(const Point& x) const {
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

Point Tuner::encode(const std::vector<double>& values) const {
  Point x;
  for (std::size_t k = 0; k < spec_.parameters.size(); ++k) {
    const TuneParameter& p = spec_.parameters[k];
    const double v = std::clamp(values[k], p.min, p.max);
    x.push_back(p.log ? (std::log(v) - std::log(p.min)) / (std::log(p.max) - std::log(p.min)) : (v - p.min) / (p.max - p.min));
  }
  return x;
}

// ---- Budget

std::size_t Tuner::left() const {
  if (!cap_) return std::numeric_limits<std::size_t>::max() / 2;
  return used_ >= cap_ ? 0 : cap_ - used_;
}

bool Tuner::out_of_time() {
  bool late = spec_.seconds > 0 && std::chrono::duration<double>(Clock::now() - start_).count() > spec_.seconds;
  if (mpi_) late = mpi_->agree(late);  // rank 0's clock decides for every rank
  return late;
}

bool Tuner::exhausted() {
  if (over_ || left() < block() || out_of_time()) over_ = true;
  return over_;
}

// ---- Tests

std::string Tuner::name_of(std::size_t candidate, std::size_t world) const {
  char text[64];
  std::snprintf(text, sizeof text, "c%04zu_w%02zu", candidate, world);
  return text;
}

TestSpec Tuner::test_of(const Candidate& c, std::size_t world) const {
  return candidate_test(spec_, c.values, name_of(c.id, world), world, host_);
}

void Tuner::run(const std::vector<TestSpec>& tests, const std::string& label) {
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

Evaluation Tuner::read(const TestSpec& test, std::size_t candidate, std::size_t world, bool validation) const {
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

double Tuner::aggregate(const Candidate& c, std::size_t o, std::size_t worlds) const {
  std::vector<double> v;
  for (std::size_t w = 0; w < worlds && w < c.worlds.size(); ++w) v.push_back(c.worlds[w][o]);
  return minimised(o, spec_.objectives[o].aggregate_of(v));
}

std::vector<Point> Tuner::evaluate_values(const std::vector<std::vector<double>>& asked) {
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

bool Tuner::out_of_time_checked() {
  if (!over_ && out_of_time()) over_ = true;
  return over_;
}

void Tuner::race(std::vector<std::size_t>& racing, std::size_t seen) {
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

std::vector<double> Tuner::worst() const {
  std::vector<double> w(spec_.objectives.size(), -std::numeric_limits<double>::infinity());
  for (const Evaluation& e : evaluations_)
    if (!e.validation)
      for (std::size_t o = 0; o < e.objectives.size(); ++o) w[o] = std::max(w[o], minimised(o, e.objectives[o]));
  for (double& x : w)
    if (!std::isfinite(x)) x = 0;
  return w;
}

std::optional<std::size_t> Tuner::incumbent() const {
  std::optional<std::size_t> best;
  for (const Candidate& c : candidates_)
    if (c.status == Candidate::complete && !c.score.empty() && (!best || c.score[0] < candidates_[*best].score[0])) best = c.id;
  return best;
}

std::vector<std::size_t> Tuner::ranking() const {
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

bool Tuner::dominates(std::size_t a, std::size_t b) const {
  bool better = false;
  for (std::size_t o = 0; o < spec_.objectives.size(); ++o) {
    if (candidates_[a].score[o] > candidates_[b].score[o]) return false;
    better = better || candidates_[a].score[o] < candidates_[b].score[o];
  }
  return better;
}

bool Tuner::on_front(std::size_t c) const {
  if (spec_.objectives.size() < 2) return true;
  for (const Candidate& other : candidates_)
    if (other.status == Candidate::complete && dominates(other.id, c)) return false;
  return true;
}

std::size_t Tuner::best() const {
  const std::vector<std::size_t> r = ranking();
  return r.empty() ? 0 : r.front();
}

// ---- Progress

std::string Tuner::progress_label() const {
  std::ostringstream s;
  s << "tune " << used_;
  if (spec_.evaluations) s << "/" << spec_.evaluations;
  s << " evaluations, generation " << generation_ - 1;
  if (const auto inc = incumbent()) s << ", best " << six(shown(0, candidates_[*inc].score[0]));
  s << " | ";
  return s.str();
}

void Tuner::generation_done() const {
  if (!mpi_ || mpi_->rank() == 0) {
    write_tune_csv();
    write_candidates_csv();
  }
  say_generation();
}

void Tuner::say_generation() const {
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

}  // namespace salsa::cli
