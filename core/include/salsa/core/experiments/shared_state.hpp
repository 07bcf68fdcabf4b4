#pragma once
// Whether a queue compares global knowledge with a radio's: a behavior that declares global shared
// state (Behavior::shared_state) in a queue where tests have a radio ("comm") knows more than any radio
// would carry, so its lead over radio-bound drones is an idealisation (docs/experiments.md).
#include <string>
#include <vector>

#include "salsa/behavior.hpp"
#include "salsa/core/experiments/test_spec.hpp"
#include "salsa/core/plugins/plugin_host.hpp"

namespace salsa {

/// What the behavior `choice` names declares with its parameters; none when it cannot be made (its
/// values are the test reader's to refuse); what its shared_state() throws passes on.
SharedState shared_state_of(const PluginChoice& choice, const PluginHost& host);

/// One line when `tests` set a behavior with global shared state beside a radio: some test has "comm"
/// (from the start or by a timed change) and some group's behavior declares `global` (with its
/// parameters, also after timed changes). "" otherwise. Names the global variants and a radio test.
std::string shared_state_warning(const std::vector<TestSpec>& tests, const PluginHost& host);

}  // namespace salsa
