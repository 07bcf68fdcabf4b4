// The drones' state as named columns: every column is a view of the array the step itself uses (no
// copy), named once with its unit, and follows the simulation as it steps and changes.
#include <QtTest>

#include <cmath>
#include <cstring>
#include <set>

#include "common.hpp"
#include "salsa/core/model/simulation.hpp"

using namespace salsa;

namespace {

/// Flies every drone east at 2 m/s.
class East final : public Behavior {
 public:
  Vec2 decide(const Perception& me, Rng&) override { return Vec2{2, 0} - me.velocity; }
};

SimulationSetup field(std::size_t drones) {
  SimulationSetup s;
  s.map.bounds = {{0, 0}, {1000, 1000}};
  s.map.spawn = {500, 500};
  s.groups[0].drones = drones;
  s.groups[0].behavior = std::make_shared<East>();
  s.dt = 0.05;  // room for a wind: (max speed + wind) x dt stays within the radius
  s.threads = 1;
  return s;
}

}  // namespace

class TestColumns : public QObject {
  Q_OBJECT
 private Q_SLOTS:
  void views_share_memory_with_the_simulation() {
    Simulation sim(field(25));
    sim.run_steps(3);
    const StateColumn position = sim.column("position"), velocity = sim.column("velocity"), status = sim.column("status");
    // The very arrays WorldView hands to plugins: no copy was made.
    QCOMPARE(position.data, static_cast<const void*>(sim.drone_positions().data()));
    QCOMPARE(velocity.data, static_cast<const void*>(sim.drone_velocities().data()));
    QCOMPARE(status.data, static_cast<const void*>(sim.drone_status().data()));
    QCOMPARE(position.rows, std::size_t{25});
    QCOMPARE(position.width, std::size_t{2});
    QCOMPARE(position.unit, std::string_view("m"));
    QCOMPARE(velocity.unit, std::string_view("m/s"));
    QVERIFY(position.type == StateColumn::Type::f64 && status.type == StateColumn::Type::u8);
    // Read through the column as Python would (x then y per drone): the simulation's values.
    const auto* xy = static_cast<const double*>(position.data);
    for (std::size_t i = 0; i < 25; ++i) {
      QCOMPARE(xy[2 * i], sim.drone_positions()[i].x);
      QCOMPARE(xy[2 * i + 1], sim.drone_positions()[i].y);
    }
    // Stepping moves the drones; the view (taken again: a step may not move memory, a change may) sees it.
    const double before = xy[0];
    sim.step();
    QVERIFY(static_cast<const double*>(sim.column("position").data)[0] > before);
  }

  void every_column_is_named_once_with_a_unit_and_its_size() {
    Simulation sim(field(10));
    std::set<std::string_view> names;
    for (const StateColumn& c : sim.columns()) {
      QVERIFY2(names.insert(c.name).second, std::string(c.name).c_str());
      QVERIFY2(!c.meaning.empty() && !c.model.empty(), std::string(c.name).c_str());
      QCOMPARE(c.rows, std::size_t{10});
      QVERIFY(c.data != nullptr);
      QVERIFY(c.item_size() == 8 || c.item_size() == 4 || c.item_size() == 1);
    }
    for (const char* name : {"position", "velocity", "group", "status", "energy_used", "battery_left", "camera_works"})
      QVERIFY2(names.count(name), name);
    QVERIFY(sim.column("no_such_column").data == nullptr);
  }

  void a_model_adds_its_columns_while_it_keeps_them() {
    Simulation sim(field(4));
    QVERIFY(sim.column("air_velocity").data == nullptr);  // no wind: no air velocities are kept
    Wind w;
    w.velocity = {1, 0};
    sim.set_wind(w, nullptr);
    sim.step();
    const StateColumn air = sim.column("air_velocity"), wind = sim.column("wind");
    QCOMPARE(air.rows, std::size_t{4});
    QCOMPARE(air.data, static_cast<const void*>(sim.air_velocities().data()));
    QCOMPARE(static_cast<const double*>(wind.data)[0], 1.0);  // the wind each drone flew in
  }

  void the_declared_columns_are_those_a_simulation_keeps() {
    SimulationSetup s = field(3);
    DroneConfig& d = s.groups[0].drone;  // return to base keeps its columns too
    d.battery_capacity = 1, d.charge_power = 100, d.return_to_base = 1;
    Simulation sim(std::move(s));
    Wind w;
    w.velocity = {1, 0};
    sim.set_wind(w, nullptr);
    sim.step();  // every model on: the wind's and return to base's columns too
    const std::vector<StateColumn> kept = sim.columns(), declared = Simulation::declared_columns();
    QCOMPARE(declared.size(), kept.size());
    for (std::size_t k = 0; k < kept.size(); ++k) {
      QCOMPARE(declared[k].name, kept[k].name);
      QCOMPARE(declared[k].unit, kept[k].unit);
      QCOMPARE(declared[k].model, kept[k].model);
      QVERIFY(declared[k].type == kept[k].type && declared[k].width == kept[k].width && declared[k].data == nullptr);
    }
  }

  void a_changed_drone_count_is_seen_by_name() {
    Simulation sim(field(5));
    sim.set_drone_count(8);
    QCOMPARE(sim.column("status").rows, std::size_t{8});
    sim.set_drone_count(3);
    const StateColumn status = sim.column("status");
    QCOMPARE(status.rows, std::size_t{8});  // ids are never reused: removed drones keep their rows
    QCOMPARE(static_cast<const std::uint8_t*>(status.data)[7], static_cast<std::uint8_t>(DroneStatus::removed));
  }
};

QTEST_GUILESS_MAIN(TestColumns)
#include "test_columns.moc"
