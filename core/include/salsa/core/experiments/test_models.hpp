#pragma once
// A test's models, each declared once (core/src/experiments/models/, one file each): the fleet (groups,
// batteries, failures' counts), failures, comm, wind and sensor noise. A declaration gives the model's
// section key, what it is, its numbers bound into the test, when it is in use, what it refuses, how a
// running simulation takes a change, and its columns in summary.csv and outcome.csv. The test reader
// and writer, timed changes and sweeps (<key>.<field>), tune keys, `salsa describe` and the data files
// iterate test_models(); a model declared outside the core (a test's own, a tool's) joins them with
// add_test_model.
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "salsa/core/model/drone_model.hpp"
#include "salsa/core/model/schema.hpp"
#include "salsa/parameters.hpp"

namespace salsa {

struct TestSpec;
class Simulation;

/// One number of a model, bound into the test.
struct ModelField {
  Parameter spec;  ///< "gusts.strength": a dot nests it in the section ({"gusts": {"strength": ...}})
  bool flag = false;  ///< true/false in files (0 or 1 in timed changes and sweeps)
  std::function<double(const TestSpec&)> get;
  std::function<void(TestSpec&, double)> set;
};

struct TestModel {
  std::string key{};    ///< its section in a test file and the first part of its keys ("comm.range")
  /// false: no section of its own in test files; its settings are the drone's (battery, noise) and it
  /// declares its outputs alone.
  bool section = true;
  std::string meaning{};///< a paragraph for `salsa describe <key>`
  std::vector<ModelField> fields{};
  /// Written to config.json (and its keys tunable) only then, so a test without it keeps its bytes.
  std::function<bool(const TestSpec&)> in_use{};
  /// The section was given, even empty ("comm": {} switches messages on). May be empty.
  std::function<void(TestSpec&)> given{};
  /// Timed changes of its keys are allowed while it is not in use (the wind can start mid-run; messages
  /// cannot: a test without "comm" has no message slots).
  bool changes_while_off = true;
  /// What it refuses in a test beyond each field's range ("" when fine), checked after a timed change.
  std::function<std::string(const TestSpec&)> problem{};
  /// A running simulation takes the test's new settings (a timed change). Empty: nothing runs (a
  /// model of the files alone).
  std::function<void(Simulation&, const TestSpec&)> apply{};
  /// Its own per-drone columns and work in the step (drone_model.hpp), made from the test's settings
  /// when it is in use as the test starts, and made again after a timed change of its keys (a model
  /// off until then joins the simulation, its columns at 0). Empty: a model written into the
  /// simulation's phases, or of the files alone.
  std::function<DroneModel(const TestSpec&)> simulate{};
  /// Keys of its section read elsewhere (the wind's "field", a plugin choice), and their dotted forms.
  std::vector<std::string> other_keys{};
  std::string other_forms{}; ///< "wind.field.params.<name>": for messages listing the keys
  /// Its columns in summary.csv (each logged step) and outcome.csv (the end), after salsa's and the
  /// metrics', the models in test_models() order; none while it is off. May be empty.
  std::function<std::vector<std::string>(const TestSpec&)> output_columns{};
  /// Their values now as text, in the same order (asked only of a model that gave columns).
  std::function<std::vector<std::string>(const Simulation&, const TestSpec&)> output_values{};

  const ModelField* find(std::string_view name) const;
  std::string names() const;  ///< "range, line_of_sight, ...": for messages
};

/// Every model of a test, in file order (fleet, failures, comm, wind, noise), then those added.
const std::vector<TestModel>& test_models();
/// The columns a test's models add to summary.csv and outcome.csv, fixed as the test starts.
class ModelOutputs {
 public:
  explicit ModelOutputs(const TestSpec& test);
  const std::vector<std::string>& columns() const { return columns_; }
  /// Their values now, as text, in the same order; `test` as timed changes have left it.
  std::vector<std::string> values(const Simulation& sim, const TestSpec& test) const;

 private:
  std::vector<const TestModel*> models_;
  std::vector<std::string> columns_;
};
/// Every drone state column a test may keep (no data): the simulation's own (Simulation::declared_columns)
/// and those of the models' DroneModels. For checking a name before a run and `salsa describe columns`.
std::vector<StateColumn> declared_drone_columns();
/// The model with a section whose keys `key` starts with ("comm.range" → comm), or nullptr.
const TestModel* model_of_key(std::string_view key);
/// Adds a model declared outside the core (before any test is read); its numbers live where its own
/// fields' get and set put them (TestSpec::extra_numbers for a model with no struct in the core).
void add_test_model(TestModel model);

/// `schema`'s fields (schema.hpp) bound to the member `Member` of TestSpec that holds the model's struct.
template <auto Member, class S, class Section>
std::vector<ModelField> bound_fields(const Schema<S, Section>& schema) {
  std::vector<ModelField> out;
  for (const auto& f : schema)
    out.push_back({f.spec, f.flag, [f](const TestSpec& t) { return f.get(t.*Member); }, [f](TestSpec& t, double v) { f.set(t.*Member, v); }});
  return out;
}

}  // namespace salsa
