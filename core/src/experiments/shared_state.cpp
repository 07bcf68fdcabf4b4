#include "salsa/core/experiments/shared_state.hpp"

#include <map>
#include <memory>
#include <set>

#include "salsa/core/experiments/changes.hpp"
#include "salsa/core/experiments/queue.hpp"

namespace salsa {

SharedState shared_state_of(const PluginChoice& choice, const PluginHost& host) {
  const Entry<Behavior>* entry = nullptr;
  std::shared_ptr<Behavior> behavior;
  try {
    entry = &host.behavior(choice.name);
    behavior = PluginHost::create(*entry, choice.params);
  } catch (const std::exception&) {  // refused values are the test reader's to report, not this check's
    return SharedState::none;
  }
  // A behavior that cannot say (a Python method's error) stops the run, named.
  const std::string named = "behavior '" + choice.name + "' (" + entry->plugin().file.string() + ") shared_state(): ";
  try {
    return behavior->shared_state();
  } catch (const std::exception& e) {
    throw std::runtime_error(named + e.what());
  } catch (...) {
    throw std::runtime_error(named + "threw a non-standard exception");
  }
}

std::string shared_state_warning(const std::vector<TestSpec>& tests, const PluginHost& host) {
  std::map<std::string, SharedState> known;  // by behavior name and parameter values: a queue repeats them
  auto declared = [&](const PluginChoice& choice) {
    std::string key = choice.name;
    for (const auto& [name, value] : choice.params.items()) key += '\0' + name + '=' + std::to_string(value);
    auto it = known.find(key);
    if (it == known.end()) it = known.emplace(key, shared_state_of(choice, host)).first;
    return it->second;
  };
  std::set<std::string> global;  // the variants that know globally, in label order
  std::string radio_test;
  std::size_t radio_tests = 0;
  for (const TestSpec& t : tests) {
    // The test as it starts, then after each timed change (one may switch the radio or a behavior's sharing).
    TestSpec now = t;
    bool radio = now.comm.on, shares = false;
    auto look = [&] {
      for (const GroupSpec& g : now.groups) shares |= declared(g.behavior) == SharedState::global;
      radio |= now.comm.on;
    };
    look();
    for (const Change& c : t.changes) apply_to_test(now, c), look();
    if (shares) global.insert(variant(t, host));
    if (radio && radio_tests++ == 0) radio_test = t.name;
  }
  if (global.empty() || radio_tests == 0) return {};
  std::string names;
  for (const std::string& v : global) names += (names.empty() ? "" : "; ") + v;
  return "compares global knowledge with a radio: " + names + (global.size() == 1 ? " shares" : " share") +
         " state among all drones without messages, while " + std::to_string(radio_tests) +
         (radio_tests == 1 ? " test has" : " tests have") + " a radio (\"comm\", e.g. " + radio_test +
         "); the global variants know more than a radio carries (the built-ins' radio mode: \"sharing\": 1)";
}

}  // namespace salsa
