// flocking_plus_test.cpp: flocking_plus changes only what it adds. With migration_weight 0 every drone
// flies exactly as under the built-in flocking, step for step; with weight 1 the flock travels to its
// goal, which the built-in's does not.
#include <salsa/fixture.hpp>

#include <cstdio>
#include <string>

namespace {

const std::string kWorld = R"("drones": 12, "seed": 2, "spawn": {"point": [300, 300]},
                              "map": {"name": "empty", "params": {"size": 1000}}})";
const salsa::Vec2 kGoal{700, 700};

double centre_to_goal(const salsa::testing::Simulation& sim) {
  salsa::Vec2 centre;
  for (salsa::Vec2 p : sim.positions()) centre += p / static_cast<double>(sim.positions().size());
  return salsa::distance(centre, kGoal);
}

}  // namespace

int main() {
  salsa::testing::Simulation builtin(R"({"behavior": {"name": "flocking", "params": {"separation_distance": 60}}, )" + kWorld);
  salsa::testing::Simulation off(R"({"behavior": {"name": "flocking_plus", "params": {"separation_distance": 60,
                                     "migration_weight": 0, "goal_x": 700, "goal_y": 700}}, )" + kWorld, {SALSA_PLUGIN_FILE});
  for (int step = 0; step < 30 * 60; ++step) {
    builtin.step(), off.step();
    for (std::size_t i = 0; i < builtin.positions().size(); ++i)
      if (off.positions()[i] != builtin.positions()[i] || off.velocities()[i] != builtin.velocities()[i])
        return std::fprintf(stderr, "weight 0: drone %zu left the built-in's path at step %d\n", i, step + 1), 1;
  }
  std::printf("weight 0: 12 drones flew 30 s exactly as under flocking\n");

  salsa::testing::Simulation on(R"({"behavior": {"name": "flocking_plus", "params": {"separation_distance": 60,
                                    "migration_weight": 1, "goal_x": 700, "goal_y": 700}}, )" + kWorld, {SALSA_PLUGIN_FILE});
  const double start = centre_to_goal(on);
  on.run(90), builtin.run(60);
  std::printf("the flock's centre to the goal: %.0f m at the start; after 90 s %.0f m with migration, %.0f m without\n",
              start, centre_to_goal(on), centre_to_goal(builtin));
  if (centre_to_goal(on) > 0.2 * start) return std::fprintf(stderr, "weight 1: the flock did not reach its goal\n"), 1;
  if (centre_to_goal(builtin) < 0.8 * start) return std::fprintf(stderr, "the built-in flew to the goal too\n"), 1;
}
