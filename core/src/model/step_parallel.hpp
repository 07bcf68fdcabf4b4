#pragma once
// How the step spreads its per-drone work over threads (Simulation::Parallel), each thread's scratch
// buffers (Simulation::Scratch), and the state a map change builds aside (Simulation::World).
#include <oneapi/tbb/enumerable_thread_specific.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>
#include <oneapi/tbb/task_group.h>

#include <cxxabi.h>

#include <array>
#include <atomic>
#include <exception>
#include <limits>
#include <memory>
#include <mutex>
#include <span>
#include <vector>

#include "model/physics.hpp"
#include "salsa/core/model/batch_behavior.hpp"
#include "salsa/core/model/simulation.hpp"

namespace salsa {

struct Simulation::Scratch {
  std::vector<PointGrid::Hit> hits, senders;
  std::vector<Message> messages;
  Outbox outbox;  ///< without "comm": broadcast writes here (its size still checked), nobody reads it
  std::array<double, max_message_size> room;
  std::vector<Neighbour> neighbours;
  std::vector<TargetSeen> targets;
  std::vector<ObstacleHit> obstacles;  ///< the noisy copy of a drone's hits (obstacle or position noise)
  std::vector<std::uint32_t> segment_ids;
};

struct Simulation::Parallel {
  static constexpr std::size_t grain = 64;  // drones per task
  tbb::task_arena arena;
  tbb::enumerable_thread_specific<Scratch> scratch;
  explicit Parallel(int threads) : arena(threads > 0 ? threads : tbb::task_arena::automatic) {}

  /// Runs `side` (one long serial job) while this thread goes on with `main`; both done on return.
  /// With few drones both are shorter than waking a thread, so they simply run one after the other.
  template <class Side, class Main>
  void overlap(std::size_t drones, Side&& side, Main&& main) {
    if (drones <= grain) {
      side();
      main();
      return;
    }
    arena.execute([&] {
      tbb::task_group group;
      group.run(side);  // the oldest task: the first a free worker steals
      main();
      group.wait();
    });
  }

  /// What fn threw for the lowest drone id: the failure reported whatever the thread count and the
  /// order the drones ran in. Drones above the lowest failing id so far are skipped (none of theirs
  /// can be reported).
  struct FirstFailure {
    std::atomic<std::uint32_t> id{std::numeric_limits<std::uint32_t>::max()};
    std::mutex mutex;
    std::exception_ptr error;
    bool skip(std::uint32_t i) const { return i > id.load(std::memory_order_relaxed); }
    void note(std::uint32_t i) {
      const std::lock_guard lock(mutex);
      if (i < id.load(std::memory_order_relaxed) || !error) {
        id.store(i, std::memory_order_relaxed);
        error = std::current_exception();
      }
    }
    /// fn() for drone i unless skipped, its throw noted (a thread being cancelled passes through).
    template <class Fn>
    void guard(std::uint32_t i, Fn&& fn) {
      if (skip(i)) return;
      try {
        fn();
      } catch (const abi::__forced_unwind&) {
        throw;
      } catch (...) {
        note(i);
      }
    }
  };

  /// fn(order[k], scratch) for every k, spread over the arena's threads. Drones go in grid-cell order,
  /// so that neighbouring drones, which read the same cells, run one after the other. A throw is
  /// caught where it happens (not left to TBB, which would pass on whichever came first) and the
  /// lowest drone id's is rethrown once all are done.
  /// With `ahead`, ahead(order[k + 8], 0) and ahead(order[k + 4], 1) run before fn(order[k]): a
  /// place to prefetch what those drones will read, in two stages (a record, then what it points to).
  template <class Fn, class Ahead = void (*)(std::uint32_t, int)>
  void for_each(std::span<const std::uint32_t> order, Fn&& fn, Ahead&& ahead = [](std::uint32_t, int) {}) {
    FirstFailure failure;
    auto one = [&](std::uint32_t i, Scratch& s) { failure.guard(i, [&] { fn(i, s); }); };
    auto run = [&](std::size_t begin, std::size_t end) {
      Scratch& s = scratch.local();
      for (std::size_t k = begin; k != end; ++k) {
        if (k + 8 < end) ahead(order[k + 8], 0);
        if (k + 4 < end) ahead(order[k + 4], 1);
        one(order[k], s);
      }
    };
    if (order.size() <= grain) {  // one chunk: not worth a task
      run(0, order.size());
    } else {
      arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, order.size(), grain),
                          [&](const tbb::blocked_range<std::size_t>& r) { run(r.begin(), r.end()); });
      });
    }
    if (failure.error) std::rethrow_exception(failure.error);
  }

  /// fn(k, scratch) for every k in [0, count), one task each (as for_each, the lowest k's throw is
  /// rethrown once all are done).
  template <class Fn>
  void for_tasks(std::size_t count, Fn&& fn) {
    FirstFailure failure;
    arena.execute([&] {
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 1), [&](const tbb::blocked_range<std::size_t>& r) {
        Scratch& s = scratch.local();
        for (std::size_t k = r.begin(); k != r.end(); ++k) failure.guard(static_cast<std::uint32_t>(k), [&] { fn(k, s); });
      });
    });
    if (failure.error) std::rethrow_exception(failure.error);
  }
};

/// What decide_batch keeps between steps, so that its buffers keep their capacity.
struct Simulation::Batches {
  /// Drones per gathering task: fixed, so that what a task gathers, and so the batch, never depends
  /// on the thread count.
  static constexpr std::size_t chunk = 128;
  std::vector<std::uint32_t> ids;      ///< the group's flying drones, in id order: the batch's rows
  std::vector<PerceptionBatch> parts;  ///< one per chunk
  std::shared_ptr<PerceptionBatch> batch;  ///< replaced when the behavior still holds the last one
  std::vector<Vec2> steering;
  std::vector<Outbox*> outboxes;  ///< each row's drone's outbox (comm's), or `unheard` without comm
  Outbox unheard;                 ///< without comm: broadcast checks the size, and nobody receives
  std::vector<double> unheard_room;
};

struct Simulation::World {
  StaticGeometry geometry;
  std::vector<Group> groups;
  std::unique_ptr<Physics> physics;
  Rng spawn_rng;
  Drones drones;
  Targets targets;
};

}  // namespace salsa
