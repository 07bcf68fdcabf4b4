// salsa export --mcap (being built).
#include "export.hpp"

#include "salsa/core/files/input_error.hpp"

namespace salsa::cli {

void export_mcap(const Recording&, const std::filesystem::path& file) { throw InputError("--mcap: " + file.string() + ": not in this build yet"); }

}  // namespace salsa::cli
