// return_to_base_test.cpp: four drones with a 2 Wh battery wander a 300 m room for 4 minutes, a few
// times what one charge lasts. With a base that charges at 300 W none runs flat: each comes to rest on
// the base, charges and flies out again. With a base that does not charge they come home and stay there.
#include <salsa/fixture.hpp>

#include <cstdio>
#include <string>

constexpr double charge_radius = 5;  // m: the drone's default

salsa::testing::Simulation flight(double charge_power) {
  return salsa::testing::Simulation(R"({"behavior": "return_to_base", "drones": 4, "seed": 3,
      "map": {"name": "empty", "params": {"size": 300}},
      "drone": {"base": "small", "battery_capacity": 2, "charge_power": )" + std::to_string(charge_power) + "}}",
                                    {SALSA_PLUGIN_FILE});
}

/// The battery fraction drone `id` saw at its last decision, from its inspect() text ("out, battery 73.5%").
double battery(const salsa::testing::Simulation& sim, std::uint32_t id) {
  const std::string text = sim.behavior().inspect(id);
  return std::stod(text.substr(text.find("battery ") + 8)) / 100;
}

bool on_base(const salsa::testing::Simulation& sim, std::uint32_t id) {
  return salsa::distance(sim.positions()[id], sim.world().base(0)) <= charge_radius && sim.velocities()[id].length() < 1;
}

int fail(const char* what, std::uint32_t id, double t) { return std::fprintf(stderr, "drone %u at t = %.1f s: %s\n", id, t, what), 1; }

int main() {
  {
    auto sim = flight(300);
    struct Seen {
      double lowest = 1, last = 1;
      bool charged = false, out_again = false;
    } seen[4];
    while (sim.time() < 240) {
      sim.step();
      for (std::uint32_t i = 0; i < 4; ++i) {
        Seen& s = seen[i];
        const double b = battery(sim, i);
        if (sim.world().drone_status()[i] != salsa::DroneStatus::flying || b <= 0) return fail("ran flat", i, sim.time());
        if (on_base(sim, i) && b > s.last) s.charged = true;
        if (s.charged && salsa::distance(sim.positions()[i], sim.world().base(0)) > 50) s.out_again = true;
        s.lowest = std::min(s.lowest, b), s.last = b;
      }
    }
    for (std::uint32_t i = 0; i < 4; ++i) {
      if (!seen[i].charged) return fail("never charged on the base", i, sim.time());
      if (!seen[i].out_again) return fail("never flew out again after charging", i, sim.time());
      std::printf("drone %u: lowest battery %.0f%%, charged and flew out again\n", i, 100 * seen[i].lowest);
    }
  }
  {
    auto sim = flight(0);
    sim.run(240);
    for (std::uint32_t i = 0; i < 4; ++i)
      if (salsa::distance(sim.positions()[i], sim.world().base(0)) > charge_radius) return fail("is not home", i, sim.time());
    std::printf("without charging all four are home after 240 s\n");
  }
}
