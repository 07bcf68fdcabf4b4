// Behaviors written in Python (docs/python.md, "Behaviors in Python"): a salsa.Behavior subclass
// registered in the process's PluginHost as a Factory<Behavior>, each instance wrapped in a core
// BatchBehavior that hands decide() its group's perceptions as numpy views and the drones' own Rng
// streams, once per group per step, with the GIL taken back for the call (stepping released it).
#include <pybind11/numpy.h>

#include <cmath>
#include <cstddef>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "bindings.hpp"
#include "salsa/core/model/batch_behavior.hpp"

namespace salsa::python {

namespace {

static_assert(sizeof(Vec2) == 2 * sizeof(double), "a Vec2 array is viewed as (n, 2) doubles");

/// "none", "global" or "radio" as the SDK's SharedState; nothing for any other object.
std::optional<SharedState> shared_state_named(const py::handle& word) {
  if (!py::isinstance<py::str>(word)) return std::nullopt;
  const auto text = word.cast<std::string>();
  if (text == "none") return SharedState::none;
  if (text == "global") return SharedState::global;
  if (text == "radio") return SharedState::radio;
  return std::nullopt;
}

/// A Python reference that may outlive the interpreter (a factory in the static plugin host): released
/// with the GIL while Python runs, left alone after it finalised.
class PyRef {
 public:
  explicit PyRef(py::object o) : o_(o.release().ptr()) {}
  PyRef(const PyRef&) = delete;
  PyRef& operator=(const PyRef&) = delete;
  ~PyRef() {
    if (!Py_IsInitialized()) return;
    py::gil_scoped_acquire gil;
    Py_XDECREF(o_);
  }
  py::handle get() const { return o_; }

 private:
  PyObject* o_;
};

/// "ValueError: why (file.py:12)": a Python exception on one line, with where it was raised.
std::string describe(py::error_already_set& e) {
  std::string out = py::str(e.type().attr("__name__")).cast<std::string>();
  const std::string what = py::str(e.value()).cast<std::string>();
  if (!what.empty()) out += ": " + what;
  try {
    if (e.trace()) {
      py::list frames = py::module_::import("traceback").attr("extract_tb")(e.trace());
      if (!frames.empty()) {
        py::handle last = frames[frames.size() - 1];
        out += " (" + py::str(last.attr("filename")).cast<std::string>() + ":" +
               py::str(last.attr("lineno")).cast<std::string>() + ")";
      }
    }
  } catch (py::error_already_set&) {  // no location, then
  }
  return one_line(out);
}

/// "(4, 3)", "(2,)".
std::string shape(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t d = 0; d < a.ndim(); ++d) s += (d ? ", " : "") + std::to_string(a.shape(d));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

/// "float64 of shape (4, 3)", or the type's name of what is not an array.
std::string shape_of(const py::handle& o) {
  if (!py::isinstance<py::array>(o)) return py::str(py::type::of(o).attr("__name__")).cast<std::string>();
  const py::array a = py::reinterpret_borrow<py::array>(o);
  return py::str(a.dtype()).cast<std::string>() + " of shape " + shape(a);
}

using Doubles = py::array_t<double, py::array::c_style | py::array::forcecast>;

/// `o` as a C-ordered (rows, columns) array of doubles (numbers converted; 0: any length), or a
/// ValueError "name: what it is (allowed: ...)", what it is as "an array of shape (2,)" or "str".
Doubles numbers(const py::object& o, const char* name, py::ssize_t rows, py::ssize_t columns, const std::string& allowed) {
  Doubles a;
  try {
    a = Doubles::ensure(o);
  } catch (py::error_already_set&) {
  }
  if (!a || a.ndim() != 2 || (rows && a.shape(0) != rows) || (columns && a.shape(1) != columns))
    throw py::value_error(std::string(name) + ": " + (a ? "an array of shape " + shape(a) : shape_of(o)) + " (allowed: " + allowed + ")");
  return a;
}

using Bools = py::array_t<bool, py::array::c_style | py::array::forcecast>;

/// `where`, a numpy bool array of one entry per row, C-ordered (None, every row: an empty array).
Bools rows_where(const py::object& where, std::size_t n) {
  if (where.is_none()) return Bools(0);
  const py::array mask = py::isinstance<py::array>(where) ? py::array(where) : py::array();
  if (!py::isinstance<py::array_t<bool>>(where) || mask.ndim() != 1 || static_cast<std::size_t>(mask.shape(0)) != n)
    throw py::value_error("where: " + shape_of(where) + " (allowed: a numpy bool array of shape (" + std::to_string(n) +
                          ",), one entry per row)");
  return Bools::ensure(where);
}

/// The drones' random streams as decide sees them: one draw per row (or per row of `where`), from that
/// drone's own Rng, in row order. Usable during the decide call it came with only.
class PyBatchRng {
 public:
  explicit PyBatchRng(BatchRng* rngs) : rngs_(rngs) {}
  void close() { rngs_ = nullptr; }

  std::size_t size() const { return live().size(); }

  template <class T, class Draw>
  py::array_t<T> draw(const py::object& where, T skipped, Draw one) {
    BatchRng& rngs = live();
    const std::size_t n = rngs.size();
    py::array_t<T> out(static_cast<py::ssize_t>(n));
    T* o = out.mutable_data();
    const auto mask = rows_where(where, n);
    const bool* m = where.is_none() ? nullptr : mask.data();
    for (std::size_t r = 0; r < n; ++r) o[r] = !m || m[r] ? one(rngs[r]) : skipped;
    return out;
  }

 private:
  BatchRng& live() const {
    if (!rngs_) throw py::value_error("rng: used outside the decide call it was handed to (allowed: during that call)");
    return *rngs_;
  }
  BatchRng* rngs_;
};

/// Where decide's drones broadcast (Group.broadcast): row r's message through the core's outbox of
/// that drone, as Perception::broadcast. Usable during the decide call it came with only.
class PyBatchOutbox {
 public:
  PyBatchOutbox(const BatchOutbox* outbox, std::size_t message_size) : outbox_(outbox), message_size_(message_size) {}
  void close() { outbox_ = nullptr; }

  void broadcast(const py::object& payload, const py::object& where) const {
    if (!outbox_) throw py::value_error("broadcast: called outside the decide call its group was handed to (allowed: during that call)");
    const std::size_t n = outbox_->size();
    const Doubles p = numbers(payload, "payload", static_cast<py::ssize_t>(n), 0,
                              "numbers of shape (" + std::to_string(n) + ", K), row r the message of drone group.id[r]");
    const auto k = static_cast<std::size_t>(p.shape(1));
    if (k > message_size_)
      throw py::value_error("payload: " + std::to_string(k) + " doubles a message (allowed: at most message_size = " +
                            std::to_string(message_size_) + ")");
    const auto mask = rows_where(where, n);
    const bool* m = where.is_none() ? nullptr : mask.data();
    for (std::size_t r = 0; r < n; ++r)
      if (!m || m[r]) outbox_->broadcast(r, {p.data() + r * k, k});
  }

 private:
  const BatchOutbox* outbox_;
  std::size_t message_size_;
};

constexpr double nan = std::numeric_limits<double>::quiet_NaN();

/// The map's questions prepare may ask (World.is_free, World.ray_cast), one answer per row. Usable
/// during the prepare call it came with only: the WorldView is the core's, for that call.
class PyWorldQueries {
 public:
  explicit PyWorldQueries(const WorldView* world) : world_(world) {}
  void close() { world_ = nullptr; }

  py::array_t<bool> is_free(const py::object& points, double clearance) const {
    const WorldView& world = live("is_free");
    if (!std::isfinite(clearance) || clearance < 0)
      throw py::value_error("clearance: " + Parameter::format(clearance) + " (allowed: a finite number of m >= 0)");
    const Doubles p = rows("points", points);
    py::array_t<bool> out(p.shape(0));
    bool* o = out.mutable_data();
    const double* xy = p.data();
    for (py::ssize_t i = 0; i < p.shape(0); ++i) o[i] = world.is_free({xy[2 * i], xy[2 * i + 1]}, clearance);
    return out;
  }

  py::tuple ray_cast(const py::object& start, const py::object& end) const {
    const WorldView& world = live("ray_cast");
    const Doubles a = rows("start", start), b = rows("end", end);
    if (a.shape(0) != b.shape(0))
      throw py::value_error("end: " + std::to_string(b.shape(0)) + " rows (allowed: as many as start, " + std::to_string(a.shape(0)) + ")");
    const py::ssize_t n = a.shape(0);
    py::array_t<bool> hit(n);
    py::array_t<double> point({n, py::ssize_t{2}}), distance(n);
    bool* h = hit.mutable_data();
    double *pt = point.mutable_data(), *d = distance.mutable_data();
    for (py::ssize_t i = 0; i < n; ++i) {
      const auto found = world.ray_cast({a.data()[2 * i], a.data()[2 * i + 1]}, {b.data()[2 * i], b.data()[2 * i + 1]});
      h[i] = found.has_value();
      pt[2 * i] = found ? found->point.x : nan, pt[2 * i + 1] = found ? found->point.y : nan;
      d[i] = found ? found->distance : nan;
    }
    return py::make_tuple(hit, point, distance);
  }

 private:
  const WorldView& live(const char* what) const {
    if (!world_)
      throw py::value_error(std::string(what) + ": asked outside the prepare call its world was handed to (allowed: during that call)");
    return *world_;
  }
  /// `o` as an (M, 2) array of finite m, or why not.
  static Doubles rows(const char* name, const py::object& o) {
    const Doubles p = numbers(o, name, 0, 2, "points of shape (M, 2), m");
    for (py::ssize_t i = 0; i < 2 * p.shape(0); ++i)
      if (!std::isfinite(p.data()[i])) throw py::value_error(std::string(name) + ": a coordinate that is not finite (allowed: finite m)");
    return p;
  }
  const WorldView* world_;
};

/// A read-only view of `count` items of type T laid out `stride` bytes apart from `data` (+ `offset`
/// bytes), with `width` doubles per item when width > 1: (count,) or (count, width).
template <class T>
py::array view(const void* data, std::size_t count, std::size_t stride, std::size_t offset, const py::object& base, int width = 1) {
  std::vector<py::ssize_t> shape{static_cast<py::ssize_t>(count)}, strides{static_cast<py::ssize_t>(stride)};
  if (width > 1) shape.push_back(width), strides.push_back(sizeof(T));
  py::array a = count ? py::array(py::dtype::of<T>(), shape, strides, static_cast<const char*>(data) + offset, base)
                      : py::array(py::dtype::of<T>(), shape, strides);
  py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return a;
}

template <class T>
py::array column(const std::vector<T>& v, const py::object& base) {
  return view<T>(v.data(), v.size(), sizeof(T), 0, base);
}
py::array vectors(const std::vector<Vec2>& v, const py::object& base) {
  return view<double>(v.data(), v.size(), sizeof(Vec2), 0, base, 2);
}
/// Field `offset` of each item (type F, `width` F's) of rows' items.
template <class F, class Item>
py::array field(const PerceptionBatch::Rows<Item>& rows, std::size_t offset, const py::object& base, int width = 1) {
  return view<F>(rows.items.data(), rows.items.size(), sizeof(Item), offset, base, width);
}

class PyBatchBehavior final : public BatchBehavior {
 public:
  PyBatchBehavior(py::object instance, std::string name, Senses senses, std::optional<SharedState> shared, std::size_t message_size,
                  bool prepares, py::handle group_type, py::handle rows_type, py::handle world_type)
      : instance_(std::move(instance)), name_(std::move(name)), senses_(senses), shared_(shared), message_size_(message_size),
        prepares_(prepares),
        group_type_(py::reinterpret_borrow<py::object>(group_type)), rows_type_(py::reinterpret_borrow<py::object>(rows_type)),
        world_type_(py::reinterpret_borrow<py::object>(world_type)) {}
  ~PyBatchBehavior() override {
    if (!Py_IsInitialized()) {  // at exit, after Python: leave its objects be
      instance_.release(), group_type_.release(), rows_type_.release(), world_type_.release(), params_.release();
      return;
    }
    py::gil_scoped_acquire gil;
    instance_ = py::object(), group_type_ = py::object(), rows_type_ = py::object(), world_type_ = py::object(), params_ = py::object();
  }

  Senses senses() const override { return senses_; }
  /// The declared word, or what the class's shared_state method says for these parameter values.
  SharedState shared_state() const override {
    if (shared_) return *shared_;
    py::gil_scoped_acquire gil;
    py::object said;
    try {
      said = instance_.attr("shared_state")();
    } catch (py::error_already_set& e) {
      throw std::runtime_error("raised " + describe(e));
    }
    if (const auto known = shared_state_named(said)) return *known;
    throw std::runtime_error("returned " + py::repr(said).cast<std::string>() + " (allowed: \"none\", \"global\", \"radio\")");
  }
  std::size_t message_size() const override { return message_size_; }

  void reset(std::size_t drones) override { call("reset", drones); }
  void resize(std::size_t drones) override { call("resize", drones); }

  /// Called only when the class defines prepare: a step of a behavior without one takes no GIL here.
  void prepare(const WorldView& world) override {
    if (!prepares_) return;
    py::gil_scoped_acquire gil;
    try {
      py::object queries = py::cast(std::make_unique<PyWorldQueries>(&world));
      struct Close {
        PyWorldQueries& q;
        ~Close() { q.close(); }
      } close{queries.cast<PyWorldQueries&>()};
      instance_.attr("prepare")(world_of(world, queries));
    } catch (py::error_already_set& e) {
      throw std::runtime_error("Python behavior '" + name_ + "': prepare raised " + describe(e));
    }
  }

  void decide_batch(const std::shared_ptr<const PerceptionBatch>& batch, BatchRng& rngs, const BatchOutbox& outbox,
                    std::span<Vec2> steering) override {
    py::gil_scoped_acquire gil;
    auto fail = [&](const std::string& why) { return std::runtime_error("Python behavior '" + name_ + "': " + why); };
    try {
      // Owned by Python (decide may keep them), closed when the call returns: streams and outboxes are the core's.
      py::object rng_object = py::cast(std::make_unique<PyBatchRng>(&rngs));
      py::object outbox_object = py::cast(std::make_unique<PyBatchOutbox>(&outbox, message_size_));
      struct Close {
        PyBatchRng& r;
        PyBatchOutbox& o;
        ~Close() { r.close(), o.close(); }
      } close{rng_object.cast<PyBatchRng&>(), outbox_object.cast<PyBatchOutbox&>()};
      py::object g = group(batch);
      g.attr("__dict__")["broadcast"] = outbox_object.attr("broadcast");  // bound: an error names decide's line
      py::object result = instance_.attr("decide")(g, rng_object);
      take(result, steering, fail);
    } catch (py::error_already_set& e) {
      throw fail("decide raised " + describe(e));
    }
  }

 protected:
  void configure() override {
    py::gil_scoped_acquire gil;
    try {
      py::object values = group_type_.attr("__new__")(group_type_);
      py::dict d = values.attr("__dict__");
      for (const auto& [key, value] : parameters().items()) d[py::str(key)] = value;
      params_ = values;
      instance_.attr("params") = values;
    } catch (py::error_already_set& e) {
      throw std::runtime_error("Python behavior '" + name_ + "': " + describe(e));
    }
  }

 private:
  void call(const char* method, std::size_t drones) {
    py::gil_scoped_acquire gil;
    try {
      instance_.attr(method)(drones);
    } catch (py::error_already_set& e) {
      throw std::runtime_error("Python behavior '" + name_ + "': " + method + " raised " + describe(e));
    }
  }

  py::object rows(const std::vector<std::int64_t>& offsets, const py::object& base) const {
    py::object r = rows_type_.attr("__new__")(rows_type_);
    r.attr("__dict__")["offsets"] = column(offsets, base);
    return r;
  }

  /// The salsa.World prepare gets: copies of every drone's state, by id (the core's arrays change as it
  /// steps, and may grow or shrink between steps).
  py::object world_of(const WorldView& world, const py::object& queries) const {
    py::object w = world_type_.attr("__new__")(world_type_);
    py::dict d = w.attr("__dict__");
    const auto n = static_cast<py::ssize_t>(world.drone_positions().size());
    const auto vectors = [n](std::span<const Vec2> v) { return py::array_t<double>({n, py::ssize_t{2}}, &v.data()->x); };
    d["time"] = world.time(), d["dt"] = world.dt();
    const Rect b = world.bounds();
    d["bounds"] = py::make_tuple(b.min.x, b.min.y, b.max.x, b.max.y);
    d["position"] = vectors(world.drone_positions());
    d["velocity"] = vectors(world.drone_velocities());
    const auto groups_of = world.drone_groups();
    const auto status = world.drone_status();
    static_assert(sizeof(DroneStatus) == sizeof(std::uint8_t));
    d["group"] = py::array_t<std::uint32_t>(static_cast<py::ssize_t>(groups_of.size()), groups_of.data());
    d["status"] = py::array_t<std::uint8_t>(static_cast<py::ssize_t>(status.size()), reinterpret_cast<const std::uint8_t*>(status.data()));
    const auto groups = static_cast<py::ssize_t>(world.group_count());
    py::array_t<double> bases({groups, py::ssize_t{2}});
    for (py::ssize_t g = 0; g < groups; ++g) {
      const Vec2 base = world.base(static_cast<std::uint32_t>(g));
      bases.mutable_at(g, 0) = base.x, bases.mutable_at(g, 1) = base.y;
    }
    d["group_count"] = groups, d["bases"] = bases, d["own_group"] = Behavior::group();
    // Bound methods, so that an error names the line of prepare that asked.
    d["is_free"] = queries.attr("is_free"), d["ray_cast"] = queries.attr("ray_cast");
    return w;
  }

  /// The salsa.Group decide gets: views of the batch, which the capsule keeps alive as long as any is.
  py::object group(const std::shared_ptr<const PerceptionBatch>& shared) const {
    const PerceptionBatch& b = *shared;
    const py::object base = py::capsule(new std::shared_ptr<const PerceptionBatch>(shared),
                                        [](void* p) { delete static_cast<std::shared_ptr<const PerceptionBatch>*>(p); });
    py::object g = group_type_.attr("__new__")(group_type_);
    py::dict d = g.attr("__dict__");
    d["id"] = column(b.id, base);
    d["position"] = vectors(b.position, base);
    d["velocity"] = vectors(b.velocity, base);
    d["air_velocity"] = vectors(b.air_velocity, base);
    d["wind"] = vectors(b.wind, base);
    d["battery"] = column(b.battery, base);
    d["time"] = b.time, d["dt"] = b.dt, d["group"] = b.group;
    d["max_speed"] = b.drone.max_speed, d["max_force"] = b.drone.max_force, d["radius"] = b.drone.radius;
    d["mass"] = b.drone.mass, d["camera_range"] = b.drone.camera_range, d["obstacle_range"] = b.drone.obstacle_range;
    d["detection_range"] = b.drone.detection_range, d["battery_capacity"] = b.battery_capacity;
    d["base"] = py::make_tuple(b.base.x, b.base.y);

    py::object n = rows(b.neighbours.offsets, base);
    py::dict nd = n.attr("__dict__");
    nd["id"] = field<std::uint32_t>(b.neighbours, offsetof(Neighbour, id), base);
    nd["group"] = field<std::uint32_t>(b.neighbours, offsetof(Neighbour, group), base);
    nd["position"] = field<double>(b.neighbours, offsetof(Neighbour, position), base, 2);
    nd["velocity"] = field<double>(b.neighbours, offsetof(Neighbour, velocity), base, 2);
    nd["distance"] = field<double>(b.neighbours, offsetof(Neighbour, distance), base);
    d["neighbours"] = n;

    py::object t = rows(b.targets.offsets, base);
    py::dict td = t.attr("__dict__");
    td["id"] = field<std::uint32_t>(b.targets, offsetof(TargetSeen, id), base);
    td["position"] = field<double>(b.targets, offsetof(TargetSeen, position), base, 2);
    td["distance"] = field<double>(b.targets, offsetof(TargetSeen, distance), base);
    td["found"] = field<bool>(b.targets, offsetof(TargetSeen, found), base);
    d["targets"] = t;

    py::object o = rows(b.obstacles.offsets, base);
    py::dict od = o.attr("__dict__");
    od["point"] = field<double>(b.obstacles, offsetof(ObstacleHit, point), base, 2);
    od["distance"] = field<double>(b.obstacles, offsetof(ObstacleHit, distance), base);
    d["obstacles"] = o;

    py::object m = rows(b.messages.offsets, base);
    py::dict md = m.attr("__dict__");
    md["sender"] = field<std::uint32_t>(b.messages, offsetof(Message, sender), base);
    md["group"] = field<std::uint32_t>(b.messages, offsetof(Message, group), base);
    md["offset"] = field<double>(b.messages, offsetof(Message, offset), base, 2);
    md["time"] = field<double>(b.messages, offsetof(Message, time), base);
    md["payload"] = column(b.payloads, base);
    md["payload_offsets"] = column(b.payload_offsets, base);
    d["messages"] = m;

    for (const auto& [key, value] : parameters().items()) d[py::str(key)] = value;
    return g;
  }

  /// decide's return value into `steering`, or why it cannot be (shape, dtype, a value not finite).
  template <class Fail>
  void take(const py::object& result, std::span<Vec2> steering, Fail fail) const {
    const std::string allowed = " (allowed: a numpy float64 array of shape (" + std::to_string(steering.size()) +
                                ", 2), m/s, one row per drone of group.id)";
    if (!py::isinstance<py::array>(result)) throw fail("decide returned " + shape_of(result) + allowed);
    const py::array a = result;
    if (!a.dtype().is(py::dtype::of<double>()) || a.ndim() != 2 || a.shape(0) != static_cast<py::ssize_t>(steering.size()) ||
        a.shape(1) != 2)
      throw fail("decide returned " + shape_of(result) + allowed);
    const auto s = py::array_t<double>(result).unchecked<2>();
    for (py::ssize_t r = 0; r < s.shape(0); ++r) {
      const Vec2 v{s(r, 0), s(r, 1)};
      if (!v.finite())
        throw fail("decide returned a steering that is not finite, (" + Parameter::format(v.x) + ", " + Parameter::format(v.y) +
                   ") at row " + std::to_string(r) + allowed);
      steering[static_cast<std::size_t>(r)] = v;
    }
  }

  py::object instance_;
  std::string name_;
  Senses senses_;
  std::optional<SharedState> shared_;  // none: the class asks its shared_state method
  std::size_t message_size_;
  bool prepares_;  // the class defines prepare
  py::object group_type_, rows_type_, world_type_, params_;
};

/// Every behavior registered from Python, with its origin, for hosts made later (add_python_behaviors).
std::vector<std::pair<Factory<Behavior>, std::string>>& registered() {
  static std::vector<std::pair<Factory<Behavior>, std::string>> list;
  return list;
}

/// The class's declarations checked, then registered in the plugin host.
void register_behavior(const py::object& cls) {
  const py::module_ declared = py::module_::import("salsa._behavior");
  const py::object base = declared.attr("Behavior");
  if (!py::isinstance<py::type>(cls) || !PyObject_IsSubclass(cls.ptr(), base.ptr()))
    throw py::type_error("register: " + py::repr(cls).cast<std::string>() + " (allowed: a subclass of salsa.Behavior)");
  const std::string label = py::str(cls.attr("__module__")).cast<std::string>() + "." + py::str(cls.attr("__qualname__")).cast<std::string>();
  auto refuse = [&](const std::string& why) { return py::value_error("register: " + label + ": " + why); };
  if (!py::isinstance<py::str>(cls.attr("name")))
    throw refuse("name: " + py::repr(cls.attr("name")).cast<std::string>() + " (allowed: a str, the name tests use)");
  Factory<Behavior> f;
  f.name = cls.attr("name").cast<std::string>();
  if (!py::isinstance<py::str>(cls.attr("brief"))) throw refuse("brief: not a str");
  f.brief = cls.attr("brief").cast<std::string>();
  const py::object senses = cls.attr("senses");
  if (!py::isinstance(senses, declared.attr("Senses")))
    throw refuse("senses: " + py::repr(senses).cast<std::string>() + " (allowed: a salsa.Senses)");
  const Senses sensed{senses.attr("neighbours").cast<bool>(), senses.attr("targets").cast<bool>()};
  // A word, or a method that says it from the parameter values (as a C++ behavior's shared_state()).
  const py::object shared_declared = cls.attr("shared_state");
  const std::optional<SharedState> shared = shared_state_named(shared_declared);
  if (!shared && !py::isinstance(shared_declared, py::module_::import("types").attr("FunctionType")))
    throw refuse("shared_state: " + py::repr(shared_declared).cast<std::string>() +
                 " (allowed: \"none\", \"global\", \"radio\", or a method returning one)");
  const py::object size = cls.attr("message_size");
  if (!py::isinstance<py::int_>(size) || py::isinstance<py::bool_>(size) || size.cast<long long>() < 0 ||
      size.cast<long long>() > static_cast<long long>(max_message_size))
    throw refuse("message_size: " + py::repr(size).cast<std::string>() + " (allowed: a whole number of doubles in [0, " +
                 std::to_string(max_message_size) + "])");
  const auto message_size = size.cast<std::size_t>();
  // Group's own fields: a parameter of one of these names would hide it.
  static const char* taken[] = {"id", "position", "velocity", "air_velocity", "wind", "battery", "time", "dt", "group",
                                "max_speed", "max_force", "radius", "mass", "camera_range", "obstacle_range",
                                "detection_range", "battery_capacity", "base", "neighbours", "targets", "obstacles", "messages", "broadcast"};
  for (const py::handle p : py::iter(cls.attr("parameters"))) {
    if (!py::isinstance(p, declared.attr("Param")))
      throw refuse("parameters: " + py::repr(p).cast<std::string>() + " (allowed: a list of salsa.Param)");
    Parameter q;
    q.name = p.attr("name").cast<std::string>();
    for (const char* t : taken)
      if (q.name == t) throw refuse("parameter '" + q.name + "' has the name of a field of the group decide gets (choose another)");
    q.value = p.attr("default").cast<double>();
    const auto range = p.attr("range").cast<std::pair<double, double>>();
    q.min = range.first, q.max = range.second;
    q.unit = p.attr("unit").cast<std::string>();
    q.description = p.attr("meaning").cast<std::string>();
    q.step = p.attr("step").cast<double>();
    f.parameters.push_back(std::move(q));
  }
  auto type = std::make_shared<PyRef>(cls);
  auto group_type = std::make_shared<PyRef>(declared.attr("Group"));
  auto rows_type = std::make_shared<PyRef>(declared.attr("Rows"));
  auto world_type = std::make_shared<PyRef>(declared.attr("World"));
  const bool prepares = !cls.attr("prepare").is(base.attr("prepare"));
  f.create = [type, group_type, rows_type, world_type, name = f.name, sensed, shared, message_size, prepares,
              label]() -> std::unique_ptr<Behavior> {
    // The core makes behaviors while stepping or starting a Session, without the GIL.
    py::gil_scoped_acquire gil;
    try {
      return std::make_unique<PyBatchBehavior>(type->get()(), name, sensed, shared, message_size, prepares, group_type->get(),
                                               rows_type->get(), world_type->get());
    } catch (py::error_already_set& e) {
      throw std::runtime_error(label + "() raised " + describe(e));
    }
  };
  if (sessions_stepping() > 0)
    throw refuse("a Session is stepping in another thread (allowed: once no Session steps)");
  try {
    plugin_host().add_behavior(f, "Python class " + label);
  } catch (const std::invalid_argument& e) {
    throw refuse(e.what());
  }
  std::erase_if(registered(), [&](const auto& r) { return r.first.name == f.name; });
  registered().emplace_back(std::move(f), "Python class " + label);
}

}  // namespace

void add_python_behaviors(PluginHost& host) {
  for (const auto& [factory, origin] : registered()) host.add_behavior(factory, origin);
}

void bind_behavior(py::module_& m) {
  py::class_<PyBatchRng>(m, "BatchRng", R"(The drones' own random streams, handed to Behavior.decide.

Each draw gives one number per row of the group (an array of shape (N,)), each from that drone's own
stream: the Rng a C++ behavior draws from, so drawing in the order a C++ behavior does gives its
numbers. `where` (a bool array of shape (N,)) draws only for its True rows; the others are NaN
(False for chance, -1 for index) and their streams do not move. Usable during that decide call only.)")
      .def("__len__", &PyBatchRng::size)
      .def(
          "uniform",
          [](PyBatchRng& r, double low, double high, const py::object& where) {
            return r.draw<double>(where, nan, [&](Rng& g) { return g.uniform(low, high); });
          },
          py::arg("low") = 0.0, py::arg("high") = 1.0, py::arg("where") = py::none(), "Uniform in [low, high) (Rng::uniform).")
      .def(
          "angle", [](PyBatchRng& r, const py::object& where) { return r.draw<double>(where, nan, [](Rng& g) { return g.angle(); }); },
          py::arg("where") = py::none(), "Uniform angle in [0, 2π) rad (Rng::angle).")
      .def(
          "normal",
          [](PyBatchRng& r, double mean, double stddev, const py::object& where) {
            return r.draw<double>(where, nan, [&](Rng& g) { return g.normal(mean, stddev); });
          },
          py::arg("mean") = 0.0, py::arg("stddev") = 1.0, py::arg("where") = py::none(), "Normal (Rng::normal, Box–Muller).")
      .def(
          "chance",
          [](PyBatchRng& r, double p, const py::object& where) { return r.draw<bool>(where, false, [&](Rng& g) { return g.chance(p); }); },
          py::arg("p"), py::arg("where") = py::none(), "True with probability p (Rng::chance).")
      .def(
          "index",
          [](PyBatchRng& r, std::uint64_t n, const py::object& where) {
            if (n == 0) throw py::value_error("n: 0 (allowed: a whole number >= 1)");
            return r.draw<std::int64_t>(where, -1, [&](Rng& g) { return static_cast<std::int64_t>(g.index(n)); });
          },
          py::arg("n"), py::arg("where") = py::none(), "Uniform whole number in [0, n) (Rng::index).");
  py::class_<PyBatchOutbox>(m, "BatchOutbox", "Where decide's drones broadcast (Group.broadcast), during that call only.")
      .def("broadcast", &PyBatchOutbox::broadcast, py::arg("payload"), py::arg("where") = py::none(),
           R"(Row r's drone broadcasts payload[r] this step ((N, K) numbers, K <= the class's message_size), as
Perception::broadcast: drones in the comm model's reach receive it in a later step's messages; a second
call for a row replaces its first. `where` (a bool array of shape (N,)) broadcasts only for its True rows.)");
  py::class_<PyWorldQueries>(m, "WorldQueries", "The map's questions a World answers, during the prepare call only.")
      .def("is_free", &PyWorldQueries::is_free, py::arg("points"), py::arg("clearance") = 0.0,
           R"(Whether a disc of radius `clearance` (m) at each of `points` ((M, 2), m) is inside the map and
touches no obstacle: (M,) bool (WorldView::is_free).)")
      .def("ray_cast", &PyWorldQueries::ray_cast, py::arg("start"), py::arg("end"),
           R"(The first obstacle on each segment start[i] -> end[i] ((M, 2) each, m): (hit (M,) bool,
point (M, 2), distance (M,) m from start), NaN where nothing is hit (WorldView::ray_cast).)");
  m.def("register_behavior", &register_behavior, py::arg("cls"), "salsa.register's work: the class checked and registered.");
  m.def("_behaviors", [] {
    py::list out;
    for (const auto& e : shared_host()->behaviors()) {
      py::list params;
      for (const Parameter& p : e.factory.parameters)
        params.append(py::make_tuple(p.name, p.value, py::make_tuple(p.min, p.max), p.unit, p.description, p.step));
      out.append(py::make_tuple(e.factory.name, e.factory.brief, e.plugin().file.string(), params));
    }
    return out;
  });
}

}  // namespace salsa::python
