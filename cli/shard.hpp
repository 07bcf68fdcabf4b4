#pragma once
// Which share of a queue this process runs: --shard i/n, or a Slurm job array's task.
#include <boost/program_options/variables_map.hpp>

#include <cstddef>
#include <utility>

namespace salsa::cli {

/// --shard i/n, or from a Slurm job array (SLURM_ARRAY_TASK_ID, _MIN, _STEP and _COUNT; an id without
/// the count is refused); {0, 1}: the whole queue. InputError (one line) for anything else.
std::pair<std::size_t, std::size_t> shard_option(const boost::program_options::variables_map& vm);

}  // namespace salsa::cli
