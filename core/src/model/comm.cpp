#include "salsa/core/model/comm.hpp"

#include <algorithm>
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
  for (Slot& s : ring_) {
    s.offset.resize(drones, 0);
    s.size.resize(drones, none);
    s.inbox.resize(drones);
  }
}

void CommState::clear() {
  for (Slot& s : ring_) {
    s.pool.clear();
    s.senders = 0;
    std::fill(s.size.begin(), s.size.end(), none);
    for (auto& box : s.inbox) box.clear();
  }
  for (Outbox& o : outboxes_) o.sent = false, o.size = 0;
}

std::span<const Message> CommState::inbox(std::uint64_t step, std::uint32_t id) const {
  const auto wait = static_cast<std::uint64_t>(latency_) + 1;
  if (step < wait) return {};
  const Slot& s = slot(step - wait);
  return id < s.inbox.size() ? std::span<const Message>(s.inbox[id]) : std::span<const Message>();
}

std::size_t CommState::collect(std::uint64_t step, double time, std::span<const DroneStatus> status) {
  Slot& s = slot(step);
  s.time = time;
  s.pool.clear();
  std::size_t sent = 0;
  for (std::uint32_t i = 0; i < outboxes_.size(); ++i) {
    Outbox& o = outboxes_[i];
    s.size[i] = none;
    if (!o.sent) continue;
    o.sent = false;
    if (status[i] != DroneStatus::flying) continue;  // only flying drones decide: a stale slot at most
    s.offset[i] = static_cast<std::uint32_t>(s.pool.size());
    s.size[i] = static_cast<std::uint32_t>(o.size);
    s.pool.insert(s.pool.end(), o.room.begin(), o.room.begin() + static_cast<std::ptrdiff_t>(o.size));
    ++sent;
  }
  return s.senders = sent;
}

void CommState::receive(std::uint64_t step, std::uint32_t r, const CommSetup& comm, std::uint64_t seed,
                        std::span<const Vec2> positions, std::span<const std::uint32_t> groups, std::span<const DroneStatus> status,
                        const PointGrid& grid, const StaticGeometry& geometry, std::vector<PointGrid::Hit>& hits, Counts& counts) {
  Slot& s = slot(step);
  std::vector<Message>& inbox = s.inbox[r];
  inbox.clear();
  if (s.senders == 0 || status[r] != DroneStatus::flying) return;
  const Vec2 p = positions[r];
  hits.clear();
  grid.gather(p, comm.range, hits);
  // Senders in range that broadcast; the range test is the grid's (strictly closer than range).
  std::erase_if(hits, [&](const PointGrid::Hit& h) { return h.index == r || s.size[h.index] == none || status[h.index] != DroneStatus::flying; });
  counts.in_range += hits.size();
  if (comm.line_of_sight)
    std::erase_if(hits, [&](const PointGrid::Hit& h) {
      const bool blocked = geometry.blocked(p, positions[h.index]);
      counts.obstacle += blocked;
      return blocked;
    });
  const bool lossy = comm.loss > 0 || comm.loss_at_range > 0;
  if (lossy)
    std::erase_if(hits, [&](const PointGrid::Hit& h) {
      PairDraws draws(seed, step, h.index, r);
      const bool lost = draws.uniform() < comm_loss(comm, std::sqrt(h.distance_squared));
      counts.loss += lost;
      return lost;
    });
  const auto cap = static_cast<std::size_t>(comm.max_received);
  if (cap > 0 && hits.size() > cap) {  // nearest first, then the lower id: a fixed choice
    const auto nearer = [](const PointGrid::Hit& a, const PointGrid::Hit& b) {
      return a.distance_squared != b.distance_squared ? a.distance_squared < b.distance_squared : a.index < b.index;
    };
    std::nth_element(hits.begin(), hits.begin() + static_cast<std::ptrdiff_t>(cap), hits.end(), nearer);
    counts.cap += hits.size() - cap;
    hits.resize(cap);
  }
  std::sort(hits.begin(), hits.end(), [](const PointGrid::Hit& a, const PointGrid::Hit& b) { return a.index < b.index; });
  counts.delivered += hits.size();
  const bool noisy = comm.range_noise > 0 || comm.bearing_noise > 0;
  for (const PointGrid::Hit& h : hits) {
    const std::uint32_t j = h.index;
    const Vec2 to = positions[j] - p;
    double range = std::sqrt(h.distance_squared), bearing = std::atan2(to.y, to.x);
    if (noisy) {
      PairDraws draws(seed, step, j, r);
      draws.uniform();  // the loss draw (drawn or not): a pair's noise is the same with and without loss
      const double dr = draws.normal(), db = draws.normal();
      range = std::max(0.0, range + comm.range_noise * dr);
      bearing = std::remainder(bearing + comm.bearing_noise * db, 2 * pi);  // back to [−π, π]
    }
    inbox.push_back({j, groups[j], range, bearing, s.time, {s.pool.data() + s.offset[j], s.size[j]}});
  }
}

}  // namespace salsa
