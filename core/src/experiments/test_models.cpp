// The list of a test's models (test_models.hpp); each is declared in its own file in models/.
#include "salsa/core/experiments/test_models.hpp"

#include "models/models.hpp"

#include "salsa/core/experiments/test_spec.hpp"
#include "salsa/core/model/simulation.hpp"

namespace salsa {

const ModelField* TestModel::find(std::string_view name) const {
  for (const ModelField& f : fields)
    if (f.spec.name == name) return &f;
  return nullptr;
}

std::string TestModel::names() const {
  std::string out;
  for (const ModelField& f : fields) out += (out.empty() ? "" : ", ") + f.spec.name;
  return out;
}

namespace {

std::vector<TestModel>& registry() {
  static std::vector<TestModel> models = models::core_models();
  return models;
}

}  // namespace

const std::vector<TestModel>& test_models() { return registry(); }

ModelOutputs::ModelOutputs(const TestSpec& test) {
  for (const TestModel& m : registry())
    if (m.output_columns) {
      std::vector<std::string> columns = m.output_columns(test);
      if (columns.empty()) continue;
      models_.push_back(&m);
      columns_.insert(columns_.end(), columns.begin(), columns.end());
    }
}

std::vector<std::string> ModelOutputs::values(const Simulation& sim, const TestSpec& test) const {
  std::vector<std::string> out;
  for (const TestModel* m : models_)
    for (std::string& v : m->output_values(sim, test)) out.push_back(std::move(v));
  return out;
}

const TestModel* model_of_key(std::string_view key) {
  for (const TestModel& m : registry())
    if (m.section && key.size() > m.key.size() && key.starts_with(m.key) && key[m.key.size()] == '.') return &m;
  return nullptr;
}

void add_test_model(TestModel model) { registry().push_back(std::move(model)); }

std::vector<StateColumn> declared_drone_columns() {
  std::vector<StateColumn> out = Simulation::declared_columns();
  for (const TestModel& m : registry())
    if (m.simulate) {
      const DroneModel d = m.simulate(TestSpec{});
      for (StateColumn c : d.columns) out.push_back((c.model = d.name, c));
    }
  return out;
}

}  // namespace salsa
