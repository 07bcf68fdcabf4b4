// Batch behaviors (core/include/salsa/core/model/batch_behavior.hpp): the batch a group's behavior gets
// holds exactly the Perceptions its drones would get one by one (neighbours, targets, obstacle hits,
// messages with their payloads, sensor noise), in id order whatever the thread count, and its draws come
// from the drones' own streams; a behavior that keeps a batch keeps it unchanged.
#include <QtTest>

#include <memory>
#include <vector>

#include "common.hpp"
#include "salsa/core/experiments/test_spec.hpp"
#include "salsa/core/model/batch_behavior.hpp"
#include "salsa/core/model/simulation.hpp"

using namespace salsa;
using namespace salsa_test;

namespace {

/// Broadcasts its id and position every step (so the other group has messages to read).
class Talker final : public Behavior {
 public:
  Vec2 decide(const Perception& me, Rng& rng) override {
    const double payload[] = {static_cast<double>(me.id), me.position.x, me.position.y};
    me.broadcast(payload);
    return Vec2::polar(me.max_force, rng.angle());
  }
  std::size_t message_size() const override { return 3; }
};

/// The same Talker deciding in batches: its messages sent through the batch's outbox.
class BatchTalker final : public BatchBehavior {
 public:
  void decide_batch(const std::shared_ptr<const PerceptionBatch>& batch, BatchRng& rng, const BatchOutbox& outbox,
                    std::span<Vec2> steering) override {
    const PerceptionBatch& b = *batch;
    QVERIFY(outbox.size() == b.size());
    for (std::size_t r = 0; r < b.size(); ++r) {
      const double payload[] = {static_cast<double>(b.id[r]), b.position[r].x, b.position[r].y};
      outbox.broadcast(r, payload);
      steering[r] = Vec2::polar(b.drone.max_force, rng[r].angle());
    }
  }
  std::size_t message_size() const override { return 3; }
};

/// Steers by everything it perceives, so that any difference in what it got moves a drone.
class Listener : public Behavior {
 public:
  Vec2 decide(const Perception& me, Rng& rng) override {
    Vec2 s = Vec2::polar(0.05, rng.angle()) + 1e-3 * me.wind + 1e-3 * me.air_velocity;
    for (const Neighbour& n : me.neighbours) s += 1e-4 * (n.position - me.position) + 1e-5 * n.velocity * (1 + n.group);
    for (const TargetSeen& t : me.targets) s += (t.found ? 1e-3 : 2e-3) * (t.position - me.position) / (1 + t.distance);
    for (const ObstacleHit& h : me.obstacles) s += 1e-3 * (me.position - h.point) / (1 + h.distance);
    for (const Message& m : me.messages) {
      s += 1e-4 * m.offset + 1e-6 * (me.time - m.time) * Vec2{1, 1};
      for (double v : m.payload) s += Vec2{1e-7 * v, -1e-7 * v};
      s += 1e-5 * static_cast<double>(m.sender % 7 + m.group) * Vec2{1, 0};
    }
    return (s + me.battery * 1e-3 * Vec2{0, 1}).clamped(me.max_force);
  }
};

/// The same Listener deciding in batches: each row rebuilt as the Perception it stands for.
class BatchListener final : public BatchBehavior {
 public:
  std::vector<std::shared_ptr<const PerceptionBatch>> kept;  ///< every batch, to check they stay as they were
  std::vector<std::vector<Vec2>> kept_positions;
  bool keep = false;

  void decide_batch(const std::shared_ptr<const PerceptionBatch>& batch, BatchRng& rng, const BatchOutbox&,
                    std::span<Vec2> steering) override {
    const PerceptionBatch& b = *batch;
    QVERIFY(b.size() == steering.size() && rng.size() == b.size());
    for (std::size_t r = 0; r < b.size(); ++r) {
      if (r > 0) QVERIFY(b.id[r - 1] < b.id[r]);
      Perception me;
      me.id = b.id[r], me.position = b.position[r], me.velocity = b.velocity[r];
      me.air_velocity = b.air_velocity[r], me.wind = b.wind[r], me.battery = b.battery[r];
      me.max_speed = b.drone.max_speed, me.max_force = b.drone.max_force, me.radius = b.drone.radius;
      me.mass = b.drone.mass, me.camera_range = b.drone.camera_range, me.obstacle_range = b.drone.obstacle_range;
      me.detection_range = b.drone.detection_range, me.dt = b.dt, me.time = b.time, me.group = b.group;
      me.base = b.base, me.battery_capacity = b.battery_capacity;
      me.neighbours = rows(b.neighbours, r), me.targets = rows(b.targets, r), me.obstacles = rows(b.obstacles, r);
      me.messages = rows(b.messages, r);
      for (const Message& m : me.messages)
        QVERIFY(m.payload.data() >= b.payloads.data() && m.payload.data() + m.payload.size() <= b.payloads.data() + b.payloads.size());
      steering[r] = inner_.decide(me, rng[r]);
    }
    if (keep) kept.push_back(batch), kept_positions.push_back(b.position);
  }
  Senses senses() const override { return inner_.senses(); }

 private:
  template <class Item>
  static std::span<const Item> rows(const PerceptionBatch::Rows<Item>& rows, std::size_t r) {
    return {rows.items.data() + rows.offsets[r], static_cast<std::size_t>(rows.offsets[r + 1] - rows.offsets[r])};
  }
  Listener inner_;
};

}  // namespace

class TestBatchBehavior : public QObject {
  Q_OBJECT

  std::unique_ptr<PluginHost> host_ = builtin_host();

  /// Two groups, a talker and a listener (one by one, or in batches), over a forest, with comm and
  /// sensor noise; `drones` per group. `batch_talkers`: the talkers decide in batches too.
  SimulationSetup setup(bool batch, int threads, std::size_t drones, std::shared_ptr<BatchListener>* made = nullptr,
                        bool batch_talkers = false) {
    const std::string test = R"({"groups": [
        {"name": "talkers", "drones": )" + std::to_string(drones) + R"(, "behavior": "random_walk"},
        {"name": "listeners", "drones": )" + std::to_string(drones) + R"(, "behavior": "random_walk",
         "drone": {"base": "small", "position_noise": 1, "neighbour_noise": 0.5, "obstacle_noise": 0.3,
                   "false_detection_rate": 0.05, "battery_capacity": 10}}],
      "map": {"name": "forest", "params": {"size": 400}}, "targets": {"kind": "tree", "count": 300},
      "comm": {"range": 120}, "time": 10, "seed": 5})";
    SimulationSetup s = make_setup(parse_test(test, "batch.json", *host_), *host_, threads);
    s.groups[0].behavior = batch_talkers ? std::shared_ptr<Behavior>(std::make_shared<BatchTalker>()) : std::make_shared<Talker>();
    if (batch) {
      auto b = std::make_shared<BatchListener>();
      if (made) *made = b;
      s.groups[1].behavior = b;
    } else {
      s.groups[1].behavior = std::make_shared<Listener>();
    }
    return s;
  }

 private Q_SLOTS:
  void a_batch_holds_what_each_drone_perceives() {
    // 150 per group: the listeners' batch is gathered in two chunks.
    for (int threads : {1, 2}) {
      Simulation one_by_one(setup(false, threads, 150)), batched(setup(true, threads, 150));
      std::uint64_t messages = 0;
      for (int k = 0; k < 240; ++k) {
        one_by_one.step(), batched.step();
        const auto a = one_by_one.drone_positions(), b = batched.drone_positions();
        QVERIFY(std::equal(a.begin(), a.end(), b.begin()));
        QCOMPARE(one_by_one.flying_count(), batched.flying_count());
      }
      messages = batched.comm_counters().delivered;
      QVERIFY(messages > 1000);  // the listeners did read messages
      QVERIFY(batched.false_detections() > 0);
    }
  }

  // The talkers' messages sent through a batch's outbox reach the listeners as those sent one by one.
  void a_batch_broadcasts_what_each_drone_broadcasts() {
    Simulation one_by_one(setup(false, 2, 150)), batched(setup(false, 2, 150, nullptr, true));
    for (int k = 0; k < 240; ++k) {
      one_by_one.step(), batched.step();
      const auto a = one_by_one.drone_positions(), b = batched.drone_positions();
      QVERIFY(std::equal(a.begin(), a.end(), b.begin()));
    }
    QCOMPARE(batched.comm_counters().delivered, one_by_one.comm_counters().delivered);
    QVERIFY(batched.comm_counters().delivered > 1000);
  }

  void the_batch_is_the_same_for_any_thread_count() {
    Simulation one(setup(true, 1, 300)), two(setup(true, 2, 300));
    one.run_steps(120), two.run_steps(120);
    const auto a = one.drone_positions(), b = two.drone_positions();
    QVERIFY(std::equal(a.begin(), a.end(), b.begin()));
  }

  void a_kept_batch_stays_as_it_was() {
    std::shared_ptr<BatchListener> listener;
    Simulation sim(setup(true, 2, 150, &listener));
    listener->keep = true;
    sim.run_steps(30);
    QCOMPARE(listener->kept.size(), std::size_t{30});
    for (std::size_t k = 0; k < listener->kept.size(); ++k) {
      QVERIFY(listener->kept[k]->position == listener->kept_positions[k]);
      if (k > 0) QVERIFY(listener->kept[k].get() != listener->kept[k - 1].get());  // kept: gathered elsewhere
    }
  }

  void a_batch_behavior_decides_one_perception_as_a_batch_of_one() {
    BatchListener batched;
    Listener plain;
    Neighbour n{{3, 4}, {1, 0}, 5, 9, 1};
    Perception me;
    me.id = 4, me.position = {1, 1}, me.max_force = 1, me.max_speed = 10, me.neighbours = {&n, 1};
    Rng a(3, 4), b(3, 4);
    QVERIFY(batched.decide(me, a) == plain.decide(me, b));
    QCOMPARE(a.next(), b.next());
  }
};

QTEST_GUILESS_MAIN(TestBatchBehavior)
#include "test_batch_behavior.moc"
