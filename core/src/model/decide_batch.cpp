// Decide for a group whose behavior decides in batches (batch_behavior.hpp): its flying drones'
// Perceptions, built as for any behavior (sensor noise included), gathered into flat arrays and
// handed to the behavior in one call on the stepping thread.
#include "salsa/core/model/simulation.hpp"

#include <algorithm>

#include "model/plugin_call.hpp"
#include "model/step_parallel.hpp"
#include "salsa/core/model/batch_behavior.hpp"
#include "salsa/core/model/comm.hpp"

namespace salsa {

using namespace detail;

void Simulation::decide_batch(std::uint32_t g, BatchBehavior& behavior, Senses senses, bool noise) {
  if (!batches_) batches_ = std::make_unique<Batches>();
  Batches& b = *batches_;
  b.ids.clear();
  for (std::uint32_t i = 0; i < drones_.status.size(); ++i)
    if (drones_.status[i] == DroneStatus::flying && drones_.groups[i] == g && !on_errand(i)) b.ids.push_back(i);
  if (b.ids.empty()) return;  // as a C++ behavior, not asked without a drone to decide for
  if (!b.batch || b.batch.use_count() > 1) b.batch = std::make_shared<PerceptionBatch>();

  // Rows in id order, gathered in chunks of fixed size (in parallel when there are several), then
  // joined in chunk order: the same batch for any thread count.
  auto gather = [&](PerceptionBatch& into, std::size_t k, Scratch& s) {
    into.clear();
    const std::size_t end = std::min(b.ids.size(), (k + 1) * Batches::chunk);
    for (std::size_t r = k * Batches::chunk; r < end; ++r) {
      Perception me = perceive(b.ids[r], senses, s);
      if (noise) add_noise(me, senses, s);
      into.append(me, senses);
    }
    into.finish();
  };
  const std::size_t chunks = (b.ids.size() + Batches::chunk - 1) / Batches::chunk;
  if (chunks == 1) {
    gather(*b.batch, 0, parallel_->scratch.local());
  } else {
    b.parts.resize(chunks);
    parallel_->for_tasks(chunks, [&](std::size_t k, Scratch& s) { gather(b.parts[k], k, s); });
    b.batch->assign(b.parts);
  }

  b.steering.assign(b.ids.size(), Vec2{});
  BatchRng rng(drones_.rngs, b.ids);
  // Each row's outbox as perceive() gives a drone one: comm's slot, or a room nobody reads.
  b.outboxes.resize(b.ids.size());
  if (setup_.comm.on) {
    for (std::size_t r = 0; r < b.ids.size(); ++r) b.outboxes[r] = &comm_->outbox(b.ids[r]);
  } else {
    b.unheard_room.resize(message_sizes_[g]);
    b.unheard = {b.unheard_room, 0, false};
    std::fill(b.outboxes.begin(), b.outboxes.end(), &b.unheard);
  }
  const std::shared_ptr<const PerceptionBatch> batch = b.batch;
  plugin_call(behavior_kind, g, [&] { behavior.decide_batch(batch, rng, BatchOutbox(b.outboxes, b.ids), b.steering); });
  for (std::size_t r = 0; r < b.ids.size(); ++r) drones_.steering[b.ids[r]] = b.steering[r];
}

}  // namespace salsa
