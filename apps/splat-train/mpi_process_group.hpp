#pragma once
// splat-train's ranks when an MPI launcher (mpirun, or Slurm's srun) started it: the
// ProcessGroup the trainer and the training loop share steps through. Without a launcher
// nothing here touches MPI, so a plain `splat-train` is a plain process; a build without MPI
// (SPLAT_MPI=OFF, or no MPI library found) refuses to run as several ranks rather than
// train the same run several times over into one folder.
#include <memory>
#include <string>

#include "splat/train/process_group.hpp"

namespace splat::cli {

// The world's ranks if an MPI launcher started this process (its environment says so),
// initialising MPI; otherwise null. Throws Error when the launcher started several ranks
// and this build has no MPI.
std::unique_ptr<ProcessGroup> join_launched_ranks(int& argc, char**& argv);

// Ends every rank of the run with `status` after a failure on this one (the caller has
// printed what failed, naming this rank). Does not return.
[[noreturn]] void abort_all_ranks(int status);

}  // namespace splat::cli
