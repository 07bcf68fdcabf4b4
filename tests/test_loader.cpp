// Loading plugins: the handshake, refusals with reasons that name the file, duplicates, registration
// failures, the search order, and object lifetime across the host's. Uses the test plugins built by
// tests/CMakeLists.txt, each in its own folder under test-plugins/.
#include <QtTest>

#include <filesystem>

#include "common.hpp"
#include "salsa/core/plugin_host.hpp"

using namespace salsa_test;
namespace fs = std::filesystem;

namespace {

fs::path plugin_folder(const char* name) { return test_plugins_dir() / name; }
fs::path plugin_file(const char* folder, const char* file) { return plugin_folder(folder) / file; }

/// The failure recorded for `file`, or nullptr.
const salsa::LoadFailure* failure_of(const salsa::PluginHost& host, const fs::path& file) {
  for (const auto& f : host.failures())
    if (fs::equivalent(f.file, file)) return &f;
  return nullptr;
}

bool has_behavior(const salsa::PluginHost& host, const std::string& name) {
  for (const auto& e : host.behaviors())
    if (e.factory.name == name) return true;
  return false;
}

/// Whether a shared library of that file name is mapped into this process.
bool is_mapped(const QString& file_name) {
  return read_file("/proc/self/maps").contains(("/" + file_name + "\n").toUtf8());
}

QString all_failures(const salsa::PluginHost& host) {
  QString out;
  for (const auto& f : host.failures()) out += q(f.file) + ": " + q(f.reason) + "\n";
  return out;
}

/// A folder holding copies of the bad test plugins (and the text file named like a library).
void fill_bad_folder(const QString& dir) {
  for (const auto& [folder, file] : std::vector<std::pair<const char*, const char*>>{
           {"abi99", "libtest_abi99.so"}, {"noentry", "libtest_noentry.so"}, {"notalib", "notalib.so"},
           {"registration-throws", "libtest_registration_throws.so"}})
    QVERIFY(QFile::copy(q(plugin_file(folder, file)), dir + "/" + file));
}

}  // namespace

class TestLoader : public QObject {
  Q_OBJECT

 private Q_SLOTS:
  void good_plugin_loads_and_decides() {
    salsa::PluginHost host;
    host.load({{plugin_folder("good"), "test"}});
    QVERIFY2(host.failures().empty(), qPrintable(all_failures(host)));
    QCOMPARE(host.plugins().size(), std::size_t(1));
    const salsa::PluginInfo& info = *host.plugins()[0];
    QCOMPARE(info.name, std::string("test_good"));
    QCOMPARE(info.version, std::string("1.2.3"));
    QCOMPARE(info.author, std::string("salsa tests"));
    QCOMPARE(info.brief, std::string("A good test plugin"));
    QVERIFY(fs::equivalent(info.file, plugin_file("good", "libtest_good.so")));

    const auto& entry = host.behavior("test_good");
    QCOMPARE(entry.factory.brief, std::string("Test behavior: steers (gain, id)"));
    QCOMPARE(entry.factory.parameters.size(), std::size_t(1));
    QCOMPARE(entry.factory.parameters[0].name, std::string("gain"));
    QCOMPARE(&entry.plugin(), &info);

    salsa::ParameterValues values(entry.factory.parameters);
    auto behavior = salsa::PluginHost::create(entry, values);
    salsa::Perception me;
    me.id = 7;
    salsa::Rng rng;
    QCOMPARE(behavior->decide(me, rng), salsa::Vec2(2, 7));  // the default gain
    values.set("gain", 5.5);
    auto tuned = salsa::PluginHost::create(entry, values);
    QCOMPARE(tuned->decide(me, rng), salsa::Vec2(5.5, 7));  // create() configures with the values given
    QCOMPARE(tuned->param("gain"), 5.5);

    // Unknown names list what exists.
    try {
      (void)host.behavior("nope");
      QFAIL("an unknown behavior must throw");
    } catch (const salsa::UnknownPlugin& e) {
      const QString what = e.what();
      QVERIFY2(what.contains("unknown behavior 'nope'") && what.contains("known: test_good, test_throws"), e.what());
    }
    try {
      (void)host.map("nowhere");
      QFAIL("an unknown map must throw");
    } catch (const salsa::UnknownPlugin& e) {
      QVERIFY2(QString(e.what()).contains("none loaded"), e.what());
    }
  }

  void plugin_exceptions_name_the_plugin() {
    salsa::PluginHost host;
    host.load({{plugin_folder("good"), "test"}});
    const auto& entry = host.behavior("test_throws");
    salsa::ParameterValues values(entry.factory.parameters);
    QVERIFY(salsa::PluginHost::create(entry, values));  // explode = 0: fine
    values.set("explode", 1);
    try {
      (void)salsa::PluginHost::create(entry, values);
      QFAIL("create() must pass the plugin's exception on");
    } catch (const std::runtime_error& e) {
      const QString what = e.what();
      QVERIFY2(what.contains("'test_throws'") && what.contains("libtest_good.so") && what.contains("exploded as asked"),
               e.what());
    }
  }

  void refusals_data() {
    QTest::addColumn<QString>("folder");
    QTest::addColumn<QString>("file");
    QTest::addColumn<QString>("reason");
    QTest::addColumn<QString>("never_registered");
    QTest::newRow("other ABI") << "abi99" << "libtest_abi99.so" << "built for salsa ABI 99, this is 1" << "test_abi99";
    QTest::newRow("text file") << "notalib" << "notalib.so" << "not a shared library" << "";
    QTest::newRow("no entry point") << "noentry" << "libtest_noentry.so" << "no entry point 'salsa_plugin_descriptor'" << "";
    QTest::newRow("registration throws") << "registration-throws" << "libtest_registration_throws.so"
                                         << "registration threw: declare() failed on purpose"
                                         << "test_registered_before_throw";
  }
  void refusals() {
    QFETCH(QString, folder);
    QFETCH(QString, file);
    QFETCH(QString, reason);
    QFETCH(QString, never_registered);
    const fs::path path = plugin_file(folder.toUtf8().constData(), file.toUtf8().constData());
    QVERIFY2(fs::exists(path), path.c_str());

    salsa::PluginHost host;
    QVERIFY(!host.load_file(path));
    QCOMPARE(host.failures().size(), std::size_t(1));
    QCOMPARE(host.failures()[0].file, path);
    QVERIFY2(q(host.failures()[0].reason).contains(reason), host.failures()[0].reason.c_str());
    QVERIFY(host.plugins().empty());
    QVERIFY(host.behaviors().empty());
    if (!never_registered.isEmpty()) QVERIFY(!has_behavior(host, never_registered.toStdString()));

    // The same through load(): the file is reported and skipped, nothing thrown.
    salsa::PluginHost by_folder;
    by_folder.load({{plugin_folder(folder.toUtf8().constData()), "test"}});
    QCOMPARE(by_folder.failures().size(), std::size_t(1));
    QVERIFY(q(by_folder.failures()[0].reason).contains(reason));
    QVERIFY(by_folder.behaviors().empty());
  }

  void duplicates_name_both_files() {
    const fs::path a = plugin_file("dup-a", "libtest_dup_a.so"), b = plugin_file("dup-b", "libtest_dup_b.so");
    salsa::PluginHost host;
    host.load({{plugin_folder("dup-a"), "test"}, {plugin_folder("dup-b"), "test"}});
    QCOMPARE(host.failures().size(), std::size_t(1));
    const salsa::LoadFailure* f = failure_of(host, b);
    QVERIFY2(f, qPrintable(all_failures(host)));
    const QString reason = q(f->reason);
    QVERIFY2(reason.contains("behavior 'test_dup' is already provided by " + q(a)), f->reason.c_str());
    // The first file wins; the second is refused whole.
    QCOMPARE(host.plugins().size(), std::size_t(1));
    QVERIFY(fs::equivalent(host.behavior("test_dup").plugin().file, a));
    QVERIFY(has_behavior(host, "test_dup_a_only"));
    QVERIFY(!has_behavior(host, "test_dup_b_only"));
    salsa::Rng rng;
    QCOMPARE(salsa::PluginHost::create(host.behavior("test_dup"), {})->decide({}, rng), salsa::Vec2(1, 0));
  }

  void good_plugins_still_load_after_failures() {
    QTemporaryDir bad;
    QVERIFY(bad.isValid());
    fill_bad_folder(bad.path());
    salsa::PluginHost host;
    host.load({{bad.path().toStdString(), "bad"},
               {plugin_folder("dup-a"), "test"},
               {plugin_folder("dup-b"), "test"},
               {plugin_folder("good"), "test"},
               {plugin_dir(), "build"}});
    QCOMPARE(host.failures().size(), std::size_t(5));  // 4 bad files + the duplicate
    QCOMPARE(host.searched().size(), std::size_t(5));
    QVERIFY(has_behavior(host, "test_good"));
    QVERIFY(has_behavior(host, "test_dup"));
    QVERIFY(has_behavior(host, "flocking"));
    auto behavior = salsa::PluginHost::create(host.behavior("test_good"), salsa::ParameterValues(host.behavior("test_good").factory.parameters));
    salsa::Rng rng;
    QCOMPARE(behavior->decide({}, rng), salsa::Vec2(2, 0));
  }

  void objects_outlive_the_host() {
    std::shared_ptr<salsa::Behavior> good, flocking;
    std::shared_ptr<salsa::MapGenerator> map;
    {
      salsa::PluginHost host;
      host.load({{plugin_folder("good"), "test"}, {plugin_dir(), "build"}});
      QVERIFY2(host.failures().empty(), qPrintable(all_failures(host)));
      good = salsa::PluginHost::create(host.behavior("test_good"), salsa::ParameterValues(host.behavior("test_good").factory.parameters));
      flocking = salsa::PluginHost::create(host.behavior("flocking"), salsa::ParameterValues(host.behavior("flocking").factory.parameters));
      map = salsa::PluginHost::create(host.map("forest"), salsa::ParameterValues(host.map("forest").factory.parameters));
      QVERIFY(is_mapped("libtest_good.so"));
    }  // the host and its registries are gone; the objects keep their libraries loaded
    QVERIFY(is_mapped("libtest_good.so"));
    QVERIFY(is_mapped("libflocking.so"));
    salsa::Perception me;
    me.id = 3;
    me.max_speed = 10;
    me.max_force = 0.3;
    salsa::Rng rng;
    QCOMPARE(good->decide(me, rng), salsa::Vec2(2, 3));
    QCOMPARE(good->param("gain"), 2.0);
    flocking->reset(5);
    QCOMPARE(flocking->decide(me, rng), salsa::Vec2());
    salsa::Rng map_rng(1, 0);
    QVERIFY(!map->generate("", map_rng).obstacles.empty());
    good.reset();  // the last reference: now the library is unloaded
    QVERIFY(!is_mapped("libtest_good.so"));
    flocking.reset();
    map.reset();
  }

  void search_order() {
    const QByteArray home = qgetenv("HOME");
    qputenv("SALSA_PLUGIN_PATH", "/tmp/salsa-env-a::/tmp/salsa-env-b");
    qputenv("HOME", "/tmp/salsa-home");
    const auto dirs = salsa::PluginHost::default_search_path({"/tmp/first", "/tmp/second"});
    qunsetenv("SALSA_PLUGIN_PATH");
    qputenv("HOME", home);
    QVERIFY(dirs.size() >= 5);
    QCOMPARE(dirs[0].path, fs::path("/tmp/first"));
    QCOMPARE(dirs[0].origin, std::string("--plugin-dir"));
    QCOMPARE(dirs[1].path, fs::path("/tmp/second"));
    QCOMPARE(dirs[2].path, fs::path("/tmp/salsa-env-a"));
    QCOMPARE(dirs[2].origin, std::string("SALSA_PLUGIN_PATH"));
    QCOMPARE(dirs[3].path, fs::path("/tmp/salsa-env-b"));  // empty entries are skipped
    QCOMPARE(dirs[4].path, fs::path("/tmp/salsa-home/.local/share/salsa/plugins"));
    QCOMPARE(dirs[4].origin, std::string("user"));
    // Run from the build tree: its plugin folder comes last.
    QVERIFY(dirs.size() == 6);
    QCOMPARE(dirs[5].origin, std::string("build tree"));
    QVERIFY(fs::equivalent(dirs[5].path, plugin_dir()));
  }

  void cli_plugins_lists_refusals() {
    QTemporaryDir bad;
    QVERIFY(bad.isValid());
    fill_bad_folder(bad.path());
    const CliResult r = run_salsa({"plugins", "--plugin-dir", bad.path()});
    QVERIFY2(!r.crashed && r.exit_code == 0, describe(r));
    const QStringList lines = r.out.split('\n');
    // Search order: --plugin-dir first.
    const qsizetype header = lines.indexOf("Folders searched, in order:");
    QVERIFY2(header >= 0, describe(r));
    QVERIFY2(lines[header + 1].contains("--plugin-dir") && lines[header + 1].contains(bad.path()), describe(r));
    QVERIFY2(r.out.indexOf("user") > r.out.indexOf("--plugin-dir"), describe(r));
    // The built-in plugins are still listed.
    for (const char* name : {"flocking", "pheromone_avoidance", "dynamic_space_partitioning", "random_walk", "tree",
                             "forest", "empty", "json", "detect_targets"})
      QVERIFY2(r.out.contains(QString(" %1 ").arg(name)), qPrintable(QString("%1 missing\n").arg(name) + describe(r)));
    // Every refused file on a line of its own, with its reason.
    const qsizetype refused = lines.indexOf("Refused:");
    QVERIFY2(refused > header, describe(r));
    auto line_of = [&](const QString& file) {
      for (qsizetype i = refused + 1; i < lines.size(); ++i)
        if (lines[i].contains(bad.path() + "/" + file)) return lines[i];
      return QString();
    };
    QVERIFY2(line_of("libtest_abi99.so").contains("built for salsa ABI 99, this is 1"), describe(r));
    QVERIFY2(line_of("notalib.so").contains("not a shared library"), describe(r));
    QVERIFY2(line_of("libtest_noentry.so").contains("no entry point"), describe(r));
    QVERIFY2(line_of("libtest_registration_throws.so").contains("registration threw"), describe(r));
  }

  void cli_plugins_duplicate_names_both_files() {
    const CliResult r =
        run_salsa({"plugins", "--plugin-dir", q(plugin_folder("dup-a")), "--plugin-dir", q(plugin_folder("dup-b"))});
    QVERIFY2(!r.crashed && r.exit_code == 0, describe(r));
    const QStringList lines = r.out.split('\n');
    const qsizetype header = lines.indexOf("Folders searched, in order:");
    QVERIFY2(header >= 0 && lines[header + 1].contains(q(plugin_folder("dup-a"))) &&
                 lines[header + 2].contains(q(plugin_folder("dup-b"))),
             describe(r));  // in the order given
    bool found = false;
    for (const QString& line : lines)
      found = found || (line.contains(q(plugin_file("dup-b", "libtest_dup_b.so"))) &&
                        line.contains("is already provided by " + q(plugin_file("dup-a", "libtest_dup_a.so"))));
    QVERIFY2(found, describe(r));
  }

  void cli_describe_shows_parameters() {
    const CliResult r = run_salsa({"describe", "flocking"});
    QVERIFY2(!r.crashed && r.exit_code == 0, describe(r));
    for (const char* p : {"separation_distance", "alignment_weight", "cohesion_weight", "separation_weight",
                          "obstacle_avoidance_weight"})
      QVERIFY2(r.out.contains(p), describe(r));
    const CliResult unknown = run_salsa({"describe", "no_such_plugin"});
    QVERIFY2(unknown.exit_code != 0 && unknown.err.contains("no_such_plugin"), describe(unknown));
  }
};

QTEST_GUILESS_MAIN(TestLoader)
#include "test_loader.moc"
