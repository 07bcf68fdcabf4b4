// salsa suite: runs a behavior on the benchmark suite's tasks (each a queue: the task as its base, the
// suite's conditions, its paired seeds) and places it among the committed references; --references
// regenerates those, --check reruns them and says, per task, whether they are reproduced.
#include <unistd.h>

#include <oneapi/tbb/info.h>

#include <algorithm>
#include <iostream>
#include <set>

#include "salsa/core/experiments/queue.hpp"
#include "salsa/core/files/input_error.hpp"
#include "salsa/core/files/names.hpp"
#include "salsa/core/plugins/plugin_host.hpp"
#include "salsa/core/results/queue_summary.hpp"
#include "salsa/core/run/output_folder.hpp"
#include "salsa/core/run/runner.hpp"
#include "commands.hpp"
#include "options.hpp"
#include "queue_run.hpp"
#include "strict_json.hpp"
#include "suite.hpp"

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;
using namespace salsa;
using namespace salsa::cli;

#ifndef SALSA_SUITE_SOURCE
#define SALSA_SUITE_SOURCE ""
#endif
#ifndef SALSA_SUITE_INSTALLED
#define SALSA_SUITE_INSTALLED ""
#endif

namespace salsa::cli {

Suite read_suite(const fs::path& file) {
  const std::string where = strict_json::printable(file.string(), 200);
  json j;
  try {
    j = strict_json::read_file<json>(file, "a suite file (see docs/suite.md)");
  } catch (const strict_json::Error& e) {
    throw InputError(e.what());
  }
  auto refuse = [&](const std::string& field, const std::string& what) -> void { throw InputError(where + ": " + field + ": " + what); };
  if (!j.is_object()) throw InputError(where + ": " + strict_json::shown(j) + " is not a suite object (see docs/suite.md)");
  const std::set<std::string> keys{"version", "seed", "repeats", "references", "conditions", "tasks", "results"};
  for (const auto& item : j.items())
    if (!keys.count(item.key()))
      refuse(strict_json::printable(item.key()), "unknown key (allowed: version, seed, repeats, references, conditions, tasks, results)");
  for (const char* k : {"version", "seed", "repeats", "references", "conditions", "tasks", "results"})
    if (!j.contains(k)) refuse(k, "missing");
  auto whole = [&](const char* k, std::uint64_t lo, std::uint64_t hi) {
    const json& v = j[k];
    if (!v.is_number_unsigned() || v.get<std::uint64_t>() < lo || v.get<std::uint64_t>() > hi)
      refuse(k, strict_json::shown(v) + " is not a whole number in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return v.get<std::uint64_t>();
  };
  Suite s;
  s.file = file;
  s.version = whole("version", 1, 1000000);
  s.seed = whole("seed", 0, std::uint64_t{1} << 53);
  s.repeats = whole("repeats", 2, 1000);  // a paired interval needs two worlds
  s.references = j["references"];
  if (!s.references.is_array() || s.references.empty()) refuse("references", "must be a non-empty list of behaviors (as sweep.behaviors)");
  s.conditions = j["conditions"];
  if (!s.conditions.is_array() || s.conditions.empty()) refuse("conditions", "must be a non-empty list of conditions (as a queue's)");
  if (!j["results"].is_string() || j["results"].get<std::string>().empty()) refuse("results", "must be a file name");
  s.results = file.parent_path() / j["results"].get<std::string>();
  if (!j["tasks"].is_array() || j["tasks"].empty()) refuse("tasks", "must be a non-empty list of tasks");
  for (std::size_t i = 0; i < j["tasks"].size(); ++i) {
    const json& t = j["tasks"][i];
    const std::string at = "tasks[" + std::to_string(i) + "]";
    if (!t.is_object()) refuse(at, strict_json::shown(t) + " must be an object with name, file, metric, better");
    for (const auto& item : t.items())
      if (item.key() != "name" && item.key() != "file" && item.key() != "metric" && item.key() != "better")
        refuse(at + "." + strict_json::printable(item.key()), "unknown key (allowed: name, file, metric, better)");
    for (const char* k : {"name", "file", "metric", "better"})
      if (!t.contains(k) || !t[k].is_string() || t[k].get<std::string>().empty()) refuse(at + "." + k, "missing or not a non-empty string");
    SuiteTask task{t["name"].get<std::string>(), file.parent_path() / t["file"].get<std::string>(), t["metric"].get<std::string>(),
                   t["better"].get<std::string>() == "higher"};
    if (!name_problem(task.name).empty()) refuse(at + ".name", name_problem(task.name));
    if (t["better"] != "higher" && t["better"] != "lower") refuse(at + ".better", strict_json::shown(t["better"]) + " (allowed: \"higher\", \"lower\")");
    if (!fs::is_regular_file(task.file)) refuse(at + ".file", strict_json::printable(task.file.string(), 200) + " is not a file");
    for (const SuiteTask& other : s.tasks)
      if (other.name == task.name) refuse(at + ".name", "\"" + task.name + "\" is used twice (allowed: each name once)");
    s.tasks.push_back(std::move(task));
  }
  return s;
}

}  // namespace salsa::cli

namespace {

po::options_description suite_options() {
  po::options_description o("suite options");
  o.add_options()("behavior", po::value<std::string>(), "the behavior to place among the references (a plugin's name)")(
      "params", po::value<std::string>(), "its parameters: a JSON object, or a file holding one")(
      "out,o", po::value<std::string>(), "output folder (default results/suite-<behavior>): OUT/<task>/ per task, report.csv, report.md, plots/")(
      "jobs,j", po::value<std::string>(), "tests run at once (default: all cores)")(
      "time", po::value<std::string>(), "a quick trial: every test cut to this many seconds, the references rerun at it beside the behavior")(
      "suite", po::value<std::string>(), "the suite file (default: the suite installed with salsa, suite/v1/suite.json)")(
      "references", "run the reference behaviors and write the suite's references file (and references.md beside it)")(
      "check", "run the reference behaviors and say, per task, whether the committed references are reproduced")(
      "resume", "skip tests whose output folder holds the identical finished test")(
      "force", "replace the output folders salsa wrote for these tests");
  return o;
}

/// The suite file: --suite, else the source tree's (a build tree's salsa), else the installed one.
fs::path suite_file(const po::variables_map& vm) {
  if (vm.count("suite")) return vm["suite"].as<std::string>();
  if (fs::path source = SALSA_SUITE_SOURCE; !source.empty() && fs::is_regular_file(source)) return source;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  const fs::path installed = exe.parent_path().parent_path() / SALSA_SUITE_INSTALLED;
  if (!ec && fs::is_regular_file(installed)) return installed;
  throw InputError("--suite: no suite file found beside this salsa (looked for " + installed.string() + "); give --suite FILE");
}

/// --params: a JSON object given inline, or the file that holds one.
json params_option(const po::variables_map& vm) {
  if (!vm.count("params")) return json::object();
  const std::string text = vm["params"].as<std::string>();
  json p;
  try {
    const auto first = text.find_first_not_of(" \t\n");
    const bool inline_json = first != std::string::npos && (text[first] == '{' || text[first] == '[');
    p = inline_json ? strict_json::parse<json>(text, "--params") : strict_json::read_file<json>(text, "a JSON object of parameters");
  } catch (const strict_json::Error& e) {
    const std::string what = e.what();
    throw InputError((what.starts_with("--params") ? "" : "--params: ") + what + " (allowed: a JSON object of parameters, or a file holding one)");
  }
  if (!p.is_object()) throw InputError("--params: " + strict_json::shown(p) + " is not a JSON object of parameters");
  return p;
}

/// A task's queue: the task's test as the base (its behavior and name dropped), the suite's conditions,
/// seed and repeats, and `behaviors` swept.
std::string task_queue(const Suite& suite, const SuiteTask& task, const json& behaviors) {
  json base;
  try {
    base = strict_json::read_file<json>(task.file, "a test object");
  } catch (const strict_json::Error& e) {
    throw InputError(e.what());
  }
  if (!base.is_object()) throw InputError(task.file.string() + ": a suite task is one test object");
  base.erase("behavior");
  base.erase("name");
  json q;
  q["seed"] = suite.seed;
  q["repeats"] = suite.repeats;
  q["base"] = base;
  q["conditions"] = suite.conditions;
  q["sweep"] = json{{"behaviors", behaviors}};
  return q.dump();
}

/// {"name", "params"} of a behavior as sweep.behaviors gives it, for comparing two.
json normalised(const json& b) {
  if (b.is_string()) return json{{"name", b}, {"params", json::object()}};
  json n{{"name", b.value("name", json())}, {"params", b.value("params", json::object())}};
  return n;
}

/// Runs the tests into OUT as `salsa run` does: the folder claimed, the tests run, summary.csv written.
int run_tests(const std::vector<TestSpec>& tests, const PluginHost& host, const fs::path& out, const po::variables_map& vm,
              std::size_t jobs, const std::vector<std::string>& command) {
  RunOptions options;
  options.out = out;
  options.force = vm.count("force");
  options.resume = vm.count("resume");
  options.threads = 1;
  options.drones_csv = false;  // the suite scores outcomes; drones.csv would be most of the disk
  std::string line;
  for (const auto& a : command) line += (line.empty() ? "" : " ") + a;
  fs::create_directories(out);
  OutputLock lock = claim_output(out, 0, 1, line);
  QueueRecord record = queue_record(tests, host, command);
  check_queue_folder(out, record, options.resume, options.force);
  check_outputs(tests, host, options);
  claim_queue_folder(out, record, options.resume, options.force);
  QueueRunOptions run;
  run.jobs = std::max<std::size_t>(1, std::min(jobs, tests.size()));
  run.quiet = vm.count("quiet");
  run.plots = false;
  run.terminal = ::isatty(STDOUT_FILENO);
  run.label = out.filename().string();
  std::vector<std::size_t> all(tests.size());
  for (std::size_t k = 0; k < all.size(); ++k) all[k] = k;
  ListDispatch dispatch(all);
  stop_may_exit(false);
  const QueueResult result = run_queue(tests, host, options, run, dispatch);
  stop_may_exit(true);
  if (result.write_failed || (result.status != 0 && result.status != 1)) return result.status == 0 ? 1 : result.status;
  finish_queue(out, host, false);
  return result.status;
}

}  // namespace

int cmd_suite(int argc, char** argv) {
  po::variables_map vm;
  if (!parse(argc, argv, "suite", "BEHAVIOR [options] | --references | --check", suite_options(), vm, plugin_options,
             positional("behavior", 1)))
    return 0;
  const bool references = vm.count("references"), check = vm.count("check");
  if (references && check) throw InputError("--references and --check: one at a time (--references writes the file --check compares with)");
  const bool mine = vm.count("behavior");
  if (mine && (references || check))
    throw InputError(std::string(references ? "--references" : "--check") + ": runs the reference behaviors only, not with BEHAVIOR");
  if (!mine && !references && !check) throw InputError("missing BEHAVIOR (a behavior plugin's name), or --references, or --check");
  if (!mine && vm.count("params")) throw InputError("--params: the parameters of BEHAVIOR, which is not given");
  if ((references || check) && vm.count("time"))
    throw InputError("--time: not with " + std::string(references ? "--references" : "--check") + " (the references are at the tasks' full time)");
  std::size_t jobs = vm.count("jobs") ? whole_option(vm, "jobs", 1024, "; 0 means all cores") : 0;
  if (jobs == 0) jobs = static_cast<std::size_t>(std::max(1, tbb::info::default_concurrency()));
  const Suite suite = read_suite(suite_file(vm));

  install_signal_handlers();
  PluginHost host;
  load_plugins(host, vm, true);
  // The behavior swept: the user's (first) and, when the references are rerun, every reference.
  json behaviors = json::array();
  if (mine) {
    const std::string name = vm["behavior"].as<std::string>();
    const auto& known = host.behaviors();
    if (std::none_of(known.begin(), known.end(), [&](const auto& e) { return e.factory.name == name; })) {
      std::string list;
      for (const auto& e : known) list += (list.empty() ? "" : ", ") + e.factory.name;
      throw InputError("BEHAVIOR: unknown behavior '" + strict_json::printable(name) + "' (known: " + list + "; salsa plugins lists the folders searched)");
    }
    const json params = params_option(vm);
    // Its parameters checked once, as a test file's are, with --params named.
    (void)parse_queue(json{{"behavior", {{"name", name}, {"params", params}}}}.dump(), "--params", host, QueueOptions{});
    behaviors.push_back(json{{"name", name}, {"params", params}});
  }
  const bool rerun = !mine || vm.count("time");
  if (rerun)
    for (const json& r : suite.references)
      if (behaviors.empty() || normalised(r) != normalised(behaviors[0])) behaviors.push_back(r);

  // Every task's queue read and checked before the first test runs.
  std::vector<std::vector<TestSpec>> queues;
  for (const SuiteTask& task : suite.tasks) {
    Queue q = parse_queue(task_queue(suite, task, behaviors), task.file.string(), host, QueueOptions{}, task.file.parent_path(), task.name);
    for (TestSpec& t : q.tests)
      if (vm.count("time")) {
        t.time = seconds_option(vm, "time", t);
        std::erase_if(t.changes, [&](const Change& c) { return c.time > t.time; });
      }
    queues.push_back(std::move(q.tests));
  }
  const std::string label = mine ? variant(queues.front().front(), host) : "";
  const fs::path out = vm.count("out") ? fs::path(vm["out"].as<std::string>())
                                       : fs::path("results") / (mine ? "suite-" + vm["behavior"].as<std::string>() : "suite-references");
  std::vector<std::string> command{"salsa"};
  command.insert(command.end(), argv, argv + argc);

  std::vector<SuiteValue> values;
  int status = 0;
  for (std::size_t i = 0; i < suite.tasks.size(); ++i) {
    const int s = run_tests(queues[i], host, out / suite.tasks[i].name, vm, jobs, command);
    if (s != 0 && s != 1) return s;  // stopped: --resume goes on
    status = std::max(status, s);
    auto v = task_values(out / suite.tasks[i].name, suite.tasks[i]);
    values.insert(values.end(), v.begin(), v.end());
  }
  const bool quiet = vm.count("quiet");
  if (references) {
    if (status != 0) {
      std::cerr << "salsa: a reference test failed (its line above): " << suite.results.string() << " left as it was" << std::endl;
      return status;
    }
    write_references(suite, values, suite.results);
    write_reference_table(suite, values, fs::path(suite.results).replace_extension(".md"));
    if (!quiet) std::cout << "references written to " << suite.results.string() << " and " << fs::path(suite.results).replace_extension(".md").string() << std::endl;
    return status;
  }
  const std::vector<SuiteValue> committed = read_references(suite, suite.results);
  if (check) {
    // Byte-equal values, task by task: the same seeds and code give the same data files.
    bool all = true;
    for (const SuiteTask& task : suite.tasks) {
      std::vector<const SuiteValue*> now, then;
      for (const auto& v : values)
        if (v.task == task.name) now.push_back(&v);
      for (const auto& v : committed)
        if (v.task == task.name) then.push_back(&v);
      std::string first;
      auto key = [](const SuiteValue& v) { return v.condition + "/" + v.variant + "/r" + std::to_string(v.repeat); };
      if (now.size() != then.size()) first = std::to_string(now.size()) + " values, the references hold " + std::to_string(then.size());
      for (std::size_t k = 0; first.empty() && k < now.size(); ++k)
        if (key(*now[k]) != key(*then[k]) || now[k]->seed != then[k]->seed || now[k]->value != then[k]->value)
          first = key(*now[k]) + " gives " + (now[k]->value.empty() ? "no value" : now[k]->value) + ", the references " +
                  (then[k]->value.empty() ? "no value" : then[k]->value) + " (" + key(*then[k]) + ")";
      std::cout << task.name << ": " << (first.empty() ? "reproduced (" + std::to_string(now.size()) + " values byte-equal)" : "DIFFERS: " + first)
                << std::endl;
      all = all && first.empty();
    }
    return all ? status : 1;
  }
  // The user's behavior against the references: the committed ones, or (--time) those just rerun.
  if (!rerun) values.insert(values.end(), committed.begin(), committed.end());
  const std::string note = rerun ? "A quick trial: every test cut to " + vm["time"].as<std::string>() +
                                       " s, the references rerun at that time on the same seeds (not the committed references)."
                                 : "Against the committed references (" + suite.results.filename().string() + ") on the same seeds.";
  write_report(suite, label, values, out, note);
  if (!quiet) std::cout << "report in " << (out / "report.md").string() << std::endl;
  return status;
}
