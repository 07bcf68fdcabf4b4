// salsa new-plugin KIND NAME [--dir D]: writes D/NAME/, a plugin folder that builds, tests and installs
// against the installed salsa (find_package(salsa) + salsa_add_plugin). The templates are the files
// in cli/templates/ (one plugin and one test per kind, and CMakeLists.txt.in), embedded at build time
// (templates.hpp).
#include <boost/program_options.hpp>

#include <unistd.h>

#include <array>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <string_view>
#include <vector>

#include "salsa/core/experiments/test_spec.hpp"
#include "commands.hpp"
#include "options.hpp"
#include "templates.hpp"

namespace po = boost::program_options;
namespace fs = std::filesystem;

namespace {

struct Kind {
  std::string_view name;      // on the command line, and the template's folder (cli/templates/<name>/)
  std::string_view words;     // in comments
  std::string_view brief;
  std::string_view example;   // the template's own plugin name (my_behavior), replaced by NAME
  std::string_view example_class;  // and its class (MyBehavior), replaced by the class made from NAME
};

const std::array<Kind, 6> kinds{{
    {"behavior", "behavior", "Own heading drifting at random, avoids drones and obstacles", "my_behavior", "MyBehavior"},
    {"target", "target kind", "Small targets, seen within part of the camera range", "my_target", "MyTarget"},
    {"map", "map", "Square with a grid of pillars, clear around the centre", "my_map", "MyMap"},
    {"contact-handler", "contact handler", "A target is found once several drones have seen it", "my_contact_handler", "MyContactHandler"},
    {"metric", "metric", "Polarisation of the swarm: 1 when all fly the same way", "my_metric", "MyMetric"},
    {"wind", "wind field", "A sea breeze: wind that strengthens towards the coast", "my_wind", "MyWind"},
}};

std::string replace_all(std::string text, std::string_view from, std::string_view to) {
  for (std::size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size()))
    text.replace(at, from.size(), to);
  return text;
}

/// my_great_behavior -> MyGreatBehavior
std::string class_name(const std::string& name) {
  std::string out;
  bool upper = true;
  for (char c : name) {
    if (c == '_') {
      upper = true;
      continue;
    }
    out += upper ? static_cast<char>(std::toupper(static_cast<unsigned char>(c))) : c;
    upper = false;
  }
  return out;
}

/// Names a plugin may not take although they are identifiers: C and C++ keywords (with the
/// alternative tokens) and standard names that are macros or would read as the language's own.
constexpr std::string_view language_names[] = {
    "alignas", "alignof", "and", "and_eq", "asm", "assert", "atomic_cancel", "atomic_commit", "atomic_noexcept", "auto",
    "bitand", "bitor", "bool", "break", "case", "catch", "char", "char8_t", "char16_t", "char32_t", "class", "co_await",
    "co_return", "co_yield", "compl", "complex", "concept", "const", "const_cast", "consteval", "constexpr", "constinit",
    "continue", "decltype", "default", "defined", "delete", "do", "double", "dynamic_cast", "else", "enum", "errno",
    "explicit", "export", "extern", "false", "final", "float", "for", "fortran", "friend", "goto", "if", "imaginary",
    "import", "inline", "int", "long", "main", "module", "mutable", "namespace", "new", "noexcept", "noreturn", "not",
    "not_eq", "nullptr", "offsetof", "operator", "or", "or_eq", "override", "private", "protected", "public", "reflexpr",
    "register", "reinterpret_cast", "requires", "restrict", "return", "salsa", "setjmp", "short", "signed", "sizeof",
    "static", "static_assert", "static_cast", "std", "stderr", "stdin", "stdout", "struct", "switch", "synchronized",
    "template", "this", "thread_local", "throw", "true", "try", "typedef", "typeid", "typename", "union", "unsigned",
    "using", "va_arg", "va_copy", "va_end", "va_start", "virtual", "void", "volatile", "wchar_t", "while", "xor", "xor_eq"};

/// Empty when `name` may name the plugin: it becomes the plugin's name, its files, CMake targets, and
/// (as MyName) a C++ class, so it must be a plain lowercase identifier that no compiler, standard
/// header or CMake reads as its own.
std::string name_problem(const std::string& name) {
  const std::string allowed =
      " (allowed: a lowercase letter, then lowercase letters, digits and single '_', 1 to 64 characters, not a C or C++ "
      "keyword or standard name; e.g. my_behavior)";
  auto letter = [](char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z'); };
  bool identifier = !name.empty() && (letter(name[0]) || name[0] == '_');
  for (char c : name) identifier = identifier && (letter(c) || (c >= '0' && c <= '9') || c == '_');
  std::string shown = name.size() > 70 ? name.substr(0, 70) + "..." : name;
  for (char& c : shown)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = '?';  // one line, whatever the input
  const std::string quoted = "\"" + shown + "\"";
  if (!identifier) return quoted + " is not a C identifier" + allowed;
  if (!letter(name[0])) return quoted + " starts with '_' (C and C++ reserve such names)" + allowed;
  if (name.size() > 64) return quoted + " is " + std::to_string(name.size()) + " characters long" + allowed;
  if (std::any_of(name.begin(), name.end(), [](char c) { return c >= 'A' && c <= 'Z'; }))
    return quoted + " has capital letters (C and C++ use such names for macros: NULL, EOF, NDEBUG...)" + allowed;
  if (name.find("__") != std::string::npos) return quoted + " holds '__' (C and C++ reserve such names)" + allowed;
  if (name.back() == '_') return quoted + " ends with '_'" + allowed;
  if (std::find(std::begin(language_names), std::end(language_names), name) != std::end(language_names))
    return quoted + " is a C or C++ keyword or standard name" + allowed;
  for (const char* reserved : {"all", "clean", "help", "install", "package", "package_source", "test", "edit_cache",
                               "rebuild_cache", "list_install_components", "preinstall"})
    if (name == reserved) return quoted + " is a name CMake reserves for its own targets" + allowed;
  return {};
}

/// How to point CMake at this salsa, for the "next" lines.
std::string prefix_hint() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) return "";
  const fs::path prefix = exe.parent_path().parent_path();
  if (!fs::exists(prefix / SALSA_LIBDIR / "cmake/salsa/salsaConfig.cmake", ec))
    return " -DCMAKE_PREFIX_PATH=<where salsa is installed>";  // a build tree: install it first
  if (prefix == "/usr" || prefix == "/usr/local") return "";
  return " -DCMAKE_PREFIX_PATH=" + prefix.string();
}

void write_file(const fs::path& file, const std::string& text) {
  std::ofstream out(file, std::ios::binary);
  out << text;
  out.close();
  if (!out) throw std::runtime_error("new-plugin: cannot write " + file.string());
}

}  // namespace

int cmd_new_plugin(int argc, char** argv) {
  po::options_description o("new-plugin options");
  o.add_options()("dir", po::value<std::string>()->default_value("."), "create the folder NAME/ in this folder");
  po::options_description hidden;
  hidden.add_options()("args", po::value<std::vector<std::string>>(), "");
  po::variables_map vm;
  if (!salsa::cli::parse(argc, argv, "new-plugin",
                         "behavior|target|map|contact-handler|metric|wind NAME [--dir D]\n\n"
                         "Writes D/NAME/: NAME.cpp (a small working plugin of that kind), NAME_test.cpp (a short real\n"
                         "simulation with it: salsa/fixture.hpp) and a CMakeLists.txt that builds it against the\n"
                         "installed salsa, tests it (ctest) and installs it into ~/.local/share/salsa/plugins\n"
                         "(cmake --install).",
                         o, vm, salsa::cli::help_only, salsa::cli::positional("args"), hidden))
    return 0;
  const auto args = vm.count("args") ? vm["args"].as<std::vector<std::string>>() : std::vector<std::string>{};
  const std::string allowed_kinds = "behavior, target, map, contact-handler, metric, wind";
  if (args.empty()) throw salsa::InputError("new-plugin: missing KIND (allowed: " + allowed_kinds + ")");
  const Kind* kind = nullptr;
  for (const Kind& k : kinds)
    if (k.name == args[0]) kind = &k;
  if (!kind) throw salsa::InputError("new-plugin: unknown kind '" + args[0] + "' (allowed: " + allowed_kinds + ")");
  if (args.size() < 2) throw salsa::InputError("new-plugin: missing NAME (a C identifier, e.g. my_" + std::string(args[0] == "contact-handler" ? "handler" : args[0]) + ")");
  if (args.size() > 2) throw salsa::InputError("new-plugin: one NAME at a time (got '" + args[2] + "' too)");
  const std::string name = args[1];
  if (const std::string why = name_problem(name); !why.empty()) throw salsa::InputError("new-plugin: NAME: " + why);

  const fs::path parent = vm["dir"].as<std::string>();
  const fs::path folder = parent / name;
  std::error_code ec;
  if (fs::exists(fs::symlink_status(folder, ec)))
    throw salsa::InputError("new-plugin: " + folder.string() + " already exists (allowed: a folder that does not exist yet)");
  fs::create_directories(parent, ec);
  if (ec || !fs::create_directory(folder, ec) || ec)
    throw salsa::InputError("new-plugin: cannot create " + folder.string() + (ec ? " (" + ec.message() + ")" : ""));

  std::string version = salsa::salsa_version();  // major.minor: the package's versions that build it
  version = version.substr(0, version.find('.', version.find('.') + 1));
  // The templates are real plugins (cli/templates/<kind>/my_<kind>.cpp, built and tested as they are
  // by the test suite): their own name and class become NAME and its class; the test's include of
  // the shared CHECK macro becomes the macro itself, so the folder stands alone.
  const std::string folder_name(kind->name);
  auto source = [&](const std::string& file) {
    std::string text = salsa::cli::template_file(folder_name + "/" + file);
    text = replace_all(std::move(text), "#include \"test_preamble.hpp\"\n", salsa::cli::template_file("test_preamble.hpp"));
    text = replace_all(std::move(text), kind->example_class, class_name(name));
    return replace_all(std::move(text), kind->example, name);
  };
  std::string cmake = salsa::cli::template_file("CMakeLists.txt.in");
  for (const auto& [from, to] : {std::pair<std::string_view, std::string>{"@NAME@", name}, {"@KIND@", std::string(kind->words)},
                                 {"@BRIEF@", std::string(kind->brief)}, {"@VERSION@", version}})
    cmake = replace_all(std::move(cmake), from, to);
  write_file(folder / (name + ".cpp"), source(std::string(kind->example) + ".cpp"));
  write_file(folder / (name + "_test.cpp"), source(std::string(kind->example) + "_test.cpp"));
  write_file(folder / "CMakeLists.txt", cmake);
  write_file(folder / ".gitignore", "build/\n");

  const std::string f = folder.string();
  std::cout << "wrote " << f << "/: " << name << ".cpp (the " << kind->words << "), " << name << "_test.cpp, CMakeLists.txt\n"
            << "next:\n"
            << "  cmake -S " << f << " -B " << f << "/build" << prefix_hint() << "\n"
            << "  cmake --build " << f << "/build && ctest --test-dir " << f << "/build\n"
            << "  cmake --install " << f << "/build    # into ~/.local/share/salsa/plugins\n"
            << "  salsa describe " << name << "\n";
  return 0;
}
