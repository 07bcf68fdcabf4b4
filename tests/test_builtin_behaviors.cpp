// The built-in behavior classes as the SDK publishes them (salsa/behaviors/*.hpp), on a hand-made world:
// their shared state counts only their group's flying drones, a count change keeps what the others
// remember, and the hooks a derived class overrides are the ones the behavior uses.
#include <salsa/behaviors/dynamic_space_partitioning.hpp>
#include <salsa/behaviors/dynamic_space_partitioning_paper.hpp>
#include <salsa/behaviors/flocking.hpp>
#include <salsa/behaviors/pheromone_avoidance.hpp>
#include <salsa/behaviors/random_walk.hpp>
#include <salsa/sdk.hpp>
#include <salsa/testing.hpp>

#include <QtTest>

#include <array>
#include <cmath>
#include <vector>

#include "common.hpp"

using salsa::DroneStatus;
using salsa::Vec2;

namespace {

/// A 1000 m × 1000 m world without obstacles whose drones the test places, groups and fails.
class World final : public salsa::WorldView {
 public:
  std::vector<Vec2> positions, velocities;
  std::vector<std::uint32_t> groups;
  std::vector<DroneStatus> status;
  double now = 0;

  std::uint32_t add(Vec2 p, std::uint32_t group = 0, DroneStatus s = DroneStatus::flying) {
    positions.push_back(p), velocities.push_back({}), groups.push_back(group), status.push_back(s);
    return static_cast<std::uint32_t>(positions.size() - 1);
  }
  salsa::Rect bounds() const override { return map_.bounds; }
  double time() const override { return now; }
  double dt() const override { return 1.0 / 60; }
  std::span<const Vec2> drone_positions() const override { return positions; }
  std::span<const Vec2> drone_velocities() const override { return velocities; }
  bool is_free(Vec2 p, double clearance) const override {
    return p.x - clearance >= 0 && p.y - clearance >= 0 && p.x + clearance <= 1000 && p.y + clearance <= 1000;
  }
  std::optional<salsa::ObstacleHit> ray_cast(Vec2, Vec2) const override { return std::nullopt; }
  const salsa::DroneProperties& drone(std::uint32_t) const override { return drone_; }
  std::span<const std::uint32_t> drone_groups() const override { return groups; }
  std::span<const DroneStatus> drone_status() const override { return status; }
  std::size_t group_count() const override { return 2; }
  Vec2 base(std::uint32_t) const override { return {500, 500}; }
  const salsa::MapData& map() const override { return map_; }

 private:
  salsa::MapData map_{{{0, 0}, {1000, 1000}}, {}, {}, {}, {500, 500}};
  salsa::DroneProperties drone_{15, 50.2, 134, 10, 0.3, 1, 1.5};
};

/// A behavior with its declared defaults, as the registry makes it.
template <class B>
std::unique_ptr<B> make() {
  auto b = std::make_unique<B>();
  b->set_parameters(salsa::ParameterValues(salsa::detail::declared_parameters<B>()));
  return b;
}

}  // namespace

class TestBuiltinBehaviors : public QObject {
  Q_OBJECT

 private Q_SLOTS:
  // Drone 0 flies east; 30 m ahead (where it samples the field) sits drone 1. Counted, drone 1's mark
  // turns drone 0 by 45° (ln 2 ≈ 0.69 against the turn's 2 · (1 − cos 45°) ≈ 0.59, jitter under 0.1);
  // not counted (failed, landed, or of another group), drone 0 flies straight on.
  void pheromone_field_counts_only_the_groups_flying_drones_data() {
    QTest::addColumn<int>("group");
    QTest::addColumn<int>("status");
    QTest::addColumn<bool>("counted");
    QTest::newRow("flying, same group") << 0 << int(DroneStatus::flying) << true;
    QTest::newRow("failed") << 0 << int(DroneStatus::failed) << false;
    QTest::newRow("landed") << 0 << int(DroneStatus::landed) << false;
    QTest::newRow("another group") << 1 << int(DroneStatus::flying) << false;
  }
  void pheromone_field_counts_only_the_groups_flying_drones() {
    QFETCH(int, group);
    QFETCH(int, status);
    QFETCH(bool, counted);
    World world;
    world.add({100, 100});
    world.add({130, 100}, static_cast<std::uint32_t>(group), static_cast<DroneStatus>(status));
    auto pheromone = make<salsa::behaviors::PheromoneAvoidance>();
    pheromone->reset(2);
    pheromone->prepare(world);
    salsa::testing::Scene scene;
    scene.at({100, 100}, {10, 0});
    salsa::Rng rng(1, 0);
    const Vec2 steering = pheromone->decide(scene.perception(), rng);
    QCOMPARE(steering.y != 0, counted);
  }

  // sharing 1 (messages): drone 1's mark reaches drone 0's own field only as a message from its
  // group, and drone 0 broadcasts where it marked. Same layout as above: counted, drone 0 turns.
  void pheromone_messages_mark_only_what_was_received_data() {
    QTest::addColumn<bool>("received");
    QTest::addColumn<int>("sender_group");
    QTest::addColumn<bool>("counted");
    QTest::newRow("no message") << false << 0 << false;
    QTest::newRow("a message from its group") << true << 0 << true;
    QTest::newRow("a message from another group") << true << 1 << false;
  }
  void pheromone_messages_mark_only_what_was_received() {
    QFETCH(bool, received);
    QFETCH(int, sender_group);
    QFETCH(bool, counted);
    World world;
    world.add({100, 100});
    world.add({130, 100}, static_cast<std::uint32_t>(sender_group));
    auto pheromone = make<salsa::behaviors::PheromoneAvoidance>();
    salsa::ParameterValues values = pheromone->parameters();
    values.set("sharing", 1);
    pheromone->set_parameters(values);
    pheromone->reset(2);
    pheromone->prepare(world);
    salsa::testing::Scene scene;
    scene.at({100, 100}, {10, 0});
    const double where[2] = {130, 100};
    const salsa::Message message{1, static_cast<std::uint32_t>(sender_group), {30, 0}, 0, where};
    std::array<double, 2> room{};
    salsa::Outbox outbox{room};
    salsa::Perception me = scene.perception();
    if (received) me.messages = {&message, 1};
    me.outbox = &outbox;
    salsa::Rng rng(1, 0);
    const Vec2 steering = pheromone->decide(me, rng);
    QCOMPARE(steering.y != 0, counted);
    QVERIFY(outbox.sent);
    QCOMPARE(outbox.size, std::size_t{2});
    QCOMPARE(room[0], 100.0);
    QCOMPARE(room[1], 100.0);
  }

  // The partition points: only members (drones 0 and 1) repel and move, and the spacing counts only
  // them. Drone 2 (failed) and drone 3 (another group) sit right above drone 0: counted, they would
  // push its point down.
  void partition_points_count_only_members() {
    World world;
    world.add({500, 500});
    world.add({510, 500});
    world.add({500, 505}, 0, DroneStatus::failed);
    world.add({502, 506}, 1);
    auto dsp = make<salsa::behaviors::DynamicSpacePartitioningPaper>();
    dsp->reset(4);
    dsp->prepare(world);
    const auto& points = dsp->points();
    QCOMPARE(points.size(), std::size_t(4));
    QCOMPARE(std::vector<std::uint32_t>(points.members().begin(), points.members().end()), (std::vector<std::uint32_t>{0, 1}));
    QCOMPARE(points.spacing(), std::sqrt(1000.0 * 1000.0 / 2));
    QCOMPARE(dsp->disc_radius(), 0.3 * points.spacing());
    QCOMPARE(points[0].y, 500.0);  // pushed straight away from drone 1 only
    QVERIFY(points[0].x < 500 && points[1].x > 510);
    QCOMPARE(points[2], Vec2(500, 505));  // non-members' points stay where they were
    QCOMPARE(points[3], Vec2(502, 506));
    QCOMPARE(dsp->inspect(2), std::string());  // and they have no disc
    QVERIFY(!dsp->inspect(0).empty());
  }

  // Salsa's DSP: the regions are shared out among the members only; a failed drone owns nothing.
  void partition_regions_go_to_members_only() {
    World world;
    world.add({200, 200});
    world.add({800, 800});
    world.add({500, 500}, 0, DroneStatus::failed);
    auto dsp = make<salsa::behaviors::DynamicSpacePartitioning>();
    dsp->reset(3);
    dsp->prepare(world);
    QVERIFY2(dsp->inspect(2).starts_with("region: 0 cells"), dsp->inspect(2).c_str());
    // The 2500 cells of 20 m split between the two members.
    const auto cells = [&](std::uint32_t id) { return std::stoi(dsp->inspect(id).substr(8)); };
    QCOMPARE(cells(0) + cells(1), 2500);
    QVERIFY(cells(0) > 1000 && cells(1) > 1000);
  }

  // A count change (resize) keeps what the other drones remember: random walk's headings, the DSP's
  // points, pheromone's field; reset forgets it all.
  void resize_keeps_memory() {
    World world;
    world.add({100, 100});
    world.add({900, 900});
    salsa::Rng rng(3, 0);
    salsa::testing::Scene scene;
    scene.at({100, 100}, {3, 4});

    auto walk = make<salsa::behaviors::RandomWalk>();
    walk->reset(2);
    static_cast<salsa::Behavior&>(*walk).decide(scene.perception(), rng);
    const std::string remembered = walk->inspect(0);
    QVERIFY(!remembered.empty());
    walk->resize(3);
    QCOMPARE(walk->inspect(0), remembered);
    QCOMPARE(walk->inspect(2), std::string());  // the new drone starts fresh
    walk->resize(1);
    QCOMPARE(walk->inspect(0), remembered);
    walk->reset(1);
    QCOMPARE(walk->inspect(0), std::string());

    auto dsp = make<salsa::behaviors::DynamicSpacePartitioningPaper>();
    dsp->reset(2);
    for (int k = 0; k < 60; ++k) dsp->prepare(world);
    const Vec2 point = dsp->points()[0];
    QVERIFY(point != Vec2(100, 100));
    world.add({400, 700});
    dsp->resize(3);
    dsp->prepare(world);
    QCOMPARE(dsp->points().size(), std::size_t(3));
    QVERIFY(salsa::distance(dsp->points()[0], point) < 0.2);  // moved on one step from where it was
    QVERIFY(salsa::distance(dsp->points()[2], Vec2(400, 700)) < 0.2);  // the new one starts at its drone

    // Pheromone: drone 1 marks (130, 100) ahead of a drone flying east there; after a resize the mark
    // still turns it, after a reset it does not.
    World field;
    field.add({100, 100}, 0, DroneStatus::failed);
    field.add({130, 100});
    auto pheromone = make<salsa::behaviors::PheromoneAvoidance>();
    pheromone->reset(2);
    pheromone->prepare(field);
    field.status[1] = DroneStatus::failed;  // no one marks from now on
    pheromone->resize(3);
    pheromone->prepare(field);
    QVERIFY(pheromone->decide(scene.at({100, 100}, {10, 0}).perception(), rng).y != 0);
    pheromone->reset(2);
    pheromone->prepare(field);
    QCOMPARE(pheromone->decide(scene.perception(), rng).y, 0.0);
  }

  // The hooks are what the behaviors use: a derived class's override changes the decision.
  void hooks_are_used() {
    struct Still final : salsa::behaviors::Flocking {  // no steering at all
      Vec2 combine(const salsa::Perception&, const salsa::BoidTerms&, salsa::Rng&) override { return {}; }
    };
    struct Forever final : salsa::behaviors::PheromoneAvoidance {  // marks never fade
      double evaporate(double value, double) const override { return value; }
    };
    salsa::testing::Scene scene;
    scene.at({100, 100}, {10, 0}).neighbour({120, 100}, {0, 10});
    salsa::Rng rng(1, 0);
    auto flocking = make<salsa::behaviors::Flocking>();
    QVERIFY(flocking->decide(scene.perception(), rng) != Vec2());
    QCOMPARE(make<Still>()->decide(scene.perception(), rng), Vec2());

    // A mark made at t = 0 and sampled at t = 1000 s: gone with evaporation 0.01/s (e^-10), not with
    // the override.
    World world;
    world.add({130, 100});
    auto fading = make<salsa::behaviors::PheromoneAvoidance>();
    auto forever = make<Forever>();
    for (salsa::behaviors::PheromoneAvoidance* b : {fading.get(), static_cast<salsa::behaviors::PheromoneAvoidance*>(forever.get())}) {
      b->reset(1);
      b->prepare(world);
    }
    scene.me().time = 1000;
    QCOMPARE(fading->decide(scene.perception(), rng).y, 0.0);
    QVERIFY(forever->decide(scene.perception(), rng).y != 0);
  }
};

QTEST_GUILESS_MAIN(TestBuiltinBehaviors)
#include "test_builtin_behaviors.moc"
