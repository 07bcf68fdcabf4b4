// Loading plugins: the handshake, refusals with reasons that name the file, truncated and damaged
// files, folder entries that are not files, private snapshots, names decided per registration,
// declarations, exceptions of any type, the search order, and object lifetime across the host's.
// Uses the test plugins built by tests/CMakeLists.txt, each in its own folder under test-plugins/.
#include <QCryptographicHash>
#include <QtTest>

#include <elf.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <cstring>
#include <filesystem>
#include <functional>
#include <random>
#include <tuple>

#include <nlohmann/json.hpp>

#include "common.hpp"
#include "salsa/core/plugins/plugin_host.hpp"

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

/// Whether a shared library of that file name is mapped into this process (from its private copy,
/// removed once mapped, hence " (deleted)").
bool is_mapped(const QString& file_name) {
  const QByteArray maps = read_file("/proc/self/maps");
  return maps.contains(("/" + file_name + "\n").toUtf8()) || maps.contains(("/" + file_name + " (deleted)\n").toUtf8());
}

/// The failures recorded for `file`, one reason per line.
QString failures_of(const salsa::PluginHost& host, const fs::path& file) {
  QString out;
  for (const auto& f : host.failures())
    if (f.file == file) out += q(f.reason) + "\n";
  return out;
}

/// Sets an environment variable for one scope.
struct ScopedEnv {
  QByteArray name, old;
  bool had;
  ScopedEnv(const char* n, const QByteArray& value) : name(n), old(qgetenv(n)), had(qEnvironmentVariableIsSet(n)) {
    qputenv(n, value);
  }
  ~ScopedEnv() {
    if (had) qputenv(name.constData(), old);
    else qunsetenv(name.constData());
  }
};

QStringList entries(const QString& dir) { return QDir(dir).entryList(QDir::AllEntries | QDir::Hidden | QDir::NoDotAndDotDot | QDir::System); }

QString all_failures(const salsa::PluginHost& host) {
  QString out;
  for (const auto& f : host.failures()) out += q(f.file) + ": " + q(f.reason) + "\n";
  return out;
}

/// A folder holding copies of the bad test plugins (and the text file named like a library).
void fill_bad_folder(const QString& dir) {
  for (const auto& [folder, file] : std::vector<std::pair<const char*, const char*>>{
           {"abi99", "libtest_abi99.so"}, {"noentry", "libtest_noentry.so"}, {"notalib", "notalib.so"},
           {"registration-throws", "libtest_registration_throws.so"}, {"static-init", "libtest_static_init.so"}})
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

  void plugin_exceptions_name_the_plugin_data() {
    QTest::addColumn<double>("explode");
    QTest::addColumn<QString>("said");
    QTest::newRow("std::runtime_error") << 1.0 << "exploded as asked";
    QTest::newRow("std::bad_alloc") << 2.0 << "out of memory (std::bad_alloc)";
    QTest::newRow("int") << 3.0 << "an exception of type int (not a std::exception)";
  }
  void plugin_exceptions_name_the_plugin() {
    QFETCH(double, explode);
    QFETCH(QString, said);
    salsa::PluginHost host;
    host.load({{plugin_folder("good"), "test"}});
    const auto& entry = host.behavior("test_throws");
    salsa::ParameterValues values(entry.factory.parameters);
    QVERIFY(salsa::PluginHost::create(entry, values));  // explode = 0: fine
    values.set("explode", explode);
    try {
      (void)salsa::PluginHost::create(entry, values);
      QFAIL("create() must pass the plugin's exception on");
    } catch (const std::runtime_error& e) {
      const QString what = e.what();
      QVERIFY2(what.contains("'test_throws'") && what.contains(q(plugin_file("good", "libtest_good.so"))) &&
                   what.contains(said) && !what.contains('\n'),
               e.what());
    }
  }

  void refusals_data() {
    QTest::addColumn<QString>("folder");
    QTest::addColumn<QString>("file");
    QTest::addColumn<QString>("reason");
    QTest::addColumn<QString>("never_registered");
    QTest::newRow("other ABI") << "abi99" << "libtest_abi99.so" << "built for salsa ABI 99, this is 11" << "test_abi99";
    QTest::newRow("text file") << "notalib" << "notalib.so" << "not a shared library" << "";
    QTest::newRow("no entry point") << "noentry" << "libtest_noentry.so" << "no entry point 'salsa_plugin_descriptor'" << "";
    // dlopen's own words, about the original file (not the private copy that was loaded).
    QTest::newRow("undefined symbol") << "undefined-symbol" << "libtest_undefined_symbol.so"
                                      << "cannot be loaded: undefined symbol: salsa_test_missing_function" << "";
    QTest::newRow("registration throws") << "registration-throws" << "libtest_registration_throws.so"
                                         << "registration threw: declare() failed on purpose"
                                         << "test_registered_before_throw";
    QTest::newRow("registration throws std::bad_alloc")
        << "registration-bad-alloc" << "libtest_registration_bad_alloc.so"
        << "registration threw: out of memory (std::bad_alloc)" << "test_registered_before_throw";
    QTest::newRow("registration throws an int")
        << "registration-throws-int" << "libtest_registration_throws_int.so"
        << "registration threw: an exception of type int (not a std::exception)" << "test_registered_before_throw";
    // Thrown inside dlopen, before the entry point: this file alone is refused (it once ended salsa).
    QTest::newRow("static initialiser throws")
        << "static-init" << "libtest_static_init.so"
        << "its static initialiser threw while the file was loaded: static init exploded" << "test_static_init";
    QTest::newRow("static initialiser calls exit")
        << "static-init-exit" << "libtest_static_init_exit.so"
        << "its static initialiser called exit(3) while the file was loaded" << "test_static_init";
    QTest::newRow("static initialiser aborts")
        << "static-init-abort" << "libtest_static_init_abort.so"
        << "its static initialiser crashed (SIGABRT) while the file was loaded" << "test_static_init";
    QTest::newRow("old C++ ABI") << "old-cxx-abi" << "libtest_old_cxx_abi.so"
                                 << "incompatible C++ standard library: built with the old C++ ABI "
                                    "(_GLIBCXX_USE_CXX11_ABI=0), this salsa uses the new one; std::string is 8 "
                                    "bytes there, 32 here"
                                 << "test_old_cxx_abi";
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
    QVERIFY2(!q(host.failures()[0].reason).contains("salsa-plugin-"), host.failures()[0].reason.c_str());
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

  // One child process probes a folder's static initialisers in turn; a file that throws, exits or
  // crashes there is refused alone, and the files after it (also two bad ones in a row) are still
  // probed and loaded.
  void a_folders_static_initialisers_fail_each_alone() {
    QTemporaryDir dir;
    QVERIFY(dir.isValid());
    const std::vector<std::tuple<const char*, const char*, const char*>> files{
        {"good", "libtest_good.so", "a_good.so"},
        {"static-init", "libtest_static_init.so", "b_throws.so"},
        {"dup-a", "libtest_dup_a.so", "c_good.so"},
        {"static-init-exit", "libtest_static_init_exit.so", "d_exits.so"},
        {"static-init-abort", "libtest_static_init_abort.so", "e_aborts.so"},
        {"metric", "libtest_metric.so", "f_good.so"}};
    for (const auto& [folder, file, as] : files) QVERIFY(QFile::copy(q(plugin_file(folder, file)), dir.filePath(as)));
    salsa::PluginHost host;
    host.load({{dir.path().toStdString(), "test"}});
    QCOMPARE(host.failures().size(), std::size_t(3));
    const std::vector<std::pair<const char*, const char*>> refused{
        {"b_throws.so", "its static initialiser threw while the file was loaded: static init exploded"},
        {"d_exits.so", "its static initialiser called exit(3) while the file was loaded"},
        {"e_aborts.so", "its static initialiser crashed (SIGABRT) while the file was loaded"}};
    for (std::size_t i = 0; i < refused.size(); ++i) {
      QCOMPARE(host.failures()[i].file.filename().string(), std::string(refused[i].first));
      QCOMPARE(host.failures()[i].reason, std::string(refused[i].second));
    }
    QCOMPARE(host.plugins().size(), std::size_t(3));
    for (std::size_t i = 0; i < 3; ++i)
      QCOMPARE(host.plugins()[i]->file.filename().string(), std::string(std::array{"a_good.so", "c_good.so", "f_good.so"}[i]));
  }

  void duplicates_name_both_files() {
    const fs::path a = plugin_file("dup-a", "libtest_dup_a.so"), b = plugin_file("dup-b", "libtest_dup_b.so");
    salsa::PluginHost host;
    host.load({{plugin_folder("dup-a"), "test"}, {plugin_folder("dup-b"), "test"}});
    QCOMPARE(host.failures().size(), std::size_t(1));
    const salsa::LoadFailure* f = failure_of(host, b);
    QVERIFY2(f, qPrintable(all_failures(host)));
    QCOMPARE(f->reason, "behavior 'test_dup' not registered: the name is taken by " + a.string() +
                            " (the file found first wins)");
    QCOMPARE(f->registration, std::string("behavior 'test_dup'"));
    // The first file wins that name; the second file's other registrations stay.
    QCOMPARE(host.plugins().size(), std::size_t(2));
    QVERIFY(fs::equivalent(host.behavior("test_dup").plugin().file, a));
    QVERIFY(has_behavior(host, "test_dup_a_only"));
    QVERIFY(fs::equivalent(host.behavior("test_dup_b_only").plugin().file, b));
    salsa::Rng rng;
    QCOMPARE(salsa::PluginHost::create(host.behavior("test_dup"), {})->decide({}, rng), salsa::Vec2(1, 0));
    QCOMPARE(salsa::PluginHost::create(host.behavior("test_dup_b_only"), {})->decide({}, rng), salsa::Vec2(2, 0));
  }

  // A third-party map named like a built-in: the built-in library keeps its other maps.
  void shadowing_is_decided_per_registration() {
    const fs::path shadow = plugin_file("shadow", "libtest_shadow.so"), builtin = plugin_dir() / "libbasic_maps.so";
    {
      salsa::PluginHost host;  // the third-party folder first (a --plugin-dir): its "forest" wins
      host.load({{plugin_folder("shadow"), "--plugin-dir"}, {plugin_dir(), "build"}});
      QCOMPARE(host.failures().size(), std::size_t(1));
      QCOMPARE(host.failures()[0].file, builtin);
      QCOMPARE(host.failures()[0].registration, std::string("map 'forest'"));
      QCOMPARE(host.failures()[0].reason, "map 'forest' not registered: the name is taken by " + shadow.string() +
                                              " (the file found first wins)");
      QCOMPARE(host.map("forest").plugin().file, shadow);
      QCOMPARE(host.map("empty").plugin().file, builtin);  // the rest of the built-in library stays
      QVERIFY(host.map("test_shadow_only").factory.create);
      QVERIFY(has_behavior(host, "flocking"));
      salsa::Rng rng(1, 0);
      const auto map = salsa::PluginHost::create(host.map("forest"), salsa::ParameterValues(host.map("forest").factory.parameters));
      QCOMPARE(map->generate("", rng).bounds.max, salsa::Vec2(50, 50));
    }
    {
      salsa::PluginHost host;  // the other way round: the built-in wins, the third party keeps its own map
      host.load({{plugin_dir(), "build"}, {plugin_folder("shadow"), "test"}});
      QCOMPARE(host.failures().size(), std::size_t(1));
      QCOMPARE(host.failures()[0].file, shadow);
      QVERIFY(q(host.failures()[0].reason).contains("the name is taken by " + q(builtin)));
      QCOMPARE(host.map("forest").plugin().file, builtin);
      QCOMPARE(host.map("test_shadow_only").plugin().file, shadow);
    }
    // The CLI: a warning names both files, and a test without a map still runs on the built-in "empty".
    QTemporaryDir dir;
    QVERIFY(dir.isValid());
    QVERIFY(write_file(dir.path() + "/test.json", R"({"behavior": "random_walk", "drones": 2, "time": 0.5})"));
    const CliResult r = run_salsa({"run", "test.json", "--out", "out", "--plugin-dir", q(plugin_folder("shadow"))}, dir.path());
    QVERIFY2(!r.crashed && r.exit_code == 0, describe(r));
    QCOMPARE(non_empty_lines(r.err).size(), 1);
    QVERIFY2(r.err.contains(q(builtin)) && r.err.contains("map 'forest'") && r.err.contains(q(shadow)), describe(r));
    QVERIFY(QFile::exists(dir.path() + "/out/test/summary.csv"));
  }

  // A folder on the search path twice ($SALSA_PLUGIN_PATH naming the install folder, say) is no clash.
  void same_folder_twice_loads_once() {
    salsa::PluginHost host;
    host.load({{plugin_folder("good"), "--plugin-dir"}, {plugin_folder("good"), "SALSA_PLUGIN_PATH"}});
    QVERIFY2(host.failures().empty(), qPrintable(all_failures(host)));
    QCOMPARE(host.plugins().size(), std::size_t(1));
    QCOMPARE(host.searched().size(), std::size_t(2));
  }

  void same_name_twice_in_one_file() {
    const fs::path file = plugin_file("twice", "libtest_twice.so");
    salsa::PluginHost host;
    host.load({{plugin_folder("twice"), "test"}});
    QCOMPARE(failures_of(host, file),
             QString("behavior 'test_twice' not registered: registered twice in this file (the first registration is kept)\n"));
    QCOMPARE(host.behaviors().size(), std::size_t(2));
    salsa::Rng rng;
    QCOMPARE(salsa::PluginHost::create(host.behavior("test_twice"), {})->decide({}, rng), salsa::Vec2(1, 0));
    QVERIFY(has_behavior(host, "test_once"));
  }

  // Declarations are validated like a user's JSON, per registration.
  void bad_declarations_are_refused_per_registration() {
    const fs::path file = plugin_file("bad-declarations", "libtest_bad_declarations.so");
    salsa::PluginHost host;
    QVERIFY(host.load_file(file));
    const QString all = failures_of(host, file);
    const QString rule = "not a valid name: a name starts with a letter and uses only letters, digits, '_' and '-', 1 to 64 characters";
    for (const QString& line : {
             QString("behavior 'test_decl_min_above_max' not registered: parameter 'gain': min 10 is greater than max 0"),
             QString("behavior 'test_decl_default_outside' not registered: parameter 'gain': default 12 is outside [0, 10]"),
             QString("behavior 'test_decl_nan' not registered: parameter 'gain': default nan is not a finite number"),
             QString("behavior 'test_decl_inf' not registered: parameter 'gain': max inf is not a finite number"),
             "behavior 'test_decl_empty_name' not registered: parameter \"\": " + rule,
             QString("behavior 'test_decl_duplicate' not registered: parameter 'gain': declared twice"),
             QString("behavior 'test_decl_fraction' not registered: parameter 'count': default 2.5 is not a whole number (step 1)"),
             "behavior 'test_decl_bad_name' not registered: parameter \"two words\": " + rule,
             QString("behavior 'test_decl_negative_step' not registered: parameter 'gain': step -1 is negative"),
             "behavior \"\" not registered: " + rule, "behavior \"../escape\" not registered: " + rule})
      QVERIFY2(all.contains(line + "\n"), qPrintable(line + "\nnot in\n" + all));
    QCOMPARE(all.count('\n'), 11);
    QCOMPARE(host.behaviors().size(), std::size_t(1));
    QVERIFY(has_behavior(host, "test_decl_ok"));
  }

  // A truncated or half-copied file was mapped as it was and died of SIGBUS inside dlopen: every cut
  // must be refused with a reason, and the other plugins still load.
  void truncated_files_are_refused_data() {
    QTest::addColumn<QByteArray>("bytes");
    QTest::addColumn<QString>("reason");
    const QByteArray whole = read_file(q(plugin_file("good", "libtest_good.so")));
    QVERIFY(whole.size() > 8192);
    auto cut = [&](qsizetype n) { return whole.left(n); };
    auto said = [&](const QString& what, qsizetype end, qsizetype size) {
      return QString("truncated: %1 ends at byte %2, the file has %3 bytes (a half-copied file?)").arg(what).arg(end).arg(size);
    };
    Elf64_Ehdr eh;
    std::memcpy(&eh, whole.constData(), sizeof eh);
    QTest::newRow("0 bytes") << cut(0) << "an empty file, not a shared library";
    QTest::newRow("3 bytes") << cut(3) << said("the ELF header", 64, 3);
    QTest::newRow("64 bytes") << cut(64) << said("the program header table", qsizetype(eh.e_phoff + eh.e_phnum * sizeof(Elf64_Phdr)), 64);
    QTest::newRow("4096 bytes") << cut(4096) << "truncated: loaded segment";
    for (int i = 0; i < eh.e_phnum; ++i) {
      Elf64_Phdr ph;
      std::memcpy(&ph, whole.constData() + eh.e_phoff + i * sizeof ph, sizeof ph);
      if (ph.p_type != PT_LOAD || ph.p_filesz == 0) continue;
      const qsizetype end = qsizetype(ph.p_offset + ph.p_filesz);
      QTest::addRow("1 byte before segment %d ends", i) << cut(end - 1) << said(QString("loaded segment %1").arg(i), end, end - 1);
    }
    QTest::newRow("size - 1") << cut(whole.size() - 1) << said("the section header table", whole.size(), whole.size() - 1);
    // Garbage behind a valid identification, and behind a valid ELF header.
    std::mt19937 gen(6);
    QByteArray garbage = whole.left(16);
    while (garbage.size() < 8192) garbage.append(char(gen()));
    QTest::newRow("garbage after the identification") << garbage << "";
    QByteArray header_then_garbage = whole.left(64);
    while (header_then_garbage.size() < 8192) header_then_garbage.append(char(gen()));
    QTest::newRow("garbage after the ELF header") << header_then_garbage << "";
    QByteArray huge_segment = whole;  // the first program header: 2^63 bytes at byte 2^63, ending past 2^64
    Elf64_Phdr ph;
    std::memcpy(&ph, whole.constData() + eh.e_phoff, sizeof ph);
    ph.p_offset = ph.p_filesz = ph.p_memsz = std::uint64_t(1) << 63;
    std::memcpy(huge_segment.data() + eh.e_phoff, &ph, sizeof ph);
    QTest::newRow("a segment past any file's end") << huge_segment << "damaged: ";
    // Found by fuzzing the check, then loading what it accepted: headers that point the dynamic loader
    // at memory no segment maps (dlopen segfaulted on both).
    for (int i = 0; i < eh.e_phnum; ++i) {
      std::memcpy(&ph, whole.constData() + eh.e_phoff + i * sizeof ph, sizeof ph);
      if (ph.p_type == PT_LOAD) {
        QByteArray load_as_dynamic = whole;  // the first loaded segment turned into a second dynamic section
        ph.p_type = PT_DYNAMIC;
        std::memcpy(load_as_dynamic.data() + eh.e_phoff + i * sizeof ph, &ph, sizeof ph);
        QTest::newRow("a loaded segment turned dynamic") << load_as_dynamic << "damaged: two dynamic sections";
        break;
      }
    }
    // Single header fields changed (from loading header mutations the check accepted): each crashed dlopen.
    auto mutated = [&](int i, const std::function<void(Elf64_Phdr&)>& change) {
      QByteArray out = whole;
      Elf64_Phdr h;
      std::memcpy(&h, whole.constData() + eh.e_phoff + i * sizeof h, sizeof h);
      change(h);
      std::memcpy(out.data() + eh.e_phoff + i * sizeof h, &h, sizeof h);
      return out;
    };
    for (int i = 0; i < eh.e_phnum; ++i) {
      std::memcpy(&ph, whole.constData() + eh.e_phoff + i * sizeof ph, sizeof ph);
      if (ph.p_type != PT_LOAD) continue;
      if (ph.p_flags & PF_X)
        QTest::addRow("code segment %d not executable", i) << mutated(i, [](Elf64_Phdr& h) { h.p_flags &= ~PF_X; })
                                                           << "damaged: section";
      if ((ph.p_flags & PF_W) && ph.p_memsz > ph.p_filesz) {
        QTest::addRow("data segment %d reads its zero fill from the file", i)
            << mutated(i, [](Elf64_Phdr& h) { h.p_filesz = h.p_memsz; }) << "damaged: section";
        QTest::addRow("data segment %d too short for its zero fill", i)
            << mutated(i, [](Elf64_Phdr& h) { h.p_memsz = h.p_filesz; }) << "damaged: section";
      }
      if (i > 0)
        QTest::addRow("segment %d overlaps the one before", i)
            << mutated(i, [](Elf64_Phdr& h) { h.p_vaddr -= 0x2000, h.p_paddr -= 0x2000; }) << "damaged: ";
    }
    for (int i = 0; i < eh.e_phnum; ++i) {
      std::memcpy(&ph, whole.constData() + eh.e_phoff + i * sizeof ph, sizeof ph);
      if (ph.p_type == PT_DYNAMIC) {
        QByteArray dynamic_elsewhere = whole;  // the dynamic section's address outside every loaded segment
        ph.p_vaddr += 0x40000000;
        std::memcpy(dynamic_elsewhere.data() + eh.e_phoff + i * sizeof ph, &ph, sizeof ph);
        QTest::newRow("dynamic section outside the loaded segments")
            << dynamic_elsewhere << QString("damaged: the dynamic section (segment %1) lies outside every loaded segment").arg(i);
      }
    }
  }
  void truncated_files_are_refused() {
    QFETCH(QByteArray, bytes);
    QFETCH(QString, reason);
    QTemporaryDir dir;
    QVERIFY(dir.isValid());
    QVERIFY(write_file(dir.path() + "/libcut.so", bytes));
    QVERIFY(QFile::copy(q(plugin_file("good", "libtest_good.so")), dir.path() + "/libtest_good.so"));
    salsa::PluginHost host;
    host.load({{dir.path().toStdString(), "test"}});
    QCOMPARE(host.failures().size(), std::size_t(1));
    QCOMPARE(host.failures()[0].file, fs::path(dir.path().toStdString()) / "libcut.so");
    QVERIFY2(!host.failures()[0].reason.empty() && q(host.failures()[0].reason).startsWith(reason),
             host.failures()[0].reason.c_str());
    QVERIFY(has_behavior(host, "test_good"));
  }

  void cli_survives_a_truncated_plugin() {
    QTemporaryDir dir;
    QVERIFY(dir.isValid());
    QVERIFY(write_file(dir.path() + "/plugins/libx.so", read_file(q(plugin_dir() / "libflocking.so")).left(4096)));
    QVERIFY(write_file(dir.path() + "/test.json", R"({"behavior": "random_walk", "drones": 2, "time": 0.5})"));
    const CliResult plugins = run_salsa({"plugins", "--plugin-dir", "plugins"}, dir.path());
    QVERIFY2(!plugins.crashed && plugins.exit_code == 0, describe(plugins));
    QVERIFY2(plugins.out.contains("plugins/libx.so: truncated: loaded segment"), describe(plugins));
    const CliResult run = run_salsa({"run", "test.json", "--out", "out", "--plugin-dir", "plugins"}, dir.path());
    QVERIFY2(!run.crashed && run.exit_code == 0 && non_empty_lines(run.err).size() == 1, describe(run));
    QVERIFY2(run.err.contains("plugins/libx.so") && run.err.contains("(a half-copied file?)"), describe(run));
    const CliResult validate = run_salsa({"validate", "test.json", "--plugin-dir", "plugins"}, dir.path());
    QVERIFY2(!validate.crashed && validate.exit_code == 0, describe(validate));
  }

  // Provenance: config.json names each plugin's file and the SHA-256 of its bytes, so two builds of one
  // plugin version are told apart; --resume refuses a test made with other bytes, not one whose
  // plugin folder merely moved.
  void config_json_records_each_plugins_file_and_hash() {
    QTemporaryDir dir;
    QVERIFY(dir.isValid());
    const QByteArray bytes = read_file(q(plugin_file("metric", "libtest_metric.so")));  // behavior test_straight
    const QString a = dir.path() + "/a/straight.so", b = dir.path() + "/b/straight.so";
    QVERIFY(write_file(a, bytes));
    QVERIFY(write_file(dir.path() + "/test.json", R"({"name": "t", "behavior": "test_straight", "drones": 2, "time": 0.5})"));
    const CliResult first = run_salsa({"run", "test.json", "--out", "out", "--no-plots", "--plugin-dir", "a"}, dir.path());
    QVERIFY2(first.exit_code == 0, describe(first));
    const auto config = nlohmann::json::parse(read_file(dir.path() + "/out/t/config.json").toStdString());
    const auto& behavior = config["versions"]["behavior"];
    QCOMPARE(q(behavior["file"].get<std::string>()), a);
    QCOMPARE(q(behavior["sha256"].get<std::string>()), QString(QCryptographicHash::hash(bytes, QCryptographicHash::Sha256).toHex()));
    QCOMPARE(config["versions"]["map"]["sha256"].get<std::string>().size(), std::size_t{64});
    // Another build of the same name and version (a byte more): not the same test.
    QVERIFY(write_file(a, bytes + QByteArray(1, '\0')));
    const CliResult rebuilt = run_salsa({"run", "test.json", "--out", "out", "--no-plots", "--resume", "--plugin-dir", "a"}, dir.path());
    QVERIFY2(rebuilt.exit_code != 0 && rebuilt.err.contains("versions.behavior.sha256"), describe(rebuilt));
    // The same bytes found elsewhere: the same test, skipped.
    QVERIFY(write_file(b, bytes));
    QVERIFY(QFile::remove(a));
    const CliResult moved = run_salsa({"run", "test.json", "--out", "out", "--no-plots", "--resume", "--plugin-dir", "b"}, dir.path());
    QVERIFY2(moved.exit_code == 0, describe(moved));
  }

  // Replacing a plugin file while it was in use crashed the process: each file is
  // loaded from a private copy, removed as soon as it is mapped.
  void originals_may_change_while_loaded() {
    QTemporaryDir tmp, plugins;
    QVERIFY(tmp.isValid() && plugins.isValid());
    ScopedEnv tmpdir("TMPDIR", tmp.path().toUtf8());
    const QString original = plugins.path() + "/libtest_good.so";
    QVERIFY(QFile::copy(q(plugin_file("good", "libtest_good.so")), original));
    salsa::PluginHost host;
    host.load({{plugins.path().toStdString(), "test"}});
    QVERIFY2(host.failures().empty(), qPrintable(all_failures(host)));
    QCOMPARE(entries(tmp.path()), QStringList());  // no copy left behind
    QCOMPARE(host.behavior("test_good").plugin().file, fs::path(original.toStdString()));  // named as found

    // Overwritten in place (as cp does: same file, truncated, rewritten) by another plugin, then deleted.
    const QByteArray other = read_file(q(plugin_file("dup-a", "libtest_dup_a.so")));
    {
      QFile f(original);
      QVERIFY(f.open(QIODevice::WriteOnly | QIODevice::Truncate));
      QCOMPARE(f.write(other), other.size());
    }
    QVERIFY(QFile::remove(original));
    const auto& entry = host.behavior("test_good");
    salsa::ParameterValues values(entry.factory.parameters);
    values.set("gain", 4);
    auto behavior = salsa::PluginHost::create(entry, values);
    salsa::Perception me;
    me.id = 2;
    salsa::Rng rng;
    QCOMPARE(behavior->decide(me, rng), salsa::Vec2(4, 2));
    QVERIFY(is_mapped("libtest_good.so"));
    QCOMPARE(entries(tmp.path()), QStringList());
  }

  void unusable_temporary_folder_is_a_reason() {
    ScopedEnv tmpdir("TMPDIR", "/nonexistent/salsa-tmp");
    salsa::PluginHost host;
    QVERIFY(!host.load_file(plugin_file("good", "libtest_good.so")));
    QCOMPARE(all_failures(host), q(plugin_file("good", "libtest_good.so")) +
                                     ": no temporary folder for its private copy ($TMPDIR /nonexistent/salsa-tmp: "
                                     "no such file or directory)\n");
  }

  // A copy left by a process that died while loading (its folder unlocked, older than a minute) is
  // removed by the next salsa; a young one may belong to a process loading right now.
  void stale_copies_are_swept() {
    QTemporaryDir tmp;
    QVERIFY(tmp.isValid());
    for (const char* name : {"salsa-plugin-stale1", "salsa-plugin-young1"})
      QVERIFY(write_file(tmp.path() + "/" + name + "/libx.so", "x"));
    std::error_code ec;
    fs::last_write_time(tmp.path().toStdString() + "/salsa-plugin-stale1", fs::file_time_type::clock::now() - std::chrono::minutes(10), ec);
    QVERIFY(!ec);
    QProcess p;
    QProcessEnvironment env = QProcessEnvironment::systemEnvironment();
    env.insert("TMPDIR", tmp.path());
    env.remove("SALSA_PLUGIN_PATH");
    p.setProcessEnvironment(env);
    p.start(salsa_executable(), {"plugins"});
    QVERIFY(p.waitForFinished(60000));
    QCOMPARE(p.exitCode(), 0);
    QCOMPARE(entries(tmp.path()), QStringList{"salsa-plugin-young1"});
  }

  // A symbolic link loop aborted discovery for every plugin; a dangling link read "no ELF header".
  // Each bad entry now gets its own reason, and the rest load.
  void bad_folder_entries_are_reported() {
    QTemporaryDir dir;
    QVERIFY(dir.isValid());
    const fs::path d = dir.path().toStdString();
    fs::create_symlink("libloop.so", d / "libloop.so");
    fs::create_symlink("libb.so", d / "liba.so");
    fs::create_symlink("liba.so", d / "libb.so");
    fs::create_symlink("nothere.so", d / "libdangling.so");
    fs::create_directory(d / "libfolder.so");
    QCOMPARE(::mkfifo((d / "libfifo.so").c_str(), 0600), 0);  // opening it for reading must not block
    QVERIFY(write_file(dir.path() + "/libempty.so", ""));
    QVERIFY(write_file(dir.path() + "/libtext.so", "just text\n"));
    fs::create_symlink(plugin_file("good", "libtest_good.so"), d / "liblinked.so");  // a good link loads
    salsa::PluginHost host;
    host.load({{d, "test"}});
    const QString all = all_failures(host);
    auto reason = [&](const char* file) { return failures_of(host, d / file); };
    QCOMPARE(reason("libloop.so"), QString("symbolic link loop\n"));
    QCOMPARE(reason("liba.so"), QString("symbolic link loop\n"));
    QCOMPARE(reason("libdangling.so"), QString("broken symbolic link to nothere.so\n"));
    QCOMPARE(reason("libfolder.so"), QString("a folder, not a shared library\n"));
    QVERIFY2(reason("libfifo.so").startsWith("not a regular file"), qPrintable(all));
    QCOMPARE(reason("libempty.so"), QString("an empty file, not a shared library\n"));
    QCOMPARE(reason("libtext.so"), QString("not a shared library (no ELF header)\n"));
    QCOMPARE(host.failures().size(), std::size_t(8));
    QCOMPARE(host.behavior("test_good").plugin().file, d / "liblinked.so");

    // The same folder as a plugin folder that is a link loop, and through the CLI.
    fs::create_symlink("libloopdir", d / "libloopdir");
    salsa::PluginHost loop_dir;
    loop_dir.load({{d / "libloopdir", "test"}, {plugin_folder("good"), "test"}});
    QCOMPARE(failures_of(loop_dir, d / "libloopdir"), QString("plugin folder cannot be read: symbolic link loop\n"));
    QVERIFY(has_behavior(loop_dir, "test_good"));
    // A folder the user named that is missing or a file is reported; a missing default folder is not.
    salsa::PluginHost odd_dirs;
    odd_dirs.load({{d / "nowhere", "--plugin-dir"}, {d / "libtext.so", "--plugin-dir"}, {d / "nowhere", "user"}});
    QCOMPARE(all_failures(odd_dirs), q(d / "nowhere") + ": no such plugin folder\n" + q(d / "libtext.so") +
                                         ": a file, not a plugin folder\n");
    const CliResult r = run_salsa({"plugins", "--plugin-dir", dir.path()});
    QVERIFY2(!r.crashed && r.exit_code == 0 && r.out.contains("libloop.so: symbolic link loop") &&
                 r.out.contains("libdangling.so: broken symbolic link to nothere.so") && r.out.contains(" flocking "),
             describe(r));
  }

  void unreadable_files_and_folders_are_reported() {
    if (::geteuid() == 0) QSKIP("root reads any file");
    QTemporaryDir dir;
    QVERIFY(dir.isValid());
    const fs::path d = dir.path().toStdString();
    QVERIFY(QFile::copy(q(plugin_file("good", "libtest_good.so")), dir.path() + "/libsecret.so"));
    fs::permissions(d / "libsecret.so", fs::perms::none);
    fs::create_directory(d / "closed");
    fs::permissions(d / "closed", fs::perms::none);
    salsa::PluginHost host;
    host.load({{d, "test"}, {d / "closed", "test"}});
    QCOMPARE(failures_of(host, d / "libsecret.so"), QString("cannot be read: permission denied\n"));
    QCOMPARE(failures_of(host, d / "closed"), QString("plugin folder cannot be listed: permission denied\n"));
    fs::permissions(d / "closed", fs::perms::owner_all);
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
    QCOMPARE(host.failures().size(), std::size_t(6));  // 5 bad files + the duplicate registration
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
    QVERIFY2(line_of("libtest_abi99.so").contains("built for salsa ABI 99, this is 11"), describe(r));
    QVERIFY2(line_of("notalib.so").contains("not a shared library"), describe(r));
    QVERIFY2(line_of("libtest_noentry.so").contains("no entry point"), describe(r));
    QVERIFY2(line_of("libtest_registration_throws.so").contains("registration threw"), describe(r));
    QVERIFY2(line_of("libtest_static_init.so").contains("its static initialiser threw while the file was loaded: static init exploded"),
             describe(r));
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
                        line.contains("behavior 'test_dup' not registered: the name is taken by " +
                                      q(plugin_file("dup-a", "libtest_dup_a.so"))));
    QVERIFY2(found, describe(r));
  }

  void cli_describe_shows_parameters() {
    const CliResult r = run_salsa({"describe", "flocking"});
    QVERIFY2(!r.crashed && r.exit_code == 0, describe(r));
    for (const char* p : {"separation_distance", "alignment_weight", "cohesion_weight", "separation_weight",
                          "obstacle_avoidance_weight"})
      QVERIFY2(r.out.contains(p), describe(r));
    // The test's own models, not plugins: each declared once (drone_schema, comm_schema, wind_schema,
    // failure_schema).
    for (const auto& [name, fields] : std::vector<std::pair<QString, QStringList>>{
             {"drone", {"camera_range", "battery_capacity", "position_noise"}},
             {"comm", {"range", "loss_at_range", "latency"}},
             {"wind", {"velocity.x", "gusts.strength", "gusts.time_scale", "wind fields"}},
             {"failures", {"drone_mtbf", "camera_mtbf", "1000000000"}}}) {
      const CliResult model = run_salsa({"describe", name});
      QVERIFY2(model.exit_code == 0, describe(model));
      for (const QString& f : fields) QVERIFY2(model.out.contains(f), describe(model));
    }
    const CliResult unknown = run_salsa({"describe", "no_such_plugin"});
    QVERIFY2(unknown.exit_code != 0 && unknown.err.contains("no_such_plugin"), describe(unknown));
  }
};

QTEST_GUILESS_MAIN(TestLoader)
#include "test_loader.moc"
