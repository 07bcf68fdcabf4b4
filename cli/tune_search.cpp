// The search algorithms: pagmo2's population methods driven a generation at a time, NLopt's local
// methods a point at a time, and the random, Latin-hypercube and grid baselines.
//
// pagmo's algorithms ask their problem for one fitness after another. To run a generation's tests side
// by side, each generation is evolved twice: first a copy of the algorithm and population evolves
// against a problem that only records the points asked for (the "probe"); those points are evaluated
// together; then the real algorithm evolves against the answers. Copies of a pagmo algorithm carry its
// random engine and memory, so both passes ask for the same points: this holds for every method used
// here (cmaes, xnes, pso_gen, de, nsga2 all draw a whole generation before evaluating any of it). A
// point the probe did not foresee is still evaluated, on its own: the result never depends on it.
#include "tune_search.hpp"

#include <nlopt.hpp>
#include <pagmo/algorithm.hpp>
#include <pagmo/algorithms/cmaes.hpp>
#include <pagmo/algorithms/de.hpp>
#include <pagmo/algorithms/nsga2.hpp>
#include <pagmo/algorithms/pso_gen.hpp>
#include <pagmo/algorithms/xnes.hpp>
#include <pagmo/population.hpp>
#include <pagmo/problem.hpp>

#include <algorithm>
#include <cmath>
#include <exception>
#include <map>
#include <memory>
#include <set>

#include <salsa/rng.hpp>

namespace salsa::cli {

namespace {

/// pagmo's seeds are 32 bits: the tune seed's own stream.
unsigned seed32(std::uint64_t seed, std::uint64_t purpose) { return static_cast<unsigned>(Rng(seed, purpose).next() >> 32); }

/// What the pagmo problem answers: recorded points (probing), or the fitness evaluated for them.
struct Oracle {
  const SearchHooks* hooks = nullptr;
  bool probing = false;
  std::vector<Point> asked;
  std::map<Point, Point> known;
};

/// The pagmo problem: the unit cube, fitness from the oracle.
struct CubeProblem {
  std::shared_ptr<Oracle> oracle;
  std::size_t dim = 1, objectives = 1;

  pagmo::vector_double fitness(const pagmo::vector_double& x) const {
    if (oracle->probing) {
      oracle->asked.push_back(x);
      return pagmo::vector_double(objectives, 0.0);
    }
    if (const auto it = oracle->known.find(x); it != oracle->known.end()) return it->second;
    const Point f = oracle->hooks->evaluate({x}).at(0);  // not foreseen by the probe: alone
    oracle->known.emplace(x, f);
    return f;
  }
  std::pair<pagmo::vector_double, pagmo::vector_double> get_bounds() const {
    return {pagmo::vector_double(dim, 0.0), pagmo::vector_double(dim, 1.0)};
  }
  pagmo::vector_double::size_type get_nobj() const { return objectives; }
  std::string get_name() const { return "salsa tune"; }
};

pagmo::algorithm pagmo_algorithm(const std::string& name, const SearchHooks& h) {
  const unsigned s = seed32(h.seed, 1);
  // One generation per evolve, memory kept between calls; the flatness exits are off (0): with noisy
  // scores a flat generation says nothing, and the budget ends the search.
  if (name == "cmaes") return pagmo::algorithm(pagmo::cmaes(1, -1, -1, -1, -1, 0.3, 0, 0, true, true, s));
  if (name == "xnes") return pagmo::algorithm(pagmo::xnes(1, -1, -1, -1, 0.3, 0, 0, true, true, s));
  if (name == "pso") return pagmo::algorithm(pagmo::pso_gen(1, 0.7298, 2.05, 2.05, 0.5, 5u, 2u, 4u, true, s));
  if (name == "de") return pagmo::algorithm(pagmo::de(1, 0.8, 0.9, 2u, 0, 0, s));
  return pagmo::algorithm(pagmo::nsga2(1, 0.95, 10., 1.0 / static_cast<double>(h.dim), 50., s));
}

std::string run_pagmo(const std::string& name, const SearchHooks& h) {
  auto oracle = std::make_shared<Oracle>();
  oracle->hooks = &h;
  pagmo::problem problem{CubeProblem{oracle, h.dim, h.objectives}};
  pagmo::algorithm algorithm = pagmo_algorithm(name, h);

  // The first generation: the start point and random points, evaluated together.
  const std::size_t size = h.population ? h.population : default_population(name, h.dim, h.objectives);
  Rng rng(h.seed, 2);
  std::vector<Point> first{h.start};
  while (first.size() < size) {
    Point x(h.dim);
    for (double& v : x) v = rng.uniform();
    first.push_back(std::move(x));
  }
  const std::vector<Point> f = h.evaluate(first);
  pagmo::population population(problem, 0u, seed32(h.seed, 3));
  for (std::size_t i = 0; i < first.size(); ++i) {
    oracle->known.emplace(first[i], f[i]);
    population.push_back(first[i], f[i]);
  }

  std::size_t idle = 0;  // generations in a row that asked only for points already evaluated
  while (!h.exhausted()) {
    pagmo::algorithm probe = algorithm;
    pagmo::population trial = population;
    oracle->probing = true;
    oracle->asked.clear();
    try {
      trial = probe.evolve(trial);
    } catch (...) {
      oracle->probing = false;
      throw;
    }
    oracle->probing = false;
    std::vector<Point> fresh;
    std::set<Point> seen;
    for (const Point& x : oracle->asked)
      if (!oracle->known.count(x) && seen.insert(x).second) fresh.push_back(x);
    if (fresh.empty()) {
      if (++idle == 20) return "converged: 20 generations asked for nothing new";
    } else {
      idle = 0;
      const std::vector<Point> values = h.evaluate(fresh);
      for (std::size_t i = 0; i < fresh.size(); ++i) oracle->known.emplace(fresh[i], values[i]);
    }
    population = algorithm.evolve(population);
  }
  return "budget";
}

std::string run_nlopt(const std::string& name, const SearchHooks& h) {
  // BOBYQA needs two or more dimensions; with one parameter COBYLA takes its place.
  const nlopt::algorithm method = name == "neldermead" ? nlopt::LN_NELDERMEAD : h.dim >= 2 ? nlopt::LN_BOBYQA : nlopt::LN_COBYLA;
  nlopt::opt opt(method, static_cast<unsigned>(h.dim));
  opt.set_lower_bounds(0.0);
  opt.set_upper_bounds(1.0);
  opt.set_initial_step(0.1);
  opt.set_xtol_abs(1e-4);  // a ten-thousandth of each range: finer than any score can tell apart
  opt.set_maxeval(static_cast<int>(std::min<std::size_t>(h.points_left(), 1'000'000'000)));
  struct Context {
    const SearchHooks* h;
    std::exception_ptr error;  // NLopt swallows what the objective throws: kept here and thrown again
  } context{&h, nullptr};
  opt.set_min_objective(
      [](const std::vector<double>& x, std::vector<double>&, void* data) -> double {
        auto* c = static_cast<Context*>(data);
        if (c->h->exhausted()) throw nlopt::forced_stop();
        try {
          return c->h->evaluate({x}).at(0).at(0);
        } catch (...) {
          c->error = std::current_exception();
          throw nlopt::forced_stop();
        }
      },
      &context);
  Point x = h.start;
  double value = 0;
  nlopt::result result = nlopt::FAILURE;
  try {
    result = opt.optimize(x, value);
  } catch (const nlopt::forced_stop&) {
    if (context.error) std::rethrow_exception(context.error);
    return "budget";
  } catch (const std::exception& e) {
    if (context.error) std::rethrow_exception(context.error);
    return std::string("NLopt stopped: ") + e.what();
  }
  if (result == nlopt::MAXEVAL_REACHED) return "budget";
  return "converged: NLopt's " + std::string(name) + " reached its tolerance";
}

/// Evaluates `points` in batches of the population size, until they are done or the budget is.
bool in_batches(const std::vector<Point>& points, std::size_t batch, const SearchHooks& h) {
  for (std::size_t i = 0; i < points.size() && !h.exhausted(); i += batch)
    h.evaluate(std::vector<Point>(points.begin() + static_cast<std::ptrdiff_t>(i),
                                  points.begin() + static_cast<std::ptrdiff_t>(std::min(points.size(), i + batch))));
  return !h.exhausted();
}

}  // namespace

std::size_t default_population(const std::string& algorithm, std::size_t dim, std::size_t objectives) {
  const auto d = static_cast<double>(dim);
  if (algorithm == "nsga2" || objectives > 1) return std::max<std::size_t>(8, (static_cast<std::size_t>(4 + 4 * d) + 3) / 4 * 4);
  if (algorithm == "de" || algorithm == "pso") return std::max<std::size_t>(8, static_cast<std::size_t>(5 * d));
  // CMA-ES's own rule, 4 + 3 ln d, at least 5 (pagmo's least); the baselines batch as many.
  return std::max<std::size_t>(5, static_cast<std::size_t>(4 + std::floor(3 * std::log(d))));
}

std::string run_search(const std::string& algorithm, const SearchHooks& h) {
  const std::size_t batch = h.population ? h.population : default_population(algorithm, h.dim, h.objectives);
  if (algorithm == "bobyqa" || algorithm == "neldermead") return run_nlopt(algorithm, h);
  if (algorithm == "random") {
    Rng rng(h.seed, 4);
    while (!h.exhausted()) {
      std::vector<Point> points(batch, Point(h.dim));
      for (Point& x : points)
        for (double& v : x) v = rng.uniform();
      h.evaluate(points);
    }
    return "budget";
  }
  if (algorithm == "lhs") {
    // A Latin hypercube of as many points as the budget allows; racing leaves budget over, which the
    // next hypercube (of what is left) uses.
    Rng rng(h.seed, 5);
    while (!h.exhausted()) {
      const std::size_t n = std::max<std::size_t>(1, h.points_left());
      std::vector<Point> points(n, Point(h.dim));
      for (std::size_t k = 0; k < h.dim; ++k) {
        std::vector<std::size_t> strata(n);
        for (std::size_t i = 0; i < n; ++i) strata[i] = i;
        for (std::size_t i = n; i > 1; --i) std::swap(strata[i - 1], strata[rng.index(i)]);  // Fisher–Yates
        for (std::size_t i = 0; i < n; ++i) points[i][k] = (static_cast<double>(strata[i]) + rng.uniform()) / static_cast<double>(n);
      }
      if (!in_batches(points, batch, h)) break;
    }
    return "budget";
  }
  if (algorithm == "grid") {
    // As the paper's permutations: k evenly spaced values per parameter, both ends included, k the
    // largest with k^dim points within the budget (at least 2).
    const std::size_t n = h.points_left();
    std::size_t k = 2;
    while (std::pow(static_cast<double>(k + 1), static_cast<double>(h.dim)) <= static_cast<double>(n)) ++k;
    std::vector<Point> points;
    std::vector<std::size_t> index(h.dim, 0);
    for (;;) {
      Point x(h.dim);
      for (std::size_t d = 0; d < h.dim; ++d) x[d] = static_cast<double>(index[d]) / static_cast<double>(k - 1);
      points.push_back(std::move(x));
      std::size_t d = h.dim;
      while (d > 0 && ++index[d - 1] == k) index[--d] = 0;
      if (d == 0) break;
    }
    in_batches(points, batch, h);
    return h.exhausted() ? "budget" : "grid done: " + std::to_string(k) + " values per parameter";
  }
  return run_pagmo(algorithm, h);
}

}  // namespace salsa::cli
