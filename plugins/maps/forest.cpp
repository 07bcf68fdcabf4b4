// Forest: clusters of convex obstacles (rocks, buildings) scattered over a square, with a clear disc
// around the spawn point. Obstacles lie inside the bounds and never overlap: their bounding circles
// are kept `gap` apart (and from the walls) so drones can pass between them. The cluster count scales
// with the area by default (48 per km²: 12 on 500 m, 192 on 2 km), so every size looks alike.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include <salsa/sdk.hpp>

namespace {

class ForestMap final : public salsa::MapGenerator {
  using Param = salsa::Param;
  Param size{this, "size", 500.0, 50.0, 1e5, "m", "side of the square"};
  Param clusters{this, "clusters", 0, 0, kMaxClusters, "", "number of obstacle clusters; 0: cluster_density × area", 1};
  Param cluster_density{this, "cluster_density", 48.0, 0.0, 10000.0, "1/km^2", "clusters per square kilometre when clusters is 0"};
  Param obstacles_per_cluster{this, "obstacles_per_cluster", 4, 1, 100, "", "obstacles tried per cluster (fewer if they do not fit)", 1};
  Param min_obstacle_size{this, "min_obstacle_size", 8.0, 1.0, 1000.0, "m", "smallest obstacle diameter"};
  Param max_obstacle_size{this, "max_obstacle_size", 25.0, 1.0, 1000.0, "m", "largest obstacle diameter"};
  Param cluster_radius{this, "cluster_radius", 40.0, 0.0, 1e4, "m", "obstacles lie within this distance of their cluster's centre"};
  Param clear_radius{this, "clear_radius", 30.0, 0.0, 1e4, "m", "no obstacle within this distance of the spawn point"};
  Param gap{this, "gap", 4.0, 0.0, 100.0, "m", "least free space between obstacles, and between obstacles and walls"};

 public:
  salsa::MapData generate(const std::string&, salsa::Rng& rng) const override {
    const double min_size = min_obstacle_size, max_size = std::max(min_size, max_obstacle_size.value());
    const double clear = clear_radius;
    salsa::MapData map;
    map.bounds = {{0, 0}, {size, size}};
    map.spawn = map.bounds.centre();

    // Placed bounding circles in a hash grid whose cells are as wide as any overlap distance, so an
    // overlap test looks at 3 × 3 cells instead of every obstacle.
    struct Circle {
      salsa::Vec2 c;
      double r;
    };
    const double cell = max_size + gap;
    std::unordered_map<std::uint64_t, std::vector<Circle>> placed;
    auto cell_of = [&](double v) { return static_cast<long long>(v / cell); };  // v >= 0
    auto key = [](long long cx, long long cy) {
      return static_cast<std::uint64_t>(cx) << 32 ^ static_cast<std::uint32_t>(cy);
    };
    auto fits = [&](salsa::Vec2 c, double r) {
      if (c.x - r - gap < 0 || c.y - r - gap < 0 || c.x + r + gap > size || c.y + r + gap > size)
        return false;
      if (salsa::distance(c, map.spawn) < clear + r) return false;
      for (long long x = cell_of(c.x) - 1; x <= cell_of(c.x) + 1; ++x)
        for (long long y = cell_of(c.y) - 1; y <= cell_of(c.y) + 1; ++y)
          if (auto it = placed.find(key(x, y)); it != placed.end())
            for (const Circle& o : it->second)
              if (salsa::distance(c, o.c) < r + o.r + gap) return false;
      return true;
    };

    const double scaled = std::min(cluster_density * size * size / 1e6, double(kMaxClusters));
    const auto cluster_count = static_cast<int>(clusters > 0 ? clusters.value() : std::round(scaled));
    const auto per_cluster = static_cast<int>(obstacles_per_cluster);
    for (int k = 0; k < cluster_count; ++k) {
      const salsa::Vec2 centre = rng.in_rect(map.bounds);
      for (int i = 0; i < per_cluster; ++i)
        for (int attempt = 0; attempt < 20; ++attempt) {
          const double r = rng.uniform(min_size, max_size) / 2;
          const salsa::Vec2 c = rng.in_disc(centre, cluster_radius);
          if (!fits(c, r)) continue;
          placed[key(cell_of(c.x), cell_of(c.y))].push_back({c, r});
          map.obstacles.push_back(polygon(c, r, rng));
          break;
        }
    }
    return map;
  }

 private:
  static constexpr int kMaxClusters = 20000;  // bounds generation: at most 20,000 × 100 × 20 placement attempts

  // 3–8 vertices at increasing angles on a squashed, rotated circle of radius r: convex and CCW
  // (an affine map with positive determinant keeps both), and inside the bounding circle.
  static salsa::Polyline polygon(salsa::Vec2 c, double r, salsa::Rng& rng) {
    const int n = 3 + static_cast<int>(rng.index(6));
    const double aspect = rng.uniform(0.5, 1.0), rotation = rng.angle(), phase = rng.angle();
    salsa::Polyline points;
    for (int v = 0; v < n; ++v) {
      const double a = phase + 2 * salsa::pi * (v + rng.uniform(-0.3, 0.3)) / n;
      points.push_back(c + salsa::Vec2{r * std::cos(a), aspect * r * std::sin(a)}.rotated(rotation));
    }
    return points;
  }
};

}  // namespace

SALSA_MAP(ForestMap, "forest", "Clusters of convex rocks and buildings, clear around the spawn point")
