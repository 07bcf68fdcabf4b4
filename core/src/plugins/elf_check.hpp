#pragma once
// The check a plugin file passes before it is mapped: glibc's dlopen maps every loaded segment
// straight from the file, so a segment that ends past the end of a truncated (half-copied) file
// becomes a SIGBUS inside dlopen, not an error. A pure function over bytes, so a fuzzer can call it.
#include <cstddef>
#include <string>

namespace salsa {

/// Empty when `data` (a whole file of `size` bytes) is a shared library for this host whose headers
/// and loaded segments all lie inside it; else why not, in words, e.g. "truncated: loaded segment 2
/// ends at byte 14832, the file has 4096 bytes (a half-copied file?)".
std::string elf_problem(const unsigned char* data, std::size_t size);

}  // namespace salsa
