#pragma once
// The search algorithms of `salsa tune`, over the unit cube [0, 1]^dim (tune.cpp maps it to the
// parameters' ranges, log scales and whole numbers). pagmo2 and NLopt do the optimising; random,
// Latin-hypercube and grid search are the baselines. All of them hand the points of one generation to
// `evaluate` at once, so a generation's tests run side by side.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace salsa::cli {

using Point = std::vector<double>;

struct SearchHooks {
  std::size_t dim = 0, objectives = 1;
  std::uint64_t seed = 1;
  std::size_t population = 0;  ///< points per generation (0: the algorithm's default)
  Point start;                 ///< where local methods start, and the first point of a population
  /// The fitness of each point (minimised; one value per objective), evaluated together.
  std::function<std::vector<Point>(const std::vector<Point>&)> evaluate;
  /// Whether the budget allows no further point.
  std::function<bool()> exhausted;
  /// How many more points the budget allows, each on every world.
  std::function<std::size_t()> points_left;
};

/// The population size `algorithm` uses for `dim` parameters when the file gives none.
std::size_t default_population(const std::string& algorithm, std::size_t dim, std::size_t objectives);

/// Runs `algorithm` (tune_algorithms()) until the budget is exhausted or it has nothing new to try.
/// Returns why it stopped, for the report ("budget", "converged: ...").
std::string run_search(const std::string& algorithm, const SearchHooks& hooks);

}  // namespace salsa::cli
