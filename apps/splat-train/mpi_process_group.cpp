#include "apps/splat-train/mpi_process_group.hpp"

#include <climits>
#include <cstdlib>
#include <string>

#include "splat/core/error.hpp"

#if SPLAT_WITH_MPI
#include <mpi.h>
#endif

namespace splat::cli {

namespace {

// The launchers' own variables: Open MPI's mpirun, and PMI / PMIx as MPICH's mpiexec and
// Slurm's srun set them. A Slurm batch script alone sets none of these.
bool started_by_mpi_launcher() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"})
    if (std::getenv(name)) return true;
  return false;
}

#if !SPLAT_WITH_MPI
// The rank count the launcher announced, 0 when it does not say.
int launched_ranks() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"})
    if (const char* value = std::getenv(name)) return std::atoi(value);
  return 0;
}
#endif

#if SPLAT_WITH_MPI
class MpiProcessGroup final : public ProcessGroup {
 public:
  MpiProcessGroup() {
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
  }
  ~MpiProcessGroup() override { MPI_Finalize(); }

  int rank() const override { return rank_; }
  int size() const override { return size_; }

  void all_gather(std::span<const float> mine, std::span<float> all) override {
    check_message_size(mine.size());
    if (all.size() != mine.size() * std::size_t(size_))
      throw ArgumentError("all_gather: " + std::to_string(all.size()) + " slots for " + std::to_string(size_) +
                          " × " + std::to_string(mine.size()) + " floats");
    MPI_Allgather(mine.data(), int(mine.size()), MPI_FLOAT, all.data(), int(mine.size()), MPI_FLOAT, MPI_COMM_WORLD);
  }

  void all_to_all(std::span<const float> send, std::span<float> receive) override {
    const std::size_t part = send.size() / std::size_t(size_);
    check_message_size(part);
    if (send.size() != part * std::size_t(size_) || receive.size() != send.size())
      throw ArgumentError("all_to_all: " + std::to_string(send.size()) + " floats to send and " +
                          std::to_string(receive.size()) + " to receive over " + std::to_string(size_) + " ranks");
    MPI_Alltoall(send.data(), int(part), MPI_FLOAT, receive.data(), int(part), MPI_FLOAT, MPI_COMM_WORLD);
  }

  void broadcast(std::span<double> values) override {
    MPI_Bcast(values.data(), int(values.size()), MPI_DOUBLE, 0, MPI_COMM_WORLD);
  }

  bool any(bool mine) override {
    int value = mine ? 1 : 0;
    MPI_Allreduce(MPI_IN_PLACE, &value, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    return value != 0;
  }

 private:
  // MPI counts are ints.
  static void check_message_size(std::size_t floats) {
    if (floats > std::size_t(INT_MAX))
      throw ArgumentError("a rank's share of the step (" + std::to_string(floats) +
                          " floats) is more than one MPI message holds: use a smaller --batch");
  }

  int rank_ = 0, size_ = 1;
};
#endif

}  // namespace

std::unique_ptr<ProcessGroup> join_launched_ranks(int& argc, char**& argv) {
  if (!started_by_mpi_launcher()) return nullptr;
#if SPLAT_WITH_MPI
  // The trainer's threads never call MPI: the main thread does all of it.
  int provided = 0;
  MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
  return std::make_unique<MpiProcessGroup>();
#else
  (void)argc;
  (void)argv;
  const int ranks = launched_ranks();
  if (ranks > 1)
    throw Error("an MPI launcher started " + std::to_string(ranks) +
                " ranks, but this splat-train was built without MPI (SPLAT_MPI=OFF, or no MPI library "
                "found): each rank would train the whole run alone into the same folder. Install Open MPI "
                "(libopenmpi-dev) and rebuild, or run splat-train without the launcher");
  return nullptr;
#endif
}

void abort_all_ranks(int status) {
#if SPLAT_WITH_MPI
  MPI_Abort(MPI_COMM_WORLD, status);
#endif
  std::exit(status);
}

}  // namespace splat::cli
