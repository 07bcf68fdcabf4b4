// Plugins in the desktop: a plugin copied into a folder while the GUI runs is found by a rescan (and by
// itself), and a behavior rebuilt while it runs is reloaded: the simulation goes on where it was with
// the new code. A broken rebuild leaves the old code running and says why. (tests/CMakeLists.txt builds
// tests/plugins/reload.cpp twice: version 1 flies along +x, version 2 along -x.)
#include "common.hpp"

#include <QSettings>
#include <QTreeWidget>
#include <algorithm>

#include "main_window.hpp"
#include "param_panel.hpp"
#include "plugins.hpp"

using namespace salsa;
using namespace salsa::gui;
using namespace salsa_test;

namespace {

QString built(const char* folder) {
  const QDir dir(q(test_plugins_dir() / folder));
  const QStringList libs = dir.entryList({"*.so"}, QDir::Files);
  return libs.size() == 1 ? dir.filePath(libs.front()) : QString();
}

/// Overwrites `to` in place (same inode: truncated, then written), as a build writing its output does.
bool overwrite(const QString& to, const QByteArray& bytes) {
  QFile f(to);
  if (!f.open(QIODevice::WriteOnly | QIODevice::Truncate)) return false;
  return f.write(bytes) == bytes.size();
}

bool has_behavior(const PluginHost& host, const std::string& name) {
  const auto& b = host.behaviors();
  return std::any_of(b.begin(), b.end(), [&](const auto& e) { return e.factory.name == name; });
}

}  // namespace

class GuiPlugins : public QObject {
  Q_OBJECT
  QTemporaryDir folder_;

  std::unique_ptr<MainWindow> window_with(const QString& dir) {
    auto host = std::make_shared<PluginHost>();
    host->load(PluginHost::default_search_path({dir.toStdString()}));
    auto w = std::make_unique<MainWindow>(host, std::vector<std::filesystem::path>{dir.toStdString()});
    w->plugins()->set_quiet_ms(200);
    w->resize(1200, 800);
    w->show();
    return w;
  }

  // decision_lag 0: the behaviors' "velocity change = wanted - current" lands in the same step (with
  // the default lag it overshoots and oscillates), so every velocity shows which version runs.
  static TestSpec reload_test(const PluginHost& host) {
    return parse_test(R"({"name": "reload", "behavior": "test_reload", "drones": 3, "map": {"name": "empty", "params": {"size": 300}},
                          "time": 60, "seed": 4, "decision_lag": 0})",
                      "test", host);
  }

  static void steps(MainWindow& w, int n) {
    for (int i = 0; i < n; ++i) QVERIFY(w.sandbox()->engine().step_once().get().empty());
  }

 private Q_SLOTS:
  void init() { QSettings().clear(); }

  void rescan_finds_a_plugin_copied_in() {
    QTemporaryDir dir;
    PluginManager manager({dir.path().toStdString()});
    manager.set_quiet_ms(100);
    QVERIFY(!has_behavior(*manager.host(), "test_straight"));
    QSignalSpy changed(&manager, &PluginManager::plugins_changed);
    // By hand: Rescan.
    QVERIFY(QFile::copy(built("metric"), dir.filePath("metric.so")));
    manager.rescan();
    QCOMPARE(changed.count(), 1);
    QVERIFY(has_behavior(*manager.host(), "test_straight"));
    // By itself: the folder is watched.
    QVERIFY(QFile::copy(built("good"), dir.filePath("good.so")));
    QTRY_VERIFY_WITH_TIMEOUT(has_behavior(*manager.host(), "test_good"), 15000);
    QVERIFY(has_behavior(*manager.host(), "test_straight"));
    // The dialog lists what loaded and what was refused, with the files.
    QVERIFY(QFile::copy(built("abi99"), dir.filePath("abi99.so")));
    manager.rescan();
    PluginsDialog dialog(manager);
    const auto found = [&](const QString& text, int column) { return !dialog.tree()->findItems(text, Qt::MatchContains | Qt::MatchRecursive, column).isEmpty(); };
    QVERIFY(found("test_good", 0));
    QVERIFY(found(dir.filePath("good.so"), 3));
    QVERIFY(found(dir.filePath("abi99.so"), 3));
    QVERIFY(found("ABI", 1));  // the refusal says why
  }

  void a_rebuilt_behavior_is_reloaded_where_it_runs() {
    const QString file = folder_.filePath("reload.so");
    QFile::remove(file);
    QVERIFY(QFile::copy(built("reload-v1"), file));
    auto w = window_with(folder_.path());
    QVERIFY(w->sandbox()->open_test_spec(reload_test(*w->host())).empty());
    steps(*w, 60);
    auto before = w->sandbox()->engine().snapshot();
    for (const Vec2& v : before->velocities) QVERIFY2(v.x > 1, qPrintable(QString("version 1 flies along +x: %1 %2 t=%3").arg(v.x).arg(v.y).arg(before->time)));
    QVERIFY(!w->sandbox()->behavior_panel()->schema().empty());
    QVERIFY(w->sandbox()->behavior_panel()->schema().size() == 1);

    // "Rebuild": version 2 written over the file while the window runs.
    QVERIFY(overwrite(file, read_file(built("reload-v2"))));
    QTRY_VERIFY_WITH_TIMEOUT(w->status_text().contains("reloaded behavior 'test_reload'"), 20000);
    w->sandbox()->engine().sync();
    auto after = w->sandbox()->engine().snapshot();
    QCOMPARE(after->time, before->time);  // nothing restarted
    QCOMPARE(after->positions.size(), before->positions.size());
    for (std::size_t i = 0; i < before->positions.size(); ++i) {
      QCOMPARE(after->positions[i].x, before->positions[i].x);
      QCOMPARE(after->velocities[i].x, before->velocities[i].x);
    }
    steps(*w, 120);
    for (const Vec2& v : w->sandbox()->engine().snapshot()->velocities) QVERIFY2(v.x < -1, "version 2 flies along -x");
    // The new code's parameters and memory are shown; the session can no longer be saved as one test.
    QCOMPARE(w->sandbox()->behavior_panel()->schema().size(), std::size_t{2});
    QCOMPARE(w->sandbox()->behavior_panel()->value("added_in_v2"), 3.0);
    w->sandbox()->engine().select(0);
    w->sandbox()->engine().sync();
    QTRY_VERIFY(w->sandbox()->engine().snapshot()->selected && w->sandbox()->engine().snapshot()->selected->memory == "test_reload version 2");
    std::string why;
    QVERIFY(!w->sandbox()->engine().as_test(&why));
    QVERIFY(QString::fromStdString(why).contains("reloaded"));
  }

  // With groups, every group running the rebuilt behavior goes on with the new code; the others are untouched.
  void every_group_running_a_rebuilt_behavior_reloads() {
    const QString file = folder_.filePath("reload.so");
    QFile::remove(file);
    QVERIFY(QFile::copy(built("reload-v1"), file));
    auto w = window_with(folder_.path());
    const TestSpec t = parse_test(R"({"name": "reload", "groups": [
        {"name": "a", "behavior": "test_reload", "drones": 2, "spawn": {"point": [40, 60]}},
        {"name": "b", "behavior": "random_walk", "drones": 2, "spawn": {"point": [150, 250]}},
        {"name": "c", "behavior": "test_reload", "drones": 2, "spawn": {"point": [40, 140]}}],
      "map": {"name": "empty", "params": {"size": 300}}, "time": 60, "seed": 4, "decision_lag": 0})", "test", *w->host());
    QVERIFY(w->sandbox()->open_test_spec(t).empty());
    steps(*w, 60);
    QVERIFY(overwrite(file, read_file(built("reload-v2"))));
    QTRY_VERIFY_WITH_TIMEOUT(w->status_text().contains("reloaded behavior 'test_reload'"), 20000);
    steps(*w, 120);
    const auto snap = w->sandbox()->engine().snapshot();
    for (std::uint32_t id : {0u, 1u, 4u, 5u}) QVERIFY2(snap->velocities[id].x < -1, qPrintable(QString("drone %1 runs version 2").arg(id)));
    const TestSpec now = *w->sandbox()->engine().current_test();
    QVERIFY(now.groups[0].behavior.params.has("added_in_v2"));
    QVERIFY(now.groups[2].behavior.params.has("added_in_v2"));
    QCOMPARE(now.groups[1].behavior.name, std::string("random_walk"));
    w->sandbox()->engine().select(4);
    w->sandbox()->engine().sync();
    QTRY_VERIFY(w->sandbox()->engine().snapshot()->selected && w->sandbox()->engine().snapshot()->selected->memory == "test_reload version 2");
  }

  void a_broken_rebuild_keeps_the_old_code_running() {
    const QString file = folder_.filePath("reload.so");
    QFile::remove(file);
    QVERIFY(QFile::copy(built("reload-v1"), file));
    auto w = window_with(folder_.path());
    QVERIFY(w->sandbox()->open_test_spec(reload_test(*w->host())).empty());
    steps(*w, 30);
    // Half a library (a build cut short): refused, and version 1 goes on.
    const QByteArray v2 = read_file(built("reload-v2"));
    QVERIFY(overwrite(file, v2.left(v2.size() / 2)));
    QTRY_VERIFY_WITH_TIMEOUT(w->status_text().contains("could not be reloaded"), 20000);
    QVERIFY(w->status_text().contains(file));
    QVERIFY(w->status_text().contains("old code keeps running"));
    steps(*w, 30);
    for (const Vec2& v : w->sandbox()->engine().snapshot()->velocities) QVERIFY(v.x > 1);
    QVERIFY(has_behavior(*w->host(), "test_reload"));
    // The build finishes: now it is reloaded.
    QVERIFY(overwrite(file, v2));
    QTRY_VERIFY_WITH_TIMEOUT(w->status_text().contains("reloaded behavior 'test_reload'"), 20000);
    steps(*w, 120);
    for (const Vec2& v : w->sandbox()->engine().snapshot()->velocities) QVERIFY(v.x < -1);
  }
};

QTEST_MAIN(GuiPlugins)
#include "gui_plugins.moc"
