// The trajectory archive's reader and writer (being built: until then, a folder's archive is refused).
#include "salsa/core/replay/archive.hpp"

#include "salsa/core/files/input_error.hpp"

namespace salsa {

void read_archive(const std::filesystem::path& file, Recording&) {
  throw InputError(file.string() + ": this salsa cannot read trajectory archives yet");
}

}  // namespace salsa
