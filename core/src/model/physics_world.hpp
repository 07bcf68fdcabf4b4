#pragma once
// Internal to libsalsa: the only place that knows Box2D.
#include <box2d/box2d.h>

#include <algorithm>
#include <cstdint>
#include <vector>

#include "model/physics.hpp"

namespace salsa {

inline b2Vec2 to_b2(Vec2 v) { return {static_cast<float>(v.x), static_cast<float>(v.y)}; }
inline Vec2 from_b2(b2Vec2 v) { return {v.x, v.y}; }

// salsa's Box2D world: one static body for the map's segments, one dynamic circle per drone, and the
// contacts that began in the last step. Shared by Simulation and the benchmark floor, so that both
// step exactly the same Box2D set-up.
struct PhysicsWorld final : Physics, b2ContactListener {
  b2World world{b2Vec2(0, 0)};
  std::vector<b2Body*> bodies;
  std::vector<ContactEvent> contacts;  // contacts begun during the last Step, in Box2D's order

  explicit PhysicsWorld(const StaticGeometry& geometry) {
    world.SetContactListener(this);
    // Contacts once per step: check_drone keeps a step within the drone radius (and Box2D's 2 m), so no
    // drone can cross a wall between two contact checks.
    world.SetContinuousPhysics(false);
    b2BodyDef def;
    b2Body* walls = world.CreateBody(&def);
    for (const Segment& s : geometry.segments()) {
      b2EdgeShape edge;
      edge.SetTwoSided(to_b2(s.a), to_b2(s.b));
      walls->CreateFixture(&edge, 0);
    }
  }
  void add_drone(std::uint32_t id, Vec2 position, Vec2 velocity, const DroneConfig& cfg, bool enabled = true) override {
    b2BodyDef def;
    def.type = b2_dynamicBody;
    def.position = to_b2(position);
    def.linearVelocity = to_b2(velocity);
    def.fixedRotation = true;
    def.userData.pointer = id + 1;  // 0 marks static geometry
    b2Body* body = world.CreateBody(&def);
    b2CircleShape circle;
    circle.m_radius = static_cast<float>(cfg.radius);
    b2FixtureDef fixture;
    fixture.shape = &circle;
    fixture.density = static_cast<float>(cfg.mass / (pi * cfg.radius * cfg.radius));
    fixture.friction = 0;
    body->CreateFixture(&fixture);
    bodies.push_back(body);
    if (!enabled) body->SetEnabled(false);
  }
  void remove_drones_from(std::size_t n) override {
    while (bodies.size() > n) {
      world.DestroyBody(bodies.back());
      bodies.pop_back();
    }
  }
  void disable(std::uint32_t id) override {
    if (!bodies[id]->IsEnabled()) return;
    bodies[id]->SetLinearVelocity({0, 0});
    bodies[id]->SetEnabled(false);  // no longer collides or is collided with
  }
  void set_velocities(std::span<const Vec2> velocities, std::span<const DroneStatus> status) override {
    for (std::size_t i = 0; i < bodies.size(); ++i)
      if (status[i] == DroneStatus::flying) bodies[i]->SetLinearVelocity(to_b2(velocities[i]));
  }
  void step(double dt, int velocity_iterations, int position_iterations) {
    contacts.clear();
    world.Step(static_cast<float>(dt), velocity_iterations, position_iterations);
  }
  void advance(const StaticGeometry&, double dt, int velocity_iterations, int position_iterations) override {
    step(dt, velocity_iterations, position_iterations);
  }
  void read_back(std::span<Vec2> positions, std::span<Vec2> velocities) const override {
    for (std::size_t i = 0; i < bodies.size(); ++i) {
      positions[i] = from_b2(bodies[i]->GetPosition());
      velocities[i] = from_b2(bodies[i]->GetLinearVelocity());
    }
  }
  std::span<const ContactEvent> begun() const override { return contacts; }
  void BeginContact(b2Contact* contact) override {
    const auto a = contact->GetFixtureA()->GetBody()->GetUserData().pointer;
    const auto b = contact->GetFixtureB()->GetBody()->GetUserData().pointer;
    if (a && b) {
      const auto lo = static_cast<std::uint32_t>(std::min(a, b) - 1), hi = static_cast<std::uint32_t>(std::max(a, b) - 1);
      const Vec2 mid = (from_b2(bodies[lo]->GetPosition()) + from_b2(bodies[hi]->GetPosition())) / 2;
      contacts.push_back({ContactKind::drone_drone, lo, hi, mid, 0});
    } else if (a || b) {
      const auto id = static_cast<std::uint32_t>(std::max(a, b) - 1);
      contacts.push_back({ContactKind::drone_obstacle, id, 0, from_b2(bodies[id]->GetPosition()), 0});
    }
  }
};

}  // namespace salsa
