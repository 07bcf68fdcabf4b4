#pragma once
// The files of cli/templates/ (what `salsa new-plugin` writes), embedded when salsa is built: CMake
// reads each into the generated templates.cpp (cli/CMakeLists.txt), so the templates stay real source
// files that the test suite compiles as they are.
#include <string>

namespace salsa::cli {

/// The text of cli/templates/<path> (e.g. "behavior/my_behavior.cpp"); std::logic_error when salsa
/// was built without it.
const std::string& template_file(const std::string& path);

}  // namespace salsa::cli
