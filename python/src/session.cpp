// salsa.Session: one test stepped from Python through the core's Session, its drones' state columns
// handed out as read-only numpy views of the simulation's own arrays (no copy).
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <string_view>
#include <thread>

#include "bindings.hpp"
#include "salsa/core/experiments/test_models.hpp"
#include "salsa/core/experiments/test_spec.hpp"
#include "salsa/core/run/session.hpp"

namespace salsa::python {

namespace {

namespace fs = std::filesystem;

/// A test from a path (read as `salsa run` reads it) or a dict (its JSON, read by the same reader).
TestSpec read_test(const py::handle& test, const PluginHost& host) {
  if (py::isinstance<py::dict>(test)) {
    std::string text;
    try {
      text = py::module_::import("json").attr("dumps")(test).cast<std::string>();
    } catch (py::error_already_set& e) {
      if (!e.matches(PyExc_TypeError) && !e.matches(PyExc_ValueError)) throw;
      throw py::type_error("test: the dict holds a value JSON cannot hold: " + std::string(py::str(e.value())) +
                           " (allowed: dict, list, str, int, float, bool, None)");
    }
    return parse_test(text, "<dict>", host, fs::current_path());
  }
  if (py::isinstance<py::str>(test) || py::hasattr(test, "__fspath__")) {
    const auto path = py::module_::import("os").attr("fsdecode")(test).cast<std::string>();
    std::vector<TestSpec> tests = load_tests(path, host);
    if (tests.size() != 1)
      throw InputError(path + ": holds " + std::to_string(tests.size()) +
                       " tests (allowed: one test in a Session; salsa.run runs a queue)");
    return std::move(tests.front());
  }
  throw py::type_error("test: " + std::string(py::str(py::type::of(test).attr("__name__"))) +
                       " (allowed: a test file's path as str or os.PathLike, or a dict holding a test)");
}

py::dtype dtype_of(StateColumn::Type type) {
  switch (type) {
    case StateColumn::Type::f64: return py::dtype::of<double>();
    case StateColumn::Type::u32: return py::dtype::of<std::uint32_t>();
    case StateColumn::Type::u8: break;
  }
  return py::dtype::of<std::uint8_t>();
}

const char* dtype_name(StateColumn::Type type) {
  return type == StateColumn::Type::f64 ? "float64" : type == StateColumn::Type::u32 ? "uint32" : "uint8";
}

void make_read_only(py::array& a) { py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_; }

/// A model output's text as a number: "" (no value) is NaN, as the metrics' empty fields.
double number(const std::string& text) {
  if (text.empty()) return std::nan("");
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  return end == text.c_str() + text.size() ? v : std::nan("");
}

/// The metrics' summary.csv columns at each logged row (every log interval, and time 0), observed
/// there only, as `salsa run` observes them: a metric's observe may change what it measures later
/// (area_coverage stamps the cameras then), so observing at other moments would change its results.
class MetricRows final : public Observer {
 public:
  explicit MetricRows(MetricSet& metrics) : metrics_(metrics) {}
  void observe(const Simulation& sim) override { values = metrics_.observe(sim); }
  std::vector<double> values;

 private:
  MetricSet& metrics_;
};

class PySession {
 public:
  PySession(const py::handle& test, int threads) {
    if (threads < 0)
      throw py::value_error("threads: " + std::to_string(threads) + " is negative (allowed: a whole number >= 0; 0 means all cores)");
    host_ = shared_host();
    TestSpec spec = read_test(test, *host_);
    std::string warning;
    {
      py::gil_scoped_release nogil;
      try {
        // What `salsa run` checks before running: the same InputError, so the same line.
        warning = workload_warning(spec, make_setup(spec, *host_));
        session_ = std::make_unique<Session>(std::move(spec), *host_, SessionOptions{threads, nullptr});
      } catch (const TestFailure& e) {  // a plugin refusing at start: bad input for the caller
        throw InputError(e.what());
      }
    }
    outputs_.emplace(session_->current());  // the test models' summary columns, fixed at the start as summary.csv's
    rows_.emplace(session_->metrics());
    try {
      rows_->observe(session_->simulation());  // time 0, as summary.csv's first row
    } catch (const MetricFailure& e) {
      throw InputError(session_->where() + ": " + e.what());
    }
    session_->add_observer(&*rows_);
    if (!warning.empty() && PyErr_WarnEx(PyExc_RuntimeWarning, one_line(warning).c_str(), 1) != 0) throw py::error_already_set();
  }

  void step(std::int64_t n) {
    if (n < 0) throw py::value_error("n: " + std::to_string(n) + " is negative (allowed: a whole number of steps >= 0)");
    auto left = static_cast<std::uint64_t>(n);
    stepping([&] { return left-- > 0; });
  }

  void run_until(std::optional<double> t) {
    if (t && !std::isfinite(*t))
      throw py::value_error("t: " + std::to_string(*t) + " is not a finite number of seconds (allowed: a time in s, or None for the test's end)");
    const Simulation& sim = session_->simulation();
    if (!t) return stepping([&] { return !session_->finished(); });
    // To the step nearest t: the rule a timed change at t follows (llround(t / dt)).
    stepping([&] { return sim.time() < *t - sim.dt() / 2; });
  }

  void change(const std::string& key, double value) {
    idle("change");
    writable("change");
    session_->change(key, value);  // std::invalid_argument "key: why" becomes ValueError
  }

  /// The session as a test: its start state and every change so far, the live ones at the times they
  /// were made (the timeline the desktop's "Save as test" writes), through the writer of config.json.
  py::dict as_test() {
    idle("test");
    TestSpec t = session_->test();
    t.changes = session_->timeline();
    // Past the test's time (step may go on): the time reached, so that its replay holds every change.
    t.time = std::max(t.time, session_->simulation().time());
    return py::module_::import("json").attr("loads")(resolved_json(t, *host_));
  }

  py::array render(int width, int height) {
    idle("render");
#ifdef SALSA_PYTHON_RENDER
    return render_session(*session_, width, height);
#else
    (void)width, (void)height;
    throw py::value_error("render: this salsa was built without the desktop's drawing (SALSA_BUILD_GUI off, or no Qt 6)");
#endif
  }

  py::dict summary() {
    idle("summary");
    const Simulation& sim = session_->simulation();
    const SummaryRow row = summary_row(sim);
    py::dict out;
    out["time"] = row.time;
    out["targets_found"] = row.targets_found;
    out["fraction_found"] = row.fraction_found;
    out["mean_speed"] = row.mean_speed;
    out["max_speed"] = row.max_speed;
    out["mean_nn_distance"] = row.mean_nn_distance;
    out["collisions"] = row.collisions;
    const auto names = session_->metrics().step_columns();
    for (std::size_t i = 0; i < names.size() && i < rows_->values.size(); ++i) out[py::str(names[i])] = rows_->values[i];
    const auto texts = outputs_->values(sim, session_->current());
    for (std::size_t i = 0; i < outputs_->columns().size() && i < texts.size(); ++i)
      out[py::str(outputs_->columns()[i])] = number(texts[i]);
    return out;
  }

  py::dict columns() {
    idle("columns");
    py::dict out;
    for (const StateColumn& c : session_->simulation().columns()) {
      py::dict meta;
      meta["unit"] = std::string(c.unit);
      meta["model"] = std::string(c.model);
      meta["meaning"] = std::string(c.meaning);
      meta["dtype"] = dtype_name(c.type);
      meta["width"] = c.width;
      meta["rows"] = c.rows;
      meta["address"] = reinterpret_cast<std::uintptr_t>(c.data);
      out[py::str(std::string(c.name))] = meta;
    }
    return out;
  }

  static py::array column(const py::object& self, const std::string& name) {
    PySession& s = self.cast<PySession&>();
    s.idle("column");
    const StateColumn c = s.find(name);
    std::vector<py::ssize_t> shape{static_cast<py::ssize_t>(c.rows)};
    const auto item = static_cast<py::ssize_t>(c.item_size());
    std::vector<py::ssize_t> strides{item * static_cast<py::ssize_t>(c.width)};
    if (c.width == 2) shape.push_back(2), strides.push_back(item);
    // The session object is the view's base: the simulation's arrays live while a view does.
    py::array view = c.rows ? py::array(dtype_of(c.type), shape, strides, c.data, self) : py::array(dtype_of(c.type), shape, strides);
    make_read_only(view);
    return view;
  }

  py::dict targets() {
    idle("targets");
    // The core keeps a target's state as one struct per target, not as columns: these are copies.
    const auto& states = session_->simulation().targets();
    const auto n = static_cast<py::ssize_t>(states.size());
    py::array_t<double> position({n, py::ssize_t{2}});
    py::array_t<bool> found(n);
    py::array_t<double> found_time(n);
    py::array_t<std::int64_t> found_by(n);
    py::array_t<std::uint64_t> observations(n);
    auto p = position.mutable_unchecked<2>();
    auto f = found.mutable_unchecked<1>();
    auto ft = found_time.mutable_unchecked<1>();
    auto fb = found_by.mutable_unchecked<1>();
    auto o = observations.mutable_unchecked<1>();
    for (py::ssize_t i = 0; i < n; ++i) {
      const TargetState& t = states[static_cast<std::size_t>(i)];
      p(i, 0) = t.position.x, p(i, 1) = t.position.y;
      f(i) = t.found(), ft(i) = t.found_time, fb(i) = t.found_by, o(i) = t.observations;
    }
    py::dict out;
    out["position"] = position, out["found"] = found, out["found_time"] = found_time;
    out["found_by"] = found_by, out["observations"] = observations;
    return out;
  }

  /// The session, for reading; refused while another thread steps it.
  const Session& session(const char* what) const {
    idle(what);
    return *session_;
  }
  bool busy() const { return busy_; }

 private:
  /// Refuses a call while another thread steps this session (the GIL is released then). The stepping
  /// thread itself may read (a Python behavior's decide runs there, between two phases of a step, while
  /// nothing else writes the simulation), and so may any thread while the stepping thread is parked.
  void idle(const char* what) const {
    if (busy_ && !parked_ && std::this_thread::get_id() != stepper_)
      throw py::value_error(std::string(what) + ": the session is stepping in another thread (allowed: once step or run_until returns)");
  }
  /// What writes: refused during any step, parked or not.
  void writable(const char* what) const {
    if (busy_)
      throw py::value_error(std::string(what) + ": the session is inside a step (allowed: once step or run_until returns)");
  }

 public:
  /// The stepping thread, inside a Python behavior's decide, waits for another thread (salsa.Env): the
  /// session's reads are allowed there meanwhile, as nothing writes the simulation until it goes on.
  void park(bool on) {
    if (!busy_ || std::this_thread::get_id() != stepper_)
      throw py::value_error("_park: only the thread stepping the session parks it (allowed: inside a behavior's decide)");
    parked_ = on;
  }

 private:
  /// Steps while `more()` says so, without the GIL, taking it back about every 50 ms to let Ctrl-C
  /// (KeyboardInterrupt) stop between two steps.
  template <class More>
  void stepping(More more) {
    idle("step");
    writable("step");
    stepper_ = std::this_thread::get_id();
    busy_ = true;
    ++sessions_stepping();  // Python behaviors are not registered meanwhile (behavior.cpp)
    struct Done {
      std::atomic<bool>& flag;
      std::atomic<bool>& parked;
      ~Done() { parked = false, flag = false, --sessions_stepping(); }
    } done{busy_, parked_};
    for (bool left = true; left;) {
      {
        py::gil_scoped_release nogil;
        const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(50);
        while ((left = more())) {
          session_->step();
          if (std::chrono::steady_clock::now() >= until) break;
        }
      }
      if (PyErr_CheckSignals() != 0) throw py::error_already_set();
    }
  }

  StateColumn find(const std::string& name) const {
    std::string kept;
    for (const StateColumn& c : session_->simulation().columns()) {
      if (c.name == name) return c;
      kept += (kept.empty() ? "" : ", ") + std::string(c.name);
    }
    for (const StateColumn& c : declared_drone_columns())
      if (c.name == name)
        throw py::value_error("name: '" + name + "' is the " + std::string(c.model) +
                              " model's, which this session keeps no state for yet (allowed now: " + kept + ")");
    throw py::value_error("name: '" + name + "' is not a drone state column (allowed now: " + kept + ")");
  }

  std::shared_ptr<const PluginHost> host_;  // declared first: outlives the session made with it
  std::optional<MetricRows> rows_;          // before the session: it outlives the simulation that calls it
  std::unique_ptr<Session> session_;
  std::optional<ModelOutputs> outputs_;
  std::atomic<bool> busy_{false};
  std::atomic<bool> parked_{false};
  std::thread::id stepper_;  // the thread stepping while busy_
};

}  // namespace

void bind_session(py::module_& m) {
  py::class_<PySession>(m, "Session", R"(One test, stepped from Python with the core that `salsa run` uses.

Session(test, threads=0): `test` is a test file's path or a dict holding a test (what a test file
holds); a file holding more than one test is refused. Bad input raises salsa.InputError with the
CLI's line. `threads`: decide threads, 0 for all cores. Nothing is written to disk.)")
      .def(py::init<const py::handle&, int>(), py::arg("test"), py::arg("threads") = 0)
      .def("step", &PySession::step, py::arg("n") = 1,
           "Steps n times (the GIL released; Ctrl-C stops between steps). May go past the test's time.")
      .def("run_until", &PySession::run_until, py::arg("t") = py::none(),
           "Steps until the time is t s (to the nearest step), or with t None until the test's time; "
           "nothing when the time is past t already.")
      .def("change", &PySession::change, py::arg("key"), py::arg("value"),
           "A live change now, as a test's timed change (key: 'drones', 'behavior.params.<name>', "
           "'drone.<field>', 'fail.drone', 'wind.velocity.x', ...; docs/test-format.md). ValueError "
           "when refused; nothing changed then. Column views taken before are invalid after it.")
      .def("test", &PySession::as_test,
           "The session as a test dict: its test, every change made through change() as a timed change at "
           "the time it was made, and the test's own timed changes; its time the test's, or the time reached "
           "when past it. `salsa run` of it (or a Session of it stepped as far) replays this session byte for byte.")
      .def("render", &PySession::render, py::arg("width") = 800, py::arg("height") = 800,
           "The session now drawn as the desktop's sandbox draws it (the map fitted in, obstacles, targets found "
           "and not, bases, drones in their groups' colours, wind arrows, the legend): a (height, width, 3) uint8 "
           "RGB array. Without a QGuiApplication in the process one on Qt's offscreen platform is made.")
      .def("summary", &PySession::summary,
           "summary.csv's row now as a dict: column -> number (NaN: empty). The metrics' columns (coverage, "
           "mean_distance, ...) are those of the latest logged row (every log_interval s, and time 0): a "
           "metric is observed there only, as summary.csv observes it.")
      .def("columns", &PySession::columns,
           "The drone state columns kept now: name -> {unit, model, meaning, dtype, width, rows, address}.")
      .def("column", &PySession::column, py::arg("name"),
           "A read-only numpy view of the drone state column `name` (shape (rows,) or (rows, 2) for a "
           "vector), sharing the simulation's memory: no copy. Valid until the next step or change; "
           "take it again after them.")
      .def("targets", &PySession::targets,
           "The targets now, copied: position (n, 2) m, found (bool), found_time (s, NaN until found), "
           "found_by (drone id, -1 until found), observations (drone-steps in view).")
      .def_property_readonly("time", [](const PySession& s) { return s.session("time").simulation().time(); }, "Simulated time (s).")
      .def_property_readonly("steps", [](const PySession& s) { return s.session("steps").simulation().step_count(); }, "Steps taken.")
      .def_property_readonly("dt", [](const PySession& s) { return s.session("dt").simulation().dt(); }, "The time step (s).")
      .def_property_readonly("end_time", [](const PySession& s) { return s.session("end_time").test().time; }, "The test's time (s).")
      .def_property_readonly("finished", [](const PySession& s) { return s.session("finished").finished(); }, "The test's time is reached.")
      .def_property_readonly("name", [](const PySession& s) { return s.session("name").test().name; }, "The test's name.")
      .def_property_readonly("drones", [](const PySession& s) { return s.session("drones").simulation().drone_count(); },
                             "Drone ids so far, removed ones included (the columns' rows).")
      .def("_park", &PySession::park, py::arg("on"),
           "From inside a Python behavior's decide: other threads may read the session (not step or "
           "change it) until _park(False) (salsa.Env's stepping thread waits there for the actions).")
      .def("__repr__", [](const PySession& s) {
        if (s.busy()) return std::string("<salsa.Session, stepping>");
        const Session& session = s.session("repr");
        return "<salsa.Session " + session.where() + " at t = " + std::to_string(session.simulation().time()) + " s>";
      });
}

}  // namespace salsa::python
