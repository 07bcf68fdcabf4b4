#include "save_checked.hpp"

#include <cerrno>
#include <cstring>
#include <fstream>

namespace fs = std::filesystem;

namespace salsa::gui {

std::string save_checked(const fs::path& file, const std::string& text, const std::function<std::string(const fs::path&)>& read_back) {
  std::string name = ".";  // appended, not "." + ...: GCC 12 warns falsely (-Wrestrict) on that
  name.append(file.filename().string()).append(".saving");
  const fs::path aside = file.parent_path() / name;
  std::string why;
  {
    std::ofstream out(aside, std::ios::binary | std::ios::trunc);
    out << text;
    out.close();
    if (!out) why = file.string() + ": cannot write (" + std::strerror(errno) + ")";
  }
  if (why.empty()) {
    try {
      why = read_back(aside);
    } catch (const std::exception& e) {
      why = e.what();
    }
    // The reader names the file it read; the user knows it by the name they chose.
    if (auto at = why.find(aside.string()); at != std::string::npos) why.replace(at, aside.string().size(), file.string());
  }
  std::error_code ec;
  if (why.empty()) {
    fs::rename(aside, file, ec);
    if (ec) why = file.string() + ": cannot write (" + ec.message() + ")";
  }
  if (!why.empty()) fs::remove(aside, ec);
  return why;
}

}  // namespace salsa::gui
