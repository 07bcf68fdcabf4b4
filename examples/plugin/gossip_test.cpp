// gossip_test.cpp: twelve drones start with random headings. Over a lossy, delayed radio (20 % loss,
// 3 steps of latency) they agree on one heading within a few seconds; without a radio ("comm" left
// out) each keeps its own.
#include <salsa/fixture.hpp>

#include <cmath>
#include <cstdio>
#include <string>

constexpr int drones = 12;

/// The largest angle (degrees) between a drone's heading and the first drone's.
double disagreement(const salsa::testing::Simulation& sim) {
  auto heading = [&](std::uint32_t id) {
    const std::string text = sim.behavior().inspect(id);  // "heading 37.251 deg"
    return std::stod(text.substr(text.find(' ') + 1));
  };
  double worst = 0;
  for (std::uint32_t i = 1; i < drones; ++i) {
    const double d = std::fabs(std::remainder(heading(i) - heading(0), 360.0));
    worst = std::max(worst, d);
  }
  return worst;
}

salsa::testing::Simulation swarm(const std::string& comm) {
  return salsa::testing::Simulation(R"({"behavior": "gossip", "drones": 12, "seed": 5,
      "map": {"name": "empty", "params": {"size": 2000}}, "spawn": {"radius": 40})" + comm + "}",
                                    {SALSA_PLUGIN_FILE});
}

int main() {
  auto talking = swarm(R"(, "comm": {"range": 300, "loss": 0.2, "latency": 3})");
  auto silent = swarm("");
  talking.step(), silent.step();
  const double at_start = disagreement(talking);
  if (at_start < 30) return std::fprintf(stderr, "the random headings start too close (%.1f deg)\n", at_start), 1;
  talking.run(10), silent.run(10);
  const double agreed = disagreement(talking), apart = disagreement(silent);
  std::printf("headings differ by up to %.1f deg at the start; after 10 s %.4f deg with a radio, %.1f deg without\n",
              at_start, agreed, apart);
  if (agreed > 0.5) return std::fprintf(stderr, "over the radio the headings did not agree\n"), 1;
  if (apart < 30) return std::fprintf(stderr, "without a radio the headings agreed anyway\n"), 1;
}
