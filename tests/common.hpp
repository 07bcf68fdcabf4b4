#pragma once
// Shared helpers of the test suites: where things are (set by tests/CMakeLists.txt), the built-in
// plugins, running the salsa CLI, small file utilities.
#include <QByteArray>
#include <QDir>
#include <QDirIterator>
#include <QFile>
#include <QMap>
#include <QProcess>
#include <QStandardPaths>
#include <QString>
#include <QStringList>
#include <QTemporaryDir>
#include <QtTest>

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#ifdef SALSA_TEST_WITH_CORE
#include "salsa/core/plugins/plugin_host.hpp"
#endif

namespace salsa_test {

namespace fs = std::filesystem;

inline fs::path source_dir() { return SALSA_SOURCE_DIR; }
inline fs::path plugin_dir() { return SALSA_PLUGIN_DIR; }
inline fs::path test_plugins_dir() { return SALSA_TEST_PLUGINS_DIR; }
inline QString salsa_executable() { return QStringLiteral(SALSA_EXECUTABLE); }

inline QString q(const fs::path& p) { return QString::fromStdString(p.string()); }
inline QString q(const std::string& s) { return QString::fromStdString(s); }

inline QByteArray read_file(const QString& path) {
  QFile f(path);
  if (!f.open(QIODevice::ReadOnly)) return {};
  return f.readAll();
}
inline bool write_file(const QString& path, const QByteArray& content) {
  QDir().mkpath(QFileInfo(path).absolutePath());
  QFile f(path);
  if (!f.open(QIODevice::WriteOnly | QIODevice::Truncate)) return false;
  return f.write(content) == content.size();
}

/// Every file under `dir` (relative path → contents), to compare a folder before and after.
inline QMap<QString, QByteArray> snapshot(const QString& dir) {
  QMap<QString, QByteArray> out;
  QDirIterator it(dir, QDir::Files | QDir::Hidden | QDir::NoDotAndDotDot, QDirIterator::Subdirectories);
  while (it.hasNext()) {
    const QString file = it.next();
    out.insert(QDir(dir).relativeFilePath(file), read_file(file));
  }
  return out;
}

/// What must be byte-identical between two runs of the same tests, from a snapshot taken of the
/// output folder `prefix` ("" for the snapshot's root). Leaves out what records the run rather than the
/// results: the wall times (every timing.json, the queue's timing.csv), the queue's queue.json (the
/// command); and the plots, which are drawn from the data kept here (test_plots checks them).
inline QMap<QString, QByteArray> results_snapshot_of(QMap<QString, QByteArray> files, const QString& prefix = "") {
  for (auto it = files.begin(); it != files.end();) {
    if (it.key().endsWith("timing.json") || it.key() == prefix + "timing.csv" || it.key() == prefix + "queue.json" ||
        it.key().endsWith(".png"))
      it = files.erase(it);
    else ++it;
  }
  return files;
}
inline QMap<QString, QByteArray> results_snapshot(const QString& dir) { return results_snapshot_of(snapshot(dir)); }

inline QStringList non_empty_lines(const QString& text) {
  QStringList out;
  for (const QString& line : text.split('\n'))
    if (!line.trimmed().isEmpty()) out << line;
  return out;
}

/// A CSV file's rows (the header first), split at commas: for files of plain fields.
inline std::vector<std::vector<std::string>> rows_of(const QString& file) {
  std::vector<std::vector<std::string>> rows;
  for (const QString& line : non_empty_lines(read_file(file))) {
    std::vector<std::string> fields;
    for (const QString& f : line.split(',')) fields.push_back(f.toStdString());
    rows.push_back(fields);
  }
  return rows;
}
/// The index of column `name` in rows_of's header; the test stops when there is none.
inline std::size_t column(const std::vector<std::vector<std::string>>& rows, const std::string& name) {
  for (std::size_t c = 0; c < rows[0].size(); ++c)
    if (rows[0][c] == name) return c;
  qFatal("no column %s", name.c_str());
}

struct CliResult {
  int exit_code = -1;
  bool crashed = false;
  QString out, err;
};

/// Runs the salsa CLI with a clean environment: no $SALSA_PLUGIN_PATH and an empty user folder, so
/// only the build's plugins (and any --plugin-dir) are found.
/// Runs `program` with `args` in `working_dir` as a user would, with a private HOME, no
/// SALSA_PLUGIN_PATH and `vars` added to the environment.
inline CliResult run_program(const QString& program, const QStringList& args, const QString& working_dir = {},
                             const QMap<QString, QString>& vars = {}) {
  static QTemporaryDir home;
  QProcess p;
  QProcessEnvironment env = QProcessEnvironment::systemEnvironment();
  env.remove("SALSA_PLUGIN_PATH");
  env.insert("HOME", home.path());
  for (auto it = vars.begin(); it != vars.end(); ++it) env.insert(it.key(), it.value());
  p.setProcessEnvironment(env);
  if (!working_dir.isEmpty()) p.setWorkingDirectory(working_dir);
  p.start(program, args);
  CliResult r;
  if (!p.waitForStarted(30000)) {
    r.err = "could not start " + program;
    return r;
  }
  p.waitForFinished(600000);  // the shortened forest-health queue under the sanitizers takes minutes
  r.crashed = p.exitStatus() != QProcess::NormalExit;
  r.exit_code = p.exitCode();
  r.out = QString::fromUtf8(p.readAllStandardOutput());
  r.err = QString::fromUtf8(p.readAllStandardError());
  return r;
}

inline CliResult run_salsa(const QStringList& args, const QString& working_dir = {}) { return run_program(salsa_executable(), args, working_dir); }

/// `salsa ARGS` under `mpirun -n ranks` in `working_dir`, or nullopt when mpirun is not installed.
inline std::optional<CliResult> run_mpi(int ranks, const QStringList& args, const QString& working_dir = {}) {
  const QString mpirun = QStandardPaths::findExecutable("mpirun");
  if (mpirun.isEmpty()) return std::nullopt;
  // OpenMPI keeps its components' allocations to the end and unloads them, so a sanitizer build
  // would report (unsymbolisable) leaks inside libmpi: not salsa's.
  return run_program(mpirun, QStringList{"--allow-run-as-root", "--oversubscribe", "-n", QString::number(ranks), salsa_executable()} + args,
                     working_dir, {{"OMPI_MCA_rmaps_base_oversubscribe", "1"}, {"ASAN_OPTIONS", "detect_leaks=0:abort_on_error=1"}});
}

/// For failure messages: what the CLI printed.
inline QByteArray describe(const CliResult& r) {
  return ("exit " + QString::number(r.exit_code) + (r.crashed ? " (crashed)" : "") + "\n--- stdout\n" + r.out +
          "--- stderr\n" + r.err)
      .toUtf8();
}

#ifdef SALSA_TEST_WITH_CORE
/// A host with the build's built-in plugins only; fails the test if any of them is refused.
inline std::unique_ptr<salsa::PluginHost> builtin_host() {
  auto host = std::make_unique<salsa::PluginHost>();
  host->load({{plugin_dir(), "test"}});
  for (const auto& f : host->failures()) qWarning("plugin %s refused: %s", f.file.c_str(), f.reason.c_str());
  return host;
}
#endif

}  // namespace salsa_test
