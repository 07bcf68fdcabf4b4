#pragma once
// Sensor noise draws: counter-based streams and the distributions the noise model draws from.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstddef>
#include <utility>

#include "model/streams.hpp"
#include "salsa/rng.hpp"
#include "salsa/vec2.hpp"

namespace salsa::detail {

/// Two independent N(0, sd²) draws: both halves of one Box–Muller pair.
inline Vec2 gaussian(Rng& rng, double sd) {
  const double u1 = 1.0 - rng.uniform();  // (0, 1]: the log is finite
  const double u2 = rng.uniform();
  const double r = sd * std::sqrt(-2.0 * std::log(u1)), a = 2 * pi * u2;
  return {r * std::cos(a), r * std::sin(a)};
}
/// A Poisson(mean) count: Knuth's product of uniforms, in parts of mean ≤ 8 so that exp(−part) stays
/// far from underflow (a sum of Poisson counts is Poisson).
inline std::size_t poisson(Rng& rng, double mean) {
  std::size_t count = 0;
  while (mean > 0) {
    const double part = std::min(mean, 8.0), limit = std::exp(-part);
    mean -= part;
    for (double product = rng.uniform(); product >= limit; product *= rng.uniform()) ++count;
  }
  return count;
}

}  // namespace salsa::detail
