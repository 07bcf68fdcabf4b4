// The models of a test's sections (test_models.hpp): failures, comm and wind, declared once each.
#include "salsa/core/experiments/test_models.hpp"

#include "salsa/core/experiments/test_spec.hpp"

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

std::vector<TestModel> builtin_models() {
  TestModel failures{
      .key = "failures",
      .meaning = "failures: a test's random failures (\"failures\": {...}; absent: no drone fails on its own). Each drone's\n"
                 "failure times come from the seed alone, so every behavior of a repeat loses the same drones at the\n"
                 "same times. Timed changes and sweeps set them as failures.<name>.",
      .fields = bound_fields<&TestSpec::failures>(failure_schema()),
      .in_use = [](const TestSpec& t) { return t.failures != FailureSetup{}; },
      .apply = [](Simulation& sim, const TestSpec& t) { sim.set_failures(t.failures); },
  };
  TestModel comm{
      .key = "comm",
      .meaning = "comm: a test's communication model (\"comm\": {...}; absent: drones exchange no messages). Timed changes\n"
                 "and sweeps set its fields as comm.<field>; line_of_sight is true or false (1 or 0 in changes and sweeps).\n"
                 "Loss at distance d: p = 1 - (1 - loss)(1 - loss_at_range (d / range)^2).",
      .fields = bound_fields<&TestSpec::comm>(comm_schema()),
      .in_use = [](const TestSpec& t) { return t.comm.on; },
      .given = [](TestSpec& t) { t.comm.on = true; },
      .changes_while_off = false,
      .apply = [](Simulation& sim, const TestSpec& t) { sim.set_comm(t.comm); },
  };
  TestModel wind{
      .key = "wind",
      .meaning = "wind: a test's moving air (\"wind\": {\"velocity\", \"gusts\", \"field\"}; absent: still air). The wind at a\n"
                 "drone is velocity + gust(t) + field(x, y, t); max speed and power are relative to the air. Timed changes\n"
                 "and sweeps set its numbers as wind.<name> and a field's parameters as wind.field.params.<p>.",
      .fields = bound_fields<&TestSpec::wind>(wind_schema()),
      .in_use = [](const TestSpec& t) { return t.has_wind(); },
      .problem =
          [](const TestSpec& t) {
            for (const GroupSpec& g : t.groups)
              if (const Problem p = check_wind(t.wind, g.drone, t.dt)) return p.what + (t.groups.size() > 1 ? " (group " + g.name + ")" : "");
            return std::string();
          },
      .apply = [](Simulation& sim, const TestSpec& t) { sim.set_wind(t.wind, sim.wind_field_ptr()); },
      .other_keys = {"field"},
      .other_forms = "wind.field.params.<name>",
  };
  return {std::move(failures), std::move(comm), std::move(wind)};
}

std::vector<TestModel>& registry() {
  static std::vector<TestModel> models = builtin_models();
  return models;
}

}  // namespace

const std::vector<TestModel>& test_models() { return registry(); }

const TestModel* model_of_key(std::string_view key) {
  for (const TestModel& m : registry())
    if (key.size() > m.key.size() && key.starts_with(m.key) && key[m.key.size()] == '.') return &m;
  return nullptr;
}

void add_test_model(TestModel model) { registry().push_back(std::move(model)); }

}  // namespace salsa
