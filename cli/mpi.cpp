#include "mpi.hpp"

#include <cstdlib>
#include <stdexcept>
#include <string>

#ifdef SALSA_WITH_MPI
#include <mpi.h>
#endif

namespace salsa::cli {

bool under_mpirun() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_SIZE"})
    if (const char* v = std::getenv(name); v && std::atoi(v) > 1) return true;
  return false;
}

#ifdef SALSA_WITH_MPI

bool mpi_built() { return true; }

namespace {

// Messages: a rank asks (request, no payload), rank 0 replies with a test index or -1 (none left);
// a rank that has run all it was given reports (done, its failed count).
constexpr int tag_request = 1, tag_reply = 2, tag_done = 3;

/// A rank other than 0: asks rank 0 for each test.
class RankDispatch final : public Dispatch {
 public:
  std::optional<std::size_t> next() override {
    if (over_) return std::nullopt;
    MPI_Send(nullptr, 0, MPI_INT, 0, tag_request, MPI_COMM_WORLD);
    long long index = -1;
    MPI_Recv(&index, 1, MPI_LONG_LONG, 0, tag_reply, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    if (index < 0) over_ = true;
    if (over_) return std::nullopt;
    return static_cast<std::size_t>(index);
  }
  void finished(std::size_t failed) override {
    long long n = static_cast<long long>(failed);
    MPI_Send(&n, 1, MPI_LONG_LONG, 0, tag_done, MPI_COMM_WORLD);
  }

 private:
  bool over_ = false;
};

}  // namespace

/// Rank 0: hands out the tests in queue order, to itself and (in serve()) to whoever asks.
class RootDispatch final : public Dispatch {
 public:
  RootDispatch(MpiRun& mpi, std::size_t tests) : mpi_(mpi), tests_(tests) {}
  std::optional<std::size_t> next() override {
    if (next_ == tests_) return std::nullopt;
    return next_++;
  }
  void serve() override {
    for (;;) {
      int waiting = 0;
      MPI_Status status;
      MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &waiting, &status);
      if (!waiting) return;
      if (status.MPI_TAG == tag_request) {
        MPI_Recv(nullptr, 0, MPI_INT, status.MPI_SOURCE, tag_request, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        // After SIGINT/SIGTERM no more tests are handed out.
        long long index = next_ == tests_ || stop_signal() ? -1 : static_cast<long long>(next_++);
        MPI_Send(&index, 1, MPI_LONG_LONG, status.MPI_SOURCE, tag_reply, MPI_COMM_WORLD);
      } else {
        long long failed = 0;
        MPI_Recv(&failed, 1, MPI_LONG_LONG, status.MPI_SOURCE, tag_done, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        mpi_.others_failed_ += static_cast<std::size_t>(failed);
        ++reported_;
      }
    }
  }
  bool all_done() override { return reported_ + 1 == mpi_.size(); }

 private:
  MpiRun& mpi_;
  std::size_t tests_, next_ = 0;
  int reported_ = 0;
};

MpiRun::MpiRun() {
  int provided = 0;
  MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
}

MpiRun::~MpiRun() { MPI_Finalize(); }

bool MpiRun::agree(bool ok_on_rank0) {
  int ok = ok_on_rank0 ? 1 : 0;
  MPI_Bcast(&ok, 1, MPI_INT, 0, MPI_COMM_WORLD);
  return ok == 1;
}

void MpiRun::barrier() { MPI_Barrier(MPI_COMM_WORLD); }

std::unique_ptr<Dispatch> MpiRun::dispatch(std::size_t tests) {
  if (rank_ == 0) return std::make_unique<RootDispatch>(*this, tests);
  return std::make_unique<RankDispatch>();
}

#else

bool mpi_built() { return false; }
MpiRun::MpiRun() { throw std::logic_error("salsa was built without MPI"); }
MpiRun::~MpiRun() = default;
bool MpiRun::agree(bool ok) { return ok; }
void MpiRun::barrier() {}
std::unique_ptr<Dispatch> MpiRun::dispatch(std::size_t) { return nullptr; }

#endif

}  // namespace salsa::cli
