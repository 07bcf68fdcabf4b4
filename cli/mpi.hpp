#pragma once
// Running a queue over MPI ranks (mpirun): rank 0 hands out test indices one at a time, on request,
// so a slow test holds up only its rank; every rank runs tests (rank 0 too: its main thread answers
// requests between its own events); rank 0 writes the queue summary when every rank has reported.
#include <cstddef>
#include <memory>

#include "queue_run.hpp"

namespace salsa::cli {

/// Whether this process was started by mpirun (or srun) as one of several ranks: OMPI_COMM_WORLD_SIZE,
/// PMI_SIZE or PMIX_SIZE above 1.
bool under_mpirun();

/// Whether this salsa was built with MPI (SALSA_WITH_MPI).
bool mpi_built();

/// MPI for one run: MPI_Init on construction, MPI_Finalize on destruction. Only the main thread
/// calls MPI (MPI_THREAD_FUNNELED).
class MpiRun {
 public:
  MpiRun();
  ~MpiRun();
  MpiRun(const MpiRun&) = delete;
  MpiRun& operator=(const MpiRun&) = delete;

  int rank() const { return rank_; }
  int size() const { return size_; }
  /// Rank 0's verdict (it checks the output folder) given to every rank; false on every rank when
  /// rank 0 said no.
  bool agree(bool ok_on_rank0);
  /// Waits until every rank is here (salsa tune: a batch's tests are all done before any rank reads them).
  void barrier();
  /// Rank 0: hands out 0..tests-1 to itself and the others; other ranks: asks rank 0.
  std::unique_ptr<Dispatch> dispatch(std::size_t tests);
  /// Rank 0, after the run: how many tests failed on the other ranks.
  std::size_t others_failed() const { return others_failed_; }

 private:
  int rank_ = 0, size_ = 1;
  std::size_t others_failed_ = 0;
  friend class RootDispatch;
};

/// Runs `claim` (the checks of the output folder: it throws to refuse) on rank 0 only and gives its
/// verdict to every rank: false on the other ranks when rank 0 refused (rank 0 rethrows, saying why).
/// Without MPI (`world` null) it simply runs `claim`.
template <class Claim>
bool claimed_on_rank0(MpiRun* world, Claim&& claim) {
  if (world && world->rank() != 0) return world->agree(false);
  try {
    claim();
  } catch (...) {
    if (world) world->agree(false);
    throw;
  }
  if (world) world->agree(true);
  return true;
}

}  // namespace salsa::cli
