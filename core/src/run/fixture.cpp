// salsa::testing::Simulation (plugin-sdk/include/salsa/fixture.hpp): a test's simulation, set up as
// `salsa run` sets one up (parse_test, make_setup, MetricSet), stepped by the caller.
#include "salsa/fixture.hpp"

#include <dlfcn.h>

#include <optional>
#include <stdexcept>

#include "salsa/core/run/session.hpp"
#include "salsa/core/plugins/plugin_host.hpp"
#include "salsa/core/model/simulation.hpp"
#include "salsa/core/experiments/test_spec.hpp"
#include "strict_json.hpp"

namespace salsa::testing {
namespace {

// libsalsa's own plugin folder, <libdir>/salsa/plugins, in a build tree and installed alike: the
// test executable lives in the author's build, so the executable's folder says nothing.
fs::path builtin_plugins() {
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&builtin_plugins), &info) == 0 || info.dli_fname == nullptr) return {};
  return fs::path(info.dli_fname).parent_path() / "salsa" / "plugins";
}

void load_plugins(PluginHost& host, const std::vector<std::string>& plugins) {
  std::vector<SearchDir> dirs;
  for (const auto& p : plugins) {
    std::error_code ec;
    if (fs::is_directory(p, ec)) dirs.push_back({p, "--plugin-dir"});
    else if (!host.load_file(p)) throw std::runtime_error(p + ": " + host.failures().back().reason);
  }
  if (const fs::path own = builtin_plugins(); !own.empty()) dirs.push_back({own, "install"});
  const std::size_t before = host.failures().size();
  host.load(dirs);
  for (std::size_t i = before; i < host.failures().size(); ++i) {  // only the caller's folders must load
    const auto& f = host.failures()[i];
    for (const auto& p : plugins)
      if (f.file.string().starts_with(p)) throw std::runtime_error(f.file.string() + ": " + f.reason);
  }
}

}  // namespace

struct Simulation::Impl {
  PluginHost host;
  std::optional<Session> session;  // the run loop `salsa run` uses
  salsa::Simulation* sim = nullptr;
  MetricSet* metrics = nullptr;
};

Simulation::Simulation(const std::string& test, const std::vector<std::string>& plugins)
    : Simulation(nullptr, test, plugins) {}

Simulation::Simulation(std::shared_ptr<Behavior> behavior, const std::string& test, const std::vector<std::string>& plugins)
    : impl_(std::make_unique<Impl>()) {
  load_plugins(impl_->host, plugins);
  std::string text = test;
  if (behavior) {  // the test's own behavior, if any, is replaced: any loaded one stands in for parsing
    auto j = strict_json::parse<nlohmann::ordered_json>(test, "fixture test");
    if (!j.is_object()) throw std::runtime_error("fixture test: must be a JSON object");
    j["behavior"] = "random_walk";
    text = j.dump();
    if (behavior->parameters().items().empty()) behavior->set_parameters(ParameterValues(behavior->bound_parameters()));
  }
  // Bad input throws InputError or strict_json::Error, both std::runtime_errors with salsa run's message.
  impl_->session.emplace(parse_test(text, "fixture test", impl_->host), impl_->host, SessionOptions{1, std::move(behavior)});
  impl_->sim = &impl_->session->simulation();
  impl_->metrics = &impl_->session->metrics();
}

Simulation::~Simulation() = default;

void Simulation::step() { impl_->session->step(); }

void Simulation::run(double seconds) {
  const auto steps = static_cast<std::size_t>(std::llround(seconds / impl_->sim->dt()));
  for (std::size_t i = 0; i < steps; ++i) step();
}

double Simulation::time() const { return impl_->sim->time(); }
const WorldView& Simulation::world() const { return *impl_->sim; }
std::size_t Simulation::targets() const { return impl_->sim->targets().size(); }
std::size_t Simulation::targets_found() const { return impl_->sim->targets_found(); }
Behavior& Simulation::behavior() const { return impl_->sim->behavior(); }

std::vector<Vec2> Simulation::target_positions() const {
  std::vector<Vec2> out;
  for (const auto& t : impl_->sim->targets()) out.push_back(t.position);
  return out;
}

std::vector<std::string> Simulation::metric_columns() const { return impl_->metrics->step_columns(); }

double Simulation::metric(const std::string& column) const {
  const auto columns = impl_->metrics->step_columns();
  for (std::size_t i = 0; i < columns.size(); ++i)
    if (columns[i] == column) return impl_->metrics->observe(*impl_->sim)[i];
  std::string known;
  for (const auto& c : columns) known += (known.empty() ? "" : ", ") + c;
  throw std::out_of_range("no metric column '" + column + "' (this test's: " + known + ")");
}

}  // namespace salsa::testing
