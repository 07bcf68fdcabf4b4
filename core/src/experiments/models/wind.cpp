// The wind model: moving air ("wind": {"velocity", "gusts", "field"}).
#include "models.hpp"

#include "salsa/core/experiments/test_spec.hpp"

namespace salsa::models {

TestModel wind() {
  return {
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
}

}  // namespace salsa::models
