#include "salsa/core/model/comm.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "salsa/core/model/static_geometry.hpp"

namespace salsa {

const std::vector<CommField>& comm_schema() {
  static const std::vector<CommField> schema{
      {{"range", 134, 1e-3, 1e6, "m", "farthest a message travels, centre to centre (default: the small drone's detection range)", 0.5}, &CommSetup::range},
      {{"line_of_sight", 1, 0, 1, "", "true: a wall or obstacle between sender and receiver blocks the message", 1}, nullptr, nullptr, &CommSetup::line_of_sight},
      {{"loss", 0, 0, 1, "", "probability a message in range and sight is lost, at any distance", 0.01}, &CommSetup::loss},
      {{"loss_at_range", 0, 0, 1, "", "extra loss at full range, growing as (distance / range)^2: p = 1 - (1 - loss)(1 - loss_at_range (d / range)^2)", 0.01}, &CommSetup::loss_at_range},
      {{"latency", 0, 0, 1000, "steps", "steps a message waits: 0 = received in the next step's decide", 1}, nullptr, &CommSetup::latency},
      {{"max_received", 0, 0, 100000, "", "messages a drone receives per step, nearest senders first; 0: no cap", 1}, nullptr, &CommSetup::max_received},
      {{"range_noise", 0, 0, 1e4, "m", "sd of the Gaussian noise on the range a receiver measures (clamped at 0)", 0.1}, &CommSetup::range_noise},
      {{"bearing_noise", 0, 0, 10, "rad", "sd of the Gaussian noise on the bearing a receiver measures", 0.01}, &CommSetup::bearing_noise},
  };
  return schema;
}

const CommField* find_comm_field(std::string_view name) {
  for (const CommField& f : comm_schema())
    if (f.spec.name == name) return &f;
  return nullptr;
}

std::string comm_field_names() {
  std::string out;
  for (const CommField& f : comm_schema()) out += (out.empty() ? "" : ", ") + f.spec.name;
  return out;
}

std::string comm_problem(const CommSetup& c) {
  for (const CommField& f : comm_schema())
    if (const double v = f.get(c); !f.spec.check(v).empty()) return "comm." + f.spec.name + ": " + Parameter::format(v) + " " + f.spec.check(v);
  return {};
}

double comm_loss(const CommSetup& c, double d) {
  const double x = d / c.range;
  return 1 - (1 - c.loss) * (1 - c.loss_at_range * x * x);
}

namespace {

std::uint64_t mix(std::uint64_t z) {  // splitmix64's output function
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

/// Counter-based draws for one (seed, step, sender, receiver): the same numbers whichever thread asks
/// and in whatever order, and independent of every Rng stream (a tag of their own is mixed in).
class PairDraws {
 public:
  PairDraws(std::uint64_t seed, std::uint64_t step, std::uint32_t sender, std::uint32_t receiver)
      : state_(mix(mix(seed ^ 0x636F6D6D5F64726FULL) ^ mix(step + 0x9E3779B97F4A7C15ULL) ^
                   (static_cast<std::uint64_t>(sender) << 32 | receiver))) {}
  double uniform() { return static_cast<double>(mix(state_ += 0x9E3779B97F4A7C15ULL) >> 11) * 0x1.0p-53; }
  double normal() {  // Box–Muller, as Rng::normal
    const double u1 = 1.0 - uniform(), u2 = uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2 * pi * u2);
  }

 private:
  std::uint64_t state_;
};

constexpr std::uint32_t none = std::numeric_limits<std::uint32_t>::max();

/// atan2(y, x) within a few ulps (test_comm checks 1e-15 rad), without libm: glibc's took a sixth of a
/// step's time at 15 deliveries per drone. Reduced to t = min/max of |x|, |y| in [0, 1]; then with the
/// nearest c = k/16, atan t = atan c + atan u, u = (t − c) / (1 + t c), |u| ≤ 1/32, whose odd Taylor
/// series to u⁹ errs by under u¹¹/11 < 3e-18. Plain arithmetic: the same bits on every machine.
double bearing_of(double y, double x) {
  static const std::array<double, 17> table = [] {
    std::array<double, 17> out{};
    for (int k = 0; k <= 16; ++k) out[static_cast<std::size_t>(k)] = std::atan(k / 16.0);
    return out;
  }();
  const double ax = std::fabs(x), ay = std::fabs(y);
  const double hi = std::max(ax, ay), lo = std::min(ax, ay);
  if (!(hi > 0)) return 0;  // the same point (or NaN): no direction
  // k only picks the expansion point: a float quotient is near enough (|u| stays within a hair of
  // 1/32), and u = (t − c) / (1 + t c) with t = lo / hi is one division.
  const auto k = static_cast<std::size_t>(static_cast<float>(lo) * 16.0f / static_cast<float>(hi) + 0.5f);
  const double c = static_cast<double>(k) / 16;
  const double u = (lo - c * hi) / (hi + c * lo), u2 = u * u;
  double a = table[k] +
             u * (1 + u2 * (-1.0 / 3 + u2 * (1.0 / 5 + u2 * (-1.0 / 7 + u2 * (1.0 / 9)))));
  if (ay > ax) a = pi / 2 - a;
  if (x < 0) a = pi - a;
  return y < 0 ? -a : a;
}

}  // namespace

void CommState::resize(std::size_t drones, std::span<const std::size_t> room, std::span<const std::uint32_t> groups, int latency) {
  if (latency != latency_ || ring_.size() != static_cast<std::size_t>(latency) + 2) {
    latency_ = latency;
    ring_.assign(static_cast<std::size_t>(latency) + 2, {});
  }
  std::size_t stride = 0;
  for (std::size_t r : room) stride = std::max(stride, r);
  room_.assign(drones * stride, 0.0);
  outboxes_.assign(drones, {});
  for (std::size_t i = 0; i < drones; ++i) outboxes_[i].room = {room_.data() + i * stride, room[groups[i]]};
}

void CommState::clear() {
  for (Slot& s : ring_) s.senders.clear(), s.positions.clear();
  for (Outbox& o : outboxes_) o.sent = false, o.size = 0;
}

std::size_t CommState::collect(std::uint64_t step, double time, std::span<const Vec2> positions, std::span<const DroneStatus> status,
                               double range) {
  Slot& s = slot(step);
  s.time = time;
  s.pool.clear();
  s.senders.clear();
  s.offset.resize(outboxes_.size());
  s.size.assign(outboxes_.size(), none);
  scratch_.clear();
  for (std::uint32_t i = 0; i < outboxes_.size(); ++i) {
    Outbox& o = outboxes_[i];
    if (!o.sent) continue;
    o.sent = false;
    if (status[i] != DroneStatus::flying) continue;  // only flying drones decide: a stale slot at most
    s.offset[i] = static_cast<std::uint32_t>(s.pool.size());
    s.size[i] = static_cast<std::uint32_t>(o.size);
    s.pool.insert(s.pool.end(), o.room.begin(), o.room.begin() + static_cast<std::ptrdiff_t>(o.size));
    s.senders.push_back(i);
    scratch_.push_back(positions[i]);
  }
  s.positions.assign(positions.begin(), positions.end());
  s.grid.build(scratch_, range / 2);  // a query touches at most 5 × 5 cells, as the drone grid's do
  return s.senders.size();
}

void CommState::receive(std::uint64_t step, std::uint32_t r, const CommSetup& comm, std::uint64_t seed,
                        std::span<const std::uint32_t> groups, const StaticGeometry& geometry, std::vector<PointGrid::Hit>& hits,
                        std::vector<Message>& out, Counts& counts) const {
  out.clear();
  const auto wait = static_cast<std::uint64_t>(latency_) + 1;
  if (step < wait) return;
  const std::uint64_t sent = step - wait;
  const Slot& s = slot(sent);
  if (s.senders.empty() || r >= s.positions.size()) return;
  const Vec2 p = s.positions[r];
  counts.offered += s.senders.size() - (s.size[r] != none);  // every sender but itself
  const bool sight = comm.line_of_sight && geometry.segments().size() > 4;  // 0–3 are the bounds, never crossed
  const bool lossy = comm.loss > 0 || comm.loss_at_range > 0, noisy = comm.range_noise > 0 || comm.bearing_noise > 0;
  const auto cap = static_cast<std::size_t>(comm.max_received);
  auto emit = [&](std::uint32_t j, Vec2 to, double d2) {
    double range = std::sqrt(d2), bearing = bearing_of(to.y, to.x);
    if (noisy) {
      PairDraws draws(seed, sent, j, r);
      draws.uniform();  // the loss draw (drawn or not): a pair's noise is the same with and without loss
      const double dr = draws.normal(), db = draws.normal();
      range = std::max(0.0, range + comm.range_noise * dr);
      bearing = std::remainder(bearing + comm.bearing_noise * db, 2 * pi);  // back to [−π, π]
    }
    out.push_back({j, groups[j], range, bearing, s.time, {s.pool.data() + s.offset[j], s.size[j]}});
  };
  // The senders the grid finds strictly within range, in its order: line of sight, then the loss
  // draw; without a cap each one left is a message at once.
  hits.clear();
  s.grid.query(p, comm.range, [&](std::uint32_t k, Vec2 q, double d2) {
    const std::uint32_t j = s.senders[k];
    if (j == r) return;
    ++counts.in_range;
    if (sight && geometry.blocked(p, q)) return void(++counts.obstacle);
    if (lossy && PairDraws(seed, sent, j, r).uniform() < comm_loss(comm, std::sqrt(d2))) return void(++counts.loss);
    if (cap == 0) emit(j, q - p, d2);
    else hits.push_back({j, d2});
  });
  if (cap > 0) {  // nearest first, then the lower id: a fixed choice, kept in that order
    const auto nearer = [](const PointGrid::Hit& a, const PointGrid::Hit& b) {
      return a.distance_squared != b.distance_squared ? a.distance_squared < b.distance_squared : a.index < b.index;
    };
    if (hits.size() > cap) {
      std::nth_element(hits.begin(), hits.begin() + static_cast<std::ptrdiff_t>(cap), hits.end(), nearer);
      counts.cap += hits.size() - cap;
      hits.resize(cap);
    }
    std::sort(hits.begin(), hits.end(), nearer);
    for (const PointGrid::Hit& h : hits) emit(h.index, s.positions[h.index] - p, h.distance_squared);
  }
  counts.delivered += out.size();
}

}  // namespace salsa
