// Every JSON reader is strict and answers bad input in one line: nesting depth, duplicate
// keys, numbers a double cannot hold, NaN and Infinity, text that is not UTF-8, empty files, folders
// and oversized files; names that become folders; values printed exactly and with a bound.
#include "common.hpp"

#include <nlohmann/json.hpp>

#include "salsa/core/experiments/test_spec.hpp"
#include "strict_json.hpp"

using namespace salsa;
using namespace salsa_test;

namespace {

QByteArray repeat(const QByteArray& s, int n) { return s.repeated(n); }
QByteArray deep(int levels) { return "{\"behavior\": " + repeat("[", levels) + repeat("]", levels) + "}"; }

/// The InputError message of `f`, or "" when it throws none.
template <class F>
QString error_of(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return QString::fromStdString(e.what());
  }
  return {};
}

}  // namespace

class TestJsonInput : public QObject {
  Q_OBJECT

  std::unique_ptr<PluginHost> host_ = builtin_host();
  QTemporaryDir dir_;

  QString file(const QString& name, const QByteArray& content) {
    const QString path = dir_.filePath(name);
    write_file(path, content);
    return path;
  }
  QString load(const QString& name, const QByteArray& content) {
    const QString path = file(name, content);
    return error_of([&] { load_tests(path.toStdString(), *host_); });
  }
  QString parse(const QByteArray& text) {
    return error_of([&] { parse_test(text.toStdString(), "t.json", *host_); });
  }
  QString load_map(const QByteArray& content) {
    const QString path = file("map.json", content);
    return error_of([&] { load_map_file(path.toStdString(), *host_); });
  }

  static void check(const QString& message, const QStringList& parts) {
    QVERIFY2(!message.isEmpty(), "no InputError");
    QVERIFY2(!message.contains('\n') && message.size() < 400, qPrintable(message));
    for (const QString& part : parts) QVERIFY2(message.contains(part), qPrintable("'" + part + "' missing from: " + message));
  }

 private Q_SLOTS:
  // 100,000 levels used to overflow the stack while the error printed the value.
  void deep_nesting_is_refused_everywhere() {
    const QStringList depth{"line 1, column 77", "nested deeper than 64 levels (allowed: at most 64)"};
    check(parse(deep(100000)), QStringList{"t.json"} + depth);
    check(load("deep.json", deep(100000)), QStringList{"deep.json"} + depth);
    check(load_map("{\"bounds\": " + repeat("[", 100000) + "}"), {"map.json", "line 1, column 75", "nested deeper than 64"});
    file("fleet.json", "{\"heavy\": " + repeat("{\"a\": ", 100000) + "}");
    check(load("uses-fleet.json", R"({"behavior": "flocking", "drone_configs": "fleet.json"})"),
          {"fleet.json", "nested deeper than 64 levels"});
    // 64 levels are fine as JSON (and then refused for what they hold).
    check(parse(deep(63)), {"behavior", "must be a non-empty string"});
  }

  void values_are_shown_with_a_bound_and_without_recursion() {
    nlohmann::json v = nlohmann::json::array();
    for (int i = 0; i < 100000; ++i) v = nlohmann::json::array({std::move(v)});
    const std::string s = strict_json::shown(v);
    QCOMPARE(s.size(), std::size_t(60));
    QVERIFY(s.ends_with("[[[..."));
    QCOMPARE(strict_json::shown(nlohmann::json::parse(R"({"a": [1, 2.5, "x\ny"], "b": null})")),
             std::string(R"({"a":[1,2.5,"x\ny"],"b":null})"));
    QCOMPARE(strict_json::shown(nlohmann::json(std::string(1000000, 'x'))).size(), std::size_t(60));
  }

  // User text in a message is valid UTF-8 on one line: other bytes escaped, characters kept whole, a
  // cut never inside a character.
  void printable_escapes_what_is_not_utf8() {
    using strict_json::printable;
    QCOMPARE(printable("a\xff" "b"), std::string("a\\xff" "b"));
    QCOMPARE(printable("caf\xc3\xa9"), std::string("caf\xc3\xa9"));             // é kept
    QCOMPARE(printable("\xc3"), std::string("\\xc3"));                            // cut short
    QCOMPARE(printable("\xc0\x80"), std::string("\\xc0\\x80"));                  // overlong NUL
    QCOMPARE(printable("\xed\xa0\x80"), std::string("\\xed\\xa0\\x80"));        // a surrogate
    QCOMPARE(printable("\xf4\x90\x80\x80"), std::string("\\xf4\\x90\\x80\\x80"));  // above U+10FFFF
    QCOMPARE(printable("\xf0\x9f\x90\x9f"), std::string("\xf0\x9f\x90\x9f"));     // an emoji kept
    QCOMPARE(printable("a\nb"), std::string("a\\nb"));
    QCOMPARE(printable(std::string(10, 'x') + "\xc3\xa9\xc3\xa9", 11), std::string(10, 'x') + "\xc3\xa9...");
    QCOMPARE(printable(std::string(100000, '\xff')).size(), std::size_t(60 + 3));
  }

  void duplicate_keys_are_refused_with_their_path() {
    check(parse(R"({"behavior": "flocking", "drones": 3, "drones": 4})"),
          {"t.json: drones: duplicate key at line 1, column 39 (each key may appear once)"});
    check(parse(R"({"behavior": {"name": "flocking", "params": {"alignment_weight": 1, "alignment_weight": 2}}})"),
          {"t.json: behavior.params.alignment_weight: duplicate key"});
    check(load("queue.json", R"({"tests": [{"behavior": "flocking"},
                                           {"behavior": "flocking", "spawn": {"point": [1, 2], "point": [3, 4]}}]})"),
          {"queue.json: tests[1].spawn.point: duplicate key at line 2, column 96"});
    check(load_map(R"({"bounds": {"min": [0, 0], "max": [10, 10], "min": [1, 1]}})"), {"map.json: bounds.min: duplicate key"});
    file("fleet2.json", R"({"heavy": {"mass": 30}, "heavy": {"mass": 40}})");
    check(load("uses-fleet2.json", R"({"behavior": "flocking", "drone_configs": "fleet2.json"})"),
          {"fleet2.json: heavy: duplicate key"});
    // Equal keys in different objects are fine.
    QVERIFY(parse(R"({"behavior": {"name": "flocking"}, "map": {"name": "empty"}})").isEmpty());
  }

  void numbers_a_double_cannot_hold_and_non_finite_literals() {
    check(parse("{\"behavior\": \"flocking\",\n \"time\": 1e400}"),
          {"t.json: line 2, column 10: 1e400 does not fit a double (allowed: finite numbers"});
    check(parse(R"({"behavior": "flocking", "time": -1e400})"), {"column 34: -1e400 does not fit a double"});
    for (const char* literal : {"NaN", "nan", "Infinity", "-Infinity", "inf", "-NaN"})
      check(parse(QByteArray(R"({"behavior": "flocking", "time": )") + literal + "}"),
            {"t.json: line 1, column 34: JSON has no NaN or Infinity (allowed: finite numbers)"});
    check(load_map(R"({"bounds": {"min": [0, 0], "max": [1e999, 10]}})"), {"map.json: line 1, column 36: 1e999 does not fit"});
    check(load_map(R"({"bounds": {"min": [0, 0], "max": [NaN, 10]}})"), {"map.json", "no NaN or Infinity"});
  }

  void values_are_printed_exactly() {
    QCOMPARE(Parameter::format(10), std::string("10"));
    QCOMPARE(Parameter::format(0.5), std::string("0.5"));
    QCOMPARE(Parameter::format(1e-9), std::string("1e-09"));
    QCOMPARE(Parameter::format(1.0 / 60), std::string("0.016666666666666666"));
    QCOMPARE(Parameter::format(1e7), std::string("10000000"));
    QCOMPARE(Parameter::format(-2.5e300), std::string("-2.5e+300"));
    for (double v : {1.0 / 3, 1e-9, 123456.789, 6.02214076e23, 5e-324})
      QCOMPARE(std::strtod(Parameter::format(v).c_str(), nullptr), v);
    // A range shown in a message reads back as what is allowed, not "0".
    check(parse(R"({"behavior": "flocking", "drone": {"max_force": 1e-9}})"),
          {"drone.max_force", "1e-09 is out of range (allowed: [1e-06, 1000] m/s per step)"});
  }

  // A test without "name" is named after its file: "...json" would become "..", and removing OUT/..
  // on --force would lose data.
  void file_stems_that_cannot_name_a_folder_are_refused() {
    for (const QString name : {"...json", "..json", ".hidden.json"})
      check(load(name, R"({"behavior": "flocking"})"), {name + ": name: missing", "allowed:", "give the test a \"name\""});
    check(load("...json", R"([{"behavior": "flocking"}])"), {"...json: [0]: name: missing", "\"..-1\"", "give the test a \"name\""});
    // With a name, the file name does not matter.
    QVERIFY(load("..json", R"({"name": "fine", "behavior": "flocking"})").isEmpty());
    QCOMPARE(load_tests(file("plain.json", R"([{"behavior": "flocking"}])").toStdString(), *host_)[0].name, std::string("plain-1"));
  }

  void test_names_go_through_the_name_check() {
    for (const QByteArray& name : {QByteArray(".."), QByteArray("a/b"), QByteArray("../x"), QByteArray(" x"), QByteArray(129, 'a')})
      check(parse("{\"behavior\": \"flocking\", \"name\": \"" + name + "\"}"), {"t.json: name:", "allowed: 1 to 128"});
    QVERIFY(parse("{\"behavior\": \"flocking\", \"name\": \"" + QByteArray(128, 'a') + "\"}").isEmpty());
  }

  void files_that_are_not_json_text() {
    QDir(dir_.path()).mkdir("folder.json");
    check(error_of([&] { load_tests(dir_.filePath("folder.json").toStdString(), *host_); }), {"folder.json: is a folder, not a file"});
    check(load("empty.json", ""), {"empty.json: the file is empty (expected a test"});
    check(load("blank.json", " \n\t\n"), {"blank.json: the file is empty"});
    check(load("latin1.json", "{\"behavior\": \"caf\xe9\"}"), {"latin1.json: line 1, column 18: not UTF-8 text (byte 0xE9"});
    check(load("utf16.json", QByteArray("\xff\xfe{\0}\0", 6)), {"not UTF-8 text", "the file is UTF-16"});
    check(load("overlong.json", "{\"behavior\": \"\xc0\xaf\"}"), {"not UTF-8 text (byte 0xC0"});
    check(load("nul.json", QByteArray("{\"behavior\"\0: 1}", 16)), {"nul.json: line 1, column 12: invalid JSON"});
    check(load_map(""), {"map.json: the file is empty (expected a map object"});
    QVERIFY(load("bom.json", "\xef\xbb\xbf{\"behavior\": \"flocking\"}").isEmpty());  // some editors write one
    // Over the size limit: a sparse file, so the test writes nothing much.
    QFile big(dir_.filePath("big.json"));
    QVERIFY(big.open(QIODevice::WriteOnly) && big.resize(qint64(strict_json::max_file_bytes) + 1));
    big.close();
    check(error_of([&] { load_tests(big.fileName().toStdString(), *host_); }), {"big.json: larger than 64 MiB"});
  }

  void syntax_errors_keep_line_and_column() {
    check(parse("{\"behavior\": \"flocking\",\n  \"drones\": 10,,\n}"), {"t.json: line 2, column 16: invalid JSON: syntax error"});
    check(parse("{\"behavior\": \"flocking\"} {}"), {"line 1, column 26: invalid JSON", "expected end of input"});
    check(parse("{\"behavior\": \"flocking\", \"a\u0001\": 1}"), {"line 1, column 28: invalid JSON"});
    check(parse("{\"behavior\": \"flocking\", \"a\\nb\": 1}"), {"t.json: a\\nb: unknown key"});
  }

  void files_for_plot() {
    auto plot = [&](const QByteArray& content) {
      return run_salsa({"plot", file("bench.json", content), "--out", dir_.filePath("out.png")});
    };
    for (const auto& [content, expected] : std::vector<std::pair<QByteArray, QString>>{
             {"{\"workload\": \"scale\", \"threads\": 1, \"cells\": " + repeat("[", 100000) + "}", "nested deeper than 64"},
             {R"({"workload": 3, "threads": 1, "cells": []})", "bench.json: workload: 3 is not a string"},
             {R"({"workload": "scale", "threads": 1, "cells": [{"drones": 10}]})", "bench.json: cells[0].rtf: missing"},
             {R"({"workload": "scale", "threads": 1, "threads": 2, "cells": []})", "bench.json: threads: duplicate key"},
             {"", "bench.json: the file is empty"}}) {
      const CliResult r = plot(content);
      QVERIFY2(!r.crashed && r.exit_code == 2, describe(r));
      QVERIFY2(non_empty_lines(r.err).size() == 1 && r.err.contains(expected), describe(r));
    }
    // summary.csv (not JSON): a cell that is not a number once escaped as "stod" with exit 1.
    const CliResult r = run_salsa({"plot", file("summary.csv", "time,targets_found\n0,1\n1,abc\n"), "--out", dir_.filePath("out.png")});
    QVERIFY2(!r.crashed && r.exit_code == 2, describe(r));
    QVERIFY2(r.err.contains("summary.csv: line 3, column targets_found: 'abc' is not a number (allowed: finite numbers)"), describe(r));
  }
};

QTEST_GUILESS_MAIN(TestJsonInput)
#include "test_json_input.moc"
