#include "salsa/core/model/comm.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "salsa/core/model/static_geometry.hpp"
#include "model/plugin_call.hpp"

namespace salsa {

const Schema<CommSetup>& comm_schema() {
  static const Schema<CommSetup> schema{
      field<&CommSetup::range>({"range", 134, 1e-3, 1e6, "m", "farthest a message travels, centre to centre (default: the small drone's detection range)", 0.5}),
      field<&CommSetup::line_of_sight>({"line_of_sight", 1, 0, 1, "", "true: a wall or obstacle between sender and receiver blocks the message", 1}),
      field<&CommSetup::loss>({"loss", 0, 0, 1, "", "probability a message in range and sight is lost, at any distance", 0.01}),
      field<&CommSetup::loss_at_range>({"loss_at_range", 0, 0, 1, "", "extra loss at full range, growing as (distance / range)^2: p = 1 - (1 - loss)(1 - loss_at_range (d / range)^2)", 0.01}),
      field<&CommSetup::latency>({"latency", 0, 0, 1000, "steps", "steps a message waits: 0 = received in the next step's decide", 1}),
      field<&CommSetup::max_received>({"max_received", 0, 0, 100000, "", "messages a drone receives per step, nearest senders first; 0: no cap", 1}),
      field<&CommSetup::range_noise>({"range_noise", 0, 0, 1e4, "m", "sd of the Gaussian noise on the range a receiver measures (clamped at 0)", 0.1}),
      field<&CommSetup::bearing_noise>({"bearing_noise", 0, 0, 10, "rad", "sd of the Gaussian noise on the bearing a receiver measures", 0.01}),
  };
  return schema;
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

/// The offset `to` as a receiver measures it with the model's range and bearing noise, from the pair's
/// draws (a range that noise takes below 0 is 0).
[[gnu::noinline]] Vec2 measured(Vec2 to, const CommSetup& comm, PairDraws draws) {
  draws.uniform();  // the loss draw (drawn or not): a pair's noise is the same with and without loss
  const double dr = draws.normal(), db = draws.normal();
  return Vec2::polar(std::max(0.0, to.length() + comm.range_noise * dr), to.angle() + comm.bearing_noise * db);
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
  rooms_.resize(drones);
  groups_.assign(groups.begin(), groups.end());
  for (std::size_t i = 0; i < drones; ++i) outboxes_[i].room = rooms_[i] = {room_.data() + i * stride, room[groups[i]]};
}

void CommState::clear() {
  for (Slot& s : ring_) s.senders = 0, s.positions.clear();
  for (Outbox& o : outboxes_) o.sent = false, o.size = 0;
}

std::size_t CommState::collect(std::uint64_t step, double time, std::span<const Vec2> positions, std::span<const DroneStatus> status) {
  Slot& s = slot(step);
  s.time = time;
  s.pool.clear();
  s.senders = 0;
  s.offset.resize(outboxes_.size());
  s.size.assign(outboxes_.size(), none);
  for (std::uint32_t i = 0; i < outboxes_.size(); ++i) {
    Outbox& o = outboxes_[i];
    if (!o.sent) continue;
    o.sent = false;
    if (status[i] != DroneStatus::flying) continue;  // only flying drones decide: a stale slot at most
    if (o.room.data() != rooms_[i].data() || o.room.size() != rooms_[i].size() || o.size > rooms_[i].size())
      throw PluginFailure(detail::behavior_kind, groups_[i],
                          "drone " + std::to_string(i) + "'s outbox says " + std::to_string(o.size) + " doubles " +
                              (o.room.data() == rooms_[i].data() ? "in its slot of " + std::to_string(o.room.size()) : std::string("in a room moved off its slot")) +
                              " (set by hand; allowed: Perception::broadcast of at most message_size() = " + std::to_string(rooms_[i].size()) + " doubles)");
    s.offset[i] = static_cast<std::uint32_t>(s.pool.size());
    s.size[i] = static_cast<std::uint32_t>(o.size);
    s.pool.insert(s.pool.end(), o.room.begin(), o.room.begin() + static_cast<std::ptrdiff_t>(o.size));
    ++s.senders;
  }
  s.positions.assign(positions.begin(), positions.end());
  return s.senders;
}

const CommState::Slot* CommState::sent_to(std::uint64_t step) const {
  const auto wait = static_cast<std::uint64_t>(latency_) + 1;
  if (step < wait) return nullptr;
  const Slot& s = slot(step - wait);
  return s.senders == 0 ? nullptr : &s;
}

double CommState::reach(std::uint64_t step, std::span<const Vec2> now, double range) const {
  const Slot* s = sent_to(step);
  if (!s) return 0;
  double moved2 = 0;  // a drone with a non-finite position is in no grid: it neither sends nor receives
  for (std::size_t i = 0, n = std::min(now.size(), s->positions.size()); i < n; ++i)
    if (const double d2 = distance_squared(now[i], s->positions[i]); std::isfinite(d2)) moved2 = std::max(moved2, d2);
  // d(then) < range implies d(now) ≤ d(then) + 2 × moved < range + 2 × moved; the factor covers
  // the rounding of the distances the grid and this test compute.
  return (range + 2 * std::sqrt(moved2)) * (1 + 1e-9);
}

void CommState::receive(std::uint64_t step, std::uint32_t r, const CommSetup& comm, std::uint64_t seed,
                        std::span<const std::uint32_t> groups, const StaticGeometry& geometry,
                        std::span<const PointGrid::Hit> candidates, std::vector<PointGrid::Hit>& hits, std::vector<Message>& out,
                        Counts& counts) const {
  out.clear();
  const Slot* found = sent_to(step);
  if (!found || r >= found->positions.size()) return;
  const Slot& s = *found;
  const std::uint64_t sent = step - static_cast<std::uint64_t>(latency_) - 1;
  const Vec2 p = s.positions[r];
  counts.offered += s.senders - (s.size[r] != none);  // every sender but itself
  const bool sight = comm.line_of_sight && geometry.segments().size() > 4;  // 0–3 are the bounds, never crossed
  const bool lossy = comm.loss > 0 || comm.loss_at_range > 0, noisy = comm.range_noise > 0 || comm.bearing_noise > 0;
  const auto cap = static_cast<std::size_t>(comm.max_received);
  // The message as measured: the true offset to the sender, or with noise (measured()) the offset at
  // the noisy range and bearing. Field by field into its place: a Message built aside and copied in
  // went through the stack in pieces, stalling the loads that copied it (a third of the delivery).
  auto deliver = [&](std::uint32_t j, Vec2 to) {
    Message& m = out.emplace_back();
    m.sender = j;
    m.group = groups[j];
    m.offset = noisy ? measured(to, comm, PairDraws(seed, sent, j, r)) : to;
    m.time = s.time;
    m.payload = {s.pool.data() + s.offset[j], s.size[j]};
  };
  // Each candidate that sent from strictly within range: line of sight, then the loss draw; without a
  // cap each one left is a message at once. Counted in locals: `out` may alias `counts` for all the
  // compiler knows.
  hits.clear();
  const double r2 = comm.range * comm.range;
  std::uint64_t in_range = 0, obstacle = 0, loss = 0;
  for (const PointGrid::Hit& h : candidates) {
    const std::uint32_t j = h.index;
    if (j == r || j >= s.size.size() || s.size[j] == none) continue;
    const Vec2 q = s.positions[j], to = q - p;
    const double d2 = to.length_squared();
    if (!(d2 < r2)) continue;
    ++in_range;
    if (sight && geometry.blocked(p, q)) {
      ++obstacle;
      continue;
    }
    if (lossy && PairDraws(seed, sent, j, r).uniform() < comm_loss(comm, std::sqrt(d2))) {
      ++loss;
      continue;
    }
    if (cap > 0) hits.push_back({j, d2});
    else deliver(j, to);
  }
  counts.in_range += in_range, counts.obstacle += obstacle, counts.loss += loss;
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
    for (const PointGrid::Hit& h : hits) deliver(h.index, s.positions[h.index] - p);
  }
  counts.delivered += out.size();
}

}  // namespace salsa
