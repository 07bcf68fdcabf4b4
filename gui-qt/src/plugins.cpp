#include "plugins.hpp"

#include <QCheckBox>
#include <QCryptographicHash>
#include <QDialogButtonBox>
#include <QFile>
#include <QHeaderView>
#include <QLabel>
#include <QPushButton>
#include <QTreeWidget>
#include <QVBoxLayout>

namespace salsa::gui {

namespace {

QString q(const std::string& s) { return QString::fromStdString(s); }

QByteArray hash_of(const std::filesystem::path& file) {
  QFile f(q(file.string()));
  if (!f.open(QIODevice::ReadOnly)) return {};
  QCryptographicHash h(QCryptographicHash::Sha256);
  h.addData(&f);
  return h.result();
}

}  // namespace

PluginManager::PluginManager(std::vector<std::filesystem::path> dirs, std::shared_ptr<const PluginHost> loaded, QObject* parent)
    : QObject(parent), dirs_(std::move(dirs)), host_(std::move(loaded)) {
  debounce_.setSingleShot(true);
  debounce_.setInterval(400);
  connect(&debounce_, &QTimer::timeout, this, &PluginManager::rescan);
  auto changed = [this] {
    if (watching_) debounce_.start();
  };
  connect(&watcher_, &QFileSystemWatcher::directoryChanged, this, changed);
  connect(&watcher_, &QFileSystemWatcher::fileChanged, this, changed);
  if (!host_) {
    auto h = std::make_shared<PluginHost>();
    h->load(PluginHost::default_search_path(dirs_));
    host_ = std::move(h);
  }
  for (const auto* p : host_->plugins()) hashes_[p->file.string()] = hash_of(p->file);
  arm();
}

void PluginManager::rescan() {
  ++scans_;
  auto next = std::make_shared<PluginHost>();
  next->load(PluginHost::default_search_path(dirs_));
  for (const auto& f : next->failures())
    if (f.registration.empty() && hashes_.count(f.file.string())) {
      arm();
      Q_EMIT reload_failed(q(f.file.string() + " could not be reloaded: " + f.reason + " (the old code keeps running)"));
      return;
    }
  std::map<std::string, QByteArray> hashes;
  QStringList rebuilt;
  for (const auto* p : next->plugins()) {
    const std::string file = p->file.string();
    hashes[file] = hash_of(p->file);
    if (auto it = hashes_.find(file); it != hashes_.end() && it->second != hashes[file]) rebuilt << q(file);
  }
  host_ = std::move(next);
  hashes_ = std::move(hashes);
  arm();
  Q_EMIT plugins_changed(host_, rebuilt);
}

void PluginManager::set_watching(bool on) {
  watching_ = on;
  if (!on) debounce_.stop();
}

void PluginManager::arm() {
  if (!watcher_.files().isEmpty()) watcher_.removePaths(watcher_.files());
  if (!watcher_.directories().isEmpty()) watcher_.removePaths(watcher_.directories());
  QStringList paths;
  for (const auto& d : host_->searched()) {
    std::error_code ec;
    if (std::filesystem::is_directory(d.path, ec)) paths << q(d.path.string());
  }
  for (const auto* p : host_->plugins()) paths << q(p->file.string());
  for (const auto& f : host_->failures()) paths << q(f.file.string());
  paths.removeDuplicates();
  if (!paths.isEmpty()) watcher_.addPaths(paths);  // a path that vanished meanwhile is skipped
}

// ---------------------------------------------------------------- the dialog

PluginsDialog::PluginsDialog(PluginManager& manager, QWidget* parent) : QDialog(parent), manager_(manager) {
  setWindowTitle("Plugins");
  resize(1150, 560);
  auto* layout = new QVBoxLayout(this);
  summary_ = new QLabel(this);
  summary_->setWordWrap(true);
  layout->addWidget(summary_);
  tree_ = new QTreeWidget(this);
  tree_->setColumnCount(4);
  tree_->setHeaderLabels({"Name", "Kind / why", "Plugin", "File"});
  tree_->header()->setSectionResizeMode(QHeaderView::ResizeToContents);
  tree_->setAlternatingRowColors(true);
  layout->addWidget(tree_, 1);
  watch_ = new QCheckBox("Reload rebuilt plugins automatically (the running behavior switches to the new code)", this);
  watch_->setChecked(manager_.watching());
  connect(watch_, &QCheckBox::toggled, this, [this](bool on) { manager_.set_watching(on); });
  layout->addWidget(watch_);
  auto* buttons = new QDialogButtonBox(QDialogButtonBox::Close, this);
  auto* rescan = buttons->addButton("Rescan", QDialogButtonBox::ActionRole);
  connect(rescan, &QPushButton::clicked, this, [this] { manager_.rescan(); });
  connect(buttons, &QDialogButtonBox::rejected, this, &QDialog::reject);
  layout->addWidget(buttons);
  connect(&manager_, &PluginManager::plugins_changed, this, &PluginsDialog::refresh);
  connect(&manager_, &PluginManager::reload_failed, this, [this](const QString& why) {
    refresh();
    summary_->setText(summary_->text() + "\n" + why);
  });
  refresh();
}

void PluginsDialog::refresh() {
  const auto host = manager_.host();
  tree_->clear();
  auto* loaded = new QTreeWidgetItem(tree_, {"Loaded"});
  std::size_t count = 0;
  auto add = [&](const auto& registry, const char* kind) {
    for (const auto& e : registry) {
      const auto& p = e.plugin();
      new QTreeWidgetItem(loaded, {q(e.factory.name), kind, q(p.name + " " + p.version), q(p.file.string())});
      ++count;
    }
  };
  add(host->behaviors(), "behavior");
  add(host->target_kinds(), "target");
  add(host->maps(), "map");
  add(host->contact_handlers(), "contact handler");
  add(host->metrics(), "metric");
  add(host->winds(), "wind");
  auto* refused = new QTreeWidgetItem(tree_, {"Refused"});
  for (const auto& f : host->failures())
    new QTreeWidgetItem(refused, {q(f.registration.empty() ? f.file.filename().string() : f.registration), q(f.reason), "",
                                  q(f.file.string())});
  auto* searched = new QTreeWidgetItem(tree_, {"Folders searched"});
  for (const auto& d : host->searched()) new QTreeWidgetItem(searched, {q(d.origin), "", "", q(d.path.string())});
  tree_->expandAll();
  summary_->setText(QString("%1 registrations from %2 files; %3 refused. Drop a compiled plugin into a folder below "
                            "and press Rescan; a rebuilt behavior is reloaded by itself.")
                        .arg(count)
                        .arg(host->plugins().size())
                        .arg(host->failures().size()));
}

}  // namespace salsa::gui
