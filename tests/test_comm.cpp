// The comm model (a test's "comm"): messages reach the drones they should (range, walls), are lost at
// the rate the formula gives, arrive exactly `latency` steps late, obey the cap nearest first, carry the
// declared noise, and are the same on any thread count and in every run; without "comm" nothing
// changes.
#include <QTemporaryDir>
#include <QtTest>

#include <array>
#include <cmath>
#include <map>
#include <memory>
#include <mutex>

#include "common.hpp"
#include "salsa/core/model/comm.hpp"
#include "salsa/core/model/static_geometry.hpp"
#include "salsa/core/run/runner.hpp"
#include "salsa/core/run/session.hpp"
#include "salsa/core/experiments/test_spec.hpp"

using namespace salsa;
using namespace salsa_test;

namespace {

/// Drones at fixed points, delivering through CommState directly: exact distances, no flight.
struct Layout {
  std::vector<Vec2> positions;
  MapData map;
  CommSetup comm;
  std::uint64_t seed = 7;
  CommState state;
  std::vector<std::uint32_t> groups;
  std::vector<DroneStatus> status;
  std::unique_ptr<StaticGeometry> geometry;
  CommState::Counts counts;

  Layout(std::vector<Vec2> points, CommSetup c) : positions(std::move(points)), comm(c) {
    comm.on = true;
    map.bounds = {{0, 0}, {400, 400}};
    map.spawn = {1, 1};
  }
  void start() {
    groups.assign(positions.size(), 0);
    status.assign(positions.size(), DroneStatus::flying);
    const std::size_t room[] = {1};
    state.resize(positions.size(), room, groups, comm.latency);
    geometry = std::make_unique<StaticGeometry>(map, 50);
  }
  /// One step: every drone broadcasts its id.
  void step(std::uint64_t k) {
    for (std::uint32_t i = 0; i < positions.size(); ++i) {
      Perception me;
      me.id = i;
      me.outbox = &state.outbox(i);
      me.broadcast(std::array{static_cast<double>(i)});
    }
    state.collect(k, static_cast<double>(k) * 0.1, positions, status);
  }
  /// What drone `r` receives in step `k` (sent in k − 1 − latency), its counts added to `counts`; the
  /// drones are at `now` when it receives (where they sent from, unless given).
  std::vector<Message> inbox(std::uint64_t k, std::uint32_t r, std::vector<Vec2> now = {}) {
    if (now.empty()) now = positions;
    PointGrid grid;
    grid.build(now, 25);
    std::vector<Message> out;
    std::vector<PointGrid::Hit> candidates, hits;
    grid.gather(now[r], state.reach(k, now, comm.range), candidates);
    state.receive(k, r, comm, seed, groups, *geometry, candidates, hits, out, counts);
    return out;
  }
  /// Their senders, by ascending id.
  std::vector<std::uint32_t> senders(std::uint64_t k, std::uint32_t r) {
    std::vector<std::uint32_t> out;
    for (const Message& m : inbox(k, r)) out.push_back(m.sender);
    std::sort(out.begin(), out.end());
    return out;
  }
};

using Ids = std::vector<std::uint32_t>;

/// Hovers where it spawned and broadcasts [its id, the step it sends in]; records every message it
/// receives (each drone into its own slot: decide runs in parallel).
struct Log {
  struct Got {
    std::uint64_t step;
    Message message;
    std::array<double, 2> payload;
  };
  std::vector<std::vector<Got>> got;
};
class Beacon final : public Behavior {
 public:
  explicit Beacon(std::shared_ptr<Log> log, std::size_t size = 2) : log_(std::move(log)), size_(size) {}
  void reset(std::size_t drones) override { log_->got.resize(drones); }
  Vec2 decide(const Perception& me, Rng&) override {
    const auto step = static_cast<std::uint64_t>(std::llround(me.time / me.dt));
    for (const Message& m : me.messages) log_->got[me.id].push_back({step, m, {m.payload[0], m.payload[1]}});
    const std::array<double, 3> payload{static_cast<double>(me.id), static_cast<double>(step), 0.0};
    me.broadcast(std::span<const double>(payload).first(size_));
    return -me.velocity;  // hover
  }
  std::size_t message_size() const override { return 2; }
  Senses senses() const override { return {false, false}; }

 private:
  std::shared_ptr<Log> log_;
  std::size_t size_;
};

/// Flies towards the mean of the positions it hears (payload [x, y]) and broadcasts its own: what it
/// receives changes where it goes, so any difference in deliveries shows in the trajectories.
class Follower final : public Behavior {
 public:
  Vec2 decide(const Perception& me, Rng& rng) override {
    me.broadcast(std::array{me.position.x, me.position.y});
    Vec2 sum;
    for (const Message& m : me.messages) sum += Vec2{m.payload[0], m.payload[1]} + Vec2::polar(m.range(), m.bearing()) * 1e-3;
    const Vec2 wander = Vec2::polar(me.max_force, rng.angle());
    if (me.messages.empty()) return wander;
    return seek(me, sum / static_cast<double>(me.messages.size())) + wander + avoid_near_obstacles(me);
  }
  std::size_t message_size() const override { return 2; }
  Senses senses() const override { return {false, false}; }
};

SimulationSetup field(std::size_t drones, std::shared_ptr<Behavior> behavior, CommSetup comm) {
  SimulationSetup s;
  s.map.bounds = {{0, 0}, {600, 600}};
  s.map.spawn = {300, 300};
  s.groups[0].drones = drones;
  s.groups[0].behavior = std::move(behavior);
  s.groups[0].spawn_radius = 150;
  s.dt = 0.1;
  s.comm = comm;
  s.comm.on = true;
  return s;
}

/// A 99.9 % interval half-width of a binomial proportion p over n trials (normal approximation).
double binomial_999(double p, double n) { return 3.29 * std::sqrt(p * (1 - p) / n); }

}  // namespace

class TestComm : public QObject {
  Q_OBJECT

  std::unique_ptr<PluginHost> host_ = builtin_host();

 private Q_SLOTS:
  // In range (strictly closer than range), out of range, behind a wall; with line of sight off the
  // wall lets it through. Messages carry the true range and bearing without noise.
  void delivery_follows_range_and_walls() {
    CommSetup c;
    c.range = 90;
    // 0 and 1: 50 m apart; 2: 200 m from 0; 3 and 4: 60 m apart with a wall between; 5: exactly 90 m from 0.
    Layout l({{100, 50}, {150, 50}, {300, 50}, {100, 250}, {160, 250}, {100, 140}}, c);
    l.map.lines.push_back({{130, 220}, {130, 290}});
    l.start();
    l.step(0);
    QCOMPARE(l.senders(1, 0), (Ids{1}));
    QCOMPARE(l.senders(1, 1), (Ids{0}));
    QCOMPARE(l.senders(1, 2), Ids{});
    QCOMPARE(l.senders(1, 3), Ids{});  // the wall
    QCOMPARE(l.senders(1, 4), Ids{});
    QCOMPARE(l.senders(1, 5), Ids{});  // at exactly the range: out
    QCOMPARE(l.counts.offered, std::uint64_t(6 * 5));
    QCOMPARE(l.counts.in_range, std::uint64_t(4));  // 0↔1 and 3↔4
    QCOMPARE(l.counts.obstacle, std::uint64_t(2));
    QCOMPARE(l.counts.delivered, std::uint64_t(2));
    const Message m = l.inbox(1, 0)[0];
    QCOMPARE(m.range(), 50.0);
    QCOMPARE(m.bearing(), 0.0);  // from 0 towards 1: along +x
    QCOMPARE(l.inbox(1, 1)[0].bearing(), pi);
    QCOMPARE(m.payload.size(), std::size_t(1));
    QCOMPARE(m.payload[0], 1.0);
    QCOMPARE(m.time, 0.0);
    QCOMPARE(l.inbox(0, 0).size(), std::size_t(0));  // nothing before the step after sending

    Layout open({{100, 250}, {160, 250}}, [] { CommSetup o; o.range = 90; o.line_of_sight = false; return o; }());
    open.map.lines.push_back({{130, 220}, {130, 290}});
    open.start();
    open.step(0);
    QCOMPARE(open.senders(1, 0), (Ids{1}));
    // A solid obstacle (a square) blocks as a wall does; a wall that ends short of the line does not.
    Layout solid({{100, 100}, {200, 100}, {100, 300}, {200, 300}}, [] { CommSetup o; o.range = 150; return o; }());
    solid.map.obstacles.push_back({{140, 80}, {160, 80}, {160, 120}, {140, 120}});
    solid.map.lines.push_back({{150, 310}, {150, 380}});
    solid.start();
    solid.step(0);
    QCOMPARE(solid.senders(1, 0), Ids{});
    QCOMPARE(solid.senders(1, 2), (Ids{3}));
  }

  // p(d) = 1 − (1 − loss)(1 − loss_at_range (d / range)²), measured at two distances over many steps,
  // each within its binomial 99.9 % interval.
  void loss_rate_follows_the_formula() {
    CommSetup c;
    c.range = 100;
    c.loss = 0.3;
    c.loss_at_range = 0.4;
    Layout l({{100, 50}, {150, 50}, {20, 50}}, c);  // 0–1: 50 m, 0–2: 80 m, 1–2: 130 m (out)
    l.start();
    const int steps = 4000;
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> heard;
    for (int k = 0; k < steps; ++k) {
      l.step(static_cast<std::uint64_t>(k));
      for (std::uint32_t r = 0; r < 3; ++r)
        for (std::uint32_t s : l.senders(static_cast<std::uint64_t>(k) + 1, r)) ++heard[{std::min(r, s), std::max(r, s)}];
    }
    for (const auto& [pair, d] : {std::pair{std::pair{0u, 1u}, 50.0}, std::pair{std::pair{0u, 2u}, 80.0}}) {
      const double p = comm_loss(c, d), n = 2.0 * steps;  // both directions
      const double measured = 1 - heard[pair] / n;
      QVERIFY2(std::abs(measured - p) <= binomial_999(p, n),
               qPrintable(QString("loss at %1 m: %2, formula %3 ± %4").arg(d).arg(measured).arg(p).arg(binomial_999(p, n))));
    }
    QCOMPARE(comm_loss(c, 50), 1 - 0.7 * (1 - 0.4 * 0.25));
    QCOMPARE(heard[(std::pair{1u, 2u})], 0);
    QCOMPARE(l.counts.loss + l.counts.delivered, l.counts.in_range);
  }

  // The cap keeps the nearest senders, ties to the lower id, the same every time.
  void cap_keeps_the_nearest_then_the_lower_id() {
    CommSetup c;
    c.range = 100;
    c.max_received = 3;
    // Receiver 0 at the centre; senders at 40, 10, 30, 30 (tie: ids 3 and 4... 4 loses), 20 m.
    Layout l({{200, 200}, {240, 200}, {200, 210}, {170, 200}, {200, 170}, {220, 200}}, c);
    l.start();
    l.step(0);
    const auto got = l.inbox(1, 0);  // nearest first: 10 m, 20 m, then the lower id of the tie at 30 m
    QCOMPARE(got.size(), std::size_t(3));
    QCOMPARE(got[0].sender, 2u);
    QCOMPARE(got[1].sender, 5u);
    QCOMPARE(got[2].sender, 3u);
    QCOMPARE(l.counts.cap, std::uint64_t(2));
    for (int k = 1; k < 20; ++k) l.step(static_cast<std::uint64_t>(k));
    QCOMPARE(l.senders(20, 0), (Ids{2, 3, 5}));
  }

  // The measured range and bearing carry Gaussian noise of the declared sd (means and sds within their
  // 99.9 % intervals), the same draws for the same (seed, step, sender, receiver).
  void range_and_bearing_noise_have_the_declared_statistics() {
    CommSetup c;
    c.range = 100;
    c.range_noise = 2;
    c.bearing_noise = 0.05;
    Layout l({{100, 100}, {150, 100}}, c);
    l.start();
    const int steps = 5000;
    std::vector<double> ranges, bearings;
    for (int k = 0; k < steps; ++k) {
      l.step(static_cast<std::uint64_t>(k));
      const Message m = l.inbox(static_cast<std::uint64_t>(k) + 1, 0)[0];
      ranges.push_back(m.range()), bearings.push_back(m.bearing());
    }
    auto check = [](const std::vector<double>& x, double sd, const char* what) {
      const double n = static_cast<double>(x.size());
      double mean = 0, var = 0;
      for (double v : x) mean += v / n;
      for (double v : x) var += (v - mean) * (v - mean) / (n - 1);
      QVERIFY2(std::abs(mean) <= 3.29 * sd / std::sqrt(n), qPrintable(QString("%1 mean %2").arg(what).arg(mean)));
      QVERIFY2(std::abs(std::sqrt(var) - sd) <= 3.29 * sd / std::sqrt(2 * n), qPrintable(QString("%1 sd %2").arg(what).arg(std::sqrt(var))));
    };
    const double first = ranges[17];
    for (double& r : ranges) r -= 50;
    check(ranges, 2, "range");
    check(bearings, 0.05, "bearing");
    // Counter-based: another state with the same seed gets the same numbers at step 17.
    Layout again({{100, 100}, {150, 100}}, c);
    again.start();
    again.step(17);
    QCOMPARE(again.inbox(18, 0)[0].range(), first);
    // Without noise the offset is exactly the sender's position less the receiver's, from every
    // direction, and range and bearing are its length and atan2.
    std::vector<Vec2> ring{{200, 200}};
    for (int k = 0; k < 720; ++k) ring.push_back(Vec2{200, 200} + Vec2::polar(10 + k % 37, k * pi / 360 + 1e-3 * (k % 7)));
    CommSetup exact;
    exact.range = 100;
    Layout around(ring, exact);
    around.start();
    around.step(0);
    const std::vector<Message> heard = around.inbox(1, 0);
    QCOMPARE(heard.size(), ring.size() - 1);
    for (const Message& got : heard) {
      const Vec2 to = ring[got.sender] - ring[0];
      QCOMPARE(got.offset, to);
      QCOMPARE(got.range(), std::sqrt(to.x * to.x + to.y * to.y));
      QCOMPARE(got.bearing(), std::atan2(to.y, to.x));
    }
  }

  // Through the simulation: a message sent in step k is in decide's messages in step k + 1 + latency,
  // exactly, with the time it was sent; nothing arrives before.
  void latency_is_exact_to_the_step() {
    for (int latency : {0, 3}) {
      auto log = std::make_shared<Log>();
      CommSetup c;
      c.range = 1000;
      c.latency = latency;
      SimulationSetup s = field(4, std::make_shared<Beacon>(log), c);
      Simulation sim(s);
      sim.run_steps(30);
      for (std::uint32_t r = 0; r < 4; ++r) {
        QCOMPARE(log->got[r].size(), std::size_t(3 * (30 - 1 - latency)));  // 3 others, from step 1 + latency on
        for (const Log::Got& g : log->got[r]) {
          QCOMPARE(g.step - static_cast<std::uint64_t>(g.payload[1]), std::uint64_t(1 + latency));
          QCOMPARE(g.message.sender, static_cast<std::uint32_t>(g.payload[0]));
          QCOMPARE(g.message.time, g.payload[1] * 0.1);
        }
        QCOMPARE(log->got[r].front().step, std::uint64_t(1 + latency));
      }
    }
  }

  // The counters add up: every message is offered to every other drone flying when it arrives.
  void counters_account_for_every_message() {
    CommSetup c;
    c.range = 120;
    c.loss = 0.2;
    c.loss_at_range = 0.5;
    c.max_received = 4;
    SimulationSetup s = field(40, std::make_shared<Follower>(), c);
    s.map.obstacles.push_back({{340, 240}, {440, 240}, {440, 360}, {340, 360}});
    s.groups[0].spawn_radius = 200;
    Simulation sim(s);
    sim.run_steps(50);
    const CommCounters& k = sim.comm_counters();
    QCOMPARE(k.sent, std::uint64_t(40 * 50));
    // Offered when they arrive: the last step's 40 are still in flight.
    QCOMPARE(k.delivered + k.dropped_range + k.dropped_obstacle + k.dropped_loss + k.dropped_cap, (k.sent - 40) * 39);
    QVERIFY(k.delivered > 0 && k.dropped_range > 0 && k.dropped_obstacle > 0 && k.dropped_loss > 0 && k.dropped_cap > 0);
  }

  // A receiver finds its senders from where the drones are when it receives: every drone that sent
  // from within range of where the receiver was then, and no other, however far the drones moved since.
  void senders_are_found_after_the_drones_moved() {
    Rng rng(5, 0);
    std::vector<Vec2> points;
    for (int i = 0; i < 300; ++i) points.push_back(rng.in_disc({200, 200}, 190));
    CommSetup c;
    c.range = 60;
    Layout l(points, c);
    l.start();
    l.step(0);
    for (double moved : {0.0, 0.5, 40.0}) {
      std::vector<Vec2> now = points;
      for (Vec2& p : now) p += Vec2::polar(moved * rng.uniform(0, 1), rng.angle());
      std::size_t heard = 0;
      for (std::uint32_t r = 0; r < points.size(); ++r) {
        std::vector<std::uint32_t> got;
        for (const Message& m : l.inbox(1, r, now)) got.push_back(m.sender);
        std::sort(got.begin(), got.end());
        std::vector<std::uint32_t> expected;
        for (std::uint32_t j = 0; j < points.size(); ++j)
          if (j != r && distance_squared(points[j], points[r]) < c.range * c.range) expected.push_back(j);
        QCOMPARE(got, expected);
        heard += got.size();
      }
      QVERIFY(heard > 3000);
    }
  }

  // Deliveries (and so the flights they steer) are identical on 1 and 2 threads and across runs.
  void deliveries_are_the_same_on_any_thread_count() {
    CommSetup c;
    c.range = 80;
    c.loss = 0.1;
    c.loss_at_range = 0.3;
    c.max_received = 6;
    c.range_noise = 1;
    c.bearing_noise = 0.02;
    c.latency = 1;
    auto run = [&](int threads) {
      SimulationSetup s = field(300, std::make_shared<Follower>(), c);
      s.map.obstacles.push_back({{250, 250}, {350, 250}, {350, 270}, {250, 270}});
      s.threads = threads;
      s.seed = 11;
      Simulation sim(s);
      sim.run_steps(60);
      std::vector<double> out(sim.drone_positions().size() * 2);
      for (std::size_t i = 0; i < sim.drone_positions().size(); ++i) out[2 * i] = sim.drone_positions()[i].x, out[2 * i + 1] = sim.drone_positions()[i].y;
      for (std::uint32_t i = 0; i < sim.drone_count(); ++i)
        for (const Message& m : sim.inbox(i)) out.insert(out.end(), {double(m.sender), m.range(), m.bearing(), m.payload[0]});
      const CommCounters& k = sim.comm_counters();
      out.insert(out.end(), {double(k.delivered), double(k.dropped_loss), double(k.dropped_cap), double(k.dropped_obstacle)});
      return out;
    };
    const auto one = run(1), two = run(2), again = run(2);
    QVERIFY(one.size() > 600 + 4);
    QVERIFY(one == two);
    QVERIFY(two == again);
  }

  // A payload longer than the behavior declares stops the run with one line naming the behavior and
  // the drone; a message_size above the maximum is refused at the start.
  void oversized_messages_are_the_behaviors_failure() {
    const std::string test = R"({"name": "big", "behavior": "random_walk", "drones": 3, "comm": {}, "time": 1})";
    Session session(parse_test(test, "big.json", *host_), *host_, {1, std::make_shared<Beacon>(std::make_shared<Log>(), 3)});
    try {
      session.step();
      QFAIL("an oversized message was sent");
    } catch (const TestFailure& e) {
      const QString line = e.what();
      QVERIFY2(line.contains("behavior 'random_walk'") && line.contains("drone 0 broadcast 3 doubles, more than the 2"), e.what());
      QVERIFY(!line.contains('\n'));
    }
    class Huge final : public Behavior {
      Vec2 decide(const Perception&, Rng&) override { return {}; }
      std::size_t message_size() const override { return max_message_size + 1; }
    };
    try {
      Session s(parse_test(test, "big.json", *host_), *host_, {1, std::make_shared<Huge>()});
      QFAIL("a message size above the maximum was accepted");
    } catch (const TestFailure& e) {
      QVERIFY2(QString(e.what()).contains("message_size() is 65 doubles (allowed: at most 64)"), e.what());
    }
  }

  // Without "comm" nothing changes: the test reads as before (no comm in its TestSpec or config.json,
  // no columns). With "comm" and a behavior that never broadcasts, every data file but the counters'
  // columns is byte-identical: the model draws from no stream a drone uses.
  void without_comm_nothing_changes() {
    const std::string base = R"("name": "t", "behavior": "flocking", "drones": 12, "map": {"name": "forest", "params": {"size": 400}},
                                "targets": {"count": 100}, "time": 15)";
    const TestSpec plain = parse_test("{" + base + "}", "t.json", *host_);
    QVERIFY(!plain.comm.on);
    QVERIFY(resolved_json(plain, *host_).find("\"comm\"") == std::string::npos);
    const TestSpec talking = parse_test("{" + base + R"(, "comm": {"range": 100, "loss": 0.5}})", "t.json", *host_);
    QVERIFY(talking.comm.on);
    TestSpec off = talking;
    off.comm = {};
    QVERIFY(off == plain);

    QTemporaryDir a, b;
    RunOptions options;
    options.out = a.path().toStdString();
    run_test(plain, *host_, options);
    options.out = b.path().toStdString();
    run_test(talking, *host_, options);
    for (const char* file : {"drones.csv", "targets.csv", "map.json"})
      QVERIFY2(read_file(a.path() + "/t/" + file) == read_file(b.path() + "/t/" + file), file);
    const QStringList without = non_empty_lines(read_file(a.path() + "/t/summary.csv"));
    const QStringList with = non_empty_lines(read_file(b.path() + "/t/summary.csv"));
    QCOMPARE(with.size(), without.size());
    QCOMPARE(with[0], without[0] + ",messages_sent,messages_delivered,dropped_range,dropped_obstacle,dropped_loss,dropped_cap");
    for (qsizetype i = 1; i < with.size(); ++i) QCOMPARE(with[i], without[i] + ",0,0,0,0,0,0");
    // Rerunning config.json gives the same test back, comm and all.
    QCOMPARE(load_tests((a.path() + "/t/config.json").toStdString(), *host_)[0].comm, plain.comm);
    QCOMPARE(load_tests((b.path() + "/t/config.json").toStdString(), *host_)[0].comm, talking.comm);
  }

  // comm.<field> is a timed change (applied through set_comm) and a sweep axis; in a test without
  // "comm" a change of it is refused.
  void comm_fields_change_and_sweep() {
    const std::string test = R"({"name": "c", "behavior": "flocking", "drones": 5, "time": 4, "comm": {"range": 50},
                                 "changes": [{"time": 2, "set": {"comm.range": 80, "comm.line_of_sight": 0, "comm.latency": 2}}]})";
    const TestSpec t = parse_test(test, "c.json", *host_);
    Session session(t, *host_, {1, nullptr});
    while (!session.finished()) session.step();
    QCOMPARE(session.simulation().setup().comm.range, 80.0);
    QCOMPARE(session.simulation().setup().comm.line_of_sight, false);
    QCOMPARE(session.current().comm.latency, 2);
    QVERIFY(resolved_json(t, *host_).find("\"comm.latency\": 2") != std::string::npos);  // whole numbers stay whole
    try {
      parse_test(R"({"behavior": "flocking", "time": 4, "changes": [{"time": 1, "set": {"comm.range": 80}}]})", "n.json", *host_);
      QFAIL("a comm change without comm was accepted");
    } catch (const InputError& e) {
      QVERIFY2(QString(e.what()).contains("changes[0].set.comm.range: the test has no \"comm\""), e.what());
    }
    QTemporaryDir dir;
    const QString queue = dir.path() + "/q.json";
    write_file(queue, R"({"sweep": {"test": {"behavior": "flocking", "drones": 4, "time": 1},
                                    "set": {"comm.range": [50, 150], "comm.loss": [0, 0.25]}}})");
    const std::vector<TestSpec> tests = load_tests(queue.toStdString(), *host_);
    QCOMPARE(tests.size(), std::size_t(4));
    for (const TestSpec& s : tests) QVERIFY(s.comm.on);
    QCOMPARE(tests[3].comm.range, 150.0);
    QCOMPARE(tests[3].comm.loss, 0.25);
    QCOMPARE(tests[0].seed, tests[3].seed);  // the radio is not part of the world: paired seeds
  }
};

QTEST_GUILESS_MAIN(TestComm)
#include "test_comm.moc"
