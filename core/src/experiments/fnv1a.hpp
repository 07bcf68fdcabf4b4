#pragma once
// 64-bit FNV-1a, a hash stable across machines and releases (paired seeds, cut names, queue folder hashes). Internal to libsalsa.
#include <cstdint>
#include <string_view>

namespace salsa::detail {

/// FNV-1a over the bytes of `text`, continuing from `h` (by default the offset basis: a hash of its own).
inline std::uint64_t fnv1a64(std::string_view text, std::uint64_t h = 0xcbf29ce484222325ull) {
  for (const unsigned char c : text) h = (h ^ c) * 0x100000001b3ull;
  return h;
}

}  // namespace salsa::detail
