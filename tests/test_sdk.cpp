// The plugin SDK on its own: vector math, random numbers, parameters, the point grid, the registration
// macros and the steering helpers. Needs no core library and no plugins.
#define SALSA_PLUGIN_NAME "sdk_test"
#define SALSA_PLUGIN_VERSION "9.8.7"
#include <salsa/sdk.hpp>
#include <salsa/testing.hpp>

#include <QtTest>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <vector>

#include "common.hpp"

using salsa::Vec2;

Q_DECLARE_METATYPE(Vec2)

namespace {

bool near(double a, double b, double eps = 1e-12) { return std::abs(a - b) <= eps * std::max(1.0, std::abs(b)); }
bool near(Vec2 a, Vec2 b, double eps = 1e-12) { return near(a.x, b.x, eps) && near(a.y, b.y, eps); }
QByteArray show(Vec2 v) { return QByteArray("(") + QByteArray::number(v.x, 'g', 17) + ", " + QByteArray::number(v.y, 'g', 17) + ")"; }
#define VEC_COMPARE(actual, expected, eps)                                                          \
  QVERIFY2(near((actual), (expected), (eps)),                                                       \
           QByteArray("got " + show(actual) + ", expected " + show(expected)).constData())

// ---- Classes registered with the SDK's macros, as a plugin author writes them ----

class SdkBehavior final : public salsa::Behavior {
 public:
  static salsa::Parameters declare() {
    return {{"speed", 4.0, 1.0, 8.0, "m/s", "how fast"}, {"count", 3, 1, 10, "", "how many", 1}};
  }
  Vec2 decide(const salsa::Perception&, salsa::Rng&) override { return {speed_, 0}; }
  int configured = 0;

 protected:
  void configure() override {
    speed_ = param("speed");
    ++configured;
  }

 private:
  double speed_ = 0;
};

class SdkTarget final : public salsa::TargetKind {
 public:
  static salsa::Parameters declare() { return {{"radius", 2.5, 0.1, 10.0, "m", "target radius"}}; }
  double radius() const override { return param("radius"); }
};

class SdkMap final : public salsa::MapGenerator {
 public:
  static salsa::Parameters declare() { return {{"size", 100.0, 10.0, 1000.0, "m", "side"}}; }
  salsa::MapData generate(const std::string&, salsa::Rng&) const override {
    salsa::MapData m;
    m.bounds = {{0, 0}, {param("size"), param("size")}};
    return m;
  }
};

/// Sums the four steering helpers with Table I's weights (as the flocking plugin does).
class SdkFlock final : public salsa::Behavior {
 public:
  Vec2 decide(const salsa::Perception& me, salsa::Rng&) override {
    return 1.6 * salsa::alignment(me) + 3.0 * salsa::avoid_drones(me, 250) + 1.0 * salsa::cohesion(me) +
           4.0 * salsa::avoid_obstacles(me);
  }
};

/// Parameters written once, as members; one declared the old way too (declared first, then members).
class SdkBound final : public salsa::Behavior {
  salsa::Param speed{this, "speed", 4.0, 1.0, 8.0, "m/s", "how fast"};
  salsa::Param count{this, {"count", 3, 1, 10, "", "how many", 1}};

 public:
  static salsa::Parameters declare() { return {{"legacy", 0.5, 0.0, 1.0, "", "read by name"}}; }
  Vec2 decide(const salsa::Perception&, salsa::Rng&) override { return {speed, count + param("legacy")}; }
  double seen_in_configure = 0;

 protected:
  void configure() override { seen_in_configure = speed; }  // members are set before configure runs
};

/// Draws one number per decision: the stream goes on between calls.
class SdkDraw final : public salsa::Behavior {
 public:
  Vec2 decide(const salsa::Perception&, salsa::Rng& rng) override { return {rng.uniform(0, 1), 0}; }
};

/// Counts its decisions per drone in its memory.
class SdkCounter final : public salsa::BehaviorWithMemory<int> {
 public:
  Vec2 decide(const salsa::Perception&, int& count, salsa::Rng&) override { return {static_cast<double>(++count), 0}; }
};

class SdkHandler final : public salsa::ContactHandler {  // no declare(): no parameters
 public:
  void on_contact(const salsa::ContactEvent&, salsa::ContactActions&) override {}
};

class SdkMetric final : public salsa::Metric {
 public:
  static salsa::Parameters declare() { return {{"scale", 2.0, 0.0, 10.0, "", "factor"}}; }
  std::vector<salsa::Column> final_columns() const override { return {{"sdk_value", "m", "scale"}}; }
  void finish(const salsa::MetricView&, std::span<double> values) override { values[0] = param("scale"); }
};

class SdkWind final : public salsa::WindField {
  salsa::Param speed{this, "speed", 3.0, 0.0, 10.0, "m/s", "wind speed"};

 public:
  salsa::Vec2 velocity(salsa::Vec2 p, double t) const override { return {speed, p.y + t}; }
};

}  // namespace

SALSA_BEHAVIOR(SdkBehavior, "sdk_behavior", "behavior brief")
SALSA_TARGET(SdkTarget, "sdk_target", "target brief")
SALSA_MAP(SdkMap, "sdk_map", "map brief")
SALSA_CONTACT_HANDLER(SdkHandler, "sdk_handler", "handler brief")
SALSA_METRIC(SdkMetric, "sdk_metric", "metric brief")
SALSA_WIND(SdkWind, "sdk_wind", "wind brief")

namespace {

struct Collector final : salsa::Registrar {
  std::vector<salsa::Factory<salsa::Behavior>> behaviors;
  std::vector<salsa::Factory<salsa::TargetKind>> targets;
  std::vector<salsa::Factory<salsa::MapGenerator>> maps;
  std::vector<salsa::Factory<salsa::ContactHandler>> handlers;
  std::vector<salsa::Factory<salsa::Metric>> metrics;
  std::vector<salsa::Factory<salsa::WindField>> winds;
  void add(salsa::Factory<salsa::Behavior> f) override { behaviors.push_back(std::move(f)); }
  void add(salsa::Factory<salsa::TargetKind> f) override { targets.push_back(std::move(f)); }
  void add(salsa::Factory<salsa::MapGenerator> f) override { maps.push_back(std::move(f)); }
  void add(salsa::Factory<salsa::ContactHandler> f) override { handlers.push_back(std::move(f)); }
  void add(salsa::Factory<salsa::Metric> f) override { metrics.push_back(std::move(f)); }
  void add(salsa::Factory<salsa::WindField> f) override { winds.push_back(std::move(f)); }
};

salsa::Perception perception(Vec2 velocity, double max_force) {
  salsa::Perception me;
  me.position = {0, 0};
  me.velocity = velocity;
  me.max_speed = 10;
  me.max_force = max_force;
  return me;
}

}  // namespace

class TestSdk : public QObject {
  Q_OBJECT

 private Q_SLOTS:
  // ---------------------------------------------------------------- Vec2
  void normalized_data() {
    QTest::addColumn<Vec2>("v");
    QTest::addColumn<Vec2>("expected");
    QTest::newRow("3-4-5") << Vec2{3, 4} << Vec2{0.6, 0.8};
    QTest::newRow("negative") << Vec2{-5, 0} << Vec2{-1, 0};
    QTest::newRow("already unit") << Vec2{0, 1} << Vec2{0, 1};
    QTest::newRow("tiny") << Vec2{3e-150, -4e-150} << Vec2{0.6, -0.8};
    QTest::newRow("zero stays zero") << Vec2{} << Vec2{};
  }
  void normalized() {
    QFETCH(Vec2, v);
    QFETCH(Vec2, expected);
    const Vec2 n = v.normalized();
    VEC_COMPARE(n, expected, 1e-15);
    QVERIFY(std::isfinite(n.x) && std::isfinite(n.y));
  }

  void clamped_data() {
    QTest::addColumn<Vec2>("v");
    QTest::addColumn<double>("max");
    QTest::addColumn<Vec2>("expected");
    QTest::newRow("shorter: unchanged") << Vec2{3, 4} << 10.0 << Vec2{3, 4};
    QTest::newRow("exactly max: unchanged") << Vec2{3, 4} << 5.0 << Vec2{3, 4};
    QTest::newRow("longer: shortened") << Vec2{3, 4} << 2.5 << Vec2{1.5, 2};
    QTest::newRow("to zero") << Vec2{3, 4} << 0.0 << Vec2{0, 0};
    QTest::newRow("zero stays zero") << Vec2{} << 1.0 << Vec2{};
    QTest::newRow("zero with max zero") << Vec2{} << 0.0 << Vec2{};
  }
  void clamped() {
    QFETCH(Vec2, v);
    QFETCH(double, max);
    QFETCH(Vec2, expected);
    VEC_COMPARE(v.clamped(max), expected, 1e-15);
  }

  void with_length_data() {
    QTest::addColumn<Vec2>("v");
    QTest::addColumn<double>("length");
    QTest::addColumn<Vec2>("expected");
    QTest::newRow("longer") << Vec2{3, 4} << 10.0 << Vec2{6, 8};
    QTest::newRow("shorter") << Vec2{0, -8} << 2.0 << Vec2{0, -2};
    QTest::newRow("zero length") << Vec2{3, 4} << 0.0 << Vec2{};
    QTest::newRow("zero stays zero") << Vec2{} << 5.0 << Vec2{};
  }
  void with_length() {
    QFETCH(Vec2, v);
    QFETCH(double, length);
    QFETCH(Vec2, expected);
    VEC_COMPARE(v.with_length(length), expected, 1e-15);
  }

  void rotated_and_polar() {
    VEC_COMPARE(Vec2(1, 0).rotated(salsa::pi / 2), Vec2(0, 1), 1e-15);
    VEC_COMPARE(Vec2(1, 0).rotated(-salsa::pi / 2), Vec2(0, -1), 1e-15);
    VEC_COMPARE(Vec2(2, 1).rotated(salsa::pi), Vec2(-2, -1), 1e-15);
    VEC_COMPARE(Vec2(3, 4).rotated(0.7).rotated(-0.7), Vec2(3, 4), 1e-14);
    QVERIFY(near(Vec2(3, 4).rotated(1.234).length(), 5, 1e-14));
    VEC_COMPARE(Vec2::polar(2, salsa::pi / 3), Vec2(1, std::sqrt(3.0)), 1e-15);
    VEC_COMPARE(Vec2::polar(5, -salsa::pi / 2), Vec2(0, -5), 1e-15);
    VEC_COMPARE(Vec2::polar(0, 1.0), Vec2(), 0);
    QVERIFY(near(Vec2(-1, 1).angle(), 3 * salsa::pi / 4));
    for (double a : {-3.0, -1.0, 0.0, 0.5, 2.0, 3.1})
      QVERIFY2(near(Vec2::polar(1, a).angle(), a, 1e-14), qPrintable(QString::number(a)));
  }

  void products_and_distances() {
    QCOMPARE(Vec2(1, 0).cross(Vec2(0, 1)), 1.0);   // counter-clockwise: positive
    QCOMPARE(Vec2(0, 1).cross(Vec2(1, 0)), -1.0);  // clockwise: negative
    QCOMPARE(Vec2(2, 3).cross(Vec2(4, 6)), 0.0);   // parallel
    QCOMPARE(Vec2(2, 3).dot(Vec2(4, -5)), -7.0);
    QCOMPARE(Vec2(1, 0).dot(Vec2(0, 1)), 0.0);
    QCOMPARE(Vec2(3, 4).length(), 5.0);
    QCOMPARE(Vec2(3, 4).length_squared(), 25.0);
    QCOMPARE(salsa::distance(Vec2(1, 1), Vec2(4, 5)), 5.0);
    QCOMPARE(salsa::distance_squared(Vec2(1, 1), Vec2(4, 5)), 25.0);
    QVERIFY(Vec2().is_zero());
    QVERIFY(!Vec2(0, 1e-300).is_zero());
    QCOMPARE(Vec2(1, 2) + Vec2(3, 4), Vec2(4, 6));
    QCOMPARE(Vec2(1, 2) - Vec2(3, 5), Vec2(-2, -3));
    QCOMPARE(2.0 * Vec2(1, 2), Vec2(2, 4));
    QCOMPARE(Vec2(1, 2) * 2.0, Vec2(2, 4));
    QCOMPARE(Vec2(2, 4) / 2.0, Vec2(1, 2));
    QCOMPARE(-Vec2(1, -2), Vec2(-1, 2));
    Vec2 v{1, 1};
    v += {1, 2};
    v *= 3;
    v -= {1, 1};
    v /= 2;
    QCOMPARE(v, Vec2(2.5, 4));

    const salsa::Rect r{{-10, 0}, {30, 20}};
    QCOMPARE(r.width(), 40.0);
    QCOMPARE(r.height(), 20.0);
    QCOMPARE(r.area(), 800.0);
    QCOMPARE(r.centre(), Vec2(10, 10));
    QVERIFY(r.contains({-10, 0}));   // edges are inside
    QVERIFY(r.contains({30, 20}));
    QVERIFY(!r.contains({30.001, 5}));
    QVERIFY(!r.contains({0, -0.001}));
  }

  // ---------------------------------------------------------------- Rng
  void rng_matches_reference_xoshiro256starstar_data() {
    QTest::addColumn<quint64>("seed");
    QTest::addColumn<quint64>("stream");
    QTest::addColumn<quint64>("first");
    QTest::addColumn<quint64>("second");
    QTest::addColumn<quint64>("third");
    // From the reference splitmix64 + xoshiro256** (computed independently, in Python): the same
    // seed gives the same run on every platform and library version.
    QTest::newRow("0/0") << quint64(0) << quint64(0) << quint64(0x422ea740d0977210) << quint64(0xe062b061b42e2928)
                         << quint64(0x5a071fc5930841b6);
    QTest::newRow("42/7") << quint64(42) << quint64(7) << quint64(0xcdf2377c42bb68f5) << quint64(0x8cb64cac7d78371a)
                          << quint64(0x9a8c8ee0b16b3b9b);
    QTest::newRow("1/16") << quint64(1) << quint64(16) << quint64(0xf8a311c04391468f) << quint64(0xe54ebc5596224613)
                          << quint64(0x9a12d15b68bd0381);
  }
  void rng_matches_reference_xoshiro256starstar() {
    QFETCH(quint64, seed);
    QFETCH(quint64, stream);
    QFETCH(quint64, first);
    QFETCH(quint64, second);
    QFETCH(quint64, third);
    salsa::Rng rng(seed, stream);
    QCOMPARE(quint64(rng.next()), first);
    QCOMPARE(quint64(rng.next()), second);
    QCOMPARE(quint64(rng.next()), third);
  }

  void rng_same_seed_same_sequence() {
    salsa::Rng a(12345, 3), b(12345, 3);
    for (int i = 0; i < 10000; ++i) QCOMPARE(a.next(), b.next());
    salsa::Rng c(7, 1), d(7, 1);
    for (int i = 0; i < 1000; ++i) {
      QCOMPARE(c.uniform(), d.uniform());
      QCOMPARE(c.normal(), d.normal());
      QCOMPARE(c.angle(), d.angle());
      QCOMPARE(c.in_disc({1, 2}, 3), d.in_disc({1, 2}, 3));
    }
  }

  void rng_streams_and_seeds_differ() {
    // Streams are per drone: 1000 streams of one seed start with 1000 different values, and their
    // sequences do not coincide anywhere in the first steps.
    std::set<std::uint64_t> firsts;
    for (std::uint64_t stream = 0; stream < 1000; ++stream) firsts.insert(salsa::Rng(99, stream).next());
    QCOMPARE(firsts.size(), std::size_t(1000));
    std::set<std::uint64_t> seeds;
    for (std::uint64_t seed = 0; seed < 1000; ++seed) seeds.insert(salsa::Rng(seed, 5).next());
    QCOMPARE(seeds.size(), std::size_t(1000));
    salsa::Rng a(1, 0), b(1, 1);
    int equal = 0;
    for (int i = 0; i < 1000; ++i) equal += a.next() == b.next();
    QCOMPARE(equal, 0);
    // seed ^ f(stream) must not make (seed, stream) pairs collide trivially.
    QVERIFY(salsa::Rng(0, 1).next() != salsa::Rng(1, 0).next());
  }

  void rng_uniform_range_and_moments() {
    salsa::Rng rng(2024, 0);
    const int n = 200000;
    double sum = 0, lo = 1, hi = 0;
    for (int i = 0; i < n; ++i) {
      const double u = rng.uniform();
      QVERIFY2(u >= 0.0 && u < 1.0, qPrintable(QString::number(u, 'g', 17)));
      sum += u;
      lo = std::min(lo, u);
      hi = std::max(hi, u);
    }
    QVERIFY(std::abs(sum / n - 0.5) < 0.005);
    QVERIFY(lo < 0.001 && hi > 0.999);
    for (int i = 0; i < 10000; ++i) {
      const double u = rng.uniform(-3, 5);
      QVERIFY(u >= -3 && u < 5);
      const double a = rng.angle();
      QVERIFY(a >= 0 && a < 2 * salsa::pi);
      const Vec2 p = rng.in_disc({10, -10}, 4);
      QVERIFY(salsa::distance(p, {10, -10}) <= 4);
      const Vec2 r = rng.in_rect({{-1, 2}, {3, 4}});
      QVERIFY(r.x >= -1 && r.x < 3 && r.y >= 2 && r.y < 4);
    }
    double s1 = 0, s2 = 0;
    for (int i = 0; i < n; ++i) {
      const double x = rng.normal(2, 3);
      QVERIFY(std::isfinite(x));
      s1 += x;
      s2 += x * x;
    }
    const double mean = s1 / n, sd = std::sqrt(s2 / n - mean * mean);
    QVERIFY2(std::abs(mean - 2) < 0.05 && std::abs(sd - 3) < 0.05, qPrintable(QString("%1 %2").arg(mean).arg(sd)));
    int hits = 0;
    for (int i = 0; i < n; ++i) hits += rng.chance(0.25);
    QVERIFY(std::abs(hits / double(n) - 0.25) < 0.005);
    QVERIFY(!salsa::Rng(1, 1).chance(0.0));
  }

  void rng_index_below_n_data() {
    QTest::addColumn<quint64>("n");
    QTest::newRow("1") << quint64(1);
    QTest::newRow("2") << quint64(2);
    QTest::newRow("7") << quint64(7);
    QTest::newRow("1000") << quint64(1000);
    QTest::newRow("2^40") << (quint64(1) << 40);
    QTest::newRow("2^53") << (quint64(1) << 53);
  }
  void rng_index_below_n() {
    QFETCH(quint64, n);
    salsa::Rng rng(n, 0);
    std::set<std::uint64_t> seen;
    for (int i = 0; i < 20000; ++i) {
      const std::uint64_t k = rng.index(n);
      QVERIFY2(k < n, qPrintable(QString("%1 >= %2").arg(k).arg(n)));
      if (n <= 1000) seen.insert(k);
    }
    if (n <= 1000) QCOMPARE(seen.size(), std::size_t(n));  // every value turns up
  }

  // ---------------------------------------------------------------- Parameters
  void parameter_check_data() {
    QTest::addColumn<double>("min");
    QTest::addColumn<double>("max");
    QTest::addColumn<QString>("unit");
    QTest::addColumn<double>("step");
    QTest::addColumn<double>("value");
    QTest::addColumn<QString>("expected");  // "" when allowed
    const QString range_m = "is out of range (allowed: [0, 10] m)";
    QTest::newRow("inside") << 0.0 << 10.0 << "m" << 0.0 << 5.0 << "";
    QTest::newRow("at min") << 0.0 << 10.0 << "m" << 0.0 << 0.0 << "";
    QTest::newRow("at max") << 0.0 << 10.0 << "m" << 0.0 << 10.0 << "";
    QTest::newRow("below") << 0.0 << 10.0 << "m" << 0.0 << -0.001 << range_m;
    QTest::newRow("above") << 0.0 << 10.0 << "m" << 0.0 << 99.0 << range_m;
    QTest::newRow("nan") << 0.0 << 10.0 << "m" << 0.0 << std::numeric_limits<double>::quiet_NaN() << range_m;
    QTest::newRow("inf") << 0.0 << 10.0 << "m" << 0.0 << std::numeric_limits<double>::infinity() << range_m;
    QTest::newRow("no unit") << 0.5 << 1.5 << "" << 0.0 << 2.0 << "is out of range (allowed: [0.5, 1.5])";
    QTest::newRow("fractions") << 0.001 << 1000.0 << "" << 0.0 << 0.0 << "is out of range (allowed: [0.001, 1000])";
    QTest::newRow("integer ok") << 3.0 << 64.0 << "" << 1.0 << 8.0 << "";
    QTest::newRow("integer fraction") << 3.0 << 64.0 << "" << 1.0 << 2.5 << "is out of range (allowed: whole number in [3, 64])";
    QTest::newRow("integer fraction inside") << 3.0 << 64.0 << "" << 1.0 << 8.5 << "is out of range (allowed: whole number in [3, 64])";
    QTest::newRow("negative range") << -5.0 << -1.0 << "m/s" << 0.0 << 0.0 << "is out of range (allowed: [-5, -1] m/s)";
  }
  void parameter_check() {
    QFETCH(double, min);
    QFETCH(double, max);
    QFETCH(QString, unit);
    QFETCH(double, step);
    QFETCH(double, value);
    QFETCH(QString, expected);
    salsa::Parameter p{"x", min, min, max, unit.toStdString(), "test", step};
    QCOMPARE(QString::fromStdString(p.check(value)), expected);
  }

  void parameter_range_and_format() {
    QCOMPARE(salsa::Parameter({"a", 1, 0, 10, "m", ""}).range(), std::string("[0, 10] m"));
    QCOMPARE(salsa::Parameter({"a", 8, 3, 64, "", "", 1}).range(), std::string("whole number in [3, 64]"));
    QVERIFY(salsa::Parameter({"a", 8, 3, 64, "", "", 1}).is_integer());
    QVERIFY(!salsa::Parameter({"a", 8, 3, 64, "", "", 0.5}).is_integer());
    QCOMPARE(salsa::Parameter::format(2.5), std::string("2.5"));
    QCOMPARE(salsa::Parameter::format(1e6), std::string("1000000"));
    QCOMPARE(salsa::Parameter::format(0), std::string("0"));
    QCOMPARE(salsa::Parameter::format(-3), std::string("-3"));
    QCOMPARE(salsa::Parameter::format(0.01), std::string("0.01"));
    QCOMPARE(salsa::Parameter::format(100), std::string("100"));  // trailing zeros of the integer part stay
  }

  void parameter_values() {
    const salsa::Parameters schema{{"a", 1.5, 0, 2, "", ""}, {"b", -2, -5, 5, "", ""}};
    salsa::ParameterValues v(schema);
    QVERIFY(v.has("a") && v.has("b") && !v.has("c"));
    QCOMPARE(v.get("a"), 1.5);
    QCOMPARE(v.get("b"), -2.0);
    QCOMPARE(v.items().size(), std::size_t(2));
    QCOMPARE(v.items()[0].first, std::string("a"));  // declaration order kept
    QCOMPARE(v.items()[1].first, std::string("b"));
    v.set("b", 4);
    QCOMPARE(v.get("b"), 4.0);
    QCOMPARE(v.items().size(), std::size_t(2));
    v.set("c", 7);  // new names are appended
    QCOMPARE(v.items().back().first, std::string("c"));
    QCOMPARE(v.get("c"), 7.0);
    try {
      (void)v.get("missing");
      QFAIL("get() of an unknown name must throw");
    } catch (const std::out_of_range& e) {
      QVERIFY2(std::string(e.what()).find("'missing'") != std::string::npos, e.what());
    }
    salsa::ParameterValues w(schema);
    QVERIFY(!(v == w));
    w.set("b", 4);
    w.set("c", 7);
    QVERIFY(v == w);
    QVERIFY(salsa::ParameterValues() == salsa::ParameterValues(salsa::Parameters{}));

    SdkBehavior b;
    QCOMPARE(b.configured, 0);
    b.set_parameters(salsa::ParameterValues(SdkBehavior::declare()));
    QCOMPARE(b.configured, 1);  // configure() runs after every change
    QCOMPARE(b.param("speed"), 4.0);
    auto changed = b.parameters();
    changed.set("speed", 7);
    b.set_parameters(changed);
    QCOMPARE(b.configured, 2);
    salsa::Rng rng;
    QCOMPARE(b.decide(salsa::Perception{}, rng), Vec2(7, 0));
  }

  // ---------------------------------------------------------------- PointGrid
  void point_grid_matches_brute_force_data() {
    QTest::addColumn<int>("layout");
    QTest::addColumn<int>("points");
    QTest::addColumn<double>("cell");
    QTest::addColumn<double>("radius");
    // layout 0: uniform random; 1: on a lattice whose spacing is the cell size (points exactly on cell
    // edges, many at exactly the query radius); 2: clustered; 3: one far outlier (the grid grows its
    // cells); 4: all coincident.
    QTest::newRow("random, r = cell") << 0 << 500 << 10.0 << 10.0;
    QTest::newRow("random, r < cell") << 0 << 500 << 10.0 << 3.7;
    QTest::newRow("random, r > cell") << 0 << 500 << 5.0 << 23.0;
    QTest::newRow("random, tiny cell") << 0 << 300 << 0.01 << 12.0;
    QTest::newRow("lattice, r = 2 cells") << 1 << 400 << 1.0 << 2.0;
    QTest::newRow("lattice, r = 5") << 1 << 400 << 1.0 << 5.0;
    QTest::newRow("lattice, r = cell") << 1 << 400 << 2.5 << 2.5;
    QTest::newRow("lattice, r = 0") << 1 << 100 << 1.0 << 0.0;
    QTest::newRow("clustered") << 2 << 600 << 4.0 << 6.0;
    QTest::newRow("far outlier") << 3 << 200 << 1.0 << 50.0;
    QTest::newRow("coincident") << 4 << 50 << 1.0 << 0.5;
    QTest::newRow("single point") << 0 << 1 << 1.0 << 1000.0;
    QTest::newRow("empty") << 0 << 0 << 1.0 << 10.0;
  }
  void point_grid_matches_brute_force() {
    QFETCH(int, layout);
    QFETCH(int, points);
    QFETCH(double, cell);
    QFETCH(double, radius);
    salsa::Rng rng(static_cast<std::uint64_t>(points * 31 + layout), 1);
    std::vector<Vec2> pts;
    const int side = 20;
    for (int i = 0; i < points; ++i) {
      switch (layout) {
        case 0: pts.push_back(rng.in_rect({{-50, 20}, {150, 120}})); break;
        case 1: pts.push_back({(i % side) * cell, (i / side) * cell}); break;
        case 2: pts.push_back(rng.in_disc({static_cast<double>(rng.index(3)) * 40.0, 0}, 8)); break;
        case 3: pts.push_back(i == 0 ? Vec2{1e7, -1e7} : rng.in_rect({{0, 0}, {100, 100}})); break;
        default: pts.push_back({3, 3}); break;
      }
    }
    salsa::PointGrid grid;
    grid.build(pts, cell);
    QCOMPARE(grid.size(), pts.size());

    std::vector<Vec2> queries;
    for (Vec2 p : pts) queries.push_back(p);  // from every point (points on edges, at the radius)
    for (int i = 0; i < 200; ++i) queries.push_back(rng.in_rect({{-100, -50}, {200, 200}}));
    if (layout == 1)  // between lattice points and on cell corners
      for (int i = 0; i < 100; ++i) queries.push_back({static_cast<double>(rng.index(side)) * cell + cell / 2, static_cast<double>(rng.index(side)) * cell});
    queries.push_back({-1e9, 1e9});  // far outside the grid
    queries.push_back({1e12, 1e12});

    for (Vec2 q : queries) {
      std::vector<std::uint32_t> expected;
      for (std::uint32_t i = 0; i < pts.size(); ++i)
        if (salsa::distance_squared(pts[i], q) < radius * radius) expected.push_back(i);
      std::vector<std::uint32_t> got;
      grid.query(q, radius, [&](std::uint32_t i, Vec2 p, double d2) {
        got.push_back(i);
        QCOMPARE(p, pts[i]);
        QCOMPARE(d2, salsa::distance_squared(pts[i], q));
      });
      std::sort(got.begin(), got.end());
      QVERIFY2(std::adjacent_find(got.begin(), got.end()) == got.end(), "a point was reported twice");
      QVERIFY2(got == expected, qPrintable(QString("query at (%1, %2): %3 found, %4 expected")
                                               .arg(q.x).arg(q.y).arg(got.size()).arg(expected.size())));
    }
  }

  void point_grid_is_strict_at_the_radius() {
    const std::vector<Vec2> pts{{0, 0}, {3, 4}, {5, 0}, {0, -5}, {4.999, 0}};
    salsa::PointGrid grid;
    grid.build(pts, 1);
    std::vector<std::uint32_t> got;
    grid.query({0, 0}, 5, [&](std::uint32_t i, Vec2, double) { got.push_back(i); });
    std::sort(got.begin(), got.end());
    QCOMPARE(got, (std::vector<std::uint32_t>{0, 4}));  // exactly 5 m away: not within 5 m
  }

  void point_grid_rebuild_reuses_nothing_stale() {
    salsa::PointGrid grid;
    std::vector<Vec2> a(100, Vec2{1, 1});
    grid.build(a, 1);
    const std::vector<Vec2> b{{50, 50}, {51, 50}};
    grid.build(b, 1);
    int count = 0;
    grid.query({1, 1}, 3, [&](std::uint32_t, Vec2, double) { ++count; });
    QCOMPARE(count, 0);
    grid.query({50.5, 50}, 1, [&](std::uint32_t, Vec2, double) { ++count; });
    QCOMPARE(count, 2);
  }

  // ---------------------------------------------------------------- Registration macros
  void registration_macros_register_everything() {
    QCOMPARE(salsa::detail::registrations().size(), std::size_t(6));
    const salsa::PluginDescriptor* d = salsa_plugin_descriptor();
    QVERIFY(d);
    QCOMPARE(d->abi_version, salsa::abi_version);
    QCOMPARE(d->descriptor_size, std::uint32_t(sizeof(salsa::PluginDescriptor)));
    QCOMPARE(d->descriptor_align, std::uint32_t(alignof(salsa::PluginDescriptor)));
    QCOMPARE(d->toolchain, salsa::toolchain_tag());
    QCOMPARE(QString(d->name), QString("sdk_test"));
    QCOMPARE(QString(d->version), QString("9.8.7"));

    Collector c;
    d->register_all(c);
    QCOMPARE(c.behaviors.size(), std::size_t(1));
    QCOMPARE(c.targets.size(), std::size_t(1));
    QCOMPARE(c.maps.size(), std::size_t(1));
    QCOMPARE(c.handlers.size(), std::size_t(1));
    QCOMPARE(c.metrics.size(), std::size_t(1));
    QCOMPARE(c.winds.size(), std::size_t(1));

    const auto& b = c.behaviors[0];
    QCOMPARE(b.name, std::string("sdk_behavior"));
    QCOMPARE(b.brief, std::string("behavior brief"));
    QCOMPARE(b.parameters.size(), std::size_t(2));
    QCOMPARE(b.parameters[0].name, std::string("speed"));
    QCOMPARE(b.parameters[0].value, 4.0);
    QCOMPARE(b.parameters[0].min, 1.0);
    QCOMPARE(b.parameters[0].max, 8.0);
    QCOMPARE(b.parameters[0].unit, std::string("m/s"));
    QVERIFY(b.parameters[1].is_integer());
    auto behavior = b.create();
    QVERIFY(behavior);
    QCOMPARE(behavior->param("speed"), 4.0);  // created with the declared defaults
    QCOMPARE(behavior->param("count"), 3.0);
    QCOMPARE(dynamic_cast<SdkBehavior&>(*behavior).configured, 1);
    salsa::Rng rng;
    QCOMPARE(behavior->decide(salsa::Perception{}, rng), Vec2(4, 0));  // configure() saw the defaults
    QVERIFY(b.create().get() != behavior.get());  // a fresh object per call

    QCOMPARE(c.targets[0].name, std::string("sdk_target"));
    QCOMPARE(c.targets[0].brief, std::string("target brief"));
    QCOMPARE(c.targets[0].create()->radius(), 2.5);
    QCOMPARE(c.maps[0].name, std::string("sdk_map"));
    salsa::Rng map_rng;
    QCOMPARE(c.maps[0].create()->generate("", map_rng).bounds, (salsa::Rect{{0, 0}, {100, 100}}));
    QCOMPARE(c.handlers[0].name, std::string("sdk_handler"));
    QVERIFY(c.handlers[0].parameters.empty());  // no declare(): no parameters
    QVERIFY(c.handlers[0].create()->parameters().items().empty());
    QCOMPARE(c.metrics[0].name, std::string("sdk_metric"));
    QCOMPARE(c.metrics[0].brief, std::string("metric brief"));
    const auto metric = c.metrics[0].create();
    QCOMPARE(metric->final_columns().at(0).unit, std::string("m"));
    QVERIFY(metric->step_columns().empty());  // the default: no summary.csv columns
    QCOMPARE(c.winds[0].name, std::string("sdk_wind"));
    QCOMPARE(c.winds[0].brief, std::string("wind brief"));
    QCOMPARE(c.winds[0].parameters.at(0).name, std::string("speed"));
    QCOMPARE(c.winds[0].create()->velocity({5, 2}, 1), Vec2(3, 3));  // made with the declared default
  }

  // ---------------------------------------------------------------- Steering helpers
  // Expected values computed by hand from flocking's formulas in docs/behaviors.md (and in
  // Python): position (0, 0), velocity (1, 0), max speed 10; neighbours at (3, 4) moving (0, 2) and at
  // (-6, 8) moving (2, 0); obstacle hits at (10, 0) and (0, -5).
  void steering_helpers_data() {
    QTest::addColumn<double>("max_force");
    QTest::addColumn<Vec2>("alignment");
    QTest::addColumn<Vec2>("cohesion");
    QTest::addColumn<Vec2>("separation");
    QTest::addColumn<Vec2>("obstacles");
    QTest::newRow("max force 0.3") << 0.3 << Vec2{0.19542573998154986, 0.22761542160553108}
                                   << Vec2{-0.0998803621515561, 0.28288498238060283}
                                   << Vec2{-0.0998803621515561, -0.28288498238060283}
                                   << Vec2{-0.15656397165640434, 0.25590569118167855};
    QTest::newRow("unclamped") << 100.0 << Vec2{6.071067811865475, 7.071067811865475}
                               << Vec2{-3.42535625036333, 9.70142500145332}
                               << Vec2{-3.42535625036333, -9.70142500145332}
                               << Vec2{-5.47213595499958, 8.94427190999916};
  }
  void steering_helpers() {
    QFETCH(double, max_force);
    QFETCH(Vec2, alignment);
    QFETCH(Vec2, cohesion);
    QFETCH(Vec2, separation);
    QFETCH(Vec2, obstacles);
    salsa::Perception me = perception({1, 0}, max_force);
    const std::vector<salsa::Neighbour> neighbours{{{3, 4}, {0, 2}, 5, 1}, {{-6, 8}, {2, 0}, 10, 2}};
    const std::vector<salsa::ObstacleHit> hits{{{10, 0}, 10}, {{0, -5}, 5}};
    me.neighbours = neighbours;
    me.obstacles = hits;
    VEC_COMPARE(salsa::alignment(me), alignment, 1e-12);
    VEC_COMPARE(salsa::cohesion(me), cohesion, 1e-12);
    VEC_COMPARE(salsa::avoid_drones(me, 250), separation, 1e-12);
    VEC_COMPARE(salsa::avoid_obstacles(me), obstacles, 1e-12);
    const salsa::BoidTerms boids = salsa::boid_terms(me, 250);  // the one-pass form flocking uses
    VEC_COMPARE(boids.alignment, alignment, 1e-12);
    VEC_COMPARE(boids.cohesion, cohesion, 1e-12);
    VEC_COMPARE(boids.separation, separation, 1e-12);
    me.neighbours = {};
    QCOMPARE(salsa::boid_terms(me, 250).separation, Vec2());
    me.neighbours = neighbours;
    QVERIFY(salsa::alignment(me).length() <= max_force + 1e-12);
    QVERIFY(salsa::avoid_obstacles(me).length() <= max_force + 1e-12);
  }

  // The SDK's fixture for plugin authors hands decide() the perception it was told about.
  void testing_fixture() {
    salsa::testing::Scene scene;
    scene.at({0, 0}, {1, 0}).neighbour({3, 4}, {0, 2}).neighbour({-6, 8}, {2, 0}).obstacle({10, 0}).obstacle({0, -5});
    const salsa::Perception& me = scene.perception();
    QCOMPARE(me.neighbours.size(), std::size_t(2));
    QCOMPARE(me.neighbours[0].distance, 5.0);
    QCOMPARE(me.neighbours[1].distance, 10.0);
    QCOMPARE(me.obstacles[1].distance, 5.0);
    QCOMPARE(me.max_force, 0.3);  // the "small" drone
    SdkFlock flock;
    VEC_COMPARE(scene.decide(flock), Vec2(-0.713096151261362, 0.8220374745343582), 1e-12);
    scene.me().max_force = 100;
    VEC_COMPARE(scene.decide(flock), Vec2(-25.87626032246688, 27.687946136074757), 1e-12);

    SdkBehavior with_parameters;  // gets its declared defaults
    QCOMPARE(salsa::testing::Scene().decide(with_parameters), Vec2(4, 0));
    SdkCounter counter;  // gets memory for one drone, kept between calls
    salsa::testing::Scene counting;
    QCOMPARE(counting.decide(counter), Vec2(1, 0));
    QCOMPARE(counting.decide(counter), Vec2(2, 0));
    salsa::testing::Scene seen;
    seen.target({0, 12}, true);
    QCOMPARE(seen.perception().targets.size(), std::size_t(1));
    QCOMPARE(seen.perception().targets[0].distance, 12.0);
    QVERIFY(seen.perception().targets[0].found);
  }

  // A Param member is its declaration (the factory probes an instance) and holds the value decide reads.
  void param_members() {
    const auto f = salsa::detail::make_factory<salsa::Behavior, SdkBound>("bound", "");
    QCOMPARE(f.parameters.size(), std::size_t(3));
    QCOMPARE(f.parameters[0].name, std::string("legacy"));  // declare() first, then members in order
    QCOMPARE(f.parameters[1].name, std::string("speed"));
    QCOMPARE(f.parameters[1].unit, std::string("m/s"));
    QCOMPARE(f.parameters[2].name, std::string("count"));
    QVERIFY(f.parameters[2].is_integer());
    auto made = f.create();  // the defaults
    salsa::testing::Scene scene;
    QCOMPARE(scene.decide(*made), Vec2(4, 3.5));
    salsa::ParameterValues values(f.parameters);
    values.set("speed", 7);
    values.set("count", 2);
    made->set_parameters(values);
    QCOMPARE(scene.decide(*made), Vec2(7, 2.5));
    QCOMPARE(dynamic_cast<SdkBound&>(*made).seen_in_configure, 7.0);
    // A value the caller leaves out keeps the member's current value.
    salsa::ParameterValues only_count;
    only_count.set("count", 9);
    only_count.set("legacy", 0);
    made->set_parameters(only_count);
    QCOMPARE(scene.decide(*made), Vec2(7, 9));
  }

  // Scene: the random stream goes on between decisions; step() flies as the core does without physics.
  void scene_steps() {
    SdkDraw draw;
    salsa::testing::Scene scene;
    const double a = scene.decide(draw).x, b = scene.decide(draw).x;
    QVERIFY(a != b);
    salsa::Rng same(1, 0);
    QCOMPARE(a, same.uniform(0, 1));
    QCOMPARE(b, same.uniform(0, 1));
    SdkBehavior fly;  // steers (4, 0) every step; the small drone's max speed is 10 m/s
    salsa::testing::Scene flying;
    flying.step(fly);
    QCOMPARE(flying.me().velocity, Vec2(4, 0));
    VEC_COMPARE(flying.me().position, Vec2(4.0 / 60, 0), 1e-12);
    flying.step(fly);
    flying.step(fly);
    QCOMPARE(flying.me().velocity, Vec2(10, 0));  // clamped to max speed
    QCOMPARE(flying.me().time, 3.0 / 60);
    VEC_COMPARE(flying.me().position, Vec2(22.0 / 60, 0), 1e-12);
  }

  void steering_edge_cases() {
    salsa::Perception me = perception({1, 0}, 100);
    // Nobody around and nothing hit: no steering at all (not "stop", which would be -velocity).
    QCOMPARE(salsa::alignment(me), Vec2());
    QCOMPARE(salsa::cohesion(me), Vec2());
    QCOMPARE(salsa::avoid_drones(me, 250), Vec2());
    QCOMPARE(salsa::avoid_obstacles(me), Vec2());
    // Only neighbours closer than the separation distance count: (3, 4) is 5 m away, (-6, 8) 10 m.
    const std::vector<salsa::Neighbour> neighbours{{{3, 4}, {0, 2}, 5, 1}, {{-6, 8}, {2, 0}, 10, 2}};
    me.neighbours = neighbours;
    VEC_COMPARE(salsa::avoid_drones(me, 7), Vec2(-7, -8), 1e-12);
    QCOMPARE(salsa::avoid_drones(me, 5), Vec2());  // strictly closer than the distance
    // A neighbour at distance 0 (on top of the drone) has no direction: it is ignored, no NaN.
    const std::vector<salsa::Neighbour> on_top{{{0, 0}, {0, 0}, 0, 1}};
    me.neighbours = on_top;
    QCOMPARE(salsa::avoid_drones(me, 250), Vec2());
    // Neighbours with opposite velocities: the mean is zero, no alignment steering.
    const std::vector<salsa::Neighbour> opposite{{{3, 4}, {0, 2}, 5, 1}, {{-6, 8}, {0, -2}, 10, 2}};
    me.neighbours = opposite;
    QCOMPARE(salsa::alignment(me), Vec2());
    const std::vector<salsa::ObstacleHit> at_zero{{{0, 0}, 0}};
    me.obstacles = at_zero;
    QCOMPARE(salsa::avoid_obstacles(me), Vec2());

    // seek / steer_towards / steer_along.
    VEC_COMPARE(salsa::seek(me, {0, 20}), Vec2(-1, 10), 1e-12);
    VEC_COMPARE(salsa::seek(perception({1, 0}, 0.3), {0, 20}), Vec2(-1, 10) * (0.3 / std::sqrt(101.0)), 1e-12);
    VEC_COMPARE(salsa::steer_towards(me, {4, 4}), Vec2(3, 4), 1e-12);
    VEC_COMPARE(salsa::steer_towards(perception({1, 0}, 2.5), {4, 4}), Vec2(1.5, 2), 1e-12);
    VEC_COMPARE(salsa::steer_along(me, {0, -0.001}), Vec2(-1, -10), 1e-12);
    QCOMPARE(salsa::steer_along(me, {}), Vec2());
    // Already flying as desired: nothing to change.
    QCOMPARE(salsa::seek(perception({10, 0}, 0.3), {100, 0}), Vec2());
  }
};

QTEST_GUILESS_MAIN(TestSdk)
#include "test_sdk.moc"
