#pragma once
// Plugins in the desktop: the same folders and refusals as the CLI (PluginHost), rescanned on demand or
// when a file in a plugin folder changes. A rescan builds a whole new PluginHost; objects made from the
// old one keep their libraries loaded, so the running simulation is never left without its code.
#include <QDialog>
#include <QFileSystemWatcher>
#include <QObject>
#include <QStringList>
#include <QTimer>
#include <filesystem>
#include <map>
#include <memory>
#include <vector>

#include "salsa/core/plugins/plugin_host.hpp"

class QTreeWidget;
class QCheckBox;
class QLabel;

namespace salsa::gui {

class PluginManager : public QObject {
  Q_OBJECT
 public:
  /// `dirs`: the --plugin-dir folders (searched first, as by the CLI). `loaded`: a host already loaded
  /// from the same search path (nullptr: load now).
  explicit PluginManager(std::vector<std::filesystem::path> dirs, std::shared_ptr<const PluginHost> loaded = nullptr,
                         QObject* parent = nullptr);

  std::shared_ptr<const PluginHost> host() const { return host_; }
  /// Loads every folder again. A file that loaded before and is refused now (a build still writing it,
  /// a broken rebuild) keeps the old plugins in use: reload_failed says why, and the next change of the
  /// file tries again. Otherwise the new host is taken and plugins_changed names the rebuilt files.
  void rescan();
  /// Rescan by itself when a plugin folder or file changes (on by default). Changes are gathered for
  /// `quiet_ms` of quiet first, so a build that writes a file in several steps causes one rescan.
  void set_watching(bool on);
  bool watching() const { return watching_; }
  void set_quiet_ms(int ms) { debounce_.setInterval(ms); }
  std::size_t scans() const { return scans_; }

 Q_SIGNALS:
  /// A new host is in use. `rebuilt`: files (as found) that were loaded before and whose bytes changed.
  void plugins_changed(std::shared_ptr<const salsa::PluginHost> host, QStringList rebuilt);
  /// One line: which file could not be loaded again, why, and that the old code keeps running.
  void reload_failed(QString message);

 private:
  void arm();  ///< (re)watches every searched folder and plugin file (a replaced file is a new inode)
  std::vector<std::filesystem::path> dirs_;
  std::shared_ptr<const PluginHost> host_;
  std::map<std::string, QByteArray> hashes_;  ///< file → hash of its bytes when last loaded
  QFileSystemWatcher watcher_;
  QTimer debounce_;
  bool watching_ = true;
  std::size_t scans_ = 0;
};

/// The Plugins dialog: what loaded (kind, name, plugin, version, file), what was refused and why, the
/// folders searched; Rescan, and the automatic reload switch.
class PluginsDialog : public QDialog {
  Q_OBJECT
 public:
  explicit PluginsDialog(PluginManager& manager, QWidget* parent = nullptr);
  void refresh();
  QTreeWidget* tree() const { return tree_; }

 private:
  PluginManager& manager_;
  QTreeWidget* tree_ = nullptr;
  QCheckBox* watch_ = nullptr;
  QLabel* summary_ = nullptr;
};

}  // namespace salsa::gui
