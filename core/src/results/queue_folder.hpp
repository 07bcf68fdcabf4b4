#pragma once
// What the queue folder's record (queue_record.cpp) and summary (queue_summary.cpp) share. Internal to libsalsa.
#include <nlohmann/json.hpp>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

namespace salsa::detail {

/// The last `digits` hex digits of `v`.
std::string hex(std::uint64_t v, int digits);
/// A file's bytes; nullopt when it cannot be read.
std::optional<std::string> read_text(const std::filesystem::path& file);
/// A JSON file salsa wrote, read back; nullopt when it cannot be read or is not JSON.
std::optional<nlohmann::ordered_json> read_json(const std::filesystem::path& file);

}  // namespace salsa::detail
