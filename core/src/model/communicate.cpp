// The comm model in the step: messages packed after decide, counted, and an inbox shown ahead.
#include "salsa/core/model/simulation.hpp"

#include <limits>

#include "model/step_parallel.hpp"

namespace salsa {

// Communicate: the counts of the messages each drone received in this decide (its inbox was gathered
// right before its decide, as its neighbours are) summed, then the messages broadcast in this decide
// packed with the positions they were decided on, for the receivers'
// decide latency + 1 steps on. Serial, O(drones). Runs only with "comm".
void Simulation::communicate() {
  CommState::Counts total;
  for (const CommState::Counts& c : comm_counts_) {
    total.offered += c.offered, total.in_range += c.in_range, total.obstacle += c.obstacle, total.loss += c.loss;
    total.cap += c.cap, total.delivered += c.delivered;
  }
  // Each message is offered to every other drone flying when it arrives; those the grid did not find
  // in range are dropped by range, counted without looking at them.
  CommCounters& k = comm_counters_;
  k.dropped_range += total.offered - total.in_range;
  k.dropped_obstacle += total.obstacle;
  k.dropped_loss += total.loss;
  k.dropped_cap += total.cap;
  k.delivered += total.delivered;
  k.sent += comm_->collect(steps_, time(), drones_.positions, drones_.status);
}

void Simulation::comm_changed() {
  comm_stale_ = true;
  inbox_grid_step_ = std::numeric_limits<std::uint64_t>::max();
}

void Simulation::set_comm(const CommSetup& comm) {
  if (const std::string why = comm_problem(comm); !why.empty()) throw std::invalid_argument(why);
  setup_.comm = comm;
  comm_changed();
}

std::vector<Message> Simulation::inbox(std::uint32_t id) const {
  std::vector<Message> out;
  if (!setup_.comm.on || comm_stale_) return out;
  if (id >= drones_.positions.size()) return out;
  // The grid the next step's sense will build (drones do not move between steps), kept for the step.
  if (inbox_grid_step_ != steps_) {
    inbox_grid_.build(drones_.positions, grid_range_ / 2);
    inbox_grid_step_ = steps_;
  }
  std::vector<PointGrid::Hit> candidates, hits;
  inbox_grid_.gather(drones_.positions[id], comm_->reach(steps_, drones_.positions, setup_.comm.range), candidates);
  CommState::Counts counts;
  comm_->receive(steps_, id, setup_.comm, setup_.seed, drones_.groups, geometry_, candidates, hits, out, counts);
  return out;
}

}  // namespace salsa
