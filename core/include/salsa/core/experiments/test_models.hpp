#pragma once
// The models a test switches on with a section of its own ("failures": {...}, "comm": {...}, "wind":
// {...}), each declared once: its section's key, what it is, its numbers bound into the test, when it
// is in use, what it refuses, and how a running simulation takes a change. The test reader and writer,
// timed changes and sweeps (<key>.<field>), tune keys and `salsa describe` iterate test_models(); a
// model declared outside the core (a test's own, a tool's) joins them with add_test_model.
#include <functional>
#include <string>
#include <string_view>
#include <vector>

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
  /// Keys of its section read elsewhere (the wind's "field", a plugin choice), and their dotted forms.
  std::vector<std::string> other_keys{};
  std::string other_forms{}; ///< "wind.field.params.<name>": for messages listing the keys

  const ModelField* find(std::string_view name) const;
  std::string names() const;  ///< "range, line_of_sight, ...": for messages
};

/// Every model of a test's sections, in file order (failures, comm, wind), then those added.
const std::vector<TestModel>& test_models();
/// The model whose keys `key` starts with ("comm.range" → comm), or nullptr.
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
