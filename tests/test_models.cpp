// A model declared here, outside the core, joins a test's sections through add_test_model alone: the
// test reader (with its one-line errors), config.json, timed changes (checked, applied to the test and to
// a running simulation), sweeps, conditions, tune keys and the data files (summary.csv, outcome.csv, the
// columns a metric or tune objective may name) take it without a line of theirs changed.
#include <QtTest>

#include <set>

#include "common.hpp"
#include "salsa/core/experiments/queue.hpp"
#include "salsa/core/experiments/test_models.hpp"
#include "salsa/core/experiments/test_spec.hpp"
#include "salsa/core/experiments/tune_file.hpp"
#include "salsa/core/run/runner.hpp"

using namespace salsa;
using namespace salsa_test;

namespace {

int applied = 0;  // the simulation was told of a change of "sway"

/// "sway": {"amplitude": m, "drift": [x, y] in m/s, "pulse": true}. Its own per-drone state: each flying
/// drone's offset drifts at "drift" (m/s), and counts the steps it drifted.
TestModel sway() {
  auto number = [](const char* name) -> ModelField {
    return {{name, 0, -10, 10, "m", "test-only"}, false, [name](const TestSpec& t) {
              const auto it = t.extra_numbers.find(std::string("sway.") + name);
              return it == t.extra_numbers.end() ? 0.0 : it->second;
            },
            [name](TestSpec& t, double v) { t.extra_numbers[std::string("sway.") + name] = v; }};
  };
  ModelField amplitude = number("amplitude");
  amplitude.spec.min = 0;
  ModelField pulse = number("pulse");
  pulse.spec = {"pulse", 0, 0, 1, "", "test-only flag", 1};
  pulse.flag = true;
  return {.key = "sway",
          .meaning = "sway: a model declared by a test",
          .fields = {amplitude, number("drift.x"), number("drift.y"), pulse},
          .in_use = [](const TestSpec& t) { return !t.extra_numbers.empty(); },
          .problem = [](const TestSpec& t) -> std::string {
            const auto it = t.extra_numbers.find("sway.amplitude");
            return it != t.extra_numbers.end() && it->second > 5 ? "amplitude above 5 is refused by the model itself" : "";
          },
          .apply = [](Simulation&, const TestSpec&) { ++applied; },
          .simulate = [](const TestSpec& t) {
            const auto setting = [&](const char* key) { const auto it = t.extra_numbers.find(key); return it == t.extra_numbers.end() ? 0.0 : it->second; };
            const Vec2 drift{setting("sway.drift.x"), setting("sway.drift.y")};
            return DroneModel{"sway",
                              {{"sway_offset", "m", "how far the sway carried it", "", StateColumn::Type::f64, 2}, {"sway_steps", "", "steps it swayed", "", StateColumn::Type::u32}},
                              ModelPhase::moved,
                              [drift](const Simulation& sim, ModelState& state) {
                                const std::span<Vec2> offset = state.vec2("sway_offset");
                                const std::span<std::uint32_t> steps = state.u32("sway_steps");
                                for (std::size_t i = 0; i < offset.size(); ++i)
                                  if (sim.drone_status()[i] == DroneStatus::flying) offset[i] += drift * sim.dt(), ++steps[i];
                              }};
          },
          // Two columns while it is on: its amplitude now, and the flying drones' mean x (m).
          .output_columns = [](const TestSpec& t) { return t.extra_numbers.empty() ? std::vector<std::string>{} : std::vector<std::string>{"sway_amplitude", "sway_mean_x"}; },
          .output_values = [](const Simulation& sim, const TestSpec& t) {
            double x = 0;
            for (const Vec2 p : sim.drone_positions()) x += p.x;
            return std::vector<std::string>{std::to_string(t.extra_numbers.at("sway.amplitude")),
                                            std::to_string(x / static_cast<double>(sim.drone_count()))};
          }};
}

const std::string base = R"("behavior": "random_walk", "drones": 3, "time": 2, "map": {"name": "empty", "params": {"size": 100}})";

}  // namespace

class TestModels : public QObject {
  Q_OBJECT
  std::unique_ptr<PluginHost> host_ = builtin_host();

 private Q_SLOTS:
  void initTestCase() { add_test_model(sway()); }

  void the_reader_and_config_json_take_it() {
    const TestSpec t = parse_test("{" + base + R"(, "sway": {"amplitude": 2, "drift": [1, -1], "pulse": true}})", "t.json", *host_);
    QCOMPARE(t.extra_numbers.at("sway.amplitude"), 2.0);
    QCOMPARE(t.extra_numbers.at("sway.drift.y"), -1.0);
    QCOMPARE(t.extra_numbers.at("sway.pulse"), 1.0);
    const std::string config = resolved_json(t, *host_);
    QVERIFY2(config.find(R"("sway": {
    "amplitude": 2.0,
    "drift": [
      1.0,
      -1.0
    ],
    "pulse": true
  })") != std::string::npos, config.c_str());
    QCOMPARE(parse_test(config, "config.json", *host_).extra_numbers, t.extra_numbers);  // reads back as it was
    // The nested form too, and a test without it has no "sway" in config.json.
    QCOMPARE(parse_test("{" + base + R"(, "sway": {"drift": {"x": 3}}})", "t.json", *host_).extra_numbers.at("sway.drift.x"), 3.0);
    QVERIFY(resolved_json(parse_test("{" + base + "}", "t.json", *host_), *host_).find("sway") == std::string::npos);
  }

  void bad_values_are_refused_in_one_line() {
    auto refusal = [&](const std::string& sway) -> std::string {
      try {
        parse_test("{" + base + ", \"sway\": " + sway + "}", "t.json", *host_);
      } catch (const InputError& e) {
        return e.what();
      }
      return "accepted";
    };
    QCOMPARE(refusal(R"({"amplitude": -1})"), std::string("t.json: sway.amplitude: -1 is out of range (allowed: [0, 10] m)"));
    QCOMPARE(refusal(R"({"swing": 1})"), std::string("t.json: sway.swing: unknown key (allowed: amplitude, drift, pulse)"));
    QCOMPARE(refusal(R"({"drift": [1]})"), std::string("t.json: sway.drift: [1] must be [x, y] in m (or {\"x\": ..., \"y\": ...})"));
    QCOMPARE(refusal(R"({"pulse": 2})"), std::string("t.json: sway.pulse: 2 is not true or false (allowed: true, false, 1, 0)"));
    QCOMPARE(refusal("3"), std::string("t.json: sway: 3 must be an object"));
  }

  void timed_changes_check_and_apply_it() {
    TestSpec t = parse_test("{" + base + R"(, "changes": [{"time": 1, "set": {"sway.drift.x": 4}}]})", "t.json", *host_);
    QCOMPARE(t.changes.size(), std::size_t(1));
    QCOMPARE(check_change(t, {1, "sway.amplitude", 6}, *host_), std::string("amplitude above 5 is refused by the model itself"));
    QCOMPARE(check_change(t, {1, "sway.amplitude", 11}, *host_), std::string("11 is out of range (allowed: [0, 10] m)"));
    QVERIFY(check_change(t, {1, "sway.width", 1}, *host_).starts_with("unknown key (allowed: sway.amplitude, sway.drift.x"));
    Simulation sim(make_setup(t, *host_, 1));
    applied = 0;
    apply_change(sim, t, {1, "sway.amplitude", 3}, *host_);
    QCOMPARE(applied, 1);
    QCOMPARE(t.extra_numbers.at("sway.amplitude"), 3.0);
    // Off at the start, its state joins the simulation with the change.
    QVERIFY(sim.column("sway_offset").data != nullptr);
  }

  void the_data_files_carry_its_columns() {
    QTemporaryDir out;
    RunOptions options;
    options.out = out.path().toStdString();
    const TestSpec t = parse_test("{\"name\": \"swaying\", " + base + R"(, "sway": {"amplitude": 2}, "changes": [{"time": 1, "set": {"sway.amplitude": 4}}]})", "t.json", *host_);
    run_test(t, *host_, options);
    const QStringList summary = non_empty_lines(read_file(out.path() + "/swaying/summary.csv"));
    QVERIFY2(summary[0].endsWith(",sway_amplitude,sway_mean_x"), qPrintable(summary[0]));
    QVERIFY2(summary.first(2).last().contains(",2.000000,"), qPrintable(summary[1]));  // time 0: as the file says
    QVERIFY2(summary.last().contains(",4.000000,"), qPrintable(summary.last()));       // after the change
    const QStringList outcome = non_empty_lines(read_file(out.path() + "/swaying/outcome.csv"));
    QVERIFY2(outcome[0].endsWith(",sway_amplitude,sway_mean_x"), qPrintable(outcome[0]));
    // The run's own mean x, so the row is the simulation's, not a constant.
    const double mean_x = outcome[1].split(',').last().toDouble();
    QVERIFY2(mean_x > 0 && mean_x < 100, qPrintable(outcome[1]));
    QCOMPARE(summary.last().split(',').last().toDouble(), mean_x);
    // A metric or tune objective may name them; a test without the model has neither.
    const DataColumns columns = data_columns(t, *host_);
    QVERIFY(std::find(columns.outcome.begin(), columns.outcome.end(), "sway_mean_x") != columns.outcome.end());
    const DataColumns plain = data_columns(parse_test("{" + base + "}", "t.json", *host_), *host_);
    QVERIFY(std::find(plain.summary.begin(), plain.summary.end(), "sway_amplitude") == plain.summary.end());
  }

  // Its own per-drone state: kept as columns beside the core's (drones.csv by name, the inspector's and
  // Python's columns()), stepped at its phase, made again from a timed change's settings.
  void its_drone_state_is_kept_stepped_and_written() {
    const TestSpec t = parse_test("{\"name\": \"drifting\", " + base + R"(, "sway": {"amplitude": 1, "drift": [1, 0]}, "changes": [{"time": 1, "set": {"sway.drift.y": 2}}]})", "t.json", *host_);
    Simulation sim(make_setup(t, *host_, 1));
    QVERIFY(sim.column("sway_offset").data != nullptr);
    QCOMPARE(sim.column("sway_offset").model, std::string_view("sway"));
    QCOMPARE(sim.column("sway_offset").rows, std::size_t(3));
    // Declared for checks before a run and `salsa describe columns`; absent from a test without it.
    const std::vector<StateColumn> declared = declared_drone_columns();
    QVERIFY(std::any_of(declared.begin(), declared.end(), [](const StateColumn& c) { return c.name == "sway_steps" && c.model == "sway"; }));
    QVERIFY(Simulation(make_setup(parse_test("{" + base + "}", "t.json", *host_), *host_, 1)).column("sway_offset").data == nullptr);

    QTemporaryDir out;
    RunOptions options;
    options.out = out.path().toStdString();
    options.drone_columns = {"sway_offset", "sway_steps"};
    run_test(t, *host_, options);
    const QStringList rows = non_empty_lines(read_file(out.path() + "/drifting/drones.csv"));
    const QStringList header = rows[0].split(',');
    const auto at = [&](const QString& row, const char* name) { return row.split(',')[header.indexOf(name)].toDouble(); };
    QVERIFY2(header.contains("sway_offset_x") && header.contains("sway_steps"), qPrintable(rows[0]));
    // The last row: 2 s at 1 m/s east, and 1 s at 2 m/s north after the change at 1 s.
    QVERIFY(std::abs(at(rows.last(), "sway_offset_x") - 2.0) < 1e-9);
    QVERIFY(std::abs(at(rows.last(), "sway_offset_y") - 2.0) < 1e-9);
    QCOMPARE(at(rows.last(), "sway_steps"), 120.0);
  }

  void sweeps_conditions_and_tune_keys_reach_it() {
    QTemporaryDir dir;
    const QString queue = dir.path() + "/queue.json";
    write_file(queue, QByteArray::fromStdString(R"({"sweep": {"test": {)" + base + R"(}, "set": {"sway.amplitude": [1, 2]}},
      "conditions": [{"name": "calm"}, {"name": "drifting", "sway": {"drift": [0, 2]}}]})"));
    const std::vector<TestSpec> tests = load_tests(queue.toStdString(), *host_);
    QCOMPARE(tests.size(), std::size_t(4));
    std::multiset<double> amplitudes, drifts;
    for (const TestSpec& t : tests) {
      amplitudes.insert(t.extra_numbers.at("sway.amplitude"));
      if (t.condition == "drifting") drifts.insert(t.extra_numbers.at("sway.drift.y"));
    }
    QCOMPARE(amplitudes, (std::multiset<double>{1, 1, 2, 2}));
    QCOMPARE(drifts, (std::multiset<double>{2, 2}));
    std::vector<std::string> keys;
    for (const TunableNumber& n : tunable_numbers(tests[0], *host_)) keys.push_back(n.key);
    QVERIFY(std::find(keys.begin(), keys.end(), "sway.amplitude") != keys.end());
    QVERIFY(std::find(keys.begin(), keys.end(), "sway.pulse") == keys.end());  // a flag is no number to tune
  }
};

QTEST_GUILESS_MAIN(TestModels)
#include "test_models.moc"
