#include "shard.hpp"

#include <charconv>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <string>

#include "salsa/core/experiments/test_spec.hpp"

namespace salsa::cli {

namespace po = boost::program_options;

std::pair<std::size_t, std::size_t> shard_option(const po::variables_map& vm) {
  const std::string allowed = " (allowed: i/n with n in [1, 1000000] and i in [0, n - 1], e.g. 0/4)";
  if (vm.count("shard")) {
    const std::string text = vm["shard"].as<std::string>();
    const auto slash = text.find('/');
    std::size_t i = 0, n = 0;
    const char* mid = text.data() + (slash == std::string::npos ? text.size() : slash);
    const auto a = std::from_chars(text.data(), mid, i);
    const auto b = slash == std::string::npos ? std::from_chars_result{mid, std::errc::invalid_argument}
                                               : std::from_chars(mid + 1, text.data() + text.size(), n);
    if (slash == 0 || a.ec != std::errc() || a.ptr != mid || b.ec != std::errc() || b.ptr != text.data() + text.size() || n < 1 ||
        n > 1000000 || i >= n)
      throw InputError("--shard: \"" + text + "\" is not a shard of the queue" + allowed);
    return {i, n};
  }
  auto env = [](const char* name) -> std::optional<long long> {
    const char* v = std::getenv(name);
    if (!v || !*v) return std::nullopt;
    long long x = 0;
    const auto [end, ec] = std::from_chars(v, v + std::strlen(v), x);
    if (ec != std::errc() || *end) throw InputError(std::string(name) + ": \"" + v + "\" is not a whole number (set by Slurm; or give --shard i/n)");
    return x;
  };
  const auto id = env("SLURM_ARRAY_TASK_ID"), count = env("SLURM_ARRAY_TASK_COUNT");
  if (!id) return {0, 1};
  // Without the count every task would run the whole queue into the same folder.
  if (!count)
    throw InputError("SLURM_ARRAY_TASK_ID: " + std::to_string(*id) +
                     " is set without SLURM_ARRAY_TASK_COUNT, so this task's share is unknown (allowed: both set, as Slurm does; or give --shard i/n)");
  const long long min = env("SLURM_ARRAY_TASK_MIN").value_or(0), step = env("SLURM_ARRAY_TASK_STEP").value_or(1);
  const long long i = step > 0 ? (*id - min) / step : -1;
  if (*count < 1 || i < 0 || i >= *count)
    throw InputError("SLURM_ARRAY_TASK_ID: " + std::to_string(*id) + " is not in the job array (min " + std::to_string(min) + ", step " +
                     std::to_string(step) + ", count " + std::to_string(*count) + "; or give --shard i/n)");
  return {static_cast<std::size_t>(i), static_cast<std::size_t>(*count)};
}


}  // namespace salsa::cli
