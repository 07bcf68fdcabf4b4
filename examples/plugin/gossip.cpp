// gossip.cpp: drones agree on a heading by gossip. Each drone starts with a random heading of its own,
// broadcasts it every step and turns it towards the mean of the headings it received. Over a connected
// radio graph the headings agree and the swarm flies as one, though no drone ever sees another: they
// only talk, over whatever radio the test's "comm" describes (range, loss, latency).
#include <array>
#include <cstdio>
#include <string>

#include <salsa/sdk.hpp>

struct Heading {
  salsa::Vec2 direction;  // unit vector; zero until the drone first decides
};

class Gossip final : public salsa::BehaviorWithMemory<Heading> {
  salsa::Param trust{this, "trust", 0.5, 0.0, 1.0, "", "weight of the heard headings' mean against the drone's own, per step"};
  salsa::Param avoidance{this, "avoidance", 4.0, 0.0, 10.0, "", "weight of obstacle avoidance"};

 public:
  salsa::Vec2 decide(const salsa::Perception& me, Heading& h, salsa::Rng& rng) override {
    if (h.direction.is_zero()) h.direction = salsa::Vec2::polar(1, rng.angle());
    salsa::Vec2 heard;  // the sum of the unit headings received: it points along their mean
    for (const salsa::Message& m : me.messages) heard += {m.payload[0], m.payload[1]};
    if (!heard.is_zero()) {
      const salsa::Vec2 mixed = (1 - trust) * h.direction + trust * heard.with_length(1);
      if (!mixed.is_zero()) h.direction = mixed.with_length(1);
    }
    me.broadcast(std::array{h.direction.x, h.direction.y});  // received in the next step (or later, with latency)
    return salsa::steer_along(me, h.direction) + avoidance * salsa::avoid_near_obstacles(me);
  }

  std::size_t message_size() const override { return 2; }  // a heading: two doubles
  salsa::Senses senses() const override { return {.neighbours = false, .targets = false}; }  // it talks, it does not look

  std::string inspect(std::uint32_t id) const override {
    if (id >= memory().size() || memory()[id].direction.is_zero()) return {};
    char text[48];
    std::snprintf(text, sizeof text, "heading %.3f deg", memory()[id].direction.angle() * 180 / salsa::pi);
    return text;
  }
};
SALSA_BEHAVIOR(Gossip, "gossip", "Agrees on a heading by averaging what neighbours broadcast")
