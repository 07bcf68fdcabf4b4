#pragma once
// The communication model (a test's "comm", docs/test-format.md#communication): which broadcast
// messages reach which drones, when, and what the receiver measures of the sender. Its fields are
// declared once, in comm_schema(): the test reader and writer, timed changes and sweeps (comm.<field>),
// `salsa describe comm` and the docs' table all iterate it.
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "salsa/core/model/schema.hpp"
#include "salsa/grid.hpp"
#include "salsa/parameters.hpp"
#include "salsa/world.hpp"

namespace salsa {

class StaticGeometry;

struct CommSetup {
  bool on = false;              ///< the test has "comm"; off: no deliveries, no columns, no cost
  double range = 134;           ///< m: farther receivers never get a message
  bool line_of_sight = true;    ///< a wall or obstacle on the segment between the two drones blocks
  double loss = 0;              ///< probability a message in range is lost, whatever the distance
  double loss_at_range = 0;     ///< extra loss at the full range, growing with (distance / range)²
  int latency = 0;              ///< steps: 0 = received in the next step's decide
  int max_received = 0;         ///< messages a drone receives per step, nearest first; 0: no cap
  double range_noise = 0;       ///< m: sd of the Gaussian noise on the measured range
  double bearing_noise = 0;     ///< rad: sd of the Gaussian noise on the measured bearing
  bool operator==(const CommSetup&) const = default;
};

/// One field of CommSetup (schema.hpp): a number, a whole number, or a flag read as true/false.
using CommField = Field<CommSetup>;

/// Every field of "comm", in file order.
const Schema<CommSetup>& comm_schema();
/// Empty when every field is within its declared range, else "comm.<field>: <value> is out of range
/// (allowed: ...)".
std::string comm_problem(const CommSetup& c);

/// Probability that a message sent over `distance` m (within range) is lost:
///   p(d) = 1 − (1 − loss) · (1 − loss_at_range · (d / range)²)
double comm_loss(const CommSetup& c, double distance);

/// What became of the messages so far, cumulative. Every message a flying drone broadcasts is offered
/// to every other flying drone: sent × (flying − 1) = delivered + the four kinds of dropped.
struct CommCounters {
  std::uint64_t sent = 0;              ///< messages broadcast by flying drones
  std::uint64_t delivered = 0;         ///< (message, receiver) pairs put in an inbox
  std::uint64_t dropped_range = 0;     ///< receivers farther than range: (flying − 1) per message, less those within range
  std::uint64_t dropped_obstacle = 0;  ///< within range, line of sight blocked
  std::uint64_t dropped_loss = 0;      ///< within range and sight, lost (comm_loss)
  std::uint64_t dropped_cap = 0;       ///< received, but beyond max_received that step
  bool operator==(const CommCounters&) const = default;
};
/// summary.csv's comm columns, in order (docs/output-format.md).
inline constexpr const char* comm_columns[] = {"messages_sent", "messages_delivered", "dropped_range",
                                               "dropped_obstacle", "dropped_loss", "dropped_cap"};

/// The messages in flight: what the drones broadcast in a step, with the positions they were decided
/// on, kept for latency + 2 steps (one slot written, one read, the rest in flight). A receiver's inbox
/// is gathered in its own `decide`, right before the call (as its neighbours are), into a buffer of the
/// deciding thread: nothing per receiver is stored, and each drone writes only its own counts.
///
/// The candidate senders come from the drone grid of the receiving step, in the same search as the
/// receiver's neighbours, within `reach`: the range plus twice the farthest any drone moved since the
/// messages were sent, so every sender that was within range then is found now. Range is then decided
/// on the positions of the sent step.
class CommState {
 public:
  /// Per-drone room for `drones` drones, each `room[group]` doubles; keeps what is in flight unless
  /// the latency changed.
  void resize(std::size_t drones, std::span<const std::size_t> room, std::span<const std::uint32_t> groups, int latency);
  /// Everything in flight forgotten (a new map).
  void clear();
  Outbox& outbox(std::uint32_t id) { return outboxes_[id]; }

  /// The broadcasts of step `step` (sent at `time`, decided on `positions`) packed into its slot;
  /// outboxes cleared for the next step. Returns how many drones broadcast. Serial, O(drones + payload).
  /// An outbox is plugin-writable memory: one whose room or size is not what broadcast can leave there
  /// (the slot given, at most its message_size() doubles) is a PluginFailure naming the sender's
  /// behavior, so no plugin makes the core read outside a slot.
  std::size_t collect(std::uint64_t step, double time, std::span<const Vec2> positions, std::span<const DroneStatus> status);

  /// The radius around a receiver's position `now` within which step `step`'s receivers find every
  /// sender that was within `range` of them when it sent: range + 2 × the farthest a drone moved since
  /// (with a hair for rounding). 0 when nothing is to be received. Serial, O(drones), once a step.
  double reach(std::uint64_t step, std::span<const Vec2> now, double range) const;

  /// What each receiver's step did with the messages offered to it.
  struct Counts {
    std::uint64_t offered = 0, in_range = 0, obstacle = 0, loss = 0, cap = 0, delivered = 0;
  };
  /// Drone `receiver`'s messages in step `step` (sent in step − 1 − latency) into `out`, in the order of
  /// `candidates` (nearest first when capped): the senders among them that were strictly within range of
  /// where the receiver was then, in sight, not lost, at most max_received. `candidates` is a search of
  /// the drone grid of step `step` within `reach` (more is fine). Draws come from (seed, sent step,
  /// sender, receiver) alone. Adds to `counts` (the receiver's own). The receiver flies now, so it flew
  /// then (a stopped drone never flies again; a drone added since has no messages).
  void receive(std::uint64_t step, std::uint32_t receiver, const CommSetup& comm, std::uint64_t seed,
               std::span<const std::uint32_t> groups, const StaticGeometry& geometry, std::span<const PointGrid::Hit> candidates,
               std::vector<PointGrid::Hit>& hits, std::vector<Message>& out, Counts& counts) const;

 private:
  struct Slot {
    double time = 0;
    std::vector<double> pool;                  ///< payloads, packed
    std::vector<std::uint32_t> offset, size;   ///< per drone: its payload in pool; size UINT32_MAX: did not broadcast
    std::size_t senders = 0;                   ///< drones that broadcast
    std::vector<Vec2> positions;               ///< every drone's, as the senders decided on them
  };
  Slot& slot(std::uint64_t step) { return ring_[step % ring_.size()]; }
  const Slot& slot(std::uint64_t step) const { return ring_[step % ring_.size()]; }
  /// The slot step `step` receives from, or nullptr before anything was sent.
  const Slot* sent_to(std::uint64_t step) const;

  int latency_ = 0;
  std::vector<Slot> ring_{2};
  std::vector<double> room_;        ///< every drone's outbox room, back to back
  std::vector<Outbox> outboxes_;
  std::vector<std::span<double>> rooms_;  ///< each drone's slot in room_, as given: what its outbox is checked against
  std::vector<std::uint32_t> groups_;     ///< each drone's group at resize: whose behavior a bad outbox is
};

}  // namespace salsa
