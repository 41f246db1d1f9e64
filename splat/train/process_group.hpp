#pragma once
// The processes one training run is shared among (data-parallel training over MPI, issue 18).
// The library does not depend on MPI: the trainer sees this interface, splat-train supplies
// the MPI implementation (train/mpi_process_group.hpp) when it was started by an MPI launcher.
// Every call is collective: each rank makes the same calls in the same order.
#include <span>

namespace splat {

class ProcessGroup {
 public:
  virtual ~ProcessGroup() = default;
  virtual int rank() const = 0;  // 0 .. size() − 1
  virtual int size() const = 0;
  // Every rank's `mine` (the same length on each), concatenated in rank order into `all`
  // (size() × mine.size() values).
  virtual void all_gather(std::span<const float> mine, std::span<float> all) = 0;
  // `send` holds size() equal parts, the q-th for rank q; `receive` (as long) gets every
  // rank's part for this one, in rank order.
  virtual void all_to_all(std::span<const float> send, std::span<float> receive) = 0;
  // Rank 0's values, on every rank.
  virtual void broadcast(std::span<double> values) = 0;
  // Whether any rank passed true.
  virtual bool any(bool mine) = 0;
};

}  // namespace splat
