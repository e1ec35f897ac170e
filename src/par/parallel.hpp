#pragma once
// The ranks of a run (docs/method.md §16). Launched by mpirun/mpiexec in a build with MPI, a
// stage runs on MPI_COMM_WORLD; otherwise (no launcher, or a build without MPI) it is one rank
// and nothing here communicates, so every command keeps working without MPI and P = 1 is the
// serial program.
//
// Each rank keeps its own data (its scene, mesh, solver); what crosses ranks is said here:
// a shared counter that hands out work items in the order ranks ask for them, a barrier, and
// the agreement on an input error that every rank must see before any work starts.
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/error.hpp"

namespace dualcell::par {

// MPI_Init when launched by an MPI launcher (and built with MPI); MPI_Finalize on destruction.
// One per process, held by run_stage for the whole stage.
class Session {
 public:
  Session();
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;
};

bool built_with_mpi();
// This process's rank as its launcher numbered it (OpenMPI's OMPI_COMM_WORLD_RANK, PMIx's
// PMIX_RANK, Hydra's PMI_RANK), read before MPI starts and in a build without MPI too: 0 when
// not launched. For what happens before the Session (the command line's --help and errors).
int launcher_rank();
int rank();  // 0 without MPI
int size();  // 1 without MPI

// A counter at rank 0 that every rank increments atomically (MPI one-sided fetch-and-add):
// next() returns 0, 1, 2, ... across all ranks, each value once, in the order asked. Created
// and destroyed by every rank together (collective).
class SharedCounter {
 public:
  SharedCounter();
  ~SharedCounter();
  SharedCounter(const SharedCounter&) = delete;
  SharedCounter& operator=(const SharedCounter&) = delete;
  long next();
  // Lets MPI serve the other ranks' next() now. Over transports without hardware atomics (TCP:
  // OpenMPI's pt2pt one-sided component) a fetch-and-add is served only while the counter's
  // rank (0) is inside an MPI call, so rank 0 calls this now and then in its own work; else
  // a free rank could wait for a path until rank 0 finished its own.
  void serve() const;

 private:
  struct Impl;
  Impl* impl_;
  long serial_ = 0;
};

// The ranks that share one piece of work, e.g. the subdomains of one solve (docs/method.md §16):
// MPI_COMM_WORLD, a part of it (split), or this process alone. Every call here is collective
// over the group. A default Group is this process alone and never communicates, so a solver
// given no group is the serial one.
class Group {
 public:
  Group();
  static Group world();  // every rank of the run (this process alone without a launcher)
  // The ranks that pass the same `colour`, ordered as in this group (MPI_Comm_split).
  Group split(int colour) const;
  int rank() const { return rank_; }
  int size() const { return size_; }
  // Every rank's `mine` (counts[p] doubles on rank p) placed at all + displs[p], on every rank
  // (MPI_Allgatherv). Only copies: what arrives is bitwise what was sent, the same on every rank.
  // mine may be all + displs[rank()] (in place).
  void gather(const double* mine, double* all, const std::vector<int>& counts, const std::vector<int>& displs) const;
  double max(double mine) const;
  long max(long mine) const;
  // root's value, on every rank.
  long broadcast(long value, int root) const;
  // Every rank's `mine` (the same count on each), concatenated in rank order, on every rank.
  std::vector<double> gather(const std::vector<double>& mine) const;
  void barrier() const;

 private:
  struct Impl;
  std::shared_ptr<Impl> impl_;  // null: this process alone
  int rank_ = 0, size_ = 1;
};

void barrier();
// Collective: the sum of `mine` over the ranks, on every rank.
long sum(long mine);

// An input error every rank has seen (agree_on_error): run_stage prints it once, on rank 0,
// and every rank exits with the input-error code.
class CollectiveInputError : public InputError {
 public:
  using InputError::InputError;
};

// Collective: throws CollectiveInputError with the message of the lowest rank whose `mine` is
// not empty, on every rank; returns when every rank's is empty.
void agree_on_error(const std::string& mine);

// Stops every rank with `code` (MPI_Abort; std::exit without MPI).
[[noreturn]] void abort_all(int code);

// This process's peak resident memory so far, bytes (getrusage: ru_maxrss).
long peak_rss_bytes();

}  // namespace dualcell::par
