#pragma once
// Deterministic random numbers: xoshiro256** seeded through splitmix64. Written out here (not <random>
// distributions) because the standard distributions differ between library versions, and the same
// seed must give the same run everywhere.
#include <cmath>
#include <cstdint>

#include "salsa/vec2.hpp"

namespace salsa {

class Rng {
 public:
  /// One independent stream per (seed, stream) pair, e.g. stream = drone id.
  explicit Rng(std::uint64_t seed = 0, std::uint64_t stream = 0) {
    std::uint64_t x = seed ^ (0x9E3779B97F4A7C15ULL * (stream + 1));
    for (auto& word : s_) word = splitmix(x);
  }

  std::uint64_t next() {
    const std::uint64_t result = rotl(s_[1] * 5, 7) * 9;
    const std::uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0]; s_[3] ^= s_[1]; s_[1] ^= s_[2]; s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = rotl(s_[3], 45);
    return result;
  }
  /// Uniform in [0, 1).
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
  /// Uniform in [lo, hi).
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  /// Uniform integer in [0, n), n > 0.
  std::uint64_t index(std::uint64_t n) { return static_cast<std::uint64_t>(uniform() * static_cast<double>(n)); }
  /// Uniform angle in [0, 2π) rad.
  double angle() { return uniform(0.0, 2 * pi); }
  bool chance(double p) { return uniform() < p; }
  /// Standard normal (Box–Muller).
  double normal(double mean = 0, double stddev = 1) {
    const double u1 = 1.0 - uniform(), u2 = uniform();
    return mean + stddev * std::sqrt(-2.0 * std::log(u1)) * std::cos(2 * pi * u2);
  }
  /// Uniform point in a disc.
  Vec2 in_disc(Vec2 centre, double radius) {
    const double a = angle();  // drawn first, in its own statement: the order must not be the compiler's
    return centre + Vec2::polar(radius * std::sqrt(uniform()), a);
  }
  /// Uniform point in a rectangle.
  Vec2 in_rect(const Rect& r) { return {uniform(r.min.x, r.max.x), uniform(r.min.y, r.max.y)}; }

 private:
  static std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
  static std::uint64_t splitmix(std::uint64_t& x) {
    std::uint64_t z = (x += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
  }
  std::uint64_t s_[4];
};

}  // namespace salsa
