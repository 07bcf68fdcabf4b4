#pragma once
// User text that becomes a file or folder name (test names, file stems, queue and plot names) goes
// through this one check, so no name can reach outside the folder it is meant for ("..", "a/b"); a
// group's name, which names columns and keys, through its own.
#include <string>
#include <string_view>

namespace salsa {

/// Longest name allowed: well under the file system's 255 bytes, leaving room for ".<name>.partial".
inline constexpr std::size_t max_name_length = 128;

/// Empty when `name` may name a file or folder, else why not, ending in what is allowed, e.g.
/// "\"..\" must start with a letter or digit and use only letters, digits, '_', '-' and '.' (1 to 128
/// characters; it names a folder)".
std::string name_problem(std::string_view name);

/// Empty when `name` may name a group of a test, else why not: name_problem's rules without '.', as
/// keys such as "groups.<name>.drones" split at dots.
std::string group_name_problem(std::string_view name);

/// The names of the files and folders a queue writes at its output folder's top level (plots/,
/// summary.csv, queue.json, comparison.csv, did.csv, condition_effects.csv, ranking.csv, timing.json, timing.csv);
/// the lock file and markers start with '.', which name_problem refuses already.
inline constexpr const char* reserved_names[] = {"plots", "summary.csv", "queue.json", "comparison.csv", "did.csv", "condition_effects.csv",
                                                  "ranking.csv", "timing.json", "timing.csv"};

/// name_problem() for a test's name (it names OUT/<name>/): also refuses the reserved names, in any
/// case and with any ".<suffix>" (the temporary files salsa writes beside them), e.g. "\"plots\" is a
/// name salsa writes in the output folder itself (allowed: any other name; reserved: plots, ...)".
std::string test_name_problem(std::string_view name);

}  // namespace salsa
