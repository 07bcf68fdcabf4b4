// salsa export --html (being built).
#include "export.hpp"

#include "salsa/core/files/input_error.hpp"

namespace salsa::cli {

void export_html(const Recording&, const std::filesystem::path& dir) { throw InputError("--html: " + dir.string() + ": not in this build yet"); }

}  // namespace salsa::cli
